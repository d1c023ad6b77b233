#pragma once
/// How much of a mesh's volume each lattice node carries: ∫_mesh N_i dV, the paper's "mass per control
/// point from the object's mass distribution" for a body of uniform density. A fish's mass then sits
/// where the fish is, not spread over the corners of its box.
///
/// The integral is sampled on a grid of S³ cell centres over the lattice box: along each line of the grid
/// parallel to the box's u axis, the mesh's triangles are crossed at known u, each crossing entering
/// (outward normal against the line) or leaving the solid; a sample is inside where more crossings
/// entered than left before it. Overlapping closed parts count once; a line whose crossings do not
/// balance passes through a hole in the surface and is reported as open.

#include "core/base/result.h"
#include "core/geometry/lattice.h"
#include "core/geometry/mesh.h"

#include <vector>

namespace softtouch {

/// The result of meshVolumeShares().
struct MeshVolumeShares {
    std::vector<double> nodeVolume; ///< ∫_mesh N_i dV per lattice node, m³ (sums to `volume`).
    double volume = 0.0;            ///< The mesh's volume inside the box, m³.
    int openLines = 0;              ///< Sample lines whose crossings did not balance (holes in the surface).
    int linesThroughMesh = 0;       ///< Sample lines that crossed the mesh at all.
    /// With `occupancyCells` G > 0: the fraction of each of G³ equal cells of the parameter box that lies
    /// inside the mesh (index cu + G·(cv + G·cw)), from the same samples. Empty otherwise.
    std::vector<double> occupancy;
};

/// Samples per box axis meshVolumeShares() uses by default (48³ ≈ 110k points: a node's share is good to
/// about a percent for the bundled fish, in a few tens of milliseconds).
inline constexpr int kMeshVolumeSamples = 48;

/// Each node's share of the mesh's volume. Fails, saying why, when the mesh is not a closed surface
/// (an edge borders one triangle only, vertices at one position counted as one), when it encloses no
/// volume inside the box, or when more than 2% of the sample lines through it cross it unevenly.
/// `samples` in [4, 512].
Result<MeshVolumeShares> meshVolumeShares(const Lattice& lattice, const Mesh& mesh, int samples = kMeshVolumeSamples,
                                          int occupancyCells = 0);

/// Least mass a node gets from meshMassPerNode(), as a fraction of the mean over non-void nodes. Nodes
/// outside the mesh carry the map but no material; the paper found light "air" nodes unstable and hard to
/// calm, and an explicit step's bound falls as √(m_min): at a tenth of the mean it is at most ~3x
/// shorter than with the mass spread evenly (docs/design/lattice.md, "Mass from the mesh").
inline constexpr double kMeshMassFloor = 0.1;

/// Node masses (kg) that spread `totalMass` by each non-void node's share of the mesh's volume, none
/// below kMeshMassFloor of the mean, and adding up to `totalMass` over the non-void nodes (void nodes
/// keep 0). Precondition: shares.nodeVolume and isVoid have one entry per node, some node is not void.
std::vector<double> meshMassPerNode(const MeshVolumeShares& shares, const std::vector<std::uint8_t>& isVoid, double totalMass);

}  // namespace softtouch

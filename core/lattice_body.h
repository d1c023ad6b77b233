#pragma once
/// The paper's mass-spring lattice: nodes of a Lattice joined by unique springs per cell.
///
/// One cell (8 nodes) has 28 springs:             6-------7
///   12 edges        (e.g. 0-1)                  /|      /|
///   12 face diagonals (e.g. 0-3, two per face)  4-------5 |
///    4 body diagonals (0-7, 1-6, 2-5, 3-4)      | 2-----|-3
/// Shared edges and faces are created once, so  |/      |/
/// a 4x4x4 lattice has 144 + 216 + 108 = 468.   0-------1
/// (The paper's 504 counts 180 edge springs; a 4x4x4 grid has only 144 unique edges: docs/lattice.md.)

#include "core/body_model.h"
#include "core/lattice.h"
#include "core/mesh.h"

#include <array>
#include <vector>

namespace softtouch {

/// Per-node painted values and global material settings of a lattice body.
struct LatticeMaterial {
    std::vector<double> mass;            ///< kg per node, > 0. Filled by uniformMaterial() or painting.
    std::vector<double> stiffness;       ///< N/m per node; a spring gets the mean of its two nodes. [0, 1e9].
    std::vector<double> damping;         ///< N·s/m per node; a spring gets the mean of its two nodes. [0, 1e6].
    std::vector<AnchorMode> anchor;      ///< Per node; Free by default.
    std::vector<std::uint8_t> isVoid;    ///< Per node; 1 removes the node and its springs.
    std::array<double, 3> kindScale{1.0, 1.0, 1.0}; ///< Stiffness multiplier for edge, face-, body-diagonal springs. [0, 1e3].
    Vec3 anisotropy = Vec3::Ones();      ///< Stiffness multiplier along box axes u, v, w; a spring of rest
                                         ///< direction d (box frame) gets Σ d_a² s_a. Paper's transversely
                                         ///< isotropic material: (1, 0.1, 1). [1e-6, 1e6] each.
    double heavyAnchorRatio = 1e4;       ///< Mass multiplier of Heavy anchors (paper: 10,000x). [1, 1e9].
    double airDamping = 0.0;             ///< Absolute-velocity damping per node (the paper's d_i), N·s/m. [0, 1e6].
};

/// A material with the same values on every node of a lattice.
LatticeMaterial uniformMaterial(const Lattice& lattice, double massPerNode, double stiffness, double damping);

/// Spring counts by kind.
struct SpringCounts {
    int edges = 0;
    int faceDiagonals = 0;
    int bodyDiagonals = 0;
    int total() const { return edges + faceDiagonals + bodyDiagonals; }
};

/// The unique lattice springs between all nodes (voids not yet removed), stiffness and damping from
/// the material.
std::vector<Spring> latticeSprings(const Lattice& lattice, const LatticeMaterial& material);
/// Counts springs by kind.
SpringCounts countSprings(const std::vector<Spring>& springs);

/// Builds the body of a lattice: validates the material (errors name the node and field), removes
/// void nodes with their springs, and lets void nodes follow their non-void neighbours.
Result<std::shared_ptr<const BodyModel>> buildLatticeBody(const Lattice& lattice, const LatticeMaterial& material);

/// The material of `from` carried onto lattice `to` (another resolution or kind over the same object):
/// every node of `to` takes the painted values, anchor and void state of the node of `from` nearest in
/// lattice parameters. With `keepContinuum`, values are rescaled so the body stays the same material
/// rather than the same springs: node mass and air damping scale with the node's share of the volume,
/// spring stiffness and damping with the lattice spacing (a cubic spring lattice of spacing h and
/// spring constant k behaves like a solid of modulus ~ k/h).
LatticeMaterial resampleMaterial(const Lattice& from, const LatticeMaterial& material, const Lattice& to,
                                 bool keepContinuum);

/// Nodes none of whose adjacent grid cells hold any of the mesh (vertices or triangle centroids):
/// candidates for void (thin shapes such as fins leave whole cells empty).
std::vector<std::uint8_t> findEmptyNodes(const Lattice& lattice, const Mesh& mesh);

}  // namespace softtouch

#pragma once
/// The paper's mass-spring lattice: nodes of a Lattice joined by unique springs per cell.
///
/// One cell (8 nodes) has 28 springs:             6-------7
///   12 edges        (e.g. 0-1)                  /|      /|
///   12 face diagonals (e.g. 0-3, two per face)  4-------5 |
///    4 body diagonals (0-7, 1-6, 2-5, 3-4)      | 2-----|-3
/// Shared edges and faces are created once, so  |/      |/
/// a 4x4x4 lattice has 144 + 216 + 108 = 468.   0-------1
/// (The paper's 504 counts 180 edge springs; a 4x4x4 grid has only 144 unique edges: docs/design/lattice.md.)

#include "core/base/ranges.h"
#include "core/body/body_model.h"
#include "core/geometry/lattice.h"
#include "core/geometry/mesh.h"

#include <array>
#include <optional>
#include <vector>

namespace softtouch {

/// What a material's per-node values mean.
enum class MaterialModel : std::uint8_t {
    /// The paper's: the values belong to this lattice's nodes and springs (kg per node, N/m and N·s/m
    /// per spring, node damping N·s/m per node). The same values on another resolution are another material.
    /// Projects written before version 3 use it and keep their motion exactly.
    LatticeSprings,
    /// A solid filling the lattice box whose values do not depend on the lattice: density kg/m³,
    /// Young's modulus Pa, viscosity Pa·s, node damping rate 1/s. buildLatticeBody() turns them into
    /// node masses (density × the node's share of the box), node damping (rate × node mass) and springs
    /// (docs/design/lattice.md, "Material").
    Continuum,
};

/// What a body simulates its material with (docs/design/lattice.md, "The solid element").
enum class BodyElement : std::uint8_t {
    Springs, ///< The paper's damped springs between neighbouring nodes, one mass per node.
    /// The Galerkin solid element on the lattice's own basis with its consistent mass (core/body/element_body.h):
    /// the same modes on every lattice kind and resolution (within 5% from 4x4x4 up), at more cost a step.
    /// Continuum materials only; no void nodes, strain limits or volume preservation; heavy anchors hold like
    /// pinned ones; run by the explicit schemes (Verlet, symplectic Euler).
    Solid,
};
/// Stable name used in files ("springs", "solid").
const char* bodyElementName(BodyElement element);

/// Per-node painted values and global material settings of a lattice body. The units of mass,
/// stiffness, damping and nodeDamping depend on `model`; ranges are those of materialRanges(model).
/// The two damping terms (docs/design/lattice.md, "Two damping terms"): `damping` acts on the relative
/// velocity along each spring, `nodeDamping` on each node's absolute velocity (the paper's D).
struct LatticeMaterial {
    MaterialModel model = MaterialModel::LatticeSprings; ///< What the values below mean.
    BodyElement element = BodyElement::Springs;          ///< What simulates them.
    std::vector<double> mass;            ///< kg per node, or density kg/m³ (Continuum). > 0.
    std::vector<double> stiffness;       ///< N/m per node, or Young's modulus Pa (Continuum); a spring gets
                                         ///< the mean of its two nodes. >= 0.
    std::vector<double> damping;         ///< Spring damping: N·s/m per node, or viscosity Pa·s (Continuum); a
                                         ///< spring gets the mean of its two nodes. >= 0.
    std::vector<double> nodeDamping;     ///< Node damping on each node's absolute velocity (the paper's d_i):
                                         ///< N·s/m per node, or the rate d_i / m_i in 1/s (Continuum). >= 0.
                                         ///< Files call it "airDamping" / "dampingRate".
    std::vector<AnchorMode> anchor;      ///< Per node; Free by default.
    std::vector<std::uint8_t> isVoid;    ///< Per node; 1 removes the node and its springs.
    std::array<double, 3> kindScale{1.0, 1.0, 1.0}; ///< Stiffness multiplier for edge, face-, body-diagonal springs. [0, 1e3].
    Vec3 anisotropy = Vec3::Ones();      ///< Stiffness multiplier along box axes u, v, w; a spring of rest
                                         ///< direction d (box frame) gets Σ d_a² s_a. Paper's transversely
                                         ///< isotropic material: (1, 0.1, 1). [1e-6, 1e6] each.
    double heavyAnchorRatio = 1e4;       ///< Mass multiplier of Heavy anchors (paper: 10,000x). [1, 1e9].
    std::vector<double> goalWeight;      ///< Per node, [0, 1]: how closely the node follows a base animation
                                         ///< (core/animation/base_motion.h): 0 free, 1 exactly. Empty: 0 everywhere.
    StrainLimits strainLimits;           ///< No spring beyond stretch × (or under squash ×) its rest length; off.
    std::vector<double> volumePreservation; ///< Per node, [0, 1]: how stiffly the mesh's volume around the node
                                         ///< is kept, 0 off, 1 hard (core/body/volume_preservation.h). Empty: 0
                                         ///< everywhere. Painted like stiffness; the body's largest value sets
                                         ///< the stiffness and each region counts by its value.
    bool operator==(const LatticeMaterial&) const = default;
};

/// Name, valid range and unit of each field under a model (core/base/ranges.h's FieldRange): one table for
/// validation, the project files' keys and the editor's labels.
using MaterialRange = FieldRange;
/// The painted volume preservation and goal weight, the same under both models (fractions, no unit).
inline constexpr MaterialRange kVolumePreservationRange{"volumePreservation", "volume preservation", 0.0, 1.0, ""};
inline constexpr MaterialRange kGoalWeightRange{"goalWeight", "goal weight", 0.0, 1.0, ""};
struct MaterialRanges {
    const char* model = "";  ///< The model's name in files: "lattice-springs" or "continuum".
    MaterialRange mass, stiffness, damping, nodeDamping;
};
const MaterialRanges& materialRanges(MaterialModel model);

/// The values a new material starts with, per model (uniform over the nodes).
struct DefaultMaterialValues {
    double mass, stiffness, damping, nodeDamping;
};
const DefaultMaterialValues& defaultMaterialValues(MaterialModel model);
/// A new object's material: defaultMaterialValues(model) on every node.
LatticeMaterial defaultMaterial(const Lattice& lattice, MaterialModel model = MaterialModel::Continuum);

/// A resolution-independent material with the same values everywhere.
LatticeMaterial continuumMaterial(const Lattice& lattice, double density, double modulus, double viscosity);

/// The largest volume preservation of the material's non-void nodes (0: the body keeps no volume).
double largestVolumePreservation(const LatticeMaterial& material);
/// Every node's volume preservation set to `p` (a uniform map; 0 turns it off).
void setVolumePreservation(LatticeMaterial& material, double p);

/// Mean of a per-node field over the material's non-void nodes (0 when every node is void).
double solidMean(const std::vector<double>& values, const LatticeMaterial& material);

/// Each node's share of the lattice box, m³: the dual volume (an eighth of every adjacent grid cell
/// between rest node positions). They sum to the box volume.
std::vector<double> nodeVolumes(const Lattice& lattice);

/// The mass of every node in kg under either model (Continuum: density × node volume; heavy anchors
/// not multiplied, voids included).
std::vector<double> nodeMasses(const Lattice& lattice, const LatticeMaterial& material);

/// A material with the same values on every node of a lattice (and no node damping).
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

/// What buildLatticeBody derives from a mesh on a lattice, whatever the material: the contact sample
/// points and the volume samples' occupancy. Each is computed on first need and kept, so bodies rebuilt
/// on the same mesh and lattice (the editor's material edits) do not compute them again.
struct MeshLatticeCache {
    std::shared_ptr<const ContactPoints> contactPoints;
    std::optional<std::vector<double>> volumeOccupancy;  ///< Empty without a closed mesh.
};

/// Builds the body of a lattice: validates the material (errors name the node and field), removes
/// void nodes with their springs, and lets void nodes follow their non-void neighbours.
/// With volume preservation on, the kept volume is `mesh`'s (a closed mesh; otherwise, or without one, the
/// lattice box's). `cache`, when given, must come from this mesh and lattice (it is filled as needed).
Result<std::shared_ptr<const BodyModel>> buildLatticeBody(const Lattice& lattice, const LatticeMaterial& material,
                                                          const Mesh* mesh = nullptr, MeshLatticeCache* cache = nullptr);

/// The material of `from` carried onto lattice `to` (another resolution or kind over the same object):
/// every node of `to` takes the painted values of the node of `from` nearest in lattice parameters; anchors
/// and voids keep their extent in the material (a node is flagged where all source nodes around it are, and
/// each flagged source node flags its nearest node of `to`). A Continuum material's values are intensive and carried as they are. For a
/// LatticeSprings material with `keepContinuum`, values are rescaled so the body stays roughly the same
/// material rather than the same springs: node mass and node damping scale with the node's share of the
/// volume, spring stiffness and damping with the lattice spacing.
LatticeMaterial resampleMaterial(const Lattice& from, const LatticeMaterial& material, const Lattice& to,
                                 bool keepContinuum);

/// Nodes none of whose adjacent grid cells hold any of the mesh (vertices or triangle centroids):
/// candidates for void (thin shapes such as fins leave whole cells empty).
std::vector<std::uint8_t> findEmptyNodes(const Lattice& lattice, const Mesh& mesh);

}  // namespace softtouch

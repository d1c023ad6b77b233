#pragma once
/// The immutable description of a mass-spring body: nodes, springs, anchors, voids. Built once by
/// buildBodyModel() and shared (std::shared_ptr<const BodyModel>) by every simulator that runs it.

#include "core/base/ranges.h"
#include "core/base/result.h"
#include "core/base/types.h"
#include "core/body/colliders.h"
#include "core/body/element_body.h"
#include "core/body/spring_forces.h"
#include "core/body/strain_limits.h"
#include "core/body/volume_preservation.h"

#include <memory>
#include <mutex>
#include <vector>

namespace softtouch {

/// Where a spring sits in the lattice (for counts, per-kind stiffness and drawing).
enum class SpringKind : std::uint8_t { Edge, FaceDiagonal, BodyDiagonal, Custom };

/// A damped spring between two nodes.
struct Spring {
    std::uint32_t a = 0;       ///< First node.
    std::uint32_t b = 0;       ///< Second node.
    double restLength = 0.0;   ///< Metres, > 0; from the rest positions.
    double stiffness = 0.0;    ///< k, N/m, [0, 1e9].
    double damping = 0.0;      ///< c along the spring (relative velocity), N·s/m, [0, 1e6].
    SpringKind kind = SpringKind::Custom; ///< Lattice role.
};

/// How a node is held.
enum class AnchorMode : std::uint8_t {
    Free,   ///< Simulated normally.
    Pinned, ///< Kinematic: never moves (a constraint, not a huge mass).
    Heavy,  ///< Simulated with its mass multiplied by heavyAnchorRatio (the paper's anchors).
};

/// A void node follows the mean displacement of its donors (already-resolved neighbours), so the
/// mesh near a removed node keeps following the body.
struct VoidFollower {
    std::uint32_t node = 0;              ///< The void node.
    std::vector<std::uint32_t> donors;   ///< Nodes whose displacement it copies (resolved before it).
};

/// How many times its mass a Heavy anchor weighs, as material files name it (the reader and
/// buildBodyModel() check it).
inline constexpr FieldRange kHeavyAnchorRatio{"heavyAnchorRatio", "heavy anchor ratio", 1.0, 1e9, ""};

/// Input to buildBodyModel(): plain arrays, one entry per node.
struct BodyDescription {
    std::vector<Vec3> restPositions;     ///< Metres.
    std::vector<double> mass;            ///< kg, finite, > 0 (ignored for void nodes).
    std::vector<AnchorMode> anchor;      ///< Empty means all Free.
    std::vector<std::uint8_t> isVoid;    ///< 1: removed from the simulation. Empty means none.
    std::vector<Spring> springs;         ///< Springs touching void nodes are dropped.
    std::vector<VoidFollower> voidFollowers; ///< In resolution order; see VoidFollower.
    double heavyAnchorRatio = 1e4;       ///< Mass multiplier of Heavy anchors, kHeavyAnchorRatio. Paper: 1e4.
    std::vector<double> nodeDamping;     ///< Damping on each node's absolute velocity (the paper's d_i), N·s/m,
                                         ///< [0, 1e6]. Empty means none.
    StrainLimits strainLimits;           ///< Stretch and squash limits of every spring; off by default.
    VolumeConstraint volume;             ///< Volume preservation (core/body/volume_preservation.h); off by default.
    /// Where colliders are tested; null or empty: at the nodes. Shared, not copied: the points depend on
    /// the mesh and lattice only, so every body rebuilt on them (a material edit) keeps the same ones.
    std::shared_ptr<const ContactPoints> contactPoints;
    /// The solid element the body runs instead of springs (core/body/element_body.h); null: springs. With one,
    /// `springs` and `nodeDamping` must be empty (the element holds its damping), `mass` holds each node's
    /// ∫ρ N_i (gravity's and momentum's share) and no node may be a heavy anchor.
    std::shared_ptr<const ElementBody> element;
};

/// Immutable, validated body.
struct BodyModel {
    std::vector<Vec3> restPositions;     ///< Metres.
    std::vector<double> mass;            ///< Effective mass (heavy anchors multiplied), kg; 0 for void.
    std::vector<double> inverseMass;     ///< 0 for pinned and void nodes.
    std::vector<std::uint8_t> simulated; ///< 1 unless void.
    std::vector<std::uint8_t> pinned;    ///< 1 for pinned anchors.
    std::vector<Spring> springs;         ///< Springs between simulated nodes only.
    SpringTable springTable;             ///< The springs that move a free node, laid out for the force pass.
    std::vector<VoidFollower> voidFollowers; ///< See VoidFollower.
    std::vector<double> nodeDamping;     ///< d_i, N·s/m on absolute velocity (the paper's D); 0 for void nodes.
    StrainLimits strainLimits;           ///< Held after every substep (core/body/strain_limits.h); off by default.
    VolumeConstraint volume;             ///< Kept after every substep (core/body/volume_preservation.h); off by default.
    /// Mesh surface points colliders are tested at (core/body/colliders.h); null or empty: the nodes themselves.
    std::shared_ptr<const ContactPoints> contactPoints;
    /// The solid element the body runs instead of springs; null for a spring body. Its integrators solve with its
    /// consistent mass; `mass` is then each node's ∫ρ N_i, the share of gravity, momentum and contacts.
    std::shared_ptr<const ElementBody> element;
    bool anyNodeDamping = false;         ///< Some d_i > 0 (otherwise the force pass skips the term).
    bool anySpringDamping = false;       ///< Some spring has c > 0 (otherwise the energy account skips it); filled by build.
    double maxNodeDampingRate = 0.0;     ///< Largest d_i / m_i over free nodes (1/s); filled by build.
    double maxDampingRatio = 0.0;        ///< Largest c/k over springs (s); filled by build.
    double maxInverseMass = 0.0;         ///< Largest inverse mass of a free node (1/kg); filled by build.

    std::size_t nodeCount() const { return restPositions.size(); }
    /// Largest eigenvalue of M^-1 K at rest (1/s^2): the explicit step bound's. Computed on first use
    /// (Lanczos: more than half of what building a 4x4x4 body costs), so a body that implicit Euler or
    /// XPBD runs, such as the one a paint dab rebuilds on the bundled fish, does not pay for it. An
    /// explicit scheme's Simulator asks at construction, never inside a real-time loop. Thread-safe.
    double maxStiffnessOverMass() const;
    /// On a viscous solid element body, the modes of its viscosity bound (elementViscosityModes()), which its
    /// explicit substeps take part of implicitly; empty otherwise. Computed on first use, as
    /// maxStiffnessOverMass() (an explicit scheme's Simulator asks at construction). Thread-safe.
    const ElementViscosityModes& elementViscosityModes() const;
    /// The contact points; none (size 0) when colliders are tested at the nodes.
    const ContactPoints& contacts() const {
        static const ContactPoints none;
        return contactPoints ? *contactPoints : none;
    }

private:
    mutable std::once_flag m_stepBoundOnce;
    mutable double m_maxStiffnessOverMass = 0.0;
    mutable std::once_flag m_viscosityModesOnce;
    mutable ElementViscosityModes m_elementViscosityModes;
};

/// Validates a description and builds the model (drops void springs, computes inverse masses and
/// the stability data). Errors name the node or spring and the expected range.
Result<std::shared_ptr<const BodyModel>> buildBodyModel(const BodyDescription& description);

}  // namespace softtouch

#pragma once
/// Secondary motion on a base animation: the fish swims as its rig says, and the lattice adds the lag,
/// overshoot and settle of a soft body on top (docs/design/lattice.md, "Secondary motion on a base animation").
///
/// Each step the base animation's mesh is fitted by a lattice pose, the goal G(t) (core/animation/goal_fit.h), and
/// the body simulates its deviation from that goal in the goal's frame: a lattice body at its rest shape
/// whose node i feels, besides its springs,
///   - the inertia of following the goal, F_i = m_i Rᵀ (g − G̈_i): the frame that carries node i with its goal
///     accelerates with it, so the node lags when the fish speeds up or turns and overshoots when it stops
///     (R is the base mesh's rotation, from the polar part of its best affine fit; gravity g is the world's;
///     the rotating frame's Coriolis and centrifugal terms are left out, a small-angular-rate approximation);
///   - a goal spring back to its rest place, weighted by the painted goal weight w_i ∈ [0, 1]:
///     k_i = m_i ω² w/(1 − w), c_i = 2 ζ m_i ω √(w/(1 − w)), ω = 2π × `frequency`: a node of weight ½ alone on
///     its goal swings at `frequency` with damping ratio ζ, mass-proportional, so the weights mean the same
///     on every lattice. Weight 1 pins the node to its goal (as pinned anchors are).
/// The exported mesh is the base mesh plus the deviation carried through the binding and turned with the
/// base: p(t) = p_base(t) + R (B x − B x_rest). Where every node has weight 1 the deviation is exactly zero
/// and the output is the base animation itself; detail the lattice cannot represent is never lost.

#include "core/animation/base_animation.h"
#include "core/animation/goal_fit.h"
#include "core/body/body_model.h"
#include "core/body/forces.h"
#include "core/body/lattice_body.h"
#include "core/geometry/binding.h"
#include "core/modes/modes.h"

#include <memory>
#include <mutex>

namespace softtouch {

/// How a body follows its base animation.
struct FollowSettings {
    double frequency = 2.0;    ///< Hz: the swing of a node of goal weight ½ alone on its spring, (0, 1000].
    double dampingRatio = 0.5; ///< Of that swing, at every weight, [0, 100].
    Status validate() const;
    bool operator==(const FollowSettings&) const = default;
};

/// The goal springs of a body built from followingMaterial(): per node, k = m ω² w/(1 − w) and
/// c = 2 ζ m ω √(w/(1 − w)) for 0 < w < 1, zero elsewhere (pinned, void, or weight 0).
NodeSprings goalSprings(const BodyModel& model, std::span<const double> goalWeight, const FollowSettings& settings);

/// The material a following body is built from: nodes of goal weight 1 (or more) pinned.
LatticeMaterial followingMaterial(LatticeMaterial material);

/// The runtime of one object on a base animation.
class BaseMotion {
public:
    /// `model`: the body built from followingMaterial() (its masses set the goal springs, made once here).
    /// `goalWeight`: per lattice node, [0, 1] (empty: 0 everywhere). `restPositions` is the mesh the
    /// animation moves (its first sample is where the lattice was fitted) and `fit` the lattice's GoalFit of it
    /// (GoalFit::create with its binding's parameters), which depends on mesh and lattice only: a material edit
    /// keeps it.
    static Result<std::shared_ptr<BaseMotion>> create(const Lattice& lattice, const BodyModel& model,
                                                      std::span<const Vec3f> restPositions,
                                                      std::shared_ptr<const GoalFit> fit,
                                                      std::shared_ptr<const BaseAnimation> animation,
                                                      std::span<const double> goalWeight, const FollowSettings& settings);

    /// Adds the forces of a step of `dt` starting at `seconds` to `forces`: the inertia (node forces, with the
    /// world's gravity folded in, so `forces.gravity` is cleared) and the goal springs (drags to the rest
    /// nodes). `model` is the body being stepped (the one given to create()).
    void addForces(double seconds, double dt, const BodyModel& model, ExternalForces& forces) const;

    /// The base mesh at `seconds` plus the deviation of `nodes` from rest (see above), turned with the base;
    /// normals from the result's triangles when `normals` is not empty.
    void deform(double seconds, const Binding& binding, std::span<const Vec3> nodes,
                std::span<const std::array<std::uint32_t, 3>> triangles, std::span<Vec3f> positions,
                std::span<Vec3f> normals) const;

    /// Where the lattice is seen at `seconds` (overlays, pictures): the goal plus the turned deviation,
    /// G + R (x − x_rest); `rotation`, when given, receives R.
    void shownNodes(double seconds, std::span<const Vec3> nodes, std::vector<Vec3>& out, Mat3* rotation = nullptr) const;

    /// The goal pose and rotation at `seconds` (cached: a step asks for three times, the next reuses two).
    void goal(double seconds, std::vector<Vec3>& nodes, Mat3& rotation) const;

    const BaseAnimation& animation() const { return *m_animation; }

private:
    std::shared_ptr<const BaseAnimation> m_animation;
    std::shared_ptr<const GoalFit> m_fit;
    std::vector<Vec3> m_restNodes;
    mutable std::vector<Vec3f> m_restEvaluated;  ///< B x_rest as the binding evaluates it (so weight 1 gives exactly 0).
    std::vector<DragSpring> m_goalSprings;  ///< One per node of goal weight in (0, 1), to its rest place.
    struct Cached {
        double seconds = 0.0;
        std::vector<Vec3> nodes;
        Mat3 rotation = Mat3::Identity();
    };
    mutable std::mutex m_mutex;
    mutable std::vector<Cached> m_cache;  ///< The last few fits.
    mutable std::vector<Vec3f> m_positions;
    mutable std::vector<Vec3f> m_deformed;
};

}  // namespace softtouch

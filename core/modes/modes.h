#pragma once
/// Vibration modes of a body about its rest state: the numbers an animator tunes by ("how fast does it
/// wobble, how quickly does it settle") computed from the body itself, not from one node on one spring.
///
/// Linearised about rest (springs unstretched, so only the material stiffness remains):
///   M ü + C u̇ + K u = 0,   K = Σ_springs k n nᵀ (assembled ±),   C = Σ_springs c n nᵀ + diag(d_i)
/// over the free nodes (pinned anchors are fixed, void nodes are not simulated, heavy anchors keep
/// their multiplied mass). The undamped modes solve the generalized eigenproblem K φ = ω² M φ (dense,
/// through the symmetric form M^-½ K M^-½). Each mode's damping ratio is the modal projection
/// ζ = φᵀ C φ / (2 ω φᵀ M φ), split into the part from the paper's node (absolute) damping and the part
/// from spring (relative) damping; for the light damping of animation bodies the coupling C brings
/// between modes changes ζ at second order only (tests/core/test_modes measures baked motion against it).

#include "core/base/result.h"
#include "core/body/body_model.h"

#include <Eigen/Core>

#include <span>
#include <vector>

namespace softtouch {

/// One vibration mode.
struct VibrationMode {
    double frequencyHz = 0.0;         ///< Undamped natural frequency f = ω/2π, Hz.
    double dampingRatio = 0.0;        ///< ζ = ζ_node + ζ_spring; 1 is critical (no oscillation).
    double nodeDampingRatio = 0.0;    ///< Part of ζ from node damping on absolute velocity (paper's D).
    double springDampingRatio = 0.0;  ///< Part of ζ from spring damping on relative velocity.
    std::vector<Vec3> shape;          ///< Displacement per node, metres, scaled so max |φ_i| = 1; zero on
                                      ///< pinned nodes; void nodes follow their donors (for drawing).
    /// Frequency of the damped oscillation f·√(1−ζ²) (0 when ζ >= 1), Hz: what a baked release shows.
    double dampedFrequencyHz() const;
};

/// The result of analyseModes().
struct ModalAnalysis {
    std::vector<VibrationMode> modes;  ///< Lowest elastic modes first.
    int rigidModes = 0;                ///< Zero-frequency modes skipped (6 for a free body, fewer when anchored).
    int unknowns = 0;                  ///< Size of the eigenproblem (3 × free nodes).
};

/// How many of `ascending` eigenvalues (ω², lowest first) are rigid motions: zero up to round-off, which scales
/// with the largest. analyseModes() and the solid reference (core/modes/solid_modes.h) skip them alike.
int rigidModeCount(const Eigen::VectorXd& ascending);

/// Largest eigenproblem analyseModes() solves (dense; ~3 s at this size on one core).
inline constexpr int kMaxModalUnknowns = 3000;

/// Springs from single nodes to fixed places (a body's goal springs toward its base animation,
/// core/animation/base_motion.h), per node: stiffness N/m and damping N·s/m, isotropic. Empty: none.
struct NodeSprings {
    std::vector<double> stiffness;
    std::vector<double> damping;
};

/// The `count` lowest elastic modes of a body at rest (with `springs` added to each node's stiffness and its
/// node damping). Fails, saying why, when no node is free or the problem exceeds kMaxModalUnknowns.
Result<ModalAnalysis> analyseModes(const BodyModel& model, int count = 3, const NodeSprings& springs = {});

/// How large the editor's mode view and `softtouch-cli modes --pictures` draw a mode: its largest node
/// displacement as a fraction of the lattice box's largest side. A linear mode has no amplitude of its
/// own; this one is large enough to read and small enough to stay a small wobble.
inline constexpr double kModeDisplayFraction = 0.12;
/// Rate the editor animates every mode at, Hz: the true frequency is shown as a number beside it, so a
/// 40 Hz mode is still a shape one can follow.
inline constexpr double kModeDisplayHz = 1.0;

/// Node positions displaced along a mode: rest_i + amplitude · φ_i (amplitude in metres, since max |φ_i|
/// = 1 it is the largest node displacement). `rest` has one entry per node of the mode's body.
std::vector<Vec3> modePose(std::span<const Vec3> rest, const VibrationMode& mode, double amplitude);

}  // namespace softtouch

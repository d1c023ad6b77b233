#pragma once
/// Stretch and squash limits: the animator's "no spring longer than 1.5x its rest length", held as a
/// constraint after every substep of every integrator (X. Provot, "Deformation constraints in a
/// mass-spring model to describe rigid cloth behavior", Graphics Interface 1995). docs/design/lattice.md,
/// "Stretch and squash limits".

#include "core/base/result.h"

namespace softtouch {

struct BodyModel;
struct BodyState;

/// The ranges of the limits (besides 0, off): one place for validation, the project reader and the editor.
inline constexpr double kMinStretchLimit = 1.01, kMaxStretchLimit = 100.0;
inline constexpr double kMinSquashLimit = 0.01, kMaxSquashLimit = 0.99;

/// Bounds on every spring's length as a multiple of its rest length. 0 turns a bound off.
struct StrainLimits {
    double stretch = 0.0;  ///< Longest length / rest length: 0 (off) or [kMinStretchLimit, kMaxStretchLimit].
    double squash = 0.0;   ///< Shortest length / rest length: 0 (off) or [kMinSquashLimit, kMaxSquashLimit].
    bool any() const { return stretch > 0.0 || squash > 0.0; }
    bool operator==(const StrainLimits&) const = default;
};

/// Checks the ranges above; errors name the field ("stretch limit must be 0 (off) or in [1.01, 100]").
Status validateStrainLimits(const StrainLimits& limits);

/// What one enforcement did.
struct StrainLimitPass {
    int corrections = 0;        ///< Spring corrections made, over all sweeps (0: nothing was out of bounds).
    int sweeps = 0;             ///< Gauss-Seidel sweeps over the springs.
    double worstExcess = 0.0;   ///< Largest |length − bound| / rest length found by the first sweep.
};

/// True when some spring between simulated nodes is outside its bounds (a read-only scan).
bool strainLimitsViolated(const BodyModel& model, const StrainLimits& limits, const BodyState& state);

/// Brings every spring outside [squash, stretch] × rest length back onto the bound it crossed: both ends
/// move along the spring in proportion to their inverse masses (momentum kept; pinned ends stay), and the
/// part of their relative velocity along the spring that carries them further out is removed, as a
/// perfectly inelastic impulse (kinetic energy only falls). Gauss-Seidel sweeps repeat until no spring is
/// out by more than 1e-4 of its rest length, at most `maxSweeps`. Allocates nothing.
StrainLimitPass enforceStrainLimits(const BodyModel& model, const StrainLimits& limits, BodyState& state,
                                    int maxSweeps = 64);

}  // namespace softtouch

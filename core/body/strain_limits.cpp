#include "core/body/strain_limits.h"

#include "core/body/body_model.h"
#include "core/body/forces.h"

#include <algorithm>
#include <cmath>

namespace softtouch {

namespace {

/// Sweeps stop once no spring is out of bounds by more than this fraction of its rest length.
constexpr double kTolerance = 1e-4;

/// The bound a spring of `length` crossed (0 when inside), for rest length `rest`.
double crossedBound(const StrainLimits& limits, double length, double rest) {
    if (limits.stretch > 0.0 && length > limits.stretch * rest)
        return limits.stretch * rest;
    if (limits.squash > 0.0 && length < limits.squash * rest)
        return limits.squash * rest;
    return 0.0;
}

}  // namespace

Status validateStrainLimits(const StrainLimits& limits) {
    if (!(limits.stretch == 0.0 || (limits.stretch >= kMinStretchLimit && limits.stretch <= kMaxStretchLimit)))
        return Status::error("stretch limit must be 0 (off) or in [1.01, 100] times the rest length, got " +
                             std::to_string(limits.stretch));
    if (!(limits.squash == 0.0 || (limits.squash >= kMinSquashLimit && limits.squash <= kMaxSquashLimit)))
        return Status::error("squash limit must be 0 (off) or in [0.01, 0.99] times the rest length, got " +
                             std::to_string(limits.squash));
    return Status::success();
}

bool strainLimitsViolated(const BodyModel& model, const StrainLimits& limits, const BodyState& state) {
    if (!limits.any())
        return false;
    // Squared lengths against squared bounds: no square root per spring in the common case.
    const double stretch2 = limits.stretch > 0.0 ? limits.stretch * limits.stretch : 1e300;
    const double squash2 = limits.squash * limits.squash;
    for (const Spring& s : model.springs) {
        const double length2 = (state.position[s.b] - state.position[s.a]).squaredNorm();
        const double rest2 = s.restLength * s.restLength;
        if ((length2 > stretch2 * rest2 || length2 < squash2 * rest2) &&
            model.inverseMass[s.a] + model.inverseMass[s.b] > 0.0)
            return true;
    }
    return false;
}

StrainLimitPass enforceStrainLimits(const BodyModel& model, const StrainLimits& limits, BodyState& state, int maxSweeps) {
    StrainLimitPass pass;
    if (!limits.any())
        return pass;
    // One spring's correction; returns how far out it was (fraction of its rest length), 0 when inside.
    auto correct = [&](const Spring& s) {
        const double wa = model.inverseMass[s.a], wb = model.inverseMass[s.b];
        if (wa + wb == 0.0)
            return 0.0;
        const Vec3 r = state.position[s.b] - state.position[s.a];
        const double length = r.norm();
        const double bound = crossedBound(limits, length, s.restLength);
        if (bound == 0.0 || length == 0.0)
            return 0.0;
        const Vec3 direction = r / length;
        const double shareA = wa / (wa + wb), shareB = wb / (wa + wb);
        // Positions: each end moves along the spring by its share, so the spring lands on the bound and
        // the mass-weighted centre stays where it was.
        const Vec3 correction = (length - bound) * direction;
        state.position[s.a] += shareA * correction;
        state.position[s.b] -= shareB * correction;
        // Velocities: an over-stretched spring whose ends still part (or a squashed one whose ends still
        // close) loses that relative velocity; a velocity that already heals it is kept.
        const double closing = (state.velocity[s.b] - state.velocity[s.a]).dot(direction);
        if ((bound > s.restLength && closing > 0.0) || (bound < s.restLength && closing < 0.0)) {
            state.velocity[s.a] += shareA * closing * direction;
            state.velocity[s.b] -= shareB * closing * direction;
        }
        ++pass.corrections;
        return std::abs(length - bound) / s.restLength;
    };
    // Symmetric Gauss-Seidel (forward, then backward): a correction travels the whole lattice in one
    // sweep pair whichever end of a chain of springs it starts at.
    const std::size_t count = model.springs.size();
    for (int sweep = 0; sweep < maxSweeps; ++sweep) {
        double worst = 0.0;
        if (sweep % 2 == 0)
            for (std::size_t k = 0; k < count; ++k)
                worst = std::max(worst, correct(model.springs[k]));
        else
            for (std::size_t k = count; k-- > 0;)
                worst = std::max(worst, correct(model.springs[k]));
        if (sweep == 0)
            pass.worstExcess = worst;
        pass.sweeps = sweep + 1;
        if (worst <= kTolerance)
            break;
    }
    return pass;
}

}  // namespace softtouch

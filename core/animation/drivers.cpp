#include "core/animation/drivers.h"

#include "core/base/ranges.h"

#include <cmath>
#include <numbers>

namespace softtouch {

namespace {

Status validatePoint(const Vec3& p) {
    if (!isFinite(p) || (p.array() < 0.0).any() || (p.array() > 1.0).any())
        return Status::error("point must be lattice parameters (u,v,w) in [0,1]");
    return Status::success();
}

/// Catmull-Rom through the keys: offset and its time derivative at t.
void samplePath(const std::vector<PathKey>& keys, double t, Vec3& offset, Vec3& velocity) {
    velocity.setZero();
    if (t <= keys.front().time || keys.size() == 1) {
        offset = keys.front().offset;
        return;
    }
    if (t >= keys.back().time) {
        offset = keys.back().offset;
        return;
    }
    std::size_t i = 0;
    while (keys[i + 1].time < t)
        ++i;
    const PathKey& k1 = keys[i];
    const PathKey& k2 = keys[i + 1];
    const double dt = k2.time - k1.time;
    // Tangents from neighbours (one-sided at the ends), scaled to this segment's duration.
    auto tangent = [&](std::size_t k) -> Vec3 {
        const std::size_t lo = k == 0 ? 0 : k - 1;
        const std::size_t hi = std::min(k + 1, keys.size() - 1);
        return (keys[hi].offset - keys[lo].offset) / (keys[hi].time - keys[lo].time);
    };
    const Vec3 m1 = tangent(i) * dt, m2 = tangent(i + 1) * dt;
    const double s = (t - k1.time) / dt, s2 = s * s, s3 = s2 * s;
    offset = (2 * s3 - 3 * s2 + 1) * k1.offset + (s3 - 2 * s2 + s) * m1 + (-2 * s3 + 3 * s2) * k2.offset + (s3 - s2) * m2;
    velocity = ((6 * s2 - 6 * s) * k1.offset + (3 * s2 - 4 * s + 1) * m1 + (-6 * s2 + 6 * s) * k2.offset +
                (3 * s2 - 2 * s) * m2) / dt;
}

}  // namespace

Status validateDriver(const Driver& driver) {
    if (const auto* d = std::get_if<ScriptedDrag>(&driver)) {
        if (Status s = validatePoint(d->point); !s) return s;
        if (d->keys.empty())
            return Status::error("keys: a scripted drag needs at least one key");
        for (std::size_t i = 0; i < d->keys.size(); ++i) {
            if (!std::isfinite(d->keys[i].time) || !isFinite(d->keys[i].offset))
                return Status::error("keys/" + std::to_string(i) + ": non-finite time or offset");
            if (d->keys[i].offset.norm() > ranges::kMaxDragOffset)
                return Status::error("keys/" + std::to_string(i) + ": offset must be at most 1e4 m");
            if (i > 0 && !(d->keys[i].time > d->keys[i - 1].time))
                return Status::error("keys/" + std::to_string(i) + ": key times must increase");
        }
        if (!std::isfinite(d->releaseTime))
            return Status::error("release time must be finite");
        if (std::string p = firstProblem({{kDriverStiffness, d->stiffness},
                                          {kDriverDamping, d->damping},
                                          {kDriverRadius, d->radius},
                                          {kDragRelease, d->releaseTime < 0.0 ? 0.0 : d->releaseTime}});  // < 0: never
            !p.empty())
            return Status::error(p);
        return Status::success();
    }
    const auto& s = std::get<SwimDriver>(driver);
    if (Status st = validatePoint(s.point); !st) return st;
    if (!isFinite(s.direction) || s.direction.norm() < 1e-9)
        return Status::error("direction must be a finite, non-zero vector");
    if (std::string p = firstProblem({{kSwimFrequency, s.frequencyHz},
                                      {kSwimAmplitude, s.amplitude},
                                      {kSwimPhase, s.phase},
                                      {kSwimRamp, s.rampSeconds},
                                      {kDriverStiffness, s.stiffness},
                                      {kDriverDamping, s.damping},
                                      {kDriverRadius, s.radius}});
        !p.empty())
        return Status::error(p);
    return Status::success();
}

DriverGrip driverGrip(const Driver& driver, const Lattice& lattice) {
    return materialGrip(lattice, std::visit([](const auto& d) { return d.point; }, driver), driverRadius(driver));
}

DriverGrip materialGrip(const Lattice& lattice, const Vec3& point, double radius) {
    DriverGrip grip;
    const OrientedBox& box = lattice.box();
    if (!(radius > 0.0)) {
        grip.support = lattice.weights(point);
        grip.rest = box.toWorld(point);
        return grip;
    }
    // The ball's mean, by a grid of kSteps samples a radius: the same samples on every lattice, closer together
    // than the basis functions of the nets the study refines to are wide, so each sees one smooth pull. The
    // lattice reproduces positions, so the held material's rest is the samples' mean.
    constexpr int kSteps = 8;
    const Vec3 centre = box.toWorld(point);
    std::vector<double> sum(std::size_t(lattice.nodeCount()), 0.0);
    int samples = 0;
    for (int a = -kSteps; a <= kSteps; ++a)
        for (int b = -kSteps; b <= kSteps; ++b)
            for (int c = -kSteps; c <= kSteps; ++c) {
                if (a * a + b * b + c * c > kSteps * kSteps)
                    continue;
                const Vec3 at = centre + Vec3(a, b, c) * (radius / kSteps);
                const Vec3 uvw = box.toParameters(at);
                if ((uvw.array() < 0.0).any() || (uvw.array() > 1.0).any())
                    continue;
                for (const NodeWeight& w : lattice.weights(uvw))
                    sum[w.node] += w.weight;
                grip.rest += at;
                ++samples;
            }
    // The centre is always a sample: the point lies in the box (validateDriver; the caller's promise).
    for (std::size_t i = 0; i < sum.size(); ++i)
        if (sum[i] != 0.0)
            grip.support.push_back({std::uint32_t(i), sum[i] / samples});
    grip.rest /= samples;
    return grip;
}

std::optional<DragSpring> driverDrag(const Driver& driver, const DriverGrip& grip, double t) {
    DragSpring drag;
    Vec3 offset, velocity;
    if (const auto* d = std::get_if<ScriptedDrag>(&driver)) {
        if (d->releaseTime >= 0.0 && t >= d->releaseTime)
            return std::nullopt;
        samplePath(d->keys, t, offset, velocity);
        drag.stiffness = d->stiffness;
        drag.damping = d->damping;
    } else {
        const auto& s = std::get<SwimDriver>(driver);
        const double w = 2.0 * std::numbers::pi * s.frequencyHz;
        // Smoothstep fade-in so the first beat does not jerk the body.
        double ramp = 1.0, rampRate = 0.0;
        if (s.rampSeconds > 0.0 && t < s.rampSeconds) {
            const double x = t / s.rampSeconds;
            ramp = x * x * (3.0 - 2.0 * x);
            rampRate = 6.0 * x * (1.0 - x) / s.rampSeconds;
        }
        const Vec3 dir = s.direction.normalized();
        offset = dir * (s.amplitude * ramp * std::sin(w * t + s.phase));
        velocity = dir * (s.amplitude * (rampRate * std::sin(w * t + s.phase) + ramp * w * std::cos(w * t + s.phase)));
        drag.stiffness = s.stiffness;
        drag.damping = s.damping;
    }
    drag.support = grip.support;
    drag.target = grip.rest + offset;
    drag.targetVelocity = velocity;
    return drag;
}

}  // namespace softtouch

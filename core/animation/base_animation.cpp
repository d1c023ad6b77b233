#include "core/animation/base_animation.h"

#include <algorithm>
#include <cmath>

namespace softtouch {

double BaseAnimation::duration() const {
    if (samples.size() < 2)
        return 0.0;
    return double(loop ? samples.size() : samples.size() - 1) / rate;
}

double BaseAnimation::takeSeconds(double seconds) const {
    const double count = double(samples.size());
    double at = seconds * rate;
    if (loop) {
        at = std::fmod(at, count);
        if (at < 0.0)
            at += count;
    } else {
        at = std::clamp(at, 0.0, std::max(0.0, count - 1.0));
    }
    return start + at / rate;
}

void BaseAnimation::positionsAt(double seconds, std::span<Vec3f> out) const {
    const auto count = std::ptrdiff_t(samples.size());
    if (count == 0)
        return;
    double at = seconds * rate;
    if (loop) {
        at = std::fmod(at, double(count));
        if (at < 0.0)
            at += double(count);
    } else {
        at = std::clamp(at, 0.0, double(count - 1));
    }
    const auto k = std::min(std::ptrdiff_t(at), loop ? count - 1 : std::max<std::ptrdiff_t>(count - 2, 0));
    const double t = at - double(k);
    auto index = [&](std::ptrdiff_t i) {
        if (loop)
            return std::size_t(((i % count) + count) % count);
        return std::size_t(std::clamp<std::ptrdiff_t>(i, 0, count - 1));
    };
    const auto& p0 = samples[index(k - 1)];
    const auto& p1 = samples[index(k)];
    const auto& p2 = samples[index(k + 1)];
    const auto& p3 = samples[index(k + 2)];
    if (t == 0.0) {  // on a sample: exactly it
        std::copy(p1.begin(), p1.end(), out.begin());
        return;
    }
    // Uniform Catmull-Rom: p(t) = p1 + t (p2 − p0)/2 + t² (p0 − 5p1/2 + 2p2 − p3/2) + t³ (3(p1 − p2) + p3 − p0)/2.
    const double t2 = t * t, t3 = t2 * t;
    const float a = float(-0.5 * t3 + t2 - 0.5 * t);
    const float b = float(1.5 * t3 - 2.5 * t2 + 1.0);
    const float c = float(-1.5 * t3 + 2.0 * t2 + 0.5 * t);
    const float d = float(0.5 * t3 - 0.5 * t2);
    for (std::size_t v = 0; v < out.size() && v < p1.size(); ++v)
        out[v] = a * p0[v] + b * p1[v] + c * p2[v] + d * p3[v];
}

Status BaseAnimation::validate(std::size_t vertices) const {
    if (!(std::isfinite(rate) && rate >= 1.0 && rate <= 10000.0))
        return Status::error("base animation sample rate must be in [1, 10000] per second, got " + std::to_string(rate));
    if (samples.size() < 2)
        return Status::error("base animation needs at least 2 samples, got " + std::to_string(samples.size()));
    for (std::size_t k = 0; k < samples.size(); ++k) {
        if (samples[k].size() != vertices)
            return Status::error("base animation sample " + std::to_string(k) + " has " + std::to_string(samples[k].size()) +
                                 " positions for " + std::to_string(vertices) + " vertices");
        for (const Vec3f& p : samples[k])
            if (!p.allFinite())
                return Status::error("base animation sample " + std::to_string(k) + " has a non-finite position");
    }
    return Status::success();
}

}  // namespace softtouch

// Compiled with -fno-math-errno -fno-trapping-math (core/CMakeLists.txt) so the coefficient loop
// vectorises: std::sqrt needs no errno check, and the zero-length guard may evaluate 1/|r| before
// selecting. Neither changes a single result: IEEE square roots, divisions and selects round the same
// packed or scalar, so vector widths cannot change the bits of a step.
#include "core/body/spring_forces.h"

#include "core/base/vector_clones.h"
#include "core/body/body_model.h"

#include <cassert>
#include <cmath>

namespace softtouch {

SpringTable SpringTable::build(std::span<const Spring> springs, std::span<const double> inverseMass) {
    const std::size_t n = inverseMass.size();
    SpringTable t;
    for (const Spring& s : springs) {
        if (inverseMass[s.a] == 0.0 && inverseMass[s.b] == 0.0)
            continue;
        t.a.push_back(s.a);
        t.b.push_back(s.b);
        t.restLength.push_back(s.restLength);
        t.stiffness.push_back(s.stiffness);
        t.damping.push_back(s.damping);
    }
    // Compressed rows: count, prefix-sum, fill in spring order (so each node sums in a fixed order).
    auto rows = [&](const std::vector<std::uint32_t>& node, std::vector<std::uint32_t>& offset,
                    std::vector<std::uint32_t>& list) {
        offset.assign(n + 1, 0);
        for (std::uint32_t i : node) {
            if (inverseMass[i] > 0.0)
                ++offset[i + 1];
        }
        for (std::size_t i = 0; i < n; ++i)
            offset[i + 1] += offset[i];
        list.resize(offset[n]);
        std::vector<std::uint32_t> next(offset.begin(), offset.end() - 1);
        for (std::size_t k = 0; k < node.size(); ++k) {
            if (inverseMass[node[k]] > 0.0)
                list[next[node[k]]++] = std::uint32_t(k);
        }
    };
    rows(t.a, t.startOffset, t.startSpring);
    rows(t.b, t.endOffset, t.endSpring);
    return t;
}

namespace {

/// coefficient = (k (|r| − L) + c (r·Δv)/|r|) / |r|, so the force on a is coefficient × r. One loop
/// over contiguous arrays with no branch, which the compiler packs into vector square roots and
/// divisions; built twice, for AVX2 and for the x86-64 baseline, and picked once at load time.
SOFTTOUCH_VECTOR_CLONES
void springCoefficients(std::size_t count, const double* __restrict lengthSquared, const double* __restrict closingRate,
                        const double* __restrict stiffness, const double* __restrict restLength,
                        const double* __restrict damping, double* __restrict coefficient,
                        double* __restrict dampingPart) {
    for (std::size_t k = 0; k < count; ++k) {
        const double length = std::sqrt(lengthSquared[k]);
        const double inverse = length > 0.0 ? 1.0 / length : 0.0;  // zero length: no direction, no force
        const double damped = damping[k] * (inverse * closingRate[k]);
        const double magnitude = stiffness[k] * (length - restLength[k]) + damped;
        coefficient[k] = magnitude * inverse;
        dampingPart[k] = damped * inverse;  // kept for the energy account (springDampingLoss)
    }
}

}  // namespace

void addSpringForces(const SpringTable& t, std::span<const Vec3> x, std::span<const Vec3> v, std::span<Vec3> f,
                     SpringScratch& scratch) {
    const std::size_t count = t.size();
    assert(t.startOffset.size() == f.size() + 1);
    scratch.vector.resize(count);
    scratch.lengthSquared.resize(count);
    scratch.closingRate.resize(count);
    scratch.coefficient.resize(count);
    scratch.dampingPart.resize(count);

    // Raw pointers held in locals: Eigen's packet stores may alias anything, so through the vectors'
    // members the compiler would reload every base pointer after every store.
    const std::uint32_t* a = t.a.data();
    const std::uint32_t* b = t.b.data();
    Vec3* vector = scratch.vector.data();
    double* lengthSquared = scratch.lengthSquared.data();
    double* closingRate = scratch.closingRate.data();
    double* coefficient = scratch.coefficient.data();

    // 1. Gather: each spring's vector, squared length and closing rate.
    for (std::size_t k = 0; k < count; ++k) {
        const Vec3 r = x[b[k]] - x[a[k]];
        vector[k] = r;
        lengthSquared[k] = r.squaredNorm();
        closingRate[k] = r.dot(v[b[k]] - v[a[k]]);
    }
    // 2. Coefficients, vectorised.
    springCoefficients(count, lengthSquared, closingRate, t.stiffness.data(), t.restLength.data(), t.damping.data(),
                       coefficient, scratch.dampingPart.data());
    // 3. Each free node sums its own springs: no scatter, so no store-to-load chain between springs.
    const std::uint32_t* startOffset = t.startOffset.data();
    const std::uint32_t* startSpring = t.startSpring.data();
    const std::uint32_t* endOffset = t.endOffset.data();
    const std::uint32_t* endSpring = t.endSpring.data();
    const std::size_t n = f.size();
    for (std::size_t i = 0; i < n; ++i) {
        Vec3 sum = Vec3::Zero();
        for (std::uint32_t e = startOffset[i]; e < startOffset[i + 1]; ++e)
            sum += coefficient[startSpring[e]] * vector[startSpring[e]];
        for (std::uint32_t e = endOffset[i]; e < endOffset[i + 1]; ++e)
            sum -= coefficient[endSpring[e]] * vector[endSpring[e]];
        f[i] += sum;
    }
}

double springDampingLoss(const SpringTable& t, const SpringScratch& scratch, std::span<const Vec3> v, double h) {
    const std::size_t count = t.size();
    assert(scratch.dampingPart.size() == count);
    const std::uint32_t* a = t.a.data();
    const std::uint32_t* b = t.b.data();
    const Vec3* vector = scratch.vector.data();
    const double* closingRate = scratch.closingRate.data();
    const double* dampingPart = scratch.dampingPart.data();
    // Four partial sums: one would chain every spring's add behind the last (latency-bound).
    auto loss = [&](std::size_t k) { return dampingPart[k] * (closingRate[k] + vector[k].dot(v[b[k]] - v[a[k]])); };
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
    std::size_t k = 0;
    for (; k + 4 <= count; k += 4) {
        s0 += loss(k);
        s1 += loss(k + 1);
        s2 += loss(k + 2);
        s3 += loss(k + 3);
    }
    for (; k < count; ++k)
        s0 += loss(k);
    return 0.5 * h * ((s0 + s1) + (s2 + s3));
}

}  // namespace softtouch

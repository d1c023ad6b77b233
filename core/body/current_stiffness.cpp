#include "core/body/current_stiffness.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace softtouch {

void StiffnessTracker::reset(const BodyModel& model) {
    const std::size_t n = model.nodeCount();
    m_vector.resize(n);
    m_product.resize(n);
    m_rootInverseMass.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        m_rootInverseMass[i] = std::sqrt(model.inverseMass[i]);
        // Deterministic, non-symmetric start (as for the rest value) so no mode is missed by symmetry.
        m_vector[i] = model.inverseMass[i] > 0.0
                          ? Vec3(1.0 + 0.37 * double(i % 7), -0.5 + 0.11 * double(i % 5), 0.3 + 0.05 * double(i % 11))
                          : Vec3::Zero();
    }
    m_spring.resize(model.springTable.size());
    m_inverseSquared.resize(model.springTable.size());
    m_sideways.resize(model.springTable.size());
}

double StiffnessTracker::estimate(const BodyModel& model, std::span<const Vec3> x, int iterations) {
    const SpringTable& t = model.springTable;
    const std::size_t count = t.size();
    const std::size_t n = model.nodeCount();
    assert(m_vector.size() == n && m_spring.size() == count && iterations >= 1);
    for (std::size_t k = 0; k < count; ++k)
        m_spring[k] = x[t.b[k]] - x[t.a[k]];
    // A contiguous loop that the compiler packs into vector square roots and divisions (compiled
    // without errno, like the spring pass): this is most of a call's cost.
    const double* restLength = t.restLength.data();
    const Vec3* spring = m_spring.data();
    double* inverseSquared = m_inverseSquared.data();
    double* sideways = m_sideways.data();
    for (std::size_t k = 0; k < count; ++k) {
        const double lengthSquared = spring[k].squaredNorm();
        const double inverse = lengthSquared > 0.0 ? 1.0 / std::sqrt(lengthSquared) : 0.0;
        inverseSquared[k] = inverse * inverse;
        sideways[k] = std::max(0.0, 1.0 - restLength[k] * inverse);
    }
    double lambda = 0.0;
    for (int iteration = 0; iteration < iterations; ++iteration) {
        double norm = 0.0;
        for (const Vec3& v : m_vector)
            norm += v.squaredNorm();
        norm = std::sqrt(norm);
        if (!(norm > 0.0) || !std::isfinite(norm))
            return 0.0;  // no free node (or a non-finite state): nothing to bound
        for (Vec3& v : m_vector)
            v /= norm;
        for (Vec3& v : m_product)
            v.setZero();
        for (std::size_t k = 0; k < count; ++k) {
            const std::uint32_t a = t.a[k], b = t.b[k];
            const double sa = m_rootInverseMass[a], sb = m_rootInverseMass[b];
            const Vec3 u = sa * m_vector[a] - sb * m_vector[b];
            // K_s u = k [ (r̂·u) r̂ + s (u − (r̂·u) r̂) ], (r̂·u) r̂ = (r·u) r / |r|²
            const Vec3 along = (m_spring[k].dot(u) * m_inverseSquared[k]) * m_spring[k];
            const Vec3 ku = t.stiffness[k] * (along + m_sideways[k] * (u - along));
            m_product[a] += sa * ku;
            m_product[b] -= sb * ku;
        }
        lambda = 0.0;
        for (std::size_t i = 0; i < n; ++i)
            lambda += m_vector[i].dot(m_product[i]);
        std::swap(m_vector, m_product);
    }
    return lambda;
}

}  // namespace softtouch

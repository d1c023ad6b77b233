#pragma once
/// The explicit stability bound from the current state, not only the rest state: the largest
/// eigenvalue of M⁻¹K(x), K(x) the springs' tangent stiffness at the current positions, by power
/// iteration on M^-½ K(x) M^-½ warm-started from the last call's vector, so that a couple of
/// iterations per call follow a body as it deforms (body_model.cpp computes the rest value once).
///
/// A spring of stiffness k, rest length L₀ and current vector r (length L) has the tangent block
///
///     K_s = k [ r̂r̂ᵀ + (1 − L₀/L)(I − r̂r̂ᵀ) ]
///
/// Stretched (L > L₀), it also resists sideways motion, so a body under tension (a yank) is stiffer
/// than at rest and a substep that was stable at rest may not be. Compressed, the sideways term is
/// negative (softening: buckling is physics, no step size removes it) and is left out.

#include "core/body/body_model.h"

#include <span>
#include <vector>

namespace softtouch {

/// Tracks λ_max(M⁻¹K(x)) of one body across calls. Allocates only in reset().
class StiffnessTracker {
public:
    /// Sizes the scratch for `model` and starts the vector afresh.
    void reset(const BodyModel& model);
    /// Runs `iterations` power steps (>= 1) on the tangent stiffness at `position` and returns the last
    /// Rayleigh quotient, 1/s²: a lower bound on λ_max(M⁻¹K(x)) that converges to it from below.
    double estimate(const BodyModel& model, std::span<const Vec3> position, int iterations);

private:
    std::vector<Vec3> m_vector;          ///< Current iterate, unit length (M^-½-scaled coordinates).
    std::vector<Vec3> m_product;         ///< Scratch: M^-½ K M^-½ times m_vector.
    std::vector<double> m_rootInverseMass; ///< √(1/m) per node, 0 for pinned and void nodes.
    std::vector<Vec3> m_spring;          ///< r per spring of BodyModel::springTable at `position`, m.
    std::vector<double> m_inverseSquared; ///< 1/|r|² per spring (0 for a zero-length spring), 1/m².
    std::vector<double> m_sideways;      ///< max(0, 1 − L₀/L) per spring.
};

}  // namespace softtouch

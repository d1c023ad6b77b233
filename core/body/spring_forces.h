#pragma once
/// The spring pass of accumulateForces(), laid out for the vector unit. A spring's force needs one
/// square root and one division; done spring by spring, with each force scattered to its two nodes,
/// the pass is bound by those two latencies and by the store-to-load chain of the scatter (about
/// 6 ns per spring). Here it runs in three passes: gather each spring's vector and relative velocity,
/// compute every spring's force coefficient in one branch-free loop over contiguous arrays (packed
/// square roots and divisions), then sum each node's springs from its own list.

#include "core/base/types.h"

#include <cstdint>
#include <span>
#include <vector>

namespace softtouch {

struct Spring;

/// The springs that can move a node (at least one end free: a spring between two pinned nodes does
/// nothing), as arrays, and for each node the springs that start and end at it (compressed rows).
/// Built once with the body model (buildBodyModel fills BodyModel::springTable).
struct SpringTable {
    std::vector<std::uint32_t> a;          ///< First node of each spring.
    std::vector<std::uint32_t> b;          ///< Second node of each spring.
    std::vector<double> restLength;        ///< Metres.
    std::vector<double> stiffness;         ///< N/m.
    std::vector<double> damping;           ///< N·s/m along the spring.
    /// Springs with a == node i: startSpring[startOffset[i] .. startOffset[i + 1]). Free nodes only.
    std::vector<std::uint32_t> startOffset;
    std::vector<std::uint32_t> startSpring; ///< See startOffset.
    /// Springs with b == node i: endSpring[endOffset[i] .. endOffset[i + 1]). Free nodes only.
    std::vector<std::uint32_t> endOffset;
    std::vector<std::uint32_t> endSpring;   ///< See endOffset.

    std::size_t size() const { return a.size(); }
    /// The table of `springs` for a body whose node i is free when inverseMass[i] > 0.
    static SpringTable build(std::span<const Spring> springs, std::span<const double> inverseMass);
};

/// Per-spring scratch of one pass, kept by the caller so a step allocates nothing.
struct SpringScratch {
    std::vector<Vec3> vector;            ///< x_b − x_a per spring.
    std::vector<double> lengthSquared;   ///< |x_b − x_a|².
    std::vector<double> closingRate;     ///< (x_b − x_a)·(v_b − v_a).
    std::vector<double> coefficient;     ///< Force on a is coefficient × vector.
    std::vector<double> dampingPart;     ///< The damping's share of coefficient, c (r·Δv)/|r|² (springDampingLoss).
};

/// Adds every spring's force, elastic k(|r| − L) r̂ plus damping c (r̂·(v_b − v_a)) r̂, to `force` on
/// free nodes (pinned and void nodes get nothing). A spring of zero length has no direction and adds
/// nothing. Non-finite positions give non-finite forces.
void addSpringForces(const SpringTable& table, std::span<const Vec3> position, std::span<const Vec3> velocity,
                     std::span<Vec3> force, SpringScratch& scratch);

/// Energy the springs' damping took out over one explicit substep of h seconds, J: the force
/// c (r̂·Δv) r̂ of the pass that filled `scratch` (r and Δv at the substep's start), held over the
/// substep, works h g·(v + v')/2, so each spring dissipates h c (r·Δv)(r·(Δv + Δv'))/(2|r|²) with Δv'
/// from `velocityAfter`. Either sign per spring; positive overall below the stability bound. One
/// gather of the new velocities per spring, no division (the force pass left c (r·Δv)/|r|²).
double springDampingLoss(const SpringTable& table, const SpringScratch& scratch, std::span<const Vec3> velocityAfter,
                         double h);

}  // namespace softtouch

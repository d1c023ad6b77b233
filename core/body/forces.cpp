#include "core/body/forces.h"

#include <algorithm>
#include <cmath>

namespace softtouch {

bool BodyState::isFinite() const {
    for (std::size_t i = 0; i < position.size(); ++i) {
        if (!softtouch::isFinite(position[i]) || !softtouch::isFinite(velocity[i]))
            return false;
    }
    return true;
}

BodyState restState(const BodyModel& model) {
    BodyState s;
    s.position = model.restPositions;
    s.velocity.assign(model.nodeCount(), Vec3::Zero());
    return s;
}

std::string ExternalForces::firstNonFinite() const {
    if (!isFinite(gravity))
        return "gravity";
    for (std::size_t i = 0; i < drags.size(); ++i) {
        const DragSpring& d = drags[i];
        if (!isFinite(d.target) || !isFinite(d.targetVelocity) || !std::isfinite(d.stiffness) ||
            !std::isfinite(d.damping))
            return "drag " + std::to_string(i);
        for (const NodeWeight& w : d.support) {
            if (!std::isfinite(w.weight))
                return "drag " + std::to_string(i) + " weights";
        }
    }
    for (std::size_t i = 0; i < nodeForces.size(); ++i)
        if (!isFinite(nodeForces[i]))
            return "node force " + std::to_string(i);
    for (std::size_t i = 0; i < planes.size(); ++i) {
        const CollisionPlane& p = planes[i];
        if (!isFinite(p.point) || !isFinite(p.normal) || !std::isfinite(p.restitution) || !std::isfinite(p.friction))
            return "plane " + std::to_string(i);
    }
    for (std::size_t i = 0; i < colliders.size(); ++i) {
        const Collider& c = colliders[i];
        if (!isFinite(c.centre) || !isFinite(c.axis) || !isFinite(c.halfExtents) || !c.axes.allFinite() ||
            !std::isfinite(c.radius) || !std::isfinite(c.halfLength) || !std::isfinite(c.restitution) ||
            !std::isfinite(c.friction))
            return "collider " + std::to_string(i);
    }
    return {};
}

void dragPointState(const DragSpring& drag, std::span<const Vec3> position, std::span<const Vec3> velocity,
                    Vec3& point, Vec3& pointVelocity) {
    point.setZero();
    pointVelocity.setZero();
    for (const NodeWeight& w : drag.support) {
        point += w.weight * position[w.node];
        pointVelocity += w.weight * velocity[w.node];
    }
}

void accumulateForces(const BodyModel& model, const ExternalForces& external, std::span<const Vec3> x,
                      std::span<const Vec3> v, std::span<Vec3> f, SpringScratch& scratch, ForceTerms terms,
                      std::span<Vec3> dragPulls, std::span<Vec3> elementDamping) {
    const std::size_t n = model.nodeCount();
    const bool gravity = !external.gravity.isZero();
    for (std::size_t i = 0; i < n; ++i) {
        f[i] = gravity ? Vec3(model.mass[i] * external.gravity) : Vec3::Zero();
        if (terms.nodeDamping && model.anyNodeDamping)
            f[i] -= model.nodeDamping[i] * v[i];
    }
    if (external.nodeForces.size() == n)
        for (std::size_t i = 0; i < n; ++i)
            f[i] += external.nodeForces[i];
    if (terms.springs)
        addSpringForces(model.springTable, x, v, f, scratch);
    if (model.element)
        addElementForces(*model.element, x, v, f, terms.springs, terms.nodeDamping, elementDamping);
    for (std::size_t d = 0; d < external.drags.size(); ++d) {
        const DragSpring& drag = external.drags[d];
        Vec3 p, pv;
        dragPointState(drag, x, v, p, pv);
        const Vec3 pull = drag.stiffness * (drag.target - p) + drag.damping * (drag.targetVelocity - pv);
        forEachDragShare(model, drag, [&](std::uint32_t node, double share) { f[node] += share * pull; });
        if (!dragPulls.empty())
            dragPulls[d] = pull;
    }
}

bool resolvePlaneContact(const CollisionPlane& plane, const Vec3& stepStart, double restingSpeed, Vec3& x, Vec3& v) {
    const double depth = (x - plane.point).dot(plane.normal);
    if (depth > 0.0)
        return false;
    x -= depth * plane.normal;  // penetration: back onto the plane
    const double vn = v.dot(plane.normal);
    if (vn >= 0.0)
        return true;  // leaving the plane
    const Vec3 normalPart = vn * plane.normal;
    Vec3 tangent = v - normalPart;
    const bool wasTouching = (stepStart - plane.point).dot(plane.normal) <= 0.0;
    const double restitution = (wasTouching || -vn < restingSpeed) ? 0.0 : plane.restitution;
    // Coulomb friction: the tangential speed drops by mu times the normal speed change.
    const double tangentSpeed = tangent.norm();
    if (tangentSpeed > 0.0) {
        const double loss = plane.friction * (1.0 + restitution) * -vn;
        tangent *= std::max(0.0, 1.0 - loss / tangentSpeed);
    }
    v = tangent - restitution * normalPart;
    return true;
}

void resolvePlaneContacts(const BodyModel& model, std::span<const CollisionPlane> planes,
                          std::span<const Vec3> stepStart, double h, const Vec3& gravity, BodyState& state) {
    // Below this approach speed a contact is resting: no bounce, so bodies settle instead of jittering.
    const double restingSpeed = restingContactSpeed(gravity, h);
    for (const CollisionPlane& plane : planes) {
        for (std::size_t i = 0; i < model.nodeCount(); ++i) {
            if (model.inverseMass[i] != 0.0)
                (void)resolvePlaneContact(plane, stepStart[i], restingSpeed, state.position[i], state.velocity[i]);
        }
    }
}

void updateVoidNodes(const BodyModel& model, BodyState& state) {
    for (const VoidFollower& f : model.voidFollowers) {
        if (f.donors.empty())
            continue;
        Vec3 displacement = Vec3::Zero();
        Vec3 velocity = Vec3::Zero();
        for (std::uint32_t d : f.donors) {
            displacement += state.position[d] - model.restPositions[d];
            velocity += state.velocity[d];
        }
        const double inv = 1.0 / double(f.donors.size());
        state.position[f.node] = model.restPositions[f.node] + inv * displacement;
        state.velocity[f.node] = inv * velocity;
    }
}

double kineticEnergy(const BodyModel& model, const BodyState& state) {
    if (model.element)
        return 0.5 * elementMassProduct(*model.element, state.velocity, state.velocity);
    double e = 0.0;
    for (std::size_t i = 0; i < model.nodeCount(); ++i)
        e += 0.5 * model.mass[i] * state.velocity[i].squaredNorm();
    return e;
}

double springEnergy(const BodyModel& model, const BodyState& state) {
    double e = model.element ? elementEnergy(*model.element, state.position) : 0.0;
    for (const Spring& s : model.springs) {
        const double stretch = (state.position[s.b] - state.position[s.a]).norm() - s.restLength;
        e += 0.5 * s.stiffness * stretch * stretch;
    }
    return e;
}

double gravityEnergy(const BodyModel& model, const BodyState& state, const Vec3& gravity) {
    double e = 0.0;
    for (std::size_t i = 0; i < model.nodeCount(); ++i)
        e -= model.mass[i] * gravity.dot(state.position[i]);
    return e;
}

double massInnerProduct(const BodyModel& model, std::span<const Vec3> a, std::span<const Vec3> b) {
    double sum = 0.0;
    if (model.element)
        return elementMassProduct(*model.element, a, b);
    for (std::size_t i = 0; i < model.nodeCount(); ++i)
        if (model.inverseMass[i] > 0.0)
            sum += model.mass[i] * a[i].dot(b[i]);
    return sum;
}

Vec3 linearMomentum(const BodyModel& model, const BodyState& state) {
    Vec3 p = Vec3::Zero();
    for (std::size_t i = 0; i < model.nodeCount(); ++i)
        p += model.mass[i] * state.velocity[i];
    return p;
}

}  // namespace softtouch

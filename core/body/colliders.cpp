#include "core/body/colliders.h"

#include "core/base/ranges.h"
#include "core/body/body_model.h"
#include "core/body/contact_impulse.h"
#include "core/body/forces.h"
#include "core/geometry/mesh_surface.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace softtouch {

namespace {

bool finite(const Vec3& v) { return v.allFinite(); }

/// A unit vector perpendicular to `n`.
Vec3 perpendicular(const Vec3& n) {
    const Vec3 helper = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    return n.cross(helper).normalized();
}

}  // namespace

double colliderBoundingRadius(const Collider& c) {
    switch (c.shape) {
    case ColliderShape::Sphere: return c.radius;
    case ColliderShape::Capsule: return c.radius + c.halfLength;
    case ColliderShape::Box: return c.halfExtents.norm();
    case ColliderShape::Mesh: {
        const Bounds& b = c.surface->bounds();
        return c.scale * (0.5 * (b.min + b.max).norm() + c.surface->boundingRadius());
    }
    }
    return 0.0;
}

const char* colliderShapeName(ColliderShape shape) {
    switch (shape) {
    case ColliderShape::Sphere: return "sphere";
    case ColliderShape::Capsule: return "capsule";
    case ColliderShape::Box: return "box";
    case ColliderShape::Mesh: return "mesh";
    }
    return "sphere";
}

Status Collider::validate() {
    if (!finite(centre))
        return Status::error("the collider's centre must be finite");
    for (const auto& [range, value] : {std::pair{ranges::kRestitution, restitution}, std::pair{ranges::kFriction, friction}})
        if (std::string problem = range.problem(value); !problem.empty())
            return Status::error(std::move(problem));
    switch (shape) {
    case ColliderShape::Capsule:
        if (const std::string problem = ranges::kCapsuleHalfLength.problem(halfLength); !problem.empty())
            return Status::error("a capsule's " + problem);
        if (!finite(axis) || axis.norm() < 1e-9)
            return Status::error("a capsule's axis must be a non-zero direction");
        axis.normalize();
        [[fallthrough]];
    case ColliderShape::Sphere:
        if (const std::string problem = ranges::kColliderRadius.problem(radius); !problem.empty())
            return Status::error(std::string("a ") + colliderShapeName(shape) + "'s " + problem);
        break;
    case ColliderShape::Mesh:
        if (!surface)
            return Status::error("a mesh collider needs a mesh");
        if (const std::string problem = ranges::kMeshColliderScale.problem(scale); !problem.empty())
            return Status::error("a mesh collider's " + problem);
        if (!axes.allFinite() || (axes.transpose() * axes - Mat3::Identity()).cwiseAbs().maxCoeff() > 1e-6)
            return Status::error("a mesh collider's axes must be orthonormal");
        break;
    case ColliderShape::Box:
        if (!finite(halfExtents) || (halfExtents.array() <= 0.0).any() || (halfExtents.array() > 1e6).any())
            return Status::error("a box's halfExtents must each be in (0, 1e6] m");
        if (!axes.allFinite() || (axes.transpose() * axes - Mat3::Identity()).cwiseAbs().maxCoeff() > 1e-6)
            return Status::error("a box's axes must be orthonormal");
        break;
    }
    return Status::success();
}

double colliderDistance(const Collider& c, const Vec3& p, Vec3& normal) {
    switch (c.shape) {
    case ColliderShape::Sphere:
    case ColliderShape::Capsule: {
        // The nearest point of the core (the centre, or the capsule's segment), then the radius off it.
        Vec3 nearest = c.centre;
        if (c.shape == ColliderShape::Capsule)
            nearest += std::clamp((p - c.centre).dot(c.axis), -c.halfLength, c.halfLength) * c.axis;
        const Vec3 d = p - nearest;
        const double length = d.norm();
        normal = length > 0.0 ? Vec3(d / length) : (c.shape == ColliderShape::Capsule ? perpendicular(c.axis) : Vec3::UnitY());
        return length - c.radius;
    }
    case ColliderShape::Box: {
        const Vec3 q = c.axes.transpose() * (p - c.centre);
        const Vec3 d = q.cwiseAbs() - c.halfExtents;
        if ((d.array() > 0.0).any()) {  // outside: to the nearest point of the box
            const Vec3 outside = d.cwiseMax(0.0).cwiseProduct(q.cwiseSign());
            normal = c.axes * outside.normalized();
            return outside.norm();
        }
        int face = 0;  // inside: out through the nearest face
        d.maxCoeff(&face);
        Vec3 local = Vec3::Zero();
        local[face] = q[face] < 0.0 ? -1.0 : 1.0;
        normal = c.axes * local;
        return d[face];
    }
    case ColliderShape::Mesh: {
        Vec3 local;
        const double d = c.surface->signedDistance(c.axes.transpose() * (p - c.centre) / c.scale, local);
        normal = c.axes * local;
        return c.scale * d;
    }
    }
    normal = Vec3::UnitY();
    return 1e300;
}

ContactPoints meshContactPoints(const Lattice& lattice, const Mesh& mesh, int cells) {
    ContactPoints points;
    if (mesh.positions.empty())
        return points;
    const Bounds b = mesh.bounds();
    const Vec3 size = (b.max - b.min).cwiseMax(1e-12);
    // In each occupied cell the vertex nearest its centre: spread over the surface, and as symmetric as
    // the mesh (a symmetric body lands symmetrically).
    std::map<long long, std::pair<double, std::size_t>> nearest;
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        const Vec3 p = mesh.positions[i].cast<double>();
        long long key = 0;
        Vec3 centre;
        for (int a = 0; a < 3; ++a) {
            const int c = std::clamp(int((p[a] - b.min[a]) / size[a] * cells), 0, cells - 1);
            key = key * (cells + 1) + c;
            centre[a] = b.min[a] + (c + 0.5) * size[a] / cells;
        }
        const double d = (p - centre).squaredNorm();
        auto [it, inserted] = nearest.try_emplace(key, d, i);
        if (!inserted && d < it->second.first)
            it->second = {d, i};
    }
    points.start.push_back(0);
    for (const auto& [key, choice] : nearest) {
        for (const NodeWeight& w : lattice.weights(lattice.box().toParameters(mesh.positions[choice.second].cast<double>())))
            if (w.weight != 0.0)
                points.terms.push_back(w);
        points.start.push_back(std::uint32_t(points.terms.size()));
    }
    return points;
}

namespace {

/// The simulated nodes' bounding box.
std::pair<Vec3, Vec3> nodeBounds(const BodyModel& model, const BodyState& state) {
    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
    for (std::size_t i = 0; i < model.nodeCount(); ++i)
        if (model.simulated[i]) {
            lo = lo.cwiseMin(state.position[i]);
            hi = hi.cwiseMax(state.position[i]);
        }
    return {lo, hi};
}

bool mayTouch(const Collider& c, const Vec3& lo, const Vec3& hi) {
    return (c.centre.cwiseMax(lo).cwiseMin(hi) - c.centre).norm() <= colliderBoundingRadius(c);
}

}  // namespace

bool collidersMayTouch(const BodyModel& model, std::span<const Collider> colliders, const BodyState& state) {
    if (colliders.empty())
        return false;
    const auto [lo, hi] = nodeBounds(model, state);
    for (const Collider& c : colliders)
        if (mayTouch(c, lo, hi))
            return true;
    return false;
}

ColliderPass resolveColliders(const BodyModel& model, std::span<const Collider> colliders, BodyState& state,
                              double restingSpeed, std::vector<ColliderImpulses>& impulses) {
    ColliderPass pass;
    const auto [lo, hi] = nodeBounds(model, state);  // see collidersMayTouch
    const ContactPoints& points = model.contacts();
    const bool atNodes = points.size() == 0;
    const std::size_t count = atNodes ? model.nodeCount() : points.size();
    // k = Σ_j w_j² m_j⁻¹: how point q's velocity answers an impulse on it (m⁻¹ of a node itself).
    auto pointInverseMass = [&](std::size_t q) {
        if (atNodes)
            return model.inverseMass[q];
        double k = 0.0;
        for (std::uint32_t t = points.start[q]; t < points.start[q + 1]; ++t)
            k += points.terms[t].weight * points.terms[t].weight * model.inverseMass[points.terms[t].node];
        return k;
    };
    // Applies a change of point q's position and velocity through its weights (k > 0 its pointInverseMass):
    // node i takes w_i m_i⁻¹ / k of it, which moves the point by exactly that much.
    auto apply = [&](std::size_t q, double k, const Vec3& dx, const Vec3& dv) {
        if (atNodes) {
            state.position[q] += dx;
            state.velocity[q] += dv;
            return;
        }
        for (std::uint32_t t = points.start[q]; t < points.start[q + 1]; ++t) {
            const NodeWeight& w = points.terms[t];
            const double share = w.weight * model.inverseMass[w.node] / k;
            state.position[w.node] += share * dx;
            state.velocity[w.node] += share * dv;
        }
    };
    struct Contact {
        std::size_t point;
        ContactImpulse impulse;  ///< inverseMass: Σ w_i² m_i⁻¹ of the point (the collider does not move).
    };
    std::vector<Contact> touching;
    auto pointState = [&](std::size_t q, Vec3& x, Vec3& v) {
        x = atNodes ? state.position[q] : points.at(q, state.position);
        v = atNodes ? state.velocity[q] : points.at(q, state.velocity);
    };
    impulses.resize(colliders.size());
    for (std::size_t ci = 0; ci < colliders.size(); ++ci) {
        const Collider& c = colliders[ci];
        ColliderImpulses& warm = impulses[ci];
        warm.normal.resize(count, 0.0);
        warm.friction.resize(count, Vec3::Zero());
        if (!mayTouch(c, lo, hi)) {
            std::fill(warm.normal.begin(), warm.normal.end(), 0.0);
            continue;
        }
        if (warm.clearance.size() != count || !(warm.queriedFor == c)) {
            warm.clearance.assign(count, 0.0);  // no bound yet: the first sweep asks for every point
            warm.queriedAt.assign(count, Vec3::Zero());
            warm.queriedFor = c;
        }
        // Positions: every point inside is pushed back onto the surface (Gauss-Seidel: points share nodes).
        touching.clear();
        for (int sweep = 0; sweep < kContactSweeps; ++sweep) {
            for (std::size_t q = 0; q < count; ++q) {
                if (atNodes && model.inverseMass[q] == 0.0)
                    continue;
                Vec3 x, v, n;
                pointState(q, x, v);
                if (warm.clearance[q] > (x - warm.queriedAt[q]).norm())
                    continue;  // still outside (ColliderImpulses): the query would say so
                const double depth = colliderDistance(c, x, n);
                warm.clearance[q] = depth;
                warm.queriedAt[q] = x;
                if (depth >= 0.0)
                    continue;
                const double k = pointInverseMass(q);
                if (sweep == 0) {
                    ++pass.contacts;
                    pass.deepest = std::max(pass.deepest, -depth);
                    if (k > 0.0) {
                        const double vn = v.dot(n);
                        touching.push_back({q, {n, k, contactTargetSpeed(vn, restingSpeed, c.restitution)}});
                    }
                }
                if (k > 0.0)
                    apply(q, k, -depth * n, Vec3::Zero());
            }
        }
        // Velocities: sequential impulses (core/body/contact_impulse.h). Accumulating lets a later sweep take back
        // what an earlier one overdid, so a body resting on many points settles instead of jittering.
        // Warm start: each touching point begins with last substep's impulses (the normal one only if it still
        // pushes, the friction one within its new bound); points no longer touching forget theirs.
        thread_local std::vector<std::uint8_t> touched;
        touched.assign(count, 0);
        for (Contact& contact : touching) {
            ContactImpulse& i = contact.impulse;
            touched[contact.point] = 1;
            i.normalImpulse = std::max(0.0, warm.normal[contact.point]);
            Vec3 friction = warm.friction[contact.point] - warm.friction[contact.point].dot(i.normal) * i.normal;
            const double limit = c.friction * i.normalImpulse;
            if (friction.norm() > limit)
                friction *= limit / std::max(friction.norm(), 1e-300);
            i.frictionImpulse = friction;
            apply(contact.point, i.inverseMass, Vec3::Zero(), i.inverseMass * (i.normalImpulse * i.normal + i.frictionImpulse));
        }
        for (int sweep = 0; sweep < 4 * kContactSweeps; ++sweep) {
            for (Contact& contact : touching) {
                Vec3 x, v;
                pointState(contact.point, x, v);
                const Vec3 impulse = sequentialImpulse(contact.impulse, v, c.friction);
                // An impulse J on the point changes its velocity by k J: apply() takes that change.
                apply(contact.point, contact.impulse.inverseMass, Vec3::Zero(), contact.impulse.inverseMass * impulse);
            }
        }
        for (std::size_t q = 0; q < count; ++q)
            if (!touched[q]) {
                warm.normal[q] = 0.0;
                warm.friction[q].setZero();
            }
        for (const Contact& contact : touching) {
            warm.normal[contact.point] = contact.impulse.normalImpulse;
            warm.friction[contact.point] = contact.impulse.frictionImpulse;
        }
    }
    return pass;
}

}  // namespace softtouch

#include "core/body/body_contacts.h"

#include "core/base/ranges.h"
#include "core/body/body_model.h"
#include "core/body/colliders.h"
#include "core/body/contact_impulse.h"
#include "core/body/forces.h"
#include "core/geometry/mesh_surface.h"

#include <algorithm>
#include <cmath>

namespace softtouch {

namespace {

/// Position sweeps at most: each finds the points inside afresh, and ends the pass once none is.
constexpr int kPositionSweeps = 8;
constexpr int kNewtonIterations = 24;

/// X(uvw) and dX/duvw for the lattice deformed to `nodes`: the tensor-product sums of the basis values
/// and slopes.
void mapWithJacobian(const Lattice& lattice, std::span<const Vec3> nodes, const Vec3& uvw, Vec3& x, Mat3& jacobian) {
    const BasisSample s0 = lattice.axis(0).sample(uvw[0]), s1 = lattice.axis(1).sample(uvw[1]),
                      s2 = lattice.axis(2).sample(uvw[2]);
    x.setZero();
    jacobian.setZero();
    for (int k = 0; k < s2.order; ++k)
        for (int j = 0; j < s1.order; ++j)
            for (int i = 0; i < s0.order; ++i) {
                const Vec3& node = nodes[std::size_t(lattice.index(s0.first + i, s1.first + j, s2.first + k))];
                const double v0 = s0.value[std::size_t(i)], v1 = s1.value[std::size_t(j)], v2 = s2.value[std::size_t(k)];
                x += v0 * v1 * v2 * node;
                jacobian.col(0) += s0.slope[std::size_t(i)] * v1 * v2 * node;
                jacobian.col(1) += v0 * s1.slope[std::size_t(j)] * v2 * node;
                jacobian.col(2) += v0 * v1 * s2.slope[std::size_t(k)] * node;
            }
}

/// u ≈ meanU + inverse (p − meanP): the affine map that best fits the nodes' current positions to their
/// rest parameters (least squares). Newton starts from it, so a body that swam far from where it was
/// bound, or turned, starts near its answer.
struct AffineGuess {
    Vec3 meanU = Vec3::Constant(0.5), meanP = Vec3::Zero();
    Mat3 inverse = Mat3::Identity();
    Vec3 operator()(const Vec3& p) const { return meanU + inverse * (p - meanP); }
};

AffineGuess fitAffine(const Lattice& lattice, std::span<const Vec3> nodes) {
    AffineGuess g;
    const int n = lattice.nodeCount();
    std::vector<Vec3> u(static_cast<std::size_t>(n));
    g.meanU.setZero();
    for (int i = 0; i < n; ++i) {
        u[std::size_t(i)] = lattice.restNodeParameters(i);
        g.meanU += u[std::size_t(i)] / n;
        g.meanP += nodes[std::size_t(i)] / n;
    }
    Mat3 uu = Mat3::Zero(), pu = Mat3::Zero();
    for (int i = 0; i < n; ++i) {
        const Vec3 du = u[std::size_t(i)] - g.meanU;
        uu += du * du.transpose();
        pu += (nodes[std::size_t(i)] - g.meanP) * du.transpose();
    }
    const Mat3 forward = pu * uu.inverse();  // X ≈ meanP + forward (u − meanU)
    const Eigen::FullPivLU<Mat3> lu(forward);
    g.inverse = lu.isInvertible() ? Mat3(lu.inverse()) : lattice.box().parameterJacobian();
    return g;
}

std::pair<Vec3, Vec3> allNodeBounds(const BodyState& state) {
    const Bounds b = boundsOf(state.position);
    return {b.min, b.max};
}

/// Signed distance in the rest frame: to the rest mesh, or to the lattice box when the body has none.
double restDistance(const ContactBody& body, const Vec3& rest, Vec3& normal) {
    if (body.restSurface)
        return body.restSurface->signedDistance(rest, normal);
    const OrientedBox& box = body.lattice->box();
    Collider solid;
    solid.shape = ColliderShape::Box;
    solid.centre = box.toWorld(Vec3::Constant(0.5));
    solid.halfExtents = 0.5 * box.size;
    solid.axes = box.axes;
    return colliderDistance(solid, rest, normal);
}

/// A material point of one body: its node weights and how its velocity answers an impulse on it.
struct Side {
    ContactBody* body = nullptr;
    std::vector<NodeWeight> weights;
    double inverseMass = 0.0;  ///< Σ w_i² m_i⁻¹.
    Vec3 start = Vec3::Zero(); ///< Position when the contact was found.

    Vec3 at(const std::vector<Vec3>& values) const {
        Vec3 sum = Vec3::Zero();
        for (const NodeWeight& w : weights)
            sum += w.weight * values[w.node];
        return sum;
    }
    /// Moves the point's nodes so that, with `impulse` per unit of the point, its momentum changes by it:
    /// node i takes w_i m_i⁻¹ of it (the same split as a drag's force).
    void push(std::vector<Vec3>& values, const Vec3& impulse) const {
        for (const NodeWeight& w : weights)
            values[w.node] += w.weight * body->model->inverseMass[w.node] * impulse;
    }
};

struct Contact {
    Side point;              ///< The sample found inside the other body.
    Side other;              ///< The other body's material point where it was found.
    double depth = 0.0;      ///< How far inside, metres.
    ContactImpulse impulse;  ///< normal: out of the other body, the way `point` is pushed; inverseMass: both
                             ///< sides' (the relative velocity answers an impulse on both).
};

Side makeSide(ContactBody& body, std::vector<NodeWeight> weights) {
    Side s;
    s.body = &body;
    s.weights = std::move(weights);
    for (const NodeWeight& w : s.weights)
        s.inverseMass += w.weight * w.weight * body.model->inverseMass[w.node];
    s.start = s.at(body.state->position);
    return s;
}

/// Finds the contact points of `a` inside `b` and pushes each out at once (Gauss-Seidel: the next point sees
/// the bodies as this one left them). A point found for the first time is added to `contacts` with its
/// velocity target; `known[q]` holds its index there (−1: not yet found). Returns how many points were inside.
/// `near`: the points the first sweep (`pass` given) found in b's box; later sweeps look only at them.
int pushOut(ContactBody& a, ContactBody& b, const BodyCollisionSettings& settings, double restingSpeed,
            std::vector<int>& known, std::vector<std::uint32_t>& near, std::vector<Contact>& contacts,
            BodyContactPass* pass) {
    const auto [lo, hi] = allNodeBounds(*b.state);
    const AffineGuess guess = fitAffine(*b.lattice, b.state->position);
    const ContactPoints& points = a.model->contacts();
    const bool atNodes = points.size() == 0;
    const std::size_t count = atNodes ? a.model->nodeCount() : points.size();
    known.resize(count, -1);
    int inside = 0;
    const OrientedBox& box = b.lattice->box();
    const bool first = pass != nullptr;
    if (first)
        near.clear();
    for (std::size_t k = 0; k < (first ? count : near.size()); ++k) {
        const std::size_t q = first ? k : near[k];
        if (atNodes && a.model->inverseMass[q] == 0.0)
            continue;
        const Vec3 x = atNodes ? a.state->position[q] : points.at(q, a.state->position);
        if ((x.array() < lo.array()).any() || (x.array() > hi.array()).any())
            continue;
        Vec3 uvw = guess(x);
        // The affine guess is near the truth unless the body is bent hard: a point
        // it puts well outside the box is outside, with no Newton iterations.
        constexpr double kGuessMargin = 0.25;
        if ((uvw.array() < -kGuessMargin).any() || (uvw.array() > 1.0 + kGuessMargin).any())
            continue;
        Mat3 jacobian;
        if (!latticeParameters(*b.lattice, b.state->position, x, uvw, jacobian))
            continue;
        if (first)
            near.push_back(std::uint32_t(q));
        constexpr double kEdge = 1e-9;
        if ((uvw.array() < -kEdge).any() || (uvw.array() > 1.0 + kEdge).any())
            continue;
        Vec3 restNormal;
        const double restDepth = restDistance(b, box.toWorld(uvw), restNormal);
        if (restDepth >= 0.0)
            continue;
        // φ(p) = d_rest(X⁻¹(p)): its gradient is G⁻ᵀ n_rest with G = d world / d rest = J · d uvw / d rest,
        // and to first order the world depth is d_rest / |∇φ|.
        const Mat3 worldFromRest = jacobian * box.parameterJacobian();
        const Vec3 gradient = worldFromRest.transpose().fullPivLu().solve(restNormal);
        if (!gradient.allFinite() || gradient.norm() == 0.0)
            continue;
        std::vector<NodeWeight> own;
        if (atNodes)
            own.push_back({std::uint32_t(q), 1.0});
        else
            own.assign(points.terms.begin() + points.start[q], points.terms.begin() + points.start[q + 1]);
        Contact c;
        c.point = makeSide(a, std::move(own));
        c.other = makeSide(b, b.lattice->weights(uvw));
        c.impulse.inverseMass = c.point.inverseMass + c.other.inverseMass;
        if (c.impulse.inverseMass <= 0.0)
            continue;  // both sides held: nothing can move
        c.impulse.normal = gradient.normalized();
        c.depth = -restDepth / gradient.norm();
        ++inside;
        if (pass) {
            ++pass->contacts;
            pass->deepest = std::max(pass->deepest, c.depth);
        }
        const double lambda = c.depth / c.impulse.inverseMass;
        c.point.push(a.state->position, lambda * c.impulse.normal);
        c.other.push(b.state->position, -lambda * c.impulse.normal);
        if (known[q] >= 0) {
            Contact& previous = contacts[std::size_t(known[q])];  // found again: take the newer normal
            previous.impulse.normal = c.impulse.normal;
            continue;
        }
        const double vn = c.impulse.normal.dot(c.point.at(a.state->velocity) - c.other.at(b.state->velocity));
        c.impulse.target = contactTargetSpeed(vn, restingSpeed, settings.restitution);
        known[q] = int(contacts.size());
        contacts.push_back(std::move(c));
    }
    return inside;
}

}  // namespace

Status BodyCollisionSettings::validate() const {
    for (const auto& [range, value] : {std::pair{ranges::kRestitution, restitution}, std::pair{ranges::kFriction, friction}})
        if (const std::string problem = range.problem(value); !problem.empty())
            return Status::error("body " + problem);
    return Status::success();
}

bool latticeParameters(const Lattice& lattice, std::span<const Vec3> nodes, const Vec3& p, Vec3& uvw, Mat3& jacobian) {
    // 1e-8 of the box is far below anything a contact resolves (3 nm on a 30 cm fish) and Newton gets there
    // from the affine guess (latticeParametersInvertTheMap checks it converges on a bent lattice).
    const double tolerance = 1e-8 * lattice.box().diagonal();
    for (int iteration = 0; iteration < kNewtonIterations; ++iteration) {
        Vec3 x;
        mapWithJacobian(lattice, nodes, uvw, x, jacobian);
        const Vec3 residual = x - p;
        if (residual.norm() <= tolerance)
            return true;
        const Eigen::PartialPivLU<Mat3> lu(jacobian);
        if (!(std::abs(jacobian.determinant()) > 0.0))
            return false;
        // Far outside the box the polynomial end spans are meaningless: keep the iterate near it.
        uvw = (uvw - lu.solve(residual)).cwiseMax(-0.5).cwiseMin(1.5);
        if (!uvw.allFinite())
            return false;
    }
    return false;
}

bool bodiesMayTouch(const ContactBody& a, const ContactBody& b) {
    const auto [loA, hiA] = allNodeBounds(*a.state);
    const auto [loB, hiB] = allNodeBounds(*b.state);
    return (loA.array() <= hiB.array()).all() && (loB.array() <= hiA.array()).all();
}

BodyContactPass resolveBodyContacts(ContactBody& a, ContactBody& b, const BodyCollisionSettings& settings,
                                    double restingSpeed) {
    BodyContactPass pass;
    thread_local std::vector<Contact> contacts;
    thread_local std::vector<int> knownA, knownB;
    thread_local std::vector<std::uint32_t> nearA, nearB;
    contacts.clear();
    knownA.clear();
    knownB.clear();
    // Positions: every point inside the other body is pushed out, looked for again in each sweep among the
    // points the first sweep found in the other's box (a push moves the body's other points too, and can
    // carry one that was outside in). The first sweep's findings are the pass's report.
    for (int sweep = 0; sweep < kPositionSweeps; ++sweep) {
        const int inside = pushOut(a, b, settings, restingSpeed, knownA, nearA, contacts, sweep == 0 ? &pass : nullptr) +
                           pushOut(b, a, settings, restingSpeed, knownB, nearB, contacts, sweep == 0 ? &pass : nullptr);
        if (inside == 0)
            break;
    }
    if (contacts.empty())
        return pass;
    // Velocities: sequential impulses (core/body/contact_impulse.h, as resolveColliders) on the relative velocity
    // of the two material points; each impulse acts on both with opposite signs.
    for (int sweep = 0; sweep < 4 * kContactSweeps; ++sweep)
        for (Contact& c : contacts) {
            const Vec3 relative = c.point.at(c.point.body->state->velocity) - c.other.at(c.other.body->state->velocity);
            const Vec3 impulse = sequentialImpulse(c.impulse, relative, settings.friction);
            c.point.push(c.point.body->state->velocity, impulse);
            c.other.push(c.other.body->state->velocity, -impulse);
        }
    return pass;
}

}  // namespace softtouch

#include "core/animation/base_motion.h"

#include <algorithm>
#include <cmath>

namespace softtouch {

namespace {
/// Fits kept: a step needs three times and the next step shares two of them.
constexpr std::size_t kCachedFits = 4;
}  // namespace

Status FollowSettings::validate() const {
    if (!(std::isfinite(frequency) && frequency > 0.0 && frequency <= 1000.0))
        return Status::error("goal frequency must be in (0, 1000] Hz, got " + std::to_string(frequency));
    if (!(std::isfinite(dampingRatio) && dampingRatio >= 0.0 && dampingRatio <= 100.0))
        return Status::error("goal damping ratio must be in [0, 100], got " + std::to_string(dampingRatio));
    return Status::success();
}

NodeSprings goalSprings(const BodyModel& model, std::span<const double> goalWeight, const FollowSettings& settings) {
    NodeSprings springs;
    springs.stiffness.assign(model.nodeCount(), 0.0);
    springs.damping.assign(model.nodeCount(), 0.0);
    const double omega = 2.0 * M_PI * settings.frequency;
    for (std::size_t i = 0; i < model.nodeCount() && i < goalWeight.size(); ++i) {
        const double w = goalWeight[i];
        if (!(w > 0.0) || w >= 1.0 || model.inverseMass[i] == 0.0)
            continue;
        const double ratio = w / (1.0 - w);
        springs.stiffness[i] = model.mass[i] * omega * omega * ratio;
        springs.damping[i] = 2.0 * settings.dampingRatio * model.mass[i] * omega * std::sqrt(ratio);
    }
    return springs;
}

LatticeMaterial followingMaterial(LatticeMaterial material) {
    for (std::size_t i = 0; i < material.goalWeight.size() && i < material.anchor.size(); ++i)
        if (material.goalWeight[i] >= 1.0 && !material.isVoid[i])
            material.anchor[i] = AnchorMode::Pinned;
    return material;
}

Result<std::shared_ptr<BaseMotion>> BaseMotion::create(const Lattice& lattice, const BodyModel& model,
                                                       std::span<const Vec3f> restPositions,
                                                       std::shared_ptr<const GoalFit> fit,
                                                       std::shared_ptr<const BaseAnimation> animation,
                                                       std::span<const double> goalWeight, const FollowSettings& settings) {
    if (!animation)
        return Status::error("no base animation");
    if (Status s = animation->validate(restPositions.size()); !s)
        return s;
    if (Status s = settings.validate(); !s)
        return s;
    for (double w : goalWeight)
        if (!(w >= 0.0 && w <= 1.0))
            return Status::error("goal weight must be in [0, 1], got " + std::to_string(w));
    if (!fit)
        return Status::error("no goal fit");
    auto motion = std::make_shared<BaseMotion>();
    motion->m_animation = std::move(animation);
    motion->m_fit = std::move(fit);
    motion->m_restNodes = lattice.restNodes();
    // The goal springs do not change while the body runs: made once, appended to every step's drags.
    const NodeSprings springs = goalSprings(model, goalWeight, settings);
    for (std::size_t i = 0; i < model.nodeCount(); ++i) {
        if (springs.stiffness[i] == 0.0)
            continue;
        DragSpring spring;
        spring.support = {NodeWeight{std::uint32_t(i), 1.0}};
        spring.target = motion->m_restNodes[i];
        spring.stiffness = springs.stiffness[i];
        spring.damping = springs.damping[i];
        motion->m_goalSprings.push_back(std::move(spring));
    }
    return motion;
}

void BaseMotion::goal(double seconds, std::vector<Vec3>& nodes, Mat3& rotation) const {
    std::lock_guard lock(m_mutex);
    for (const Cached& c : m_cache)
        if (c.seconds == seconds) {
            nodes = c.nodes;
            rotation = c.rotation;
            return;
        }
    m_positions.resize(m_animation->vertexCount());
    m_animation->positionsAt(seconds, m_positions);
    Cached c;
    c.seconds = seconds;
    m_fit->fit(m_positions, c.nodes, c.rotation);
    nodes = c.nodes;
    rotation = c.rotation;
    if (m_cache.size() == kCachedFits)
        m_cache.erase(m_cache.begin());
    m_cache.push_back(std::move(c));
}

void BaseMotion::addForces(double seconds, double dt, const BodyModel& model, ExternalForces& forces) const {
    const std::size_t n = model.nodeCount();
    // The goal's acceleration at the step's middle, a central difference over one step each side. The
    // times are odd multiples of dt/2 computed from the step's index, so the next step asks for two of them
    // bit for bit (one new fit a step) and a replay computes exactly what the first run did.
    const long long half = 2 * std::llround(seconds / dt) + 1;
    std::vector<Vec3> before, at, after;
    Mat3 rotation, unused;
    goal(double(half - 2) * (0.5 * dt), before, unused);
    goal(double(half) * (0.5 * dt), at, rotation);
    goal(double(half + 2) * (0.5 * dt), after, unused);
    const Mat3 toLocal = rotation.transpose();
    const Vec3 gravity = forces.gravity;
    forces.gravity = Vec3::Zero();
    forces.nodeForces.assign(n, Vec3::Zero());
    if (model.element) {
        // The consistent mass carries the frame's acceleration: F = M Rᵀ(g − G̈) over every node, held ones
        // included (their mass is coupled to the free ones'), so a body with no deviation accelerates exactly with
        // its goal. One mass per node, m_i G̈_i, would shake the element's light wiggles with the goal's.
        std::vector<Vec3> local(n, Vec3::Zero());
        for (std::size_t i = 0; i < n && i < at.size(); ++i)
            local[i] = toLocal * (gravity - (after[i] - 2.0 * at[i] + before[i]) / (dt * dt));
        addElementMatrixTimes(*model.element, model.element->mass, 1.0, local, forces.nodeForces);
    } else {
        for (std::size_t i = 0; i < n && i < at.size(); ++i) {
            if (model.inverseMass[i] == 0.0)
                continue;
            const Vec3 acceleration = (after[i] - 2.0 * at[i] + before[i]) / (dt * dt);
            forces.nodeForces[i] = model.mass[i] * (toLocal * (gravity - acceleration));
        }
    }
    forces.drags.insert(forces.drags.end(), m_goalSprings.begin(), m_goalSprings.end());
}

void BaseMotion::shownNodes(double seconds, std::span<const Vec3> nodes, std::vector<Vec3>& out, Mat3* rotation) const {
    Mat3 turn;
    goal(seconds, out, turn);
    for (std::size_t i = 0; i < out.size() && i < nodes.size(); ++i)
        out[i] += turn * (nodes[i] - m_restNodes[i]);
    if (rotation)
        *rotation = turn;
}

void BaseMotion::deform(double seconds, const Binding& binding, std::span<const Vec3> nodes,
                        std::span<const std::array<std::uint32_t, 3>> triangles, std::span<Vec3f> positions,
                        std::span<Vec3f> normals) const {
    std::vector<Vec3> goalNodes;
    Mat3 rotation;
    goal(seconds, goalNodes, rotation);
    std::lock_guard lock(m_mutex);
    const std::size_t vertices = m_animation->vertexCount();
    if (m_restEvaluated.size() != vertices) {
        m_restEvaluated.resize(vertices);
        binding.evaluate(m_restNodes, m_restEvaluated, {}, 1);
    }
    m_deformed.resize(vertices);
    binding.evaluate(nodes, m_deformed, {}, 1);
    m_animation->positionsAt(seconds, positions);
    const Eigen::Matrix3f turn = rotation.cast<float>();
    for (std::size_t v = 0; v < vertices && v < positions.size(); ++v) {
        const Vec3f deviation = m_deformed[v] - m_restEvaluated[v];
        if (!deviation.isZero(0.0f))
            positions[v] += turn * deviation;
    }
    if (!normals.empty())
        areaWeightedNormals(positions, triangles, normals);
}

}  // namespace softtouch

#include "core/base_motion.h"

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

LatticeMaterial followingMaterial(LatticeMaterial material) {
    for (std::size_t i = 0; i < material.goalWeight.size() && i < material.anchor.size(); ++i)
        if (material.goalWeight[i] >= 1.0 && !material.isVoid[i])
            material.anchor[i] = AnchorMode::Pinned;
    return material;
}

Result<std::shared_ptr<BaseMotion>> BaseMotion::create(const Lattice& lattice, std::span<const Vec3f> restPositions,
                                                       std::span<const Vec3> parameters,
                                                       std::shared_ptr<const BaseAnimation> animation,
                                                       std::vector<double> goalWeight, const FollowSettings& settings) {
    if (!animation)
        return Status::error("no base animation");
    if (Status s = animation->validate(restPositions.size()); !s)
        return s;
    if (Status s = settings.validate(); !s)
        return s;
    goalWeight.resize(std::size_t(lattice.nodeCount()), 0.0);
    for (double w : goalWeight)
        if (!(w >= 0.0 && w <= 1.0))
            return Status::error("goal weight must be in [0, 1], got " + std::to_string(w));
    auto fit = GoalFit::create(lattice, restPositions, parameters);
    if (!fit)
        return fit.status();
    auto motion = std::make_shared<BaseMotion>();
    motion->m_animation = std::move(animation);
    motion->m_fit = std::move(fit.value());
    motion->m_restNodes = lattice.restNodes();
    motion->m_goalWeight = std::move(goalWeight);
    motion->m_settings = settings;
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
    m_fit.fit(m_positions, c.nodes, c.rotation);
    nodes = c.nodes;
    rotation = c.rotation;
    if (m_cache.size() == kCachedFits)
        m_cache.erase(m_cache.begin());
    m_cache.push_back(std::move(c));
}

void BaseMotion::addForces(double seconds, double dt, const BodyModel& model, ExternalForces& forces) const {
    const std::size_t n = model.nodeCount();
    // The goal's acceleration at the step's middle, a central difference over one step each side.
    const double middle = seconds + 0.5 * dt;
    std::vector<Vec3> before, at, after;
    Mat3 rotation, unused;
    goal(middle - dt, before, unused);
    goal(middle, at, rotation);
    goal(middle + dt, after, unused);
    const Mat3 toLocal = rotation.transpose();
    const Vec3 gravity = forces.gravity;
    forces.gravity = Vec3::Zero();
    forces.nodeForces.assign(n, Vec3::Zero());
    for (std::size_t i = 0; i < n && i < at.size(); ++i) {
        if (model.inverseMass[i] == 0.0)
            continue;
        const Vec3 acceleration = (after[i] - 2.0 * at[i] + before[i]) / (dt * dt);
        forces.nodeForces[i] = model.mass[i] * (toLocal * (gravity - acceleration));
    }
    const double omega = 2.0 * M_PI * m_settings.frequency;
    for (std::size_t i = 0; i < n && i < m_goalWeight.size(); ++i) {
        const double w = m_goalWeight[i];
        if (!(w > 0.0) || w >= 1.0 || model.inverseMass[i] == 0.0)
            continue;
        const double ratio = w / (1.0 - w);
        DragSpring spring;
        spring.support = {NodeWeight{std::uint32_t(i), 1.0}};
        spring.target = m_restNodes[i];
        spring.stiffness = model.mass[i] * omega * omega * ratio;
        spring.damping = 2.0 * m_settings.dampingRatio * model.mass[i] * omega * std::sqrt(ratio);
        forces.drags.push_back(std::move(spring));
    }
}

void BaseMotion::shownNodes(double seconds, std::span<const Vec3> nodes, std::vector<Vec3>& out) const {
    Mat3 rotation;
    goal(seconds, out, rotation);
    for (std::size_t i = 0; i < out.size() && i < nodes.size(); ++i)
        out[i] += rotation * (nodes[i] - m_restNodes[i]);
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

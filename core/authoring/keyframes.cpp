#include "core/authoring/keyframes.h"

#include <algorithm>
#include <cmath>

namespace softtouch {
namespace {

constexpr double kSameTime = 1e-9;

/// Index of `node` in a key's sorted node list, or -1.
long long findNode(const LatticeKey& key, std::uint32_t node) {
    auto it = std::lower_bound(key.nodes.begin(), key.nodes.end(), node);
    return it != key.nodes.end() && *it == node ? it - key.nodes.begin() : -1;
}

/// The track through (t[k], p[k]) at `s`, value and derivative, segment k moving as `how[k]` says: smooth is
/// Catmull-Rom with non-uniform times (cubic Hermite, tangents from the neighbouring keys), linear a straight
/// line, constant key k held. When the keys span exactly one `cycle` (> 0: the last key at the first's time
/// plus the cycle), the ends' tangents wrap round to the neighbouring pass, as a looping clip plays them.
void track(const std::vector<double>& t, const std::vector<Vec3>& p, const std::vector<KeyInterpolation>& how, double s,
           double cycle, Vec3& value, Vec3& rate) {
    rate.setZero();
    const std::size_t n = t.size();
    if (n == 1 || s < t.front()) {
        value = p.front();
        return;
    }
    if (s >= t.back()) {
        value = p.back();
        return;
    }
    const std::size_t i = std::size_t(std::upper_bound(t.begin(), t.end(), s) - t.begin()) - 1;
    const double h = t[i + 1] - t[i];
    const double x = (s - t[i]) / h;
    if (how[i] == KeyInterpolation::Constant) {
        value = p[i];
        return;
    }
    if (how[i] == KeyInterpolation::Linear) {
        value = p[i] + x * (p[i + 1] - p[i]);
        rate = (p[i + 1] - p[i]) / h;
        return;
    }
    const bool wraps = cycle > 0.0 && n >= 3 && std::abs(t.back() - t.front() - cycle) <= 1e-9 * std::max(1.0, cycle);
    auto tangent = [&](std::size_t k) -> Vec3 {
        if (wraps && k == 0)
            return (p[1] - p[n - 2]) / (t[1] - (t[n - 2] - cycle));
        if (wraps && k == n - 1)
            return (p[1] - p[n - 2]) / (t[1] + cycle - t[n - 2]);
        const std::size_t lo = k == 0 ? 0 : k - 1;
        const std::size_t hi = std::min(k + 1, n - 1);
        return (p[hi] - p[lo]) / (t[hi] - t[lo]);
    };
    const Vec3 m1 = tangent(i) * h, m2 = tangent(i + 1) * h;
    const double x2 = x * x, x3 = x2 * x;
    // Cubic Hermite basis on [0,1].
    value = (2 * x3 - 3 * x2 + 1) * p[i] + (x3 - 2 * x2 + x) * m1 + (-2 * x3 + 3 * x2) * p[i + 1] + (x3 - x2) * m2;
    rate = ((6 * x2 - 6 * x) * p[i] + (3 * x2 - 4 * x + 1) * m1 + (-6 * x2 + 6 * x) * p[i + 1] + (3 * x2 - 2 * x) * m2) / h;
}

}  // namespace

Status KeyframeAnimation::validate(const LatticeKey& key) const {
    if (!std::isfinite(key.seconds))
        return Status::error("key time must be finite");
    if (key.nodes.size() != key.displacement.size())
        return Status::error("a key needs one displacement per keyed node (" + std::to_string(key.nodes.size()) +
                             " nodes, " + std::to_string(key.displacement.size()) + " displacements)");
    if (key.nodes.empty())
        return Status::error("a key needs at least one node");
    for (std::size_t i = 0; i < key.nodes.size(); ++i) {
        if (key.nodes[i] >= m_nodeCount)
            return Status::error("key node " + std::to_string(key.nodes[i]) + " is outside the lattice (" +
                                 std::to_string(m_nodeCount) + " nodes)");
        if (i > 0 && key.nodes[i] <= key.nodes[i - 1])
            return Status::error("key nodes must increase without repeats (node " + std::to_string(key.nodes[i]) + ")");
        if (!isFinite(key.displacement[i]))
            return Status::error("key node " + std::to_string(key.nodes[i]) + ": displacement is not finite");
    }
    return Status::success();
}

Result<std::size_t> KeyframeAnimation::insertKey(LatticeKey key) {
    // Sort nodes (with their displacements) so callers may pass a selection in any order.
    std::vector<std::size_t> order(key.nodes.size());
    for (std::size_t i = 0; i < order.size(); ++i)
        order[i] = i;
    if (key.nodes.size() == key.displacement.size()) {
        std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return key.nodes[a] < key.nodes[b]; });
        LatticeKey sorted{key.seconds, {}, {}, key.interpolation};
        for (std::size_t i : order) {
            sorted.nodes.push_back(key.nodes[i]);
            sorted.displacement.push_back(key.displacement[i]);
        }
        key = std::move(sorted);
    }
    if (Status s = validate(key); !s)
        return s;
    if (const long long at = keyAt(key.seconds); at >= 0) {
        LatticeKey& old = m_keys[std::size_t(at)];
        for (std::size_t i = 0; i < key.nodes.size(); ++i) {
            const long long k = findNode(old, key.nodes[i]);
            if (k >= 0) {
                old.displacement[std::size_t(k)] = key.displacement[i];
                continue;
            }
            auto pos = std::lower_bound(old.nodes.begin(), old.nodes.end(), key.nodes[i]) - old.nodes.begin();
            old.nodes.insert(old.nodes.begin() + pos, key.nodes[i]);
            old.displacement.insert(old.displacement.begin() + pos, key.displacement[i]);
        }
        return std::size_t(at);
    }
    auto it = std::upper_bound(m_keys.begin(), m_keys.end(), key.seconds,
                               [](double s, const LatticeKey& k) { return s < k.seconds; });
    const auto index = std::size_t(it - m_keys.begin());
    m_keys.insert(it, std::move(key));
    return index;
}

Result<std::size_t> KeyframeAnimation::setKey(double seconds, std::span<const Vec3> rest, std::span<const Vec3> pose,
                                              std::vector<std::uint32_t> nodes) {
    if (rest.size() != m_nodeCount || pose.size() != m_nodeCount)
        return Status::error("the pose has " + std::to_string(pose.size()) + " nodes, the animation's lattice " +
                             std::to_string(m_nodeCount));
    if (nodes.empty()) {
        for (std::size_t i = 0; i < m_nodeCount; ++i)
            nodes.push_back(std::uint32_t(i));
    }
    LatticeKey key{seconds, std::move(nodes), {}};
    for (std::uint32_t n : key.nodes) {
        if (n >= m_nodeCount)
            return Status::error("node " + std::to_string(n) + " is outside the lattice (" + std::to_string(m_nodeCount) +
                                 " nodes)");
        key.displacement.push_back(pose[n] - rest[n]);
    }
    return insertKey(std::move(key));
}

Result<std::size_t> KeyframeAnimation::moveKey(std::size_t index, double seconds) {
    if (index >= m_keys.size())
        return Status::error("no key " + std::to_string(index) + " (" + std::to_string(m_keys.size()) + " keys)");
    if (!std::isfinite(seconds))
        return Status::error("key time must be finite");
    const long long at = keyAt(seconds);
    if (at >= 0 && std::size_t(at) != index)
        return Status::error("another key is at " + std::to_string(seconds) + " s; delete it or copy onto it instead");
    LatticeKey key = std::move(m_keys[index]);
    m_keys.erase(m_keys.begin() + std::ptrdiff_t(index));
    key.seconds = seconds;
    return insertKey(std::move(key));
}

Result<std::size_t> KeyframeAnimation::copyKey(std::size_t index, double seconds) {
    if (index >= m_keys.size())
        return Status::error("no key " + std::to_string(index) + " (" + std::to_string(m_keys.size()) + " keys)");
    LatticeKey key = m_keys[index];
    key.seconds = seconds;
    return insertKey(std::move(key));
}

Status KeyframeAnimation::deleteKey(std::size_t index) {
    if (index >= m_keys.size())
        return Status::error("no key " + std::to_string(index) + " (" + std::to_string(m_keys.size()) + " keys)");
    m_keys.erase(m_keys.begin() + std::ptrdiff_t(index));
    return Status::success();
}

Status KeyframeAnimation::setInterpolation(std::size_t index, KeyInterpolation interpolation) {
    if (index >= m_keys.size())
        return Status::error("no key " + std::to_string(index) + " (" + std::to_string(m_keys.size()) + " keys)");
    m_keys[index].interpolation = interpolation;
    return Status::success();
}

const char* keyInterpolationName(KeyInterpolation interpolation) {
    switch (interpolation) {
    case KeyInterpolation::Linear: return "linear";
    case KeyInterpolation::Constant: return "constant";
    case KeyInterpolation::Smooth: break;
    }
    return "smooth";
}

std::optional<KeyInterpolation> keyInterpolationNamed(std::string_view name) {
    for (KeyInterpolation k : {KeyInterpolation::Smooth, KeyInterpolation::Linear, KeyInterpolation::Constant})
        if (name == keyInterpolationName(k))
            return k;
    return std::nullopt;
}

long long KeyframeAnimation::keyAt(double seconds) const {
    for (std::size_t i = 0; i < m_keys.size(); ++i) {
        if (std::abs(m_keys[i].seconds - seconds) <= kSameTime)
            return (long long)i;
    }
    return -1;
}

void KeyframeAnimation::sample(double seconds, std::span<Vec3> displacement, std::span<Vec3> velocity,
                               std::vector<std::uint8_t>* keyed, double cycle) const {
    for (Vec3& d : displacement)
        d.setZero();
    for (Vec3& v : velocity)
        v.setZero();
    if (keyed)
        keyed->assign(m_nodeCount, 0);
    std::vector<double> t;
    std::vector<Vec3> p;
    std::vector<KeyInterpolation> how;
    for (std::size_t node = 0; node < m_nodeCount && node < displacement.size(); ++node) {
        t.clear();
        p.clear();
        how.clear();
        for (const LatticeKey& key : m_keys) {
            if (const long long k = findNode(key, std::uint32_t(node)); k >= 0) {
                t.push_back(key.seconds);
                p.push_back(key.displacement[std::size_t(k)]);
                how.push_back(key.interpolation);
            }
        }
        if (t.empty())
            continue;
        Vec3 value, rate;
        track(t, p, how, seconds, cycle, value, rate);
        displacement[node] = value;
        if (node < velocity.size())
            velocity[node] = rate;
        if (keyed)
            (*keyed)[node] = 1;
    }
}

std::vector<Vec3> KeyframeAnimation::pose(double seconds, std::span<const Vec3> rest, double cycle) const {
    std::vector<Vec3> out(rest.size());
    sample(seconds, out, {}, nullptr, cycle);
    for (std::size_t i = 0; i < out.size(); ++i)
        out[i] += rest[i];
    return out;
}

std::vector<DragSpring> goalDrags(const KeyframeAnimation& animation, std::span<const Vec3> rest, double seconds,
                                  const GoalSettings& settings, double cycle) {
    std::vector<DragSpring> drags;
    if (settings.weight <= 0.0 || animation.keys().empty())
        return drags;
    std::vector<Vec3> displacement(rest.size()), velocity(rest.size());
    std::vector<std::uint8_t> keyed;
    animation.sample(seconds, displacement, velocity, &keyed, cycle);
    for (std::size_t n = 0; n < rest.size(); ++n) {
        if (!keyed[n])
            continue;
        DragSpring d;
        d.support = {NodeWeight{std::uint32_t(n), 1.0}};
        d.target = rest[n] + displacement[n];
        d.targetVelocity = velocity[n];
        d.stiffness = settings.stiffness * settings.weight;
        d.damping = settings.damping * settings.weight;
        drags.push_back(std::move(d));
    }
    return drags;
}

Result<GoalPlayer> GoalPlayer::create(const SceneSimulation& sim, std::size_t object, const KeyframeAnimation& animation,
                                      GoalSettings settings) {
    if (object >= sim.objectCount())
        return Status::error("no object " + std::to_string(object));
    const std::size_t nodes = sim.simulator(object).state().position.size();
    if (animation.nodeCount() != nodes)
        return Status::error("the keyframes are for " + std::to_string(animation.nodeCount()) + " nodes, object '" +
                             sim.object(object).name + "' has " + std::to_string(nodes));
    if (!(std::isfinite(settings.stiffness) && settings.stiffness >= 0.0 && settings.stiffness <= 1e9) ||
        !(std::isfinite(settings.damping) && settings.damping >= 0.0 && settings.damping <= 1e6) ||
        !(std::isfinite(settings.weight) && settings.weight >= 0.0 && settings.weight <= 1e3))
        return Status::error("goal stiffness, damping and weight must be in [0, 1e9], [0, 1e6], [0, 1e3]");
    GoalPlayer player;
    player.m_animation = &animation;
    player.m_object = object;
    player.m_settings = settings;
    player.m_rest = sim.simulator(object).model().restPositions;
    return player;
}

void GoalPlayer::advanceTo(SceneSimulation& sim, double seconds, std::vector<std::string>* problems) {
    sim.advanceTo(seconds, problems, [this](SceneSimulation& s, std::size_t object, long long step) {
        if (object != m_object)
            return;
        // Goals sampled at the start of the step, like the drivers.
        std::vector<DragSpring> drags =
            goalDrags(*m_animation, m_rest, double(step) * s.simulator(object).settings().dt, m_settings);
        drags.insert(drags.end(), m_extra.begin(), m_extra.end());
        s.setInteractiveDrags(object, std::move(drags));
    });
}

}  // namespace softtouch

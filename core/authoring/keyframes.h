#pragma once
/// Keyframes of the lattice pose and goal springs that pull a simulated body toward them.
///
/// A key stores, at one time, the displacement from rest of some lattice nodes (all of them or the
/// selected ones). Each node has its own track made of the keys that hold it; between them the
/// displacement moves from each key to the next as that key's interpolation says: smooth (the default), a
/// Catmull-Rom spline with non-uniform times (tangent at key k: (p[k+1] − p[k−1]) / (t[k+1] − t[k−1]),
/// one-sided at the ends), which passes through every key, is C1 where neighbouring keys are smooth too and
/// reproduces motion at constant velocity exactly; linear, a straight line at constant velocity; constant, the
/// key held until the next (a pose that snaps, as in blocking). Before the first and after the last key the
/// displacement holds. Nodes no key holds stay at rest.
///
/// Keys as goals: goalDrags() turns the keyed pose at time t into one drag spring per keyed node
/// (support on that node only; target = rest + keyed displacement, target velocity = the spline's
/// derivative). Added through SceneSimulation::setInteractiveDrags (see GoalPlayer), physics adds
/// follow-through and overlap on top of the keyed motion; the weight sets how tightly the body follows.

#include "core/base/ranges.h"
#include "core/scene/scene.h"

#include <optional>
#include <string_view>
#include <vector>

namespace softtouch {

/// How the keyed displacement goes from a key to the next (Blender's and Maya's per-key interpolation).
enum class KeyInterpolation : std::uint8_t {
    Smooth,    ///< Catmull-Rom through the neighbouring keys.
    Linear,    ///< A straight line at constant velocity.
    Constant,  ///< This key held until the next.
};
/// Its name in files and menus ("smooth", "linear", "constant"), and back (nullopt for another name).
const char* keyInterpolationName(KeyInterpolation interpolation);
std::optional<KeyInterpolation> keyInterpolationNamed(std::string_view name);

/// One keyframe: some nodes' displacements at one time.
struct LatticeKey {
    double seconds = 0.0;                ///< Key time, seconds, finite.
    std::vector<std::uint32_t> nodes;    ///< Keyed nodes, increasing, unique, < node count.
    std::vector<Vec3> displacement;      ///< Per keyed node, metres from its rest position.
    KeyInterpolation interpolation = KeyInterpolation::Smooth;  ///< From this key to the next.
};

/// How keys pull a simulated body.
struct GoalSettings {
    double stiffness = 20.0;  ///< Ks per keyed node at weight 1, N/m, kGoalStiffness.
    double damping = 0.2;     ///< Kd per keyed node at weight 1, N·s/m, kGoalDamping.
    double weight = 1.0;      ///< Scales both; 0 turns the goals off, kGoalWeight.
};

/// The goal springs' ranges as a clip's "goals" names them (Clip::validate() and the reader use these).
inline constexpr FieldRange kGoalStiffness{"stiffness", "goal stiffness", 0.0, 1e9, "N/m"};
inline constexpr FieldRange kGoalDamping{"damping", "goal damping", 0.0, 1e6, "N·s/m"};
inline constexpr FieldRange kGoalWeight{"weight", "goal weight", 0.0, 1e3, ""};

/// The keyframes of one object's lattice.
class KeyframeAnimation {
public:
    /// An empty animation of a lattice with `nodeCount` nodes.
    explicit KeyframeAnimation(std::size_t nodeCount = 0) : m_nodeCount(nodeCount) {}

    /// Node count of the lattice the keys belong to.
    std::size_t nodeCount() const { return m_nodeCount; }
    /// Keys in increasing time.
    const std::vector<LatticeKey>& keys() const { return m_keys; }

    /// Keys the current pose: the displacement of `nodes` (empty: all nodes) from `rest` to `pose`
    /// at `seconds`. A key already at that time (within 1e-9 s) is updated: these nodes are replaced or
    /// added, the others kept. Returns the key's index.
    Result<std::size_t> setKey(double seconds, std::span<const Vec3> rest, std::span<const Vec3> pose,
                               std::vector<std::uint32_t> nodes = {});
    /// Inserts a ready-made key (validated; replaces the nodes of a key at the same time).
    Result<std::size_t> insertKey(LatticeKey key);
    /// Moves key `index` to `seconds`; refused when another key is there. Returns its new index.
    Result<std::size_t> moveKey(std::size_t index, double seconds);
    /// Copies key `index` to `seconds` (merging into a key there). Returns the copy's index.
    Result<std::size_t> copyKey(std::size_t index, double seconds);
    /// Deletes key `index`.
    Status deleteKey(std::size_t index);
    /// Sets how key `index` moves on to the next.
    Status setInterpolation(std::size_t index, KeyInterpolation interpolation);
    /// Index of the key at `seconds` (within 1e-9 s), or -1.
    long long keyAt(double seconds) const;

    /// Keyed displacement and its time derivative of every node at `seconds` (zero for unkeyed nodes).
    /// `keyed` (optional) gets 1 for nodes some key holds. `cycle` > 0: a loop's length, seconds; a node whose
    /// keys span exactly that (its last key the first pose again) gets tangents that wrap round at its ends.
    void sample(double seconds, std::span<Vec3> displacement, std::span<Vec3> velocity = {},
                std::vector<std::uint8_t>* keyed = nullptr, double cycle = 0.0) const;
    /// The keyed pose: rest + sample(seconds).
    std::vector<Vec3> pose(double seconds, std::span<const Vec3> rest, double cycle = 0.0) const;
    /// Time of the first and last key (0, 0 when empty).
    double firstSeconds() const { return m_keys.empty() ? 0.0 : m_keys.front().seconds; }
    double lastSeconds() const { return m_keys.empty() ? 0.0 : m_keys.back().seconds; }

private:
    Status validate(const LatticeKey& key) const;
    std::size_t m_nodeCount = 0;
    std::vector<LatticeKey> m_keys;
};

/// One drag spring per keyed node pulling it toward its keyed position at `seconds` (see the file
/// comment; `cycle` as sample() takes it). Empty when the weight is 0 or nothing is keyed.
std::vector<DragSpring> goalDrags(const KeyframeAnimation& animation, std::span<const Vec3> rest, double seconds,
                                  const GoalSettings& settings, double cycle = 0.0);

/// Steps a SceneSimulation with goal springs on one object, refreshed at the start of every step,
/// on top of its drivers and of any `extra` interactive drags (the editor's mouse). The animation
/// must outlive the player.
class GoalPlayer {
public:
    /// Goals from `animation` act on object `object`; the animation must match its node count.
    static Result<GoalPlayer> create(const SceneSimulation& sim, std::size_t object, const KeyframeAnimation& animation,
                                     GoalSettings settings);
    /// Other interactive drags applied with the goals.
    void setExtraDrags(std::vector<DragSpring> extra) { m_extra = std::move(extra); }
    /// Steps until the simulated time reaches `seconds` (SceneSimulation's rule), goals refreshed each step.
    void advanceTo(SceneSimulation& sim, double seconds, std::vector<std::string>* problems = nullptr);

private:
    const KeyframeAnimation* m_animation = nullptr;
    std::size_t m_object = 0;
    GoalSettings m_settings;
    std::vector<Vec3> m_rest;
    std::vector<DragSpring> m_extra;
};

}  // namespace softtouch

#include "core/authoring/clip.h"

#include "core/base/ranges.h"

#include <algorithm>
#include <cmath>
#include <set>

namespace softtouch {

namespace {

double smoothstep(double x) {
    x = std::clamp(x, 0.0, 1.0);
    return x * x * (3.0 - 2.0 * x);
}

/// RMS over points of the motion between two frames.
double rmsMotion(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i)
        sum += (b[i] - a[i]).squaredNorm();
    return a.empty() ? 0.0 : std::sqrt(sum / double(a.size()));
}

/// All objects' node positions at scene time `seconds`, flat: the simulation has just stepped past it
/// (SceneSimulation::advanceToSample), so a frame between two steps is sampled at its own time.
std::vector<Vec3> sampleNodes(const SceneSimulation& sim, double seconds) {
    std::vector<Vec3> out;
    for (std::size_t i = 0; i < sim.objectCount(); ++i) {
        const std::vector<Vec3> p = sim.nodesAt(i, seconds);
        out.insert(out.end(), p.begin(), p.end());
    }
    return out;
}

/// Which key time a keyframe clip shows at each frame. A loop plays its keys round and round: key time wraps
/// with the period. A goal clip's simulation starts before the clip's first frame, so frame 0 shows the body
/// already moving with the keys rather than at rest (from rest it would snap to the first key within a frame):
/// a loop first runs two passes of its cycle (two seconds of a longer one), so the seam joins the cycle's own
/// motion; a one-shot clip starts a second before its earliest key or its start, holding that key, so the body
/// has settled into it.
struct KeyTiming {
    double lead = 0.0;    ///< Simulated seconds before the clip's first frame.
    double start = 0.0;   ///< Key time of the clip's first frame.
    double period = 0.0;  ///< A loop's length, seconds; 0: no wrap.

    KeyTiming(const Clip& clip, const NamedKeyframes& keys) : start(clip.startSeconds) {
        if (clip.loop) {
            period = double(clip.frames) / clip.fps;
            // Two passes, or two seconds of a longer cycle (a long loop is not simulated three times over); at
            // least the closure's pre-roll.
            lead = std::max(double(clip.blendFrames) / clip.fps, std::min(2.0 * period, 2.0));
            return;
        }
        double earliest = clip.startSeconds;
        for (const KeyframeAnimation& k : keys.objects)
            if (!k.keys().empty())
                earliest = std::min(earliest, k.firstSeconds());
        lead = clip.startSeconds - earliest + 1.0;
    }
    /// The simulation's time of clip frame j (negative: the pre-roll).
    double simulated(int j, double fps) const { return lead + double(j) / fps; }
    /// The key time at simulated time `seconds`.
    double keyTime(double seconds) const { return fromStart(seconds - lead); }
    /// The key time `t` seconds after the clip's first frame (wrapped into the cycle for a loop).
    double fromStart(double t) const { return period > 0.0 ? start + (t - period * std::floor(t / period)) : start + t; }
};

/// Every keyed object's goal springs, refreshed at the start of each step (as GoalPlayer does for one object).
SceneSimulation::StepInputs goalInputs(const NamedKeyframes& keys, const GoalSettings& goals,
                                       const std::vector<std::vector<Vec3>>& rest, const KeyTiming& timing) {
    return [&keys, &goals, &rest, &timing](SceneSimulation& sim, std::size_t i, long long step) {
        if (!keys.objects[i].keys().empty())
            sim.setInteractiveDrags(
                i, goalDrags(keys.objects[i], rest[i], timing.keyTime(double(step) * sim.simulator(i).settings().dt), goals,
                             timing.period));
    };
}

}  // namespace

const char* clipSourceName(ClipSource source) {
    switch (source) {
    case ClipSource::Drivers: return "drivers";
    case ClipSource::Session: return "session";
    case ClipSource::Keyframes: return "keyframes";
    }
    return "drivers";
}

std::optional<ClipSource> parseClipSource(const std::string& name) {
    for (ClipSource s : {ClipSource::Drivers, ClipSource::Session, ClipSource::Keyframes}) {
        if (name == clipSourceName(s))
            return s;
    }
    return std::nullopt;
}

Status Clip::validate() const {
    const std::string where = "clip '" + name + "': ";
    if (name.empty())
        return Status::error("a clip needs a name");
    if (std::string p = firstProblem({{ranges::kClipStart, startSeconds}, {ranges::kFrames, double(frames)}, {ranges::kFps, fps}});
        !p.empty())
        return Status::error(where + p);
    if (blendFrames < 0 || blendFrames > frames)
        return Status::error(where + "blend window must be in [0, frames] (" + std::to_string(frames) + "), got " +
                             std::to_string(blendFrames));
    if (blendFrames > 0 && !loop)
        return Status::error(where + "a blend window closes a loop: set loop or remove the window");
    if (source == ClipSource::Drivers && !sourceName.empty())
        return Status::error(where + "a drivers clip names no source");
    if (source != ClipSource::Drivers && sourceName.empty())
        return Status::error(where + "a " + clipSourceName(source) + " clip needs the name of its " +
                             clipSourceName(source));
    if (goals && source != ClipSource::Keyframes)
        return Status::error(where + "goal springs apply to keyframe clips only");
    if (goals)
        if (std::string p = firstProblem({{kGoalStiffness, goals->stiffness}, {kGoalDamping, goals->damping}, {kGoalWeight, goals->weight}});
            !p.empty())
            return Status::error(where + p);
    return Status::success();
}

const Clip* ClipLibrary::findClip(const std::string& name) const {
    for (const Clip& c : clips)
        if (c.name == name) return &c;
    return nullptr;
}

const NamedSession* ClipLibrary::findSession(const std::string& name) const {
    for (const NamedSession& s : sessions)
        if (s.name == name) return &s;
    return nullptr;
}

const NamedKeyframes* ClipLibrary::findKeyframes(const std::string& name) const {
    for (const NamedKeyframes& k : keyframes)
        if (k.name == name) return &k;
    return nullptr;
}

Status ClipLibrary::validate(const Scene& scene) const {
    auto unique = [](const auto& items, const char* what) -> Status {
        std::set<std::string> seen;
        for (const auto& item : items) {
            if (item.name.empty())
                return Status::error(std::string("a ") + what + " needs a name");
            if (!seen.insert(item.name).second)
                return Status::error(std::string("two ") + what + "s are named '" + item.name + "'");
        }
        return Status::success();
    };
    if (Status s = unique(clips, "clip"); !s) return s;
    if (Status s = unique(sessions, "session"); !s) return s;
    if (Status s = unique(keyframes, "keyframe set"); !s) return s;
    if (!defaultClip.empty() && !findClip(defaultClip))
        return Status::error("the default clip '" + defaultClip + "' is not in the library");
    for (const NamedKeyframes& k : keyframes) {
        if (k.objects.size() != scene.objects.size())
            return Status::error("keyframe set '" + k.name + "' animates " + std::to_string(k.objects.size()) +
                                 " objects, the scene has " + std::to_string(scene.objects.size()));
        for (std::size_t i = 0; i < k.objects.size(); ++i) {
            const auto nodes = std::size_t(scene.objects[i].lattice.nodeCount());
            if (k.objects[i].nodeCount() != nodes)
                return Status::error("keyframe set '" + k.name + "', object '" + scene.objects[i].name + "': keys for " +
                                     std::to_string(k.objects[i].nodeCount()) + " nodes, the lattice has " +
                                     std::to_string(nodes));
        }
    }
    for (const Clip& c : clips) {
        if (Status s = c.validate(); !s)
            return s;
        if (c.source == ClipSource::Session && !findSession(c.sourceName))
            return Status::error("clip '" + c.name + "': no session named '" + c.sourceName + "'");
        if (c.source == ClipSource::Keyframes && !findKeyframes(c.sourceName))
            return Status::error("clip '" + c.name + "': no keyframe set named '" + c.sourceName + "'");
    }
    return Status::success();
}

ClipLibrary withObjectInserted(const ClipLibrary& library, std::size_t index, const std::vector<Vec3>& restNodes) {
    ClipLibrary out = library;
    for (NamedSession& named : out.sessions) {
        Session& s = named.session;
        BodyState rest;
        rest.position = restNodes;
        rest.velocity.assign(restNodes.size(), Vec3::Zero());
        s.start.bodies.insert(s.start.bodies.begin() + std::ptrdiff_t(std::min(index, s.start.bodies.size())), std::move(rest));
        if (!s.startDrags.empty())
            s.startDrags.insert(s.startDrags.begin() + std::ptrdiff_t(std::min(index, s.startDrags.size())), std::vector<DragSpring>{});
        for (DragEvent& e : s.events)
            if (e.object >= index)
                ++e.object;
    }
    for (NamedKeyframes& k : out.keyframes)
        k.objects.insert(k.objects.begin() + std::ptrdiff_t(std::min(index, k.objects.size())), KeyframeAnimation(restNodes.size()));
    return out;
}

ClipLibrary withObjectRemoved(const ClipLibrary& library, std::size_t index) {
    ClipLibrary out = library;
    for (NamedSession& named : out.sessions) {
        Session& s = named.session;
        if (index < s.start.bodies.size())
            s.start.bodies.erase(s.start.bodies.begin() + std::ptrdiff_t(index));
        if (index < s.startDrags.size())
            s.startDrags.erase(s.startDrags.begin() + std::ptrdiff_t(index));
        std::erase_if(s.events, [index](const DragEvent& e) { return e.object == index; });
        for (DragEvent& e : s.events)
            if (e.object > index)
                --e.object;
    }
    for (NamedKeyframes& k : out.keyframes)
        if (index < k.objects.size())
            k.objects.erase(k.objects.begin() + std::ptrdiff_t(index));
    return out;
}

void closeLoop(std::vector<std::vector<Vec3>>& frames, const std::vector<std::vector<Vec3>>& preroll, int window) {
    if (frames.size() < 2)
        return;
    const int n = int(frames.size()) - 1;
    window = std::clamp(window, 0, n);
    const std::vector<Vec3> drift = [&] {
        std::vector<Vec3> d(frames[0].size());
        for (std::size_t p = 0; p < d.size(); ++p)
            d[p] = frames[std::size_t(n)][p] - frames[0][p];
        return d;
    }();
    const bool crossfade = window > 0 && int(preroll.size()) == window + 1;
    for (int i = n - window; i < n && window > 0; ++i) {
        const double s = smoothstep(double(i - (n - window)) / double(window));
        std::vector<Vec3>& f = frames[std::size_t(i)];
        if (crossfade) {
            const std::vector<Vec3>& g = preroll[std::size_t(i - (n - window))];
            for (std::size_t p = 0; p < f.size(); ++p)
                f[p] = (1.0 - s) * f[p] + s * g[p];
        } else {
            for (std::size_t p = 0; p < f.size(); ++p)
                f[p] -= s * drift[p];
        }
    }
    frames.pop_back();
}

SeamMeasure measureSeam(const std::vector<std::vector<Vec3>>& frames) {
    SeamMeasure m;
    if (frames.size() < 3)
        return m;
    std::vector<double> steps;
    for (std::size_t f = 0; f + 1 < frames.size(); ++f)
        steps.push_back(rmsMotion(frames[f], frames[f + 1]));
    std::nth_element(steps.begin(), steps.begin() + std::ptrdiff_t(steps.size() / 2), steps.end());
    m.medianStep = steps[steps.size() / 2];
    m.jump = rmsMotion(frames.back(), frames.front());
    m.ratio = m.medianStep > 0.0 ? m.jump / m.medianStep : 0.0;
    const double beside = 0.5 * (rmsMotion(frames[frames.size() - 2], frames.back()) + rmsMotion(frames[0], frames[1]));
    m.localRatio = beside > 0.0 ? m.jump / beside : 0.0;
    return m;
}

SeamMeasure measureSeam(const NodeFrames& frames) {
    std::vector<std::vector<Vec3>> flat;
    for (const auto& frame : frames.nodes) {
        std::vector<Vec3> f;
        for (const auto& object : frame)
            f.insert(f.end(), object.begin(), object.end());
        flat.push_back(std::move(f));
    }
    return measureSeam(flat);
}

Result<NodeFrames> evaluateClip(const Scene& scene, const ClipLibrary& library, const Clip& clip,
                                std::vector<std::string>* problems, int firstFrames,
                                const std::function<bool(double)>& keepGoing) {
    if (Status s = clip.validate(); !s)
        return s;
    auto created = SceneSimulation::create(scene);
    if (!created)
        return Status::error(created.message());
    SceneSimulation& sim = created.value();
    const std::string where = "clip '" + clip.name + "': ";

    // Frames j = -pre .. last, at source time start + j/fps: pre-roll (j < 0), the clip (0..N-1), and
    // frame N, one period on, when a loop is closed.
    const bool close = clip.loop && clip.blendFrames > 0;
    const int n = !close && firstFrames > 0 ? std::min(firstFrames, clip.frames) : clip.frames;
    const int last = close ? n : n - 1;
    int pre = close && clip.startSeconds - double(clip.blendFrames) / clip.fps >= -1e-9 ? clip.blendFrames : 0;
    auto timeOf = [&](int j) { return std::max(0.0, clip.startSeconds + double(j) / clip.fps); };
    // The work before frame j: the simulation up to frame j - 1's time (0 before the first), and a frame's time for
    // each frame sampled. Strictly rising, and the settling before `start` counts as the time it takes.
    const double total = timeOf(last) + double(last + pre + 1) / clip.fps;
    auto stopped = [&](int j) {
        const double done = (j == -pre ? 0.0 : timeOf(j - 1)) + double(j + pre) / clip.fps;
        return keepGoing && !keepGoing(done / total);
    };

    std::vector<std::vector<Vec3>> rest;
    for (std::size_t i = 0; i < sim.objectCount(); ++i)
        rest.push_back(sim.simulator(i).model().restPositions);

    std::vector<std::vector<Vec3>> samples;  // flat, j = -pre .. last
    switch (clip.source) {
    case ClipSource::Drivers:
        for (int j = -pre; j <= last; ++j) {
            if (stopped(j))
                return Status::cancelled(where + "cancelled");
            sim.advanceToSample(timeOf(j), problems);
            samples.push_back(sampleNodes(sim, timeOf(j)));
        }
        break;
    case ClipSource::Session: {
        const NamedSession* named = library.findSession(clip.sourceName);
        if (!named)
            return Status::error(where + "no session named '" + clip.sourceName + "'");
        const Session& session = named->session;
        const double length = session.endSeconds() - session.startSeconds();
        if (timeOf(last) > length + 1e-9)
            return Status::error(where + "runs to " + std::to_string(timeOf(last)) + " s but session '" + named->name +
                                 "' is " + std::to_string(length) + " s long");
        SessionPlayer player;
        if (Status s = player.start(sim, session); !s)
            return Status::error(where + "session '" + named->name + "': " + s.message());
        for (int j = -pre; j <= last; ++j) {
            if (stopped(j))
                return Status::cancelled(where + "cancelled");
            sim.advanceToSample(session.startSeconds() + timeOf(j), problems, player.inputs());
            samples.push_back(sampleNodes(sim, session.startSeconds() + timeOf(j)));
        }
        break;
    }
    case ClipSource::Keyframes: {
        const NamedKeyframes* keys = library.findKeyframes(clip.sourceName);
        if (!keys)
            return Status::error(where + "no keyframe set named '" + clip.sourceName + "'");
        if (keys->objects.size() != sim.objectCount())
            return Status::error(where + "keyframe set '" + keys->name + "' does not match the scene's objects");
        for (std::size_t i = 0; i < sim.objectCount(); ++i) {
            if (keys->objects[i].nodeCount() != rest[i].size())
                return Status::error(where + "keyframe set '" + keys->name + "' does not fit object '" +
                                     sim.object(i).name + "' (" + std::to_string(keys->objects[i].nodeCount()) +
                                     " nodes, lattice " + std::to_string(rest[i].size()) + ")");
        }
        const KeyTiming timing(clip, *keys);
        if (close)
            pre = clip.blendFrames;  // a loop's pass before, or the goals' lead-in, is its pre-roll
        for (int j = -pre; j <= last; ++j) {
            if (stopped(j))
                return Status::cancelled(where + "cancelled");
            if (clip.goals) {
                const double at = timing.simulated(j, clip.fps);
                sim.advanceToSample(at, problems, goalInputs(*keys, *clip.goals, rest, timing));
                samples.push_back(sampleNodes(sim, at));
                continue;
            }
            std::vector<Vec3> flat;
            for (std::size_t i = 0; i < sim.objectCount(); ++i) {
                // A loop plays its keys round and round (the pre-roll is the end of the pass before).
                const double t = clip.loop ? timing.fromStart(double(j) / clip.fps) : timeOf(j);
                const std::vector<Vec3> p = keys->objects[i].pose(t, rest[i], timing.period);
                flat.insert(flat.end(), p.begin(), p.end());
            }
            samples.push_back(std::move(flat));
        }
        break;
    }
    }
    if (!sim.refusal().empty())
        return Status::error(where + sim.refusal());
    for (const auto& s : samples) {
        for (const Vec3& p : s) {
            if (!isFinite(p))
                return Status::error(where + "the simulation produced non-finite node positions");
        }
    }

    std::vector<std::vector<Vec3>> preroll(samples.begin(), samples.begin() + pre);
    std::vector<std::vector<Vec3>> frames(samples.begin() + pre, samples.end());
    if (close) {
        if (pre > 0)
            preroll.push_back(frames.front());  // G_N = F_0
        closeLoop(frames, preroll, clip.blendFrames);
    }

    NodeFrames out;
    out.fps = clip.fps;
    out.loop = clip.loop;
    for (const auto& flat : frames) {
        std::vector<std::vector<Vec3>> perObject;
        std::size_t offset = 0;
        for (const auto& r : rest) {
            perObject.emplace_back(flat.begin() + std::ptrdiff_t(offset), flat.begin() + std::ptrdiff_t(offset + r.size()));
            offset += r.size();
        }
        out.nodes.push_back(std::move(perObject));
    }
    return out;
}

}  // namespace softtouch

// Version 2 of the project file: the clip library (clips, sessions, keyframe sets), each reader beside
// its writer (io/documents/clip_library_json.h).
#include "io/documents/clip_library_json.h"
#include "io/documents/document_json.h"

#include "core/base/ranges.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace softtouch::io::document {
using nlohmann::json;

namespace {

/// "%g": a step or a distance as a person writes it (0.00416667, 10000).
std::string shortNumber(double x) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", x);
    return text;
}

std::optional<DragSpring> readDrag(const JsonValue& v, std::size_t nodes) {
    if (!v.expectObject(true))
        return std::nullopt;
    v.checkKeys({"support", "target", "targetVelocity", "stiffness", "damping"});
    DragSpring d;
    const JsonValue support = v["support"];
    if (!support.isArray() || support.size() == 0) {
        support.problem("expected a non-empty array of [node, weight] pairs");
        return std::nullopt;
    }
    for (std::size_t i = 0; i < support.size(); ++i) {
        const JsonValue pair = support.at(i);
        if (pair.size() != 2) {
            pair.problem("expected [node, weight]");
            return std::nullopt;
        }
        const auto node = pair.at(0).integer(0, int(nodes) - 1, true);
        const auto weight = pair.at(1).number(-1e3, 1e3, "", true);
        if (!node || !weight)
            return std::nullopt;
        d.support.push_back(NodeWeight{std::uint32_t(*node), *weight});
    }
    const auto target = v["target"].vec3(true);
    if (!target)
        return std::nullopt;
    d.target = *target;
    if (auto x = v["targetVelocity"].vec3()) d.targetVelocity = *x;
    if (auto x = v["stiffness"].number(0.0, 1e9, "N/m")) d.stiffness = *x;
    if (auto x = v["damping"].number(0.0, 1e6, "N·s/m")) d.damping = *x;
    return d;
}

json dragJson(const DragSpring& d) {
    json support = json::array();
    for (const NodeWeight& w : d.support)
        support.push_back(json::array({w.node, w.weight}));
    return {{"support", support}, {"target", vec(d.target)}, {"targetVelocity", vec(d.targetVelocity)},
            {"stiffness", d.stiffness}, {"damping", d.damping}};
}

std::optional<std::vector<DragSpring>> readDrags(const JsonValue& v, std::size_t nodes) {
    if (!v.isArray()) {
        v.problem("expected an array of drag springs");
        return std::nullopt;
    }
    std::vector<DragSpring> drags;
    for (std::size_t i = 0; i < v.size(); ++i) {
        auto d = readDrag(v.at(i), nodes);
        if (!d)
            return std::nullopt;
        drags.push_back(std::move(*d));
    }
    return drags;
}

json dragsJson(const std::vector<DragSpring>& drags) {
    json out = json::array();
    for (const DragSpring& d : drags)
        out.push_back(dragJson(d));
    return out;
}

/// Flat [x,y,z, x,y,z, …] of `count` points.
bool readPoints(const JsonValue& v, std::size_t count, std::vector<Vec3>& out) {
    if (!v.isArray() || v.size() != 3 * count) {
        v.problem("expected " + std::to_string(3 * count) + " numbers (x, y, z of each of " + std::to_string(count) +
                  " lattice nodes)");
        return false;
    }
    out.assign(count, Vec3::Zero());
    for (std::size_t i = 0; i < 3 * count; ++i) {
        const auto x = v.at(i).number(-1e12, 1e12, "", true);
        if (!x)
            return false;
        out[i / 3][Eigen::Index(i % 3)] = *x;
    }
    return true;
}

json pointsJson(const std::vector<Vec3>& points) {
    json out = json::array();
    for (const Vec3& p : points) {
        out.push_back(p.x());
        out.push_back(p.y());
        out.push_back(p.z());
    }
    return out;
}

std::optional<NamedSession> readSession(const JsonValue& v, const Scene& scene) {
    if (!v.expectObject(true))
        return std::nullopt;
    v.checkKeys({"name", "dt", "start", "end", "startDrags", "events"});
    NamedSession named;
    named.name = v["name"].string(true).value_or("");
    Session& s = named.session;
    const auto dt = v["dt"].number(ranges::kMinDt, ranges::kMaxDt, "s", true);
    if (!dt)
        return std::nullopt;
    // A take replays step for step: only at the step it was recorded with (Session::validateFor, which a
    // bake runs; checked here so that validate says it first).
    if (*dt != scene.world.simulation.dt) {
        v["dt"].problem("the take was recorded with a step of " + shortNumber(*dt) + " s and the scene steps " +
                        shortNumber(scene.world.simulation.dt) + " s; a take replays only at its own step (set the scene's "
                        "simulation.dt back, or record the take again)");
        return std::nullopt;
    }
    s.dt = *dt;
    const JsonValue start = v["start"];
    if (!start.expectObject(true))
        return std::nullopt;
    start.checkKeys({"step", "bodies"});
    const auto step = start["step"].integer(0, 2000000000, true);
    const JsonValue bodies = start["bodies"];
    if (!step)
        return std::nullopt;
    s.start.step = *step;
    if (bodies.size() != scene.objects.size()) {
        bodies.problem("expected one body state per object (" + std::to_string(scene.objects.size()) + ")");
        return std::nullopt;
    }
    std::vector<std::size_t> nodes;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        const JsonValue b = bodies.at(i);
        if (!b.expectObject(true))
            return std::nullopt;
        b.checkKeys({"position", "velocity"});
        nodes.push_back(std::size_t(scene.objects[i].lattice.nodeCount()));
        BodyState state;
        if (!readPoints(b["position"], nodes.back(), state.position) ||
            !readPoints(b["velocity"], nodes.back(), state.velocity))
            return std::nullopt;
        s.start.bodies.push_back(std::move(state));
    }
    const auto end = v["end"].integer(0, 2000000000, true);
    if (!end)
        return std::nullopt;
    s.endStep = *end;
    if (const JsonValue drags = v["startDrags"]; drags.exists()) {
        if (drags.size() != nodes.size()) {
            drags.problem("expected one list of drags per object (" + std::to_string(nodes.size()) + ")");
            return std::nullopt;
        }
        for (std::size_t i = 0; i < nodes.size(); ++i) {
            auto d = readDrags(drags.at(i), nodes[i]);
            if (!d)
                return std::nullopt;
            s.startDrags.push_back(std::move(*d));
        }
    }
    const JsonValue events = v["events"];
    if (events.exists() && !events.isArray())
        events.problem("expected an array of events");
    for (std::size_t e = 0; e < events.size(); ++e) {
        const JsonValue ev = events.at(e);
        if (!ev.expectObject(true))
            return std::nullopt;
        ev.checkKeys({"step", "object", "drags"});
        const auto at = ev["step"].integer(0, 2000000000, true);
        const auto object = ev["object"].integer(0, int(nodes.size()) - 1, true);
        if (!at || !object)
            return std::nullopt;
        auto d = readDrags(ev["drags"], nodes[std::size_t(*object)]);
        if (!d)
            return std::nullopt;
        s.events.push_back(DragEvent{*at, std::uint32_t(*object), std::move(*d)});
    }
    // Order and ranges: the same checks a replay makes.
    long long last = s.start.step;
    for (std::size_t e = 0; e < s.events.size(); ++e) {
        if (s.events[e].step < last || s.events[e].step > s.endStep) {
            events.at(e)["step"].problem("event steps must not decrease and must lie in [start.step, end]");
            return std::nullopt;
        }
        last = s.events[e].step;
    }
    if (s.endStep < s.start.step)
        v["end"].problem("the session ends before it starts (start.step " + std::to_string(s.start.step) + ")");
    return named;
}

std::optional<NamedKeyframes> readKeyframes(const JsonValue& v, const Scene& scene) {
    if (!v.expectObject(true))
        return std::nullopt;
    v.checkKeys({"name", "objects"});
    NamedKeyframes named;
    named.name = v["name"].string(true).value_or("");
    const JsonValue objects = v["objects"];
    if (objects.size() != scene.objects.size()) {
        objects.problem("expected one entry per object (" + std::to_string(scene.objects.size()) + ")");
        return std::nullopt;
    }
    for (std::size_t i = 0; i < objects.size(); ++i) {
        const JsonValue o = objects.at(i);
        if (!o.expectObject(true))
            return std::nullopt;
        o.checkKeys({"keys"});
        const int nodes = scene.objects[i].lattice.nodeCount();
        KeyframeAnimation anim{std::size_t(nodes)};
        const JsonValue keys = o["keys"];
        if (keys.exists() && !keys.isArray())
            keys.problem("expected an array of keys");
        for (std::size_t k = 0; k < keys.size(); ++k) {
            const JsonValue key = keys.at(k);
            if (!key.expectObject(true))
                return std::nullopt;
            key.checkKeys({"time", "nodes", "displacement", "interpolation"});
            LatticeKey lk;
            const auto t = key["time"].number(-1e6, 1e6, "s", true);
            if (!t)
                return std::nullopt;
            lk.seconds = *t;
            if (const JsonValue how = key["interpolation"]; how.exists()) {
                const auto name = how.string(true);
                const auto interpolation = name ? keyInterpolationNamed(*name) : std::nullopt;
                if (!interpolation) {
                    how.problem("expected \"smooth\", \"linear\" or \"constant\"");
                    return std::nullopt;
                }
                lk.interpolation = *interpolation;
            }
            const JsonValue ns = key["nodes"], ds = key["displacement"];
            if (!ns.isArray() || !ds.isArray() || ns.size() != ds.size()) {
                key.problem("expected \"nodes\" (node indices, i fastest) and \"displacement\" ([x,y,z] per node) of equal length");
                return std::nullopt;
            }
            for (std::size_t n = 0; n < ns.size(); ++n) {
                const auto node = ns.at(n).integer(0, nodes - 1, true);
                const auto d = ds.at(n).vec3(true);
                if (!node || !d)
                    return std::nullopt;
                if (d->cwiseAbs().maxCoeff() > ranges::kMaxDragOffset) {
                    ds.at(n).problem("a key moves a node at most " + shortNumber(ranges::kMaxDragOffset) +
                                     " m from rest in any direction");
                    return std::nullopt;
                }
                lk.nodes.push_back(std::uint32_t(*node));
                lk.displacement.push_back(*d);
            }
            if (anim.keyAt(lk.seconds) >= 0) {
                key["time"].problem("two keys at the same time");
                return std::nullopt;
            }
            if (auto r = anim.insertKey(std::move(lk)); !r) {
                key.problem(r.message());
                return std::nullopt;
            }
        }
        named.objects.push_back(std::move(anim));
    }
    return named;
}

}  // namespace

std::optional<Clip> readClip(const JsonValue& v) {
    if (!v.expectObject(true))
        return std::nullopt;
    v.checkKeys({"name", "source", "of", "start", "frames", "fps", "loop", "blend", "goals"});
    Clip c;
    c.name = v["name"].string(true).value_or("");
    if (auto src = v["source"].string()) {
        if (auto parsed = parseClipSource(*src))
            c.source = *parsed;
        else
            v["source"].problem("expected \"drivers\", \"session\" or \"keyframes\", got \"" + *src + "\"");
    }
    if (auto x = v["of"].string()) c.sourceName = *x;
    if (auto x = v.field(ranges::kClipStart)) c.startSeconds = *x;
    if (auto x = v.field(ranges::kFrames)) c.frames = int(*x);
    if (auto x = v.field(ranges::kFps)) c.fps = *x;
    if (auto x = v["loop"].boolean()) c.loop = *x;
    if (auto x = v["blend"].integer(0, 1000000)) c.blendFrames = *x;
    if (const JsonValue g = v["goals"]; g.expectObject()) {
        g.checkKeys({"stiffness", "damping", "weight"});
        GoalSettings goals;
        if (auto x = g.field(kGoalStiffness)) goals.stiffness = *x;
        if (auto x = g.field(kGoalDamping)) goals.damping = *x;
        if (auto x = g.field(kGoalWeight)) goals.weight = *x;
        c.goals = goals;
    }
    if (Status s = c.validate(); !s) {
        v.problem(s.message());
        return std::nullopt;
    }
    return c;
}

json clipJson(const Clip& c) {
    json out = {{"name", c.name}, {"source", clipSourceName(c.source)}, {"start", c.startSeconds},
                {"frames", c.frames}, {"fps", c.fps}, {"loop", c.loop}, {"blend", c.blendFrames}};
    if (!c.sourceName.empty())
        out["of"] = c.sourceName;
    if (c.goals)
        out["goals"] = {{"stiffness", c.goals->stiffness}, {"damping", c.goals->damping}, {"weight", c.goals->weight}};
    return out;
}

void readClipLibrary(const JsonValue& root, int version, Project& project) {
    if (version < 2) {
        for (const char* key : {"clips", "sessions", "keyframes"}) {
            if (root[key].exists())
                root[key].problem("clips, sessions and keyframes need project version 2");
        }
        return;
    }
    ClipLibrary& lib = project.clips;
    if (const JsonValue sessions = root["sessions"]; sessions.exists()) {
        if (!sessions.isArray())
            sessions.problem("expected an array of sessions");
        for (std::size_t i = 0; i < sessions.size(); ++i) {
            if (auto s = readSession(sessions.at(i), project.scene))
                lib.sessions.push_back(std::move(*s));
        }
    }
    if (const JsonValue keyframes = root["keyframes"]; keyframes.exists()) {
        if (!keyframes.isArray())
            keyframes.problem("expected an array of keyframe sets");
        for (std::size_t i = 0; i < keyframes.size(); ++i) {
            if (auto k = readKeyframes(keyframes.at(i), project.scene))
                lib.keyframes.push_back(std::move(*k));
        }
    }
    if (const JsonValue clips = root["clips"]; clips.expectObject()) {
        clips.checkKeys({"default", "library"});
        const JsonValue list = clips["library"];
        if (list.exists() && !list.isArray())
            list.problem("expected an array of clips");
        for (std::size_t i = 0; i < list.size(); ++i) {
            if (auto c = readClip(list.at(i)))
                lib.clips.push_back(std::move(*c));
        }
        if (auto d = clips["default"].string()) lib.defaultClip = *d;
    }
    if (Status s = lib.validate(project.scene); !s)
        root["clips"].problem(s.message());
}

/// The clip library as its three top-level members (nlohmann writes doubles with 17 significant
/// digits, so session states read back bit for bit and replays stay exact).
void writeClipLibrary(const ClipLibrary& lib, json& doc) {
    if (!lib.sessions.empty()) {
        json sessions = json::array();
        for (const NamedSession& named : lib.sessions) {
            const Session& s = named.session;
            json bodies = json::array();
            for (const BodyState& b : s.start.bodies)
                bodies.push_back({{"position", pointsJson(b.position)}, {"velocity", pointsJson(b.velocity)}});
            json startDrags = json::array();
            for (const auto& drags : s.startDrags)
                startDrags.push_back(dragsJson(drags));
            json events = json::array();
            for (const DragEvent& e : s.events)
                events.push_back({{"step", e.step}, {"object", e.object}, {"drags", dragsJson(e.drags)}});
            json out = {{"name", named.name}, {"dt", s.dt}, {"start", {{"step", s.start.step}, {"bodies", bodies}}},
                        {"end", s.endStep}, {"events", events}};
            if (!s.startDrags.empty())
                out["startDrags"] = startDrags;
            sessions.push_back(out);
        }
        doc["sessions"] = sessions;
    }
    if (!lib.keyframes.empty()) {
        json sets = json::array();
        for (const NamedKeyframes& named : lib.keyframes) {
            json objects = json::array();
            for (const KeyframeAnimation& anim : named.objects) {
                json keys = json::array();
                for (const LatticeKey& k : anim.keys()) {
                    json displacement = json::array();
                    for (const Vec3& d : k.displacement)
                        displacement.push_back(vec(d));
                    json key = {{"time", k.seconds}, {"nodes", k.nodes}, {"displacement", displacement}};
                    if (k.interpolation != KeyInterpolation::Smooth)  // smooth is what a key without it means
                        key["interpolation"] = keyInterpolationName(k.interpolation);
                    keys.push_back(std::move(key));
                }
                objects.push_back({{"keys", keys}});
            }
            sets.push_back({{"name", named.name}, {"objects", objects}});
        }
        doc["keyframes"] = sets;
    }
    if (!lib.clips.empty() || !lib.defaultClip.empty()) {
        json list = json::array();
        for (const Clip& c : lib.clips)
            list.push_back(clipJson(c));
        json clips = {{"library", list}};
        if (!lib.defaultClip.empty())
            clips["default"] = lib.defaultClip;
        doc["clips"] = clips;
    }
}

}  // namespace softtouch::io::document

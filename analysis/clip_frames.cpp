#include "analysis/clip_frames.h"

#include "analysis/trajectory_error.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace softtouch::analysis {

Result<Clip> clipToPlay(const Scene& scene, const ClipLibrary& library, const std::string& name) {
    const std::string wanted = name.empty() ? library.defaultClip : name;
    if (wanted.empty()) {
        Clip drivers;
        drivers.name = "drivers";
        drivers.frames = scene.world.frames;
        drivers.fps = scene.world.fps;
        return drivers;
    }
    if (const Clip* clip = library.findClip(wanted))
        return *clip;
    std::string known;
    for (const Clip& c : library.clips)
        known += (known.empty() ? "" : ", ") + c.name;
    return Status::error("no clip named '" + wanted + "' (the project has: " + (known.empty() ? "none" : known) + ")");
}

std::span<const Vec3f> ClipMeshFrames::frame(std::size_t object, int f) const {
    const std::vector<Vec3f>& all = positions[object];
    const std::size_t vertices = frames > 0 ? all.size() / std::size_t(frames) : 0;
    return {all.data() + std::size_t(f) * vertices, vertices};
}

namespace {

/// Every object's mesh on node positions `nodesOf(object, frame)` at each frame's time, the clip's start
/// + f / fps, as FrameSource plays it (a base animation's time). `sim` only places meshes: it steps nothing.
template <typename NodesOf>
void placeMeshes(const SceneSimulation& sim, const Scene& scene, const Clip& clip, NodesOf&& nodesOf, ClipMeshFrames& out) {
    out.positions.resize(scene.objects.size());
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        const std::size_t vertices = scene.objects[i].mesh->positions.size();
        out.positions[i].resize(std::size_t(out.frames) * vertices);
        for (int f = 0; f < out.frames; ++f) {
            const std::span<Vec3f> positions(out.positions[i].data() + std::size_t(f) * vertices, vertices);
            sim.evaluateNodes(i, nodesOf(i, f), clip.startSeconds + double(f) / clip.fps, positions, {}, 1);
        }
    }
}

}  // namespace

Result<ClipMeshFrames> clipMeshFrames(const Scene& scene, const ClipLibrary& library, const Clip& clip,
                                      const std::function<bool(double)>& keepGoing) {
    ClipMeshFrames out;
    auto nodes = evaluateClip(scene, library, clip, &out.problems, 0, keepGoing);
    if (!nodes)
        return nodes.status();
    auto sim = SceneSimulation::create(scene);
    if (!sim)
        return Status::error(sim.message());
    out.frames = int(nodes->nodes.size());
    placeMeshes(sim.value(), scene, clip,
                [&](std::size_t i, int f) -> std::span<const Vec3> { return nodes->nodes[std::size_t(f)][i]; }, out);
    return out;
}

Result<ClipMeshFrames> restFrames(const Scene& scene, const Clip& clip) {
    auto sim = SceneSimulation::create(scene);
    if (!sim)
        return Status::error(sim.message());
    ClipMeshFrames out;
    out.frames = clip.frames;
    // The body at rest: on a base animation, the animation alone.
    placeMeshes(sim.value(), scene, clip,
                [&](std::size_t i, int) -> std::span<const Vec3> { return sim->simulator(i).model().restPositions; }, out);
    return out;
}

std::vector<double> meshDiagonals(const Scene& scene) {
    std::vector<double> out;
    for (const SceneObject& object : scene.objects) {
        std::vector<Vec3> points;
        points.reserve(object.mesh->positions.size());
        for (const Vec3f& p : object.mesh->positions)
            points.push_back(p.cast<double>());
        out.push_back(boundsOf(points).diagonal());
    }
    return out;
}

std::vector<double> objectDistances(const ClipMeshFrames& a, const ClipMeshFrames& b, const std::vector<double>& diagonals) {
    std::vector<double> out;
    for (std::size_t i = 0; i < diagonals.size(); ++i) {
        const bool comparable = i < a.positions.size() && i < b.positions.size() &&
                                a.positions[i].size() == b.positions[i].size() && !a.positions[i].empty() && diagonals[i] > 0.0;
        out.push_back(comparable ? trajectoryDistance(a.positions[i], b.positions[i], diagonals[i]).rms
                                 : std::numeric_limits<double>::quiet_NaN());
    }
    return out;
}

double worstDistance(const std::vector<double>& distances) {
    double worst = 0.0;
    for (double d : distances) {
        if (!std::isfinite(d))
            return std::numeric_limits<double>::quiet_NaN();
        worst = std::max(worst, d);
    }
    return worst;
}

}  // namespace softtouch::analysis

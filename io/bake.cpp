#include "io/bake.h"

#include <cmath>

namespace softtouch::io {

std::filesystem::path restMeshPath(const std::filesystem::path& cache, CacheFormat format) {
    if (format == CacheFormat::ObjSequence)
        return cache;
    std::filesystem::path rest = cache;
    return rest.replace_extension(".obj");
}

Result<FrameTiming> resolveFrameTiming(const Scene& scene, int frames, double fps) {
    FrameTiming timing;
    timing.frames = frames > 0 ? frames : scene.world.frames;
    timing.fps = fps > 0.0 ? fps : scene.world.fps;
    if (!(std::isfinite(timing.fps) && timing.fps > 0.0 && timing.fps <= 1000.0))
        return Status::error("fps must be in (0, 1000], got " + std::to_string(timing.fps));
    if (timing.frames < 1)
        return Status::error("the frame count must be at least 1, got " + std::to_string(timing.frames));
    return timing;
}

Status simulateFrames(SceneSimulation& simulation, const FrameTiming& timing, std::vector<std::string>* warnings,
                      const std::function<Status(int frame)>& onFrame) {
    for (int f = 0; f < timing.frames; ++f) {
        simulation.advanceTo(double(f) / timing.fps, warnings);
        if (Status s = onFrame(f); !s)
            return s;
    }
    return Status::success();
}

Result<BakeResult> bake(const Scene& scene, const BakeOptions& options) {
    auto simulation = SceneSimulation::create(scene);
    if (!simulation)
        return Status::error(simulation.message());
    SceneSimulation& sim = simulation.value();

    // A clip: its node frames are evaluated first (frames x nodes, small), the mesh streamed after.
    const Clip* clip = nullptr;
    if (options.clips) {
        const std::string name = options.clip.empty() ? options.clips->defaultClip : options.clip;
        if (!name.empty()) {
            clip = options.clips->findClip(name);
            if (!clip) {
                std::string known;
                for (const Clip& c : options.clips->clips)
                    known += (known.empty() ? "" : ", ") + c.name;
                return Status::error("no clip named '" + name + "' (the scene has: " + (known.empty() ? "none" : known) + ")");
            }
        }
    } else if (!options.clip.empty()) {
        return Status::error("no clip named '" + options.clip + "' (the scene has no clip library)");
    }
    BakeResult result;
    NodeFrames clipFrames;
    std::vector<Binding> bindings;
    if (clip) {
        if (options.fps > 0.0 && std::abs(options.fps - clip->fps) > 1e-9)
            return Status::error("clip '" + clip->name + "' plays at " + std::to_string(clip->fps) +
                                 " fps; bake it without --fps or change the clip");
        auto evaluated = evaluateClip(scene, *options.clips, *clip, &result.warnings);
        if (!evaluated)
            return Status::error(evaluated.message());
        clipFrames = std::move(evaluated.value());
        if (clip->loop && clipFrames.nodes.size() >= 3)
            result.seam = measureSeam(clipFrames);
        for (std::size_t i = 0; i < sim.objectCount(); ++i) {
            Mesh m = sim.object(i).mesh;
            if (m.normals.size() != m.positions.size())
                m.computeNormals();
            bindings.push_back(Binding::create(sim.object(i).lattice, m.positions, m.normals));
        }
        result.clip = clip->name;
    }
    const int clipLength = clip ? int(clipFrames.nodes.size()) : 0;
    const int frames = options.frames > 0 ? options.frames : clip ? clipLength : scene.world.frames;
    const double fps = clip ? clip->fps : options.fps > 0.0 ? options.fps : scene.world.fps;
    if (!(std::isfinite(fps) && fps > 0.0 && fps <= 1000.0))
        return Status::error("fps must be in (0, 1000], got " + std::to_string(fps));

    // The rest mesh of all objects, concatenated in scene order: the cache's vertex order.
    Mesh rest;
    for (std::size_t i = 0; i < sim.objectCount(); ++i) {
        const Mesh& m = sim.object(i).mesh;
        const auto base = std::uint32_t(rest.positions.size());
        rest.positions.insert(rest.positions.end(), m.positions.begin(), m.positions.end());
        if (!m.normals.empty())
            rest.normals.insert(rest.normals.end(), m.normals.begin(), m.normals.end());
        for (const auto& t : m.triangles)
            rest.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    }
    if (rest.normals.size() != rest.positions.size())
        rest.computeNormals();

    result.cache = options.format == CacheFormat::ObjSequence ? objSequenceFramePath(options.output, 0) : options.output;
    result.restMesh = restMeshPath(options.output, options.format);
    result.points = rest.positions.size();

    auto writer = makeCacheWriter(options.format, rest);
    CacheInfo info;
    info.pointCount = rest.positions.size();
    info.frameCount = std::size_t(frames);
    info.fps = fps;
    if (Status s = writer->begin(options.output, info); !s)
        return s;

    std::vector<Vec3f> frame(rest.positions.size());
    for (int f = 0; f < frames; ++f) {
        if (!clip)
            sim.advanceTo(double(f) / fps, &result.warnings);
        // Past a clip's end: a loop cycles, anything else holds its last frame.
        const int c = !clip ? 0 : clip->loop ? f % clipLength : std::min(f, clipLength - 1);
        std::size_t offset = 0;
        for (std::size_t i = 0; i < sim.objectCount(); ++i) {
            const std::size_t n = sim.object(i).mesh.positions.size();
            const std::span<Vec3f> out = std::span<Vec3f>(frame).subspan(offset, n);
            if (clip)
                bindings[i].evaluate(clipFrames.nodes[std::size_t(c)][i], out, {}, options.threads);
            else
                sim.evaluate(i, out, {}, options.threads);
            offset += n;
        }
        if (Status s = writer->writeFrame(frame); !s) {
            writer->abort();
            return s;
        }
        if (options.progress && !options.progress(f + 1, frames)) {
            writer->abort();
            return Status::error("the bake was cancelled; nothing was written");
        }
    }
    // The rest mesh first: a cache is never published without the mesh it matches.
    if (Status s = writeObj(result.restMesh, rest); !s) {
        writer->abort();
        return s;
    }
    if (Status s = writer->finish(); !s)
        return s;
    result.frames = frames;
    return result;
}

}  // namespace softtouch::io

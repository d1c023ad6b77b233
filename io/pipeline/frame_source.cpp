#include "io/pipeline/frame_source.h"

#include <algorithm>
#include <cmath>

namespace softtouch::io {

Result<FrameSource> FrameSource::create(const Scene& scene, const FrameRequest& request,
                                        std::vector<std::string>* warnings) {
    auto simulation = SceneSimulation::create(scene);
    if (!simulation)
        return Status::error(simulation.message());
    FrameSource source(std::move(simulation.value()));

    const Clip* clip = nullptr;
    if (request.clips) {
        const std::string name = request.clip.empty() ? request.clips->defaultClip : request.clip;
        if (!name.empty()) {
            clip = request.clips->findClip(name);
            if (!clip) {
                std::string known;
                for (const Clip& c : request.clips->clips)
                    known += (known.empty() ? "" : ", ") + c.name;
                return Status::error("no clip named '" + name + "' (the scene has: " + (known.empty() ? "none" : known) + ")");
            }
        }
    } else if (!request.clip.empty()) {
        return Status::error("no clip named '" + request.clip + "' (the scene has no clip library)");
    }

    if (clip) {
        if (request.fps > 0.0 && std::abs(request.fps - clip->fps) > 1e-9)
            return Status::error("clip '" + clip->name + "' plays at " + std::to_string(clip->fps) +
                                 " fps; leave the frame rate out or change the clip");
        // A bake of fewer frames than a clip has, not cycling it, costs those frames (bake --frames 12 of a
        // 100,000-frame clip took 40 s and 511 MB when the whole clip was evaluated first).
        const int wanted = request.frames > 0 && request.frames < clip->frames ? request.frames : 0;
        auto evaluated = evaluateClip(scene, *request.clips, *clip, warnings, wanted, request.clipProgress);
        if (!evaluated)
            return evaluated.status();
        source.m_clipFrames = std::move(evaluated.value());
        if (source.m_clipFrames.nodes.empty())
            return Status::error("clip '" + clip->name + "' has no frames");
        if (clip->loop && int(source.m_clipFrames.nodes.size()) == clip->frames && source.m_clipFrames.nodes.size() >= 3)
            source.m_seam = measureSeam(source.m_clipFrames);
        source.m_isClip = true;
        source.m_clipStart = clip->startSeconds;
        source.m_loop = clip->loop;
        source.m_clipName = clip->name;
        source.m_fps = clip->fps;
        source.m_frames = request.frames > 0 ? request.frames : int(source.m_clipFrames.nodes.size());
    } else {
        source.m_fps = request.fps > 0.0 ? request.fps : scene.world.fps;
        source.m_frames = request.frames > 0 ? request.frames : scene.world.frames;
    }
    if (!(std::isfinite(source.m_fps) && source.m_fps > 0.0 && source.m_fps <= 1000.0))
        return Status::error("fps must be in (0, 1000], got " + std::to_string(source.m_fps));
    if (source.m_frames < 1)
        return Status::error("the frame count must be at least 1, got " + std::to_string(source.m_frames));
    return source;
}

void FrameSource::seek(int frame, std::vector<std::string>* warnings) {
    if (!m_isClip) {
        // Frame f at exactly f/fps, between the two steps around it (SceneSimulation::nodesAt).
        m_current = frame;
        m_sim.advanceToSample(seconds(), warnings);
        m_frameNodes.resize(m_sim.objectCount());
        for (std::size_t i = 0; i < m_sim.objectCount(); ++i)
            m_frameNodes[i] = m_sim.nodesAt(i, seconds());
        return;
    }
    // Past a clip's end: a loop cycles, anything else holds its last frame.
    const int length = int(m_clipFrames.nodes.size());
    m_current = m_loop ? frame % length : std::min(frame, length - 1);
}

std::span<const Vec3> FrameSource::nodes(std::size_t object) const {
    if (m_isClip)
        return m_clipFrames.nodes[std::size_t(m_current)][object];
    if (m_frameNodes.empty())  // before the first seek: the rest state
        return m_sim.simulator(object).state().position;
    return m_frameNodes[object];
}

double FrameSource::secondsAt(int frame) const {
    if (!m_isClip)
        return double(frame) / m_fps;
    const int length = int(m_clipFrames.nodes.size());
    return m_clipStart + double(m_loop ? frame % length : std::min(frame, length - 1)) / m_fps;
}

void FrameSource::evaluate(std::size_t object, std::span<Vec3f> positions, std::span<Vec3f> normals, int threads) const {
    // Frame i is at its start + i/fps (what a base animation is played at).
    m_sim.evaluateNodes(object, nodes(object), seconds(), positions, normals, threads);
}

}  // namespace softtouch::io

#pragma once
/// The frames every frame-by-frame output plays (cache bake, clip exports, video render): a clip of
/// the project's library, or the scene's drivers simulated from rest. One place decides which, how
/// many frames at what rate, and what happens past a clip's end, so `bake` and `render` can never
/// disagree about what frame f shows.

#include "core/authoring/clip.h"
#include "core/geometry/binding.h"
#include "core/scene/scene.h"

#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace softtouch::io {

/// What to play.
struct FrameRequest {
    const ClipLibrary* clips = nullptr; ///< The project's clip library; nullptr: the drivers from frame 0.
    std::string clip;                   ///< Clip to play; empty: the library's default clip, or the drivers.
    int frames = 0;                     ///< Frames; 0 takes the clip's (or the scene's) length. Past a clip's
                                        ///< end a loop cycles and other clips hold their last frame.
    double fps = 0.0;                   ///< Frame rate; 0 takes the clip's (or the scene's). A clip refuses another.
    /// A clip is simulated whole by create(): asked with the fraction done before each of its frames; false
    /// cancels (create() then fails as cancelled). Empty: not asked.
    std::function<bool(double)> clipProgress;
};

/// A scene's frames, visited in increasing order.
class FrameSource {
public:
    /// Builds the simulation (and evaluates the clip, whose node frames are small). Errors name the
    /// clip or the setting at fault. Clip evaluation problems are appended to `warnings`.
    static Result<FrameSource> create(const Scene& scene, const FrameRequest& request,
                                      std::vector<std::string>* warnings = nullptr);

    int frameCount() const { return m_frames; }
    double fps() const { return m_fps; }
    /// The clip played; empty for the drivers.
    const std::string& clipName() const { return m_clipName; }
    /// Frames in one cycle of a loop clip; 0 for anything else.
    int loopLength() const { return m_loop ? int(m_clipFrames.nodes.size()) : 0; }
    /// For a loop clip, its seam measured on the lattice nodes.
    const std::optional<SeamMeasure>& seam() const { return m_seam; }
    /// Objects, meshes and lattices.
    const SceneSimulation& simulation() const { return m_sim; }

    /// Moves to frame f (0 <= f < frameCount(), never backwards for the drivers). Simulation problems
    /// are appended to `warnings`.
    void seek(int frame, std::vector<std::string>* warnings = nullptr);
    /// Lattice node positions of object i at the current frame.
    std::span<const Vec3> nodes(std::size_t object) const;
    /// Scene time of the current frame, seconds.
    double seconds() const { return secondsAt(m_current); }
    /// Scene time of frame `frame` (0 <= frame < frameCount()), seconds: past a loop clip's end it cycles,
    /// past another clip's it holds the last frame.
    double secondsAt(int frame) const;
    /// Deformed positions (and normals, when non-empty) of object i at the current frame.
    void evaluate(std::size_t object, std::span<Vec3f> positions, std::span<Vec3f> normals, int threads = 0) const;

private:
    explicit FrameSource(SceneSimulation sim) : m_sim(std::move(sim)) {}

    SceneSimulation m_sim;
    NodeFrames m_clipFrames;          ///< Empty for the drivers.
    double m_clipStart = 0.0;         ///< Scene time of the clip's first frame, seconds.
    bool m_isClip = false;
    bool m_loop = false;
    int m_current = 0;                ///< Frame shown.
    std::vector<std::vector<Vec3>> m_frameNodes; ///< The drivers' nodes at the current frame, per object.
    int m_frames = 0;
    double m_fps = 0.0;
    std::string m_clipName;
    std::optional<SeamMeasure> m_seam;
};

}  // namespace softtouch::io

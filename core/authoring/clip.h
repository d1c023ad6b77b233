#pragma once
/// Clips: named ranges of a scene's drivers, of a recorded session or of keyed animation, with a
/// frame rate and a loop flag, evaluated to lattice node positions per frame; and loop closure, which
/// makes the last frame of a cycle lead into the first without a pop.
///
/// Everything works on lattice nodes: the mesh is linear in the nodes (Bernstein / B-spline
/// weights), so a loop closed on the nodes is closed on the mesh, and a clip is cheap to hold in
/// memory (frames × nodes) while the mesh is streamed.
///
/// Loop closure (blend window W frames, clip of N frames at times t_i = start + i/fps):
///
///   frames:     G_{N-W} … G_N   (pre-roll: the motion just before the start, t = start + (i−N)/fps)
///               F_0 … F_{N-W} … F_{N-1}  F_N
///   F'_i = (1 − s) F_i + s G_i,  s = smoothstep((i − (N−W)) / W),  for i in [N−W, N)
///
/// At i = N the blend would reach G_N = F_0 exactly, so F'_{N-1} → F_0 is an ordinary frame step of
/// the pre-roll's motion: position and velocity carry across the seam. Where no pre-roll exists
/// (a clip starting at its source's first frame), the drift is spread instead:
/// F'_i = F_i − s (F_N − F_0).

#include "core/authoring/keyframes.h"
#include "core/authoring/session.h"
#include "core/scene/scene.h"

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace softtouch {

/// What a clip plays.
enum class ClipSource : std::uint8_t {
    Drivers,   ///< The scene's drivers, simulated from rest at time 0.
    Session,   ///< A recorded session (ClipLibrary::sessions), replayed.
    Keyframes, ///< A keyframe set (ClipLibrary::keyframes): played as keyed, or as goals when `goals` is set.
};

/// A named range of animation.
struct Clip {
    std::string name;                  ///< Unique in the library; shown in the timeline.
    ClipSource source = ClipSource::Drivers; ///< What is played.
    std::string sourceName;            ///< The session or keyframe set (empty for drivers).
    double startSeconds = 0.0;         ///< First frame, seconds from the source's start (scene time 0, the
                                       ///< session's first step, key time 0). [0, 1e6].
    int frames = 24;                   ///< Frame count, [1, 1e6].
    double fps = 24.0;                 ///< Frames per second, (0, 1000].
    bool loop = false;                 ///< Plays as a cycle: frame `frames` is frame 0 again.
    int blendFrames = 0;               ///< Loop closure window W, frames, [0, frames]; 0: no closure.
    std::optional<GoalSettings> goals; ///< Keyframes only: simulate with goal springs instead of playing keys.

    /// Duration, seconds (frames / fps).
    double seconds() const { return double(frames) / fps; }
    /// Checks ranges; the message names the field.
    Status validate() const;
};

/// A recorded session with the name clips refer to it by.
struct NamedSession {
    std::string name;  ///< Unique among sessions.
    Session session;   ///< The recording.
};

/// A keyframe set: one animation per scene object (an empty animation leaves its object to physics).
struct NamedKeyframes {
    std::string name;                          ///< Unique among keyframe sets.
    std::vector<KeyframeAnimation> objects;    ///< Per scene object, in scene order.
};

/// The clips of a project and what they play.
struct ClipLibrary {
    std::vector<Clip> clips;               ///< In the order shown.
    std::string defaultClip;               ///< Baked when no clip is named; empty: the drivers from frame 0.
    std::vector<NamedSession> sessions;    ///< Recorded sessions.
    std::vector<NamedKeyframes> keyframes; ///< Keyframe sets.

    /// The clip, session or keyframe set of that name, or nullptr.
    const Clip* findClip(const std::string& name) const;
    const NamedSession* findSession(const std::string& name) const;
    const NamedKeyframes* findKeyframes(const std::string& name) const;
    /// Checks names (unique, non-empty), each clip and its source (exists, fits the scene).
    Status validate(const Scene& scene) const;
};

/// Lattice node positions of every object, per frame: nodes[frame][object][node], metres.
struct NodeFrames {
    double fps = 24.0;                                      ///< Frames per second.
    bool loop = false;                                      ///< The last frame leads into the first.
    std::vector<std::vector<std::vector<Vec3>>> nodes;      ///< [frame][object][node].
};

/// Evaluates a clip of `library` over `scene`: simulates (drivers, session, goals) or samples (keys)
/// and closes the loop when asked. Problems reported by the simulation are appended to `problems`.
/// `firstFrames` > 0: only the clip's first frames are wanted (`bake --frames 12` of a long clip). A clip
/// whose loop is not blended then evaluates only those (its frames do not depend on later ones); a blended
/// loop is evaluated whole, because its closure reaches across the clip. `keepGoing`, when set, is asked
/// before each frame with the fraction of the work done, rising from 0: the time simulated (the settling before
/// `start` included, so a loop's pre-roll counts) and a frame's time per frame sampled. False stops the
/// evaluation, which then fails as cancelled (Status::cancelled), so a long clip can be stopped between frames.
Result<NodeFrames> evaluateClip(const Scene& scene, const ClipLibrary& library, const Clip& clip,
                                std::vector<std::string>* problems = nullptr, int firstFrames = 0,
                                const std::function<bool(double)>& keepGoing = {});

/// Applies loop closure to `frames` (N+1 frames F_0..F_N, F_N one period after F_0) with optional
/// `preroll` (W+1 frames G_{N-W}..G_N, or empty) over a window of `window` frames; drops F_N.
/// Each frame is a flat list of points.
void closeLoop(std::vector<std::vector<Vec3>>& frames, const std::vector<std::vector<Vec3>>& preroll, int window);

/// How visible a loop's seam is.
struct SeamMeasure {
    double jump = 0.0;       ///< RMS point motion from the last frame to the first, metres.
    double medianStep = 0.0; ///< Median over the clip of the RMS point motion between consecutive frames, metres.
    double ratio = 0.0;      ///< jump / medianStep (0 when nothing moves). Depends on where the cycle is cut:
                             ///< a perfect sinusoidal loop cut at its fastest phase scores ~1.41, at a turning
                             ///< point ~0.
    double localRatio = 0.0; ///< jump / mean of the two steps beside the seam (last-but-one → last, first →
                             ///< second): ~1 for a seamless loop wherever it is cut; a pop shows as >> 1.
};

/// Measures the seam of a cycle given as frames of flat point lists (at least 3 frames).
SeamMeasure measureSeam(const std::vector<std::vector<Vec3>>& frames);
/// The same on node frames (all objects' nodes together).
SeamMeasure measureSeam(const NodeFrames& frames);

/// The library after an object was inserted into the scene at `index`: in every take it rests at
/// `restNodes` (still, no drags: recorded drags of the others are renumbered), and every keyframe set gets an
/// empty animation for it, so the takes and keys still fit the scene and replay as before.
ClipLibrary withObjectInserted(const ClipLibrary& library, std::size_t index, const std::vector<Vec3>& restNodes);
/// The library after object `index` was removed from the scene: its start state, drags and keys leave every
/// take and keyframe set (the drags of later objects renumbered).
ClipLibrary withObjectRemoved(const ClipLibrary& library, std::size_t index);

/// The clip's source name as written in files ("drivers", "session", "keyframes").
const char* clipSourceName(ClipSource source);
/// Parses a clip source name.
std::optional<ClipSource> parseClipSource(const std::string& name);

}  // namespace softtouch

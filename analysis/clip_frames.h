#pragma once
/// The mesh frames a clip exports, per object: what the study grades and what a bake writes. A clip of
/// the project's library, or, when none is named, what `bake` plays then (the library's default clip, or
/// the scene's drivers from frame 0 for the world's frames at its rate).

#include "core/authoring/clip.h"

#include <functional>
#include <string>
#include <vector>

namespace softtouch::analysis {

/// The clip `bake` plays for `name` ("" as bake without --clip): the named clip, the library's default
/// clip, or the drivers from rest for the world's frames. Fails naming the clips the project has.
Result<Clip> clipToPlay(const Scene& scene, const ClipLibrary& library, const std::string& name);

/// Every object's mesh positions at every frame of a clip.
struct ClipMeshFrames {
    int frames = 0;                               ///< Frames of the clip.
    std::vector<std::vector<Vec3f>> positions;    ///< [object]: frame after frame of its vertices.
    std::vector<std::string> problems;            ///< What the simulation reported (guard warnings).
    /// Object i's positions at frame f.
    std::span<const Vec3f> frame(std::size_t object, int f) const;
};

/// Evaluates `clip` over `scene` (evaluateClip, then each object's mesh at each frame's time, on a base
/// animation included) as a bake of that clip writes it. Fails where evaluateClip or the scene does, or
/// when `keepGoing` (asked before each frame with the fraction done) returns false.
Result<ClipMeshFrames> clipMeshFrames(const Scene& scene, const ClipLibrary& library, const Clip& clip,
                                      const std::function<bool(double)>& keepGoing = {});

/// What doing nothing exports for `clip`: every body at rest at every frame (on a base animation, the
/// animation alone).
Result<ClipMeshFrames> restFrames(const Scene& scene, const Clip& clip);

/// Each object's mesh bounding-box diagonal, metres: the length every error of the study is relative to.
std::vector<double> meshDiagonals(const Scene& scene);

/// RMS distance of each object's frames, relative to its diagonal; NaN for an object whose frames differ in count.
std::vector<double> objectDistances(const ClipMeshFrames& a, const ClipMeshFrames& b, const std::vector<double>& diagonals);

/// The largest of objectDistances(): the object that decides (NaN if any is NaN).
double worstDistance(const std::vector<double>& distances);

}  // namespace softtouch::analysis

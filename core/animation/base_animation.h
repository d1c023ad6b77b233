#pragma once
/// A mesh's own animation as the file brought it (a skeleton and skin, keyed node transforms, blend
/// shapes): the soft body adds its secondary motion on top of it (core/animation/base_motion.h).
///
/// Whatever the rig, what the lattice needs is where every vertex is at a time, so io/ evaluates the rig
/// once at a fixed rate over the chosen range and core keeps the vertex positions (docs/design/lattice.md,
/// "Secondary motion on a base animation"). Between samples positions follow a centripetal-free
/// (uniform) Catmull-Rom curve, so velocities and accelerations are continuous; a looping take wraps.

#include "core/base/result.h"
#include "core/base/types.h"

#include <span>
#include <string>
#include <vector>

namespace softtouch {

struct BaseAnimation {
    std::string take;                        ///< The take's name in its file ("" when the file names none).
    double start = 0.0;                      ///< Take time of the first sample, seconds.
    double rate = 240.0;                     ///< Samples per second, [1, 10000].
    bool loop = false;                       ///< Repeats: sample k + count is sample k.
    std::vector<std::vector<Vec3f>> samples; ///< Vertex positions per sample, metres, mesh order.

    /// Seconds one pass covers: count / rate when looping (the last sample runs on into the first),
    /// (count − 1) / rate otherwise.
    double duration() const;
    std::size_t vertexCount() const { return samples.empty() ? 0 : samples.front().size(); }
    /// Positions at `seconds` after the first sample: wrapped when looping, held at the ends otherwise.
    void positionsAt(double seconds, std::span<Vec3f> out) const;
    /// The take's time, seconds, that positionsAt(`seconds`) shows: the first sample's plus the offset wrapped
    /// (looping) or held at the ends. A rig evaluated at it gives the same pose where it lands on a sample.
    double takeSeconds(double seconds) const;
    /// Checks the rate, the sample count (at least 2) and that every sample has `vertices` finite positions.
    Status validate(std::size_t vertices) const;
};

}  // namespace softtouch

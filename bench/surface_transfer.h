#pragma once
/// Carries the motion of one mesh onto the vertices of another of the same shape: how a contender run on a
/// coarser mesh is graded on the finer mesh its reference moves (Table 1 at equal accuracy, table1.h).
///
/// Each target vertex is tied, at rest, to the nearest point of the source surface (a triangle and its
/// barycentric weights); at every frame it moves by that point's displacement. Displacement, not position,
/// so the gap between the two tessellations at rest (the coarse mesh's chords inside the fine one's
/// curve) is not counted as error.

#include "core/geometry/mesh.h"

#include <array>
#include <span>
#include <vector>

namespace softtouch::bench {

class SurfaceTransfer {
public:
    /// Ties every vertex of `target` to the nearest point of `source` at rest. `source` has triangles.
    SurfaceTransfer(const Mesh& source, std::span<const Vec3f> target);

    /// `sourceFrames` (frames × source vertices, positions) as frames × target vertices.
    std::vector<Vec3f> apply(std::span<const Vec3f> sourceFrames, std::span<const Vec3f> sourceRest) const;

    std::size_t targetCount() const { return m_ties.size(); }

private:
    struct Tie {
        std::array<std::uint32_t, 3> vertex{};
        std::array<float, 3> weight{};
    };
    std::vector<Tie> m_ties;
    std::vector<Vec3f> m_targetRest;
};

}  // namespace softtouch::bench

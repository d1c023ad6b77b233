#include "bench/surface_transfer.h"

#include "core/geometry/mesh_surface.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace softtouch::bench {

SurfaceTransfer::SurfaceTransfer(const Mesh& source, std::span<const Vec3f> target)
    : m_targetRest(target.begin(), target.end()) {
    assert(!source.triangles.empty());
    // Each triangle's bounding sphere, so most triangles are ruled out by one distance.
    const std::size_t triangles = source.triangles.size();
    std::vector<Vec3> centre(triangles);
    std::vector<double> radius(triangles);
    for (std::size_t t = 0; t < triangles; ++t) {
        const Vec3 a = source.positions[source.triangles[t][0]].cast<double>();
        const Vec3 b = source.positions[source.triangles[t][1]].cast<double>();
        const Vec3 c = source.positions[source.triangles[t][2]].cast<double>();
        centre[t] = (a + b + c) / 3.0;
        radius[t] = std::max({(a - centre[t]).norm(), (b - centre[t]).norm(), (c - centre[t]).norm()});
    }
    m_ties.reserve(target.size());
    for (const Vec3f& vertex : target) {
        const Vec3 p = vertex.cast<double>();
        double best = std::numeric_limits<double>::infinity();
        Tie tie;
        for (std::size_t t = 0; t < triangles; ++t) {
            const double lower = (p - centre[t]).norm() - radius[t];
            if (lower * std::abs(lower) >= best)  // signed square: a sphere around p never rules itself out
                continue;
            const std::array<std::uint32_t, 3>& v = source.triangles[t];
            const Vec3 a = source.positions[v[0]].cast<double>();
            const Vec3 b = source.positions[v[1]].cast<double>();
            const Vec3 c = source.positions[v[2]].cast<double>();
            const std::array<double, 3> w = nearestOnTriangle(p, a, b, c);
            const double d = (w[0] * a + w[1] * b + w[2] * c - p).squaredNorm();
            if (d < best) {
                best = d;
                tie.vertex = v;
                tie.weight = {float(w[0]), float(w[1]), float(w[2])};
            }
        }
        m_ties.push_back(tie);
    }
}

std::vector<Vec3f> SurfaceTransfer::apply(std::span<const Vec3f> sourceFrames, std::span<const Vec3f> sourceRest) const {
    const std::size_t n = sourceRest.size();
    const std::size_t frames = n > 0 ? sourceFrames.size() / n : 0;
    std::vector<Vec3f> out(frames * m_ties.size());
    for (std::size_t f = 0; f < frames; ++f) {
        const Vec3f* frame = sourceFrames.data() + f * n;
        Vec3f* to = out.data() + f * m_ties.size();
        for (std::size_t i = 0; i < m_ties.size(); ++i) {
            const Tie& tie = m_ties[i];
            Vec3f moved = m_targetRest[i];
            for (int k = 0; k < 3; ++k)
                moved += tie.weight[std::size_t(k)] * (frame[tie.vertex[std::size_t(k)]] - sourceRest[tie.vertex[std::size_t(k)]]);
            to[i] = moved;
        }
    }
    return out;
}

}  // namespace softtouch::bench

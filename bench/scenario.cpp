#include "bench/scenario.h"

#include "core/geometry/primitives.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace softtouch::bench {

Mesh makeEllipsoid(int triangles, const Vec3& radii) {
    // 2·s·(r−1) triangles for s segments and r rings; pick the factorisation closest to r = s/2 + 1.
    int bestSegments = 0, bestRings = 0;
    double bestScore = 1e300;
    for (int s = 3; 2 * s * 2 <= triangles; ++s) {
        if ((triangles / 2) % s != 0 || triangles % 2 != 0)
            continue;
        const int r = triangles / (2 * s) + 1;
        if (r < 3)
            continue;
        const double score = std::abs(std::log(double(r - 1) / (0.5 * s)));
        if (score < bestScore) {
            bestScore = score;
            bestSegments = s;
            bestRings = r;
        }
    }
    assert(bestSegments > 0);
    return makeUvEllipsoid(bestRings, bestSegments, radii);
}

InteractionScenario makeScenario(Mesh mesh) {
    InteractionScenario s;
    const Bounds b = mesh.bounds();
    std::vector<std::uint32_t> order(mesh.positions.size());
    for (std::uint32_t i = 0; i < order.size(); ++i)
        order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](std::uint32_t x, std::uint32_t y) { return mesh.positions[x].x() < mesh.positions[y].x(); });
    s.dragVertex = order.back();
    const std::size_t anchors = std::max<std::size_t>(1, order.size() / 20);
    s.anchors.assign(order.begin(), order.begin() + std::ptrdiff_t(anchors));
    s.gripRadius = 0.1 * b.diagonal();
    s.dragOffset = Vec3(0.6, 0.8, 0.0).normalized() * (0.2 * b.diagonal());
    s.localRadius = 0.25 * b.diagonal();
    s.mesh = std::move(mesh);
    return s;
}

std::vector<NodeWeight> surfaceGrip(const InteractionScenario& s) {
    const auto& x = s.mesh.positions;
    std::vector<double> area(x.size(), 0.0);
    for (const auto& t : s.mesh.triangles) {
        const double third = (x[t[1]] - x[t[0]]).cast<double>().cross((x[t[2]] - x[t[0]]).cast<double>()).norm() / 6.0;
        for (std::uint32_t v : t)
            area[v] += third;
    }
    const Vec3f centre = x[s.dragVertex];
    std::vector<NodeWeight> grip;
    double sum = 0.0;
    for (std::uint32_t v = 0; v < x.size(); ++v) {
        if ((x[v] - centre).norm() <= s.gripRadius && area[v] > 0.0) {
            grip.push_back({v, area[v]});
            sum += area[v];
        }
    }
    if (!(sum > 0.0))
        return {{s.dragVertex, 1.0}};
    for (NodeWeight& w : grip)
        w.weight /= sum;
    return grip;
}

}  // namespace softtouch::bench

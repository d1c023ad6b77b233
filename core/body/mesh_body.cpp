#include "core/body/mesh_body.h"

#include <algorithm>

namespace softtouch {

std::vector<std::array<std::uint32_t, 2>> uniqueEdges(const Mesh& mesh) {
    std::vector<std::array<std::uint32_t, 2>> edges;
    edges.reserve(mesh.triangles.size() * 3);
    for (const auto& t : mesh.triangles) {
        for (int e = 0; e < 3; ++e) {
            const std::uint32_t a = t[std::size_t(e)], b = t[std::size_t((e + 1) % 3)];
            edges.push_back({std::min(a, b), std::max(a, b)});
        }
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    return edges;
}

BodyDescription describeMeshBody(const Mesh& mesh, const MeshBodySettings& settings) {
    const std::size_t n = mesh.positions.size();
    BodyDescription d;
    d.restPositions.reserve(n);
    for (const Vec3f& p : mesh.positions)
        d.restPositions.push_back(p.cast<double>());
    d.mass.assign(n, settings.totalMass / double(std::max<std::size_t>(1, n)));
    d.anchor.assign(n, AnchorMode::Free);
    for (std::uint32_t a : settings.anchors)
        d.anchor[a] = AnchorMode::Pinned;
    if (!settings.simulated.empty()) {
        for (std::size_t i = 0; i < n; ++i) {
            if (!settings.simulated[i])
                d.anchor[i] = AnchorMode::Pinned;
        }
    }
    for (const auto& e : uniqueEdges(mesh)) {
        // A spring between two static vertices does nothing: leave it out of the local model.
        if (d.anchor[e[0]] == AnchorMode::Pinned && d.anchor[e[1]] == AnchorMode::Pinned)
            continue;
        Spring s;
        s.a = e[0];
        s.b = e[1];
        s.restLength = (d.restPositions[e[1]] - d.restPositions[e[0]]).norm();
        s.stiffness = settings.stiffness;
        s.damping = settings.damping;
        if (s.restLength > 0.0)
            d.springs.push_back(s);
    }
    return d;
}

}  // namespace softtouch

#include "core/geometry/mesh_surface.h"

#include "core/base/ranges.h"

#include <fcl/fcl.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <mutex>
#include <numeric>

namespace softtouch {

// Ericson, "Real-Time Collision Detection", 5.1.5: the Voronoi region of p among the triangle's features.
std::array<double, 3> nearestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0.0 && d2 <= 0.0)
        return {1.0, 0.0, 0.0};
    const Vec3 bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0.0 && d4 <= d3)
        return {0.0, 1.0, 0.0};
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        const double v = d1 / (d1 - d3);
        return {1.0 - v, v, 0.0};
    }
    const Vec3 cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0.0 && d5 <= d6)
        return {0.0, 0.0, 1.0};
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        const double w = d2 / (d2 - d6);
        return {1.0 - w, 0.0, w};
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return {0.0, 1.0 - w, w};
    }
    const double denominator = 1.0 / (va + vb + vc);
    const double v = vb * denominator, w = vc * denominator;
    return {1.0 - v - w, v, w};
}

namespace {

/// Each vertex's first vertex at the same position (equal floats: -0 and +0 are one place). Edges and
/// pseudonormals are keyed by it, so triangles that meet at split corners (an OBJ's flat-shaded corners, a UV
/// seam: assimp joins only vertices whose every attribute matches) still share their edges.
std::vector<std::uint32_t> weldedVertices(const std::vector<Vec3f>& positions) {
    std::vector<std::uint32_t> order(positions.size());
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
        const Vec3f &p = positions[a], &q = positions[b];
        if (p.x() != q.x())
            return p.x() < q.x();
        if (p.y() != q.y())
            return p.y() < q.y();
        if (p.z() != q.z())
            return p.z() < q.z();
        return a < b;
    });
    std::vector<std::uint32_t> welded(positions.size());
    for (std::size_t i = 0; i < order.size(); ++i)
        welded[order[i]] = i > 0 && positions[order[i]] == positions[order[i - 1]] ? welded[order[i - 1]] : order[i];
    return welded;
}

/// A triangle's edge between two welded vertices (an edge whose ends are one place is left out).
struct HalfEdge {
    std::uint64_t key = 0;     ///< Smaller welded end << 32 | larger.
    std::uint32_t slot = 0;    ///< 3t + e: triangle t's edge from corner e to corner e + 1.
    bool forward = false;      ///< It runs from the smaller end to the larger.
    bool counted = false;      ///< Its triangle has three distinct corners (it counts for the topology).
};

/// "1 open edge", "4 open edges".
std::string countOf(std::size_t n, const char* singular, const char* plural) {
    return std::to_string(n) + " " + (n == 1 ? singular : plural);
}

}  // namespace

struct MeshSurface::Hierarchy {
    std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> model;
    std::unique_ptr<fcl::CollisionObjectd> object;
    std::shared_ptr<fcl::Sphered> probe;  ///< A point, as FCL's distance query wants a shape on each side.
};

MeshSurface::~MeshSurface() = default;

Result<std::shared_ptr<const MeshSurface>> MeshSurface::create(Mesh mesh, std::string source, SurfaceSides sides) {
    using Made = Result<std::shared_ptr<const MeshSurface>>;
    const bool collider = sides != SurfaceSides::AsGiven;
    const std::string what = "the collider mesh" + (source.empty() ? std::string() : " " + source);
    if (mesh.positions.empty() || mesh.triangles.empty())
        return Status::error(what + " has no triangles");
    const std::size_t n = mesh.triangles.size();
    // Before anything is built: FCL's hierarchy and the pseudonormals grow with the triangles (docs/design/reliability.md).
    if (collider && n > ranges::kMaxColliderTriangles)
        return Status::error(what + " has " + std::to_string(n) + " triangles, more than the " +
                             std::to_string(ranges::kMaxColliderTriangles) +
                             " a collider may have: decimate it in your modelling tool to at most " +
                             std::to_string(ranges::kMaxColliderTriangles) + " triangles");
    for (const Vec3f& p : mesh.positions)
        if (!p.allFinite())
            return Status::error(what + " has a non-finite vertex position");
    for (const auto& t : mesh.triangles)
        for (std::uint32_t v : t)
            if (v >= mesh.positions.size())
                return Status::error(what + " has a triangle index past its " + std::to_string(mesh.positions.size()) +
                                     " vertices");

    // Topology, on welded vertices: every triangle's edges, sorted so each edge's triangles lie together.
    const Bounds bounds = mesh.bounds();
    const Vec3 centre = 0.5 * (bounds.min + bounds.max);
    const double diagonal = bounds.diagonal();
    const std::vector<std::uint32_t> welded = weldedVertices(mesh.positions);
    MeshTopology topology;
    std::vector<HalfEdge> halfEdges;
    halfEdges.reserve(3 * n);
    for (std::size_t t = 0; t < n; ++t) {
        const auto& tri = mesh.triangles[t];
        std::array<Vec3, 3> x;
        for (int c = 0; c < 3; ++c)
            x[c] = mesh.positions[tri[c]].cast<double>() - centre;
        const double area = 0.5 * (x[1] - x[0]).cross(x[2] - x[0]).norm();
        topology.volume += x[0].dot(x[1].cross(x[2])) / 6.0;  // the tetrahedron (centre, triangle), signed
        const std::array<std::uint32_t, 3> w{welded[tri[0]], welded[tri[1]], welded[tri[2]]};
        const bool collapsed = w[0] == w[1] || w[1] == w[2] || w[2] == w[0];
        topology.degenerateTriangles += collapsed || area <= 1e-12 * diagonal * diagonal;
        for (int e = 0; e < 3; ++e) {
            const std::uint32_t a = w[e], b = w[(e + 1) % 3];
            if (a != b)
                halfEdges.push_back({std::uint64_t(std::min(a, b)) << 32 | std::max(a, b), std::uint32_t(3 * t + e), a < b,
                                     !collapsed});
        }
    }
    std::sort(halfEdges.begin(), halfEdges.end(),
              [](const HalfEdge& a, const HalfEdge& b) { return a.key != b.key ? a.key < b.key : a.slot < b.slot; });
    std::vector<std::pair<std::size_t, std::size_t>> edges;  // [first, last) of each edge's half-edges
    for (std::size_t first = 0, last = 0; first < halfEdges.size(); first = last) {
        for (last = first; last < halfEdges.size() && halfEdges[last].key == halfEdges[first].key;)
            ++last;
        edges.emplace_back(first, last);
        std::size_t uses = 0, forward = 0;
        for (std::size_t h = first; h < last; ++h)
            if (halfEdges[h].counted) {
                ++uses;
                forward += halfEdges[h].forward;
            }
        topology.openEdges += uses == 1;
        topology.nonManifoldEdges += uses > 2;
        topology.flippedEdges += uses == 2 && forward != 1;
    }

    // A collider's sign is exact only on a closed, consistently wound mesh facing outwards; a one-sided sheet
    // may be open, but its faces must still agree on which side is in front.
    if (collider) {
        if (topology.degenerateTriangles == n)
            return Status::error(what + " has no area: " +
                                 (n == 1 ? std::string("its only triangle has") : "all its " + std::to_string(n) + " triangles have") +
                                 " zero area");
        const bool open = sides == SurfaceSides::Closed && topology.openEdges > 0;
        std::vector<std::string> faults;
        if (open)
            faults.push_back(countOf(topology.openEdges, "open edge", "open edges"));
        if (topology.nonManifoldEdges > 0)
            faults.push_back(countOf(topology.nonManifoldEdges, "edge", "edges") + " shared by more than two triangles");
        if (topology.flippedEdges > 0)
            faults.push_back(countOf(topology.flippedEdges, "edge", "edges") + " where the winding flips");
        if (!faults.empty()) {
            std::string message = what + " has ";
            for (std::size_t i = 0; i < faults.size(); ++i)
                message += (i == 0 ? "" : i + 1 == faults.size() ? " and " : ", ") + faults[i];
            if (topology.degenerateTriangles > 0)
                message += " (and " + countOf(topology.degenerateTriangles, "triangle", "triangles") + " of zero area)";
            if (open && faults.size() == 1)
                message += ": a collider mesh must be closed, or set \"oneSided\": true to use it as a surface that "
                           "pushes along its normals";
            else if (sides == SurfaceSides::Closed)
                message += ": a collider mesh must be closed, each edge joining exactly two triangles wound the same way "
                           "round; mend it in your modelling tool";
            else
                message += ": each edge of a one-sided collider mesh must join at most two triangles, wound the same way "
                           "round; mend it in your modelling tool";
            return Status::error(std::move(message));
        }
        // Volume is exact up to rounding (a sheet doubled back on itself sums to zero); the scale is the bounds'.
        const double noVolume = 1e-9 * diagonal * diagonal * diagonal;
        if (sides == SurfaceSides::Closed && std::abs(topology.volume) <= noVolume)
            return Status::error(what + " encloses no volume: a collider mesh must be a solid, or set \"oneSided\": true "
                                        "to use it as a surface that pushes along its normals");
        if (sides == SurfaceSides::Closed && topology.volume < 0.0)
            return Status::error(what + " faces inwards (its signed volume is negative): flip its normals in your "
                                        "modelling tool");
    }

    std::shared_ptr<MeshSurface> s(new MeshSurface());
    s->m_sides = sides;
    s->m_topology = topology;
    s->m_bounds = bounds;
    for (const Vec3f& p : mesh.positions)
        s->m_radius = std::max(s->m_radius, (p.cast<double>() - centre).norm());
    // Behind a one-sided sheet, inside reaches as deep as the sheet is wide: a body that went through it within
    // a step is pushed back out in front, however fast it came (docs/design/lattice.md, "Mesh colliders").
    s->m_backDepth = sides == SurfaceSides::OneSided ? diagonal : 0.0;

    // Pseudonormals on the welded vertices: the face normal, the sum over an edge's faces, the angle-weighted
    // sum at a vertex.
    s->m_faceNormals.resize(n);
    std::vector<Vec3> weldedNormals(mesh.positions.size(), Vec3::Zero());
    for (std::size_t t = 0; t < n; ++t) {
        const auto& tri = mesh.triangles[t];
        std::array<Vec3, 3> x;
        for (int c = 0; c < 3; ++c)
            x[c] = mesh.positions[tri[c]].cast<double>();
        const Vec3 cross = (x[1] - x[0]).cross(x[2] - x[0]);
        const Vec3 normal = cross.norm() > 0.0 ? Vec3(cross.normalized()) : Vec3::Zero();
        s->m_faceNormals[t] = normal;
        for (int c = 0; c < 3; ++c) {
            const Vec3 e1 = (x[(c + 1) % 3] - x[c]).normalized(), e2 = (x[(c + 2) % 3] - x[c]).normalized();
            const double angle = std::acos(std::clamp(e1.dot(e2), -1.0, 1.0));
            if (std::isfinite(angle))
                weldedNormals[welded[tri[c]]] += angle * normal;
        }
    }
    s->m_vertexNormals.resize(mesh.positions.size());
    for (std::size_t v = 0; v < mesh.positions.size(); ++v)
        s->m_vertexNormals[v] = weldedNormals[welded[v]];
    // An edge whose ends are one place is a point: its corner's pseudonormal.
    s->m_edgeNormals.resize(3 * n);
    for (std::size_t t = 0; t < n; ++t)
        for (int e = 0; e < 3; ++e)
            s->m_edgeNormals[3 * t + e] = s->m_vertexNormals[mesh.triangles[t][e]];
    std::vector<std::uint8_t> rimVertex(sides == SurfaceSides::OneSided ? mesh.positions.size() : 0, 0);
    if (sides == SurfaceSides::OneSided)
        s->m_rim.assign(n, 0);
    for (const auto& [first, last] : edges) {
        Vec3 sum = Vec3::Zero();
        std::size_t uses = 0;
        for (std::size_t h = first; h < last; ++h) {
            sum += s->m_faceNormals[halfEdges[h].slot / 3];
            uses += halfEdges[h].counted;
        }
        const bool rim = sides == SurfaceSides::OneSided && uses == 1;
        for (std::size_t h = first; h < last; ++h) {
            s->m_edgeNormals[halfEdges[h].slot] = sum;
            if (rim)
                s->m_rim[halfEdges[h].slot / 3] |= std::uint8_t(1u << (halfEdges[h].slot % 3));
        }
        if (rim) {
            rimVertex[halfEdges[first].key >> 32] = 1;
            rimVertex[halfEdges[first].key & 0xffffffffu] = 1;
        }
    }
    if (sides == SurfaceSides::OneSided)
        for (std::size_t t = 0; t < n; ++t)
            for (int c = 0; c < 3; ++c)
                if (rimVertex[welded[mesh.triangles[t][c]]])
                    s->m_rim[t] |= std::uint8_t(1u << (3 + c));

    auto h = std::make_unique<Hierarchy>();
    h->model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
    std::vector<fcl::Vector3d> vertices;
    vertices.reserve(mesh.positions.size());
    for (const Vec3f& p : mesh.positions)
        vertices.emplace_back(p.cast<double>());
    std::vector<fcl::Triangle> triangles;
    triangles.reserve(n);
    for (const auto& t : mesh.triangles)
        triangles.emplace_back(t[0], t[1], t[2]);
    h->model->beginModel(int(n), int(vertices.size()));
    h->model->addSubModel(vertices, triangles);
    h->model->endModel();
    h->object = std::make_unique<fcl::CollisionObjectd>(h->model);
    h->probe = std::make_shared<fcl::Sphered>(1e-12);
    s->m_hierarchy = std::move(h);
    s->m_mesh = std::move(mesh);
    s->m_source = std::move(source);
    if (sides == SurfaceSides::OneSided)  // behind it, inside reaches the whole depth: no node could rule a point out
        return Made(std::shared_ptr<const MeshSurface>(std::move(s)));

    // The distance grid: the bounds padded by a cell, about 8,000 nodes (under 0.1 s of queries).
    const Vec3 extent = (s->m_bounds.max - s->m_bounds.min).cwiseMax(1e-6 * std::max(1e-9, s->m_radius));
    const double cell = std::cbrt(extent.prod() / 6000.0);
    for (int a = 0; a < 3; ++a)
        s->m_gridNodes[std::size_t(a)] = std::clamp(int(std::ceil(extent[a] / cell)) + 3, 3, 64);
    for (int a = 0; a < 3; ++a) {
        s->m_gridStep[a] = extent[a] / (s->m_gridNodes[std::size_t(a)] - 3);
        s->m_gridOrigin[a] = s->m_bounds.min[a] - s->m_gridStep[a];
    }
    s->m_gridDistance.resize(std::size_t(s->m_gridNodes[0]) * std::size_t(s->m_gridNodes[1]) * std::size_t(s->m_gridNodes[2]));
    std::size_t index = 0;
    for (int k = 0; k < s->m_gridNodes[2]; ++k)
        for (int j = 0; j < s->m_gridNodes[1]; ++j)
            for (int i = 0; i < s->m_gridNodes[0]; ++i) {
                Vec3 normal;
                const Vec3 node = s->m_gridOrigin + s->m_gridStep.cwiseProduct(Vec3(i, j, k));
                s->m_gridDistance[index++] = float(s->exactDistance(node, normal));
            }
    return Made(std::shared_ptr<const MeshSurface>(std::move(s)));
}

Result<std::shared_ptr<const MeshSurface>> MeshSurface::shared(const Mesh& mesh) {
    // Keyed by an FNV-1a hash of the positions and triangles; a hit is confirmed by comparing them.
    std::uint64_t hash = 1469598103934665603ull;
    const auto mix = [&](const void* data, std::size_t bytes) {
        const auto* p = static_cast<const unsigned char*>(data);
        for (std::size_t i = 0; i < bytes; ++i)
            hash = (hash ^ p[i]) * 1099511628211ull;
    };
    mix(mesh.positions.data(), mesh.positions.size() * sizeof(Vec3f));
    mix(mesh.triangles.data(), mesh.triangles.size() * sizeof(mesh.triangles[0]));
    static std::mutex mutex;
    static std::multimap<std::uint64_t, std::weak_ptr<const MeshSurface>> cache;
    std::lock_guard lock(mutex);
    for (auto it = cache.begin(); it != cache.end();) {  // forget surfaces nobody holds
        if (it->second.expired())
            it = cache.erase(it);
        else
            ++it;
    }
    const auto [first, last] = cache.equal_range(hash);
    for (auto it = first; it != last; ++it)
        if (auto held = it->second.lock()) {
            const Mesh& m = held->mesh();
            if (m.positions.size() == mesh.positions.size() && m.triangles.size() == mesh.triangles.size() &&
                std::memcmp(m.positions.data(), mesh.positions.data(), mesh.positions.size() * sizeof(Vec3f)) == 0 &&
                std::memcmp(m.triangles.data(), mesh.triangles.data(), mesh.triangles.size() * sizeof(mesh.triangles[0])) == 0)
                return held;
        }
    Mesh geometry;  // only what the surface needs: not normals, parts or UVs
    geometry.positions = mesh.positions;
    geometry.triangles = mesh.triangles;
    auto made = create(std::move(geometry), {}, SurfaceSides::AsGiven);
    if (made)
        cache.emplace(hash, made.value());
    return made;
}

double MeshSurface::signedDistance(const Vec3& p, Vec3& normal, double reach) const {
    // Far from the bounds: their distance is a lower bound, and no query is needed (a one-sided surface's
    // inside reaches backDepth() beyond them).
    const Vec3 outside = (m_bounds.min - p).cwiseMax(p - m_bounds.max).cwiseMax(0.0);
    if (outside.norm() > std::max(reach, m_backDepth)) {
        const Vec3 nearestOfBox = p.cwiseMax(m_bounds.min).cwiseMin(m_bounds.max);
        normal = (p - nearestOfBox).normalized();
        return outside.norm();
    }
    if (m_gridDistance.empty())
        return exactDistance(p, normal);
    // Within them, the nearest grid node's distance less the way to it (the distance is 1-Lipschitz; the
    // float it is kept in loses at most a few ulps, covered by the 1e-6 margin).
    const Vec3 cell = (p - m_gridOrigin).cwiseQuotient(m_gridStep);
    std::array<int, 3> n{};
    for (int a = 0; a < 3; ++a)
        n[std::size_t(a)] = std::clamp(int(std::lround(cell[a])), 0, m_gridNodes[std::size_t(a)] - 1);
    const Vec3 node = m_gridOrigin + m_gridStep.cwiseProduct(Vec3(n[0], n[1], n[2]));
    const double atNode = m_gridDistance[std::size_t(n[0]) + std::size_t(m_gridNodes[0]) * (std::size_t(n[1]) + std::size_t(m_gridNodes[1]) * std::size_t(n[2]))];
    const double bound = atNode - (p - node).norm() - 1e-6 * std::abs(atNode);
    if (bound > reach) {
        normal = (p - 0.5 * (m_bounds.min + m_bounds.max)).normalized();
        return bound;
    }
    return exactDistance(p, normal);
}

double MeshSurface::exactDistance(const Vec3& p, Vec3& normal) const {
    fcl::CollisionObjectd probe(m_hierarchy->probe);
    probe.setTranslation(p);
    probe.computeAABB();
    fcl::DistanceRequestd request(true);
    fcl::DistanceResultd result;
    fcl::distance(m_hierarchy->object.get(), &probe, request, result);
    const int t = result.b1;
    if (t < 0 || std::size_t(t) >= m_faceNormals.size()) {  // not expected: FCL always names a triangle
        normal = Vec3::UnitY();
        return 0.0;
    }
    // FCL names the nearest triangle; the nearest point on it, and which of its features holds that point
    // (face, edge or corner: the pseudonormal to use), are computed exactly here. A point on the surface
    // (where contacts leave them) is where this matters: there FCL reports a collision, not nearest points.
    const auto& tri = m_mesh.triangles[std::size_t(t)];
    const Vec3 a = m_mesh.positions[tri[0]].cast<double>(), b = m_mesh.positions[tri[1]].cast<double>(),
               c = m_mesh.positions[tri[2]].cast<double>();
    const std::array<double, 3> w = nearestOnTriangle(p, a, b, c);
    const Vec3 nearest = w[0] * a + w[1] * b + w[2] * c;
    Vec3 pseudonormal = m_faceNormals[std::size_t(t)];
    int rimBit = -1;  // which bit of m_rim says the nearest feature lies on an open edge
    int zeros = 0, zeroCorner = -1, oneCorner = -1;
    for (int k = 0; k < 3; ++k) {
        if (w[std::size_t(k)] == 0.0) {
            ++zeros;
            zeroCorner = k;
        }
        if (w[std::size_t(k)] == 1.0)
            oneCorner = k;
    }
    if (oneCorner >= 0) {
        pseudonormal = m_vertexNormals[tri[std::size_t(oneCorner)]];
        rimBit = 3 + oneCorner;
    } else if (zeros == 1) {  // on the edge opposite the zero corner: edge (zero + 1, zero + 2)
        pseudonormal = m_edgeNormals[3 * std::size_t(t) + std::size_t((zeroCorner + 1) % 3)];
        rimBit = (zeroCorner + 1) % 3;
    }
    const Vec3 offset = p - nearest;
    const double distance = offset.norm();
    double sign = offset.dot(pseudonormal) < 0.0 ? -1.0 : 1.0;
    // One-sided: behind the sheet is inside only within its rim (a point whose nearest point is on an open edge
    // or corner is beside the sheet, not behind it) and backDepth() deep.
    if (m_sides == SurfaceSides::OneSided && sign < 0.0 &&
        ((rimBit >= 0 && ((m_rim[std::size_t(t)] >> rimBit) & 1u)) || distance > m_backDepth))
        sign = 1.0;
    if (distance > 1e-12 * std::max(1.0, m_radius))
        normal = sign * offset / distance;
    else
        normal = pseudonormal.norm() > 0.0 ? Vec3(pseudonormal.normalized()) : m_faceNormals[std::size_t(t)];
    return sign * distance;
}

}  // namespace softtouch

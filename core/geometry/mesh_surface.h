#pragma once
/// Signed distance to a triangle mesh: a rock a body collides with (closed), a ground or wall it pushes out of
/// along its normals (one-sided), or a body's own rest surface (the fish-against-fish contact pulls a point
/// back into the other body's rest space and asks this).
///
/// The nearest point comes from FCL's bounding-volume hierarchy (OBB-RSS; a well-kept library rather than a
/// home-made BVH). Inside or outside comes from the angle-weighted pseudonormal at that nearest point
/// (Bærentzen & Aanæs, "Signed distance computation using the angle weighted pseudonormal", 2005): the face
/// normal when the nearest point lies inside a triangle, the sum of the two faces' normals on an edge, the
/// incident angles' weighted sum at a vertex. For a closed, consistently wound mesh this sign is exact, so a
/// collider's mesh must be one (SurfaceSides::Closed) or say that it is a one-sided sheet.
///
/// A query costs FCL about 10 µs, and a contact pass asks for hundreds of points several times per
/// substep, most of them nowhere near the surface. So a closed surface also keeps its signed distance at the
/// nodes of a coarse grid (computed once, by the same exact query): the distance is 1-Lipschitz, so
/// d(node) − |p − node| bounds d(p) from below, and a point that bound puts outside needs no query.

#include "core/base/result.h"
#include "core/base/types.h"
#include "core/geometry/mesh.h"

#include <array>
#include <cstdint>
#include <memory>
#include <string>

namespace softtouch {

/// What a surface's triangles bound, which MeshSurface::create checks its mesh against.
enum class SurfaceSides : std::uint8_t {
    /// A solid (a rock): every edge joins exactly two triangles that run along it in opposite directions,
    /// facing outwards (a positive volume). Inside is what the mesh encloses.
    Closed,
    /// An open sheet (a ground, a wall) that pushes along its face normals: a point behind it, within its rim
    /// and at most backDepth() deep, is inside; beside the rim or in front of it, outside. Open edges are
    /// allowed; every edge still joins at most two triangles, wound the same way round.
    OneSided,
    /// As given, unchecked: a body's own rest surface for body contacts (its sign is exact where it is closed).
    AsGiven,
};

/// What a mesh's edges and triangles are, counted on its positions: vertices at the same place are one (an
/// OBJ's corners split by their normals or UVs still join their triangles).
struct MeshTopology {
    std::size_t openEdges = 0;            ///< Edges of exactly one triangle (a hole's rim, a sheet's border).
    std::size_t nonManifoldEdges = 0;     ///< Edges of more than two triangles.
    std::size_t flippedEdges = 0;         ///< Edges whose two triangles run along them the same way: the
                                          ///< winding (which side is out) flips across them.
    std::size_t degenerateTriangles = 0;  ///< Triangles of (next to) zero area; those with two corners at one
                                          ///< place are left out of the edge counts (their edges are points).
    double volume = 0.0;                  ///< Signed volume, m³ (divergence theorem): > 0 when the triangles
                                          ///< face outwards; meaningful for a closed mesh.
    /// Every edge joins exactly two triangles, wound the same way round.
    bool closed() const { return openEdges == 0 && nonManifoldEdges == 0 && flippedEdges == 0; }
};

/// The point of triangle (a, b, c) nearest `p`, as barycentric weights of a, b, c (each >= 0, summing to 1):
/// exact, where FCL's own nearest points come from an iterative solver with a tolerance.
std::array<double, 3> nearestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

/// An immutable triangle surface with signed distance queries. Built once (a rock: milliseconds).
class MeshSurface {
public:
    /// Checks the mesh, then builds the hierarchy, the pseudonormals and (closed or as given) the distance
    /// grid. Errors on an empty mesh, non-finite positions, out-of-range indices; for a collider (Closed or
    /// OneSided) also on more than ranges::kMaxColliderTriangles triangles (before anything is built), on a
    /// mesh that is not what `sides` says (its open, non-manifold and flipped edges counted), and on one of no
    /// area or (closed) no volume. `source`: where the mesh came from, as a project names it (kept, and named
    /// in the errors).
    static Result<std::shared_ptr<const MeshSurface>> create(Mesh mesh, std::string source = {},
                                                             SurfaceSides sides = SurfaceSides::Closed);
    /// The surface of `mesh` (no source, as given), built once per distinct mesh while anything holds it. The
    /// editor rebuilds its simulation on every edit, and building a fish's surface takes ~0.3 s (the distance
    /// grid's exact queries); the same mesh content finds the surface already built.
    static Result<std::shared_ptr<const MeshSurface>> shared(const Mesh& mesh);
    ~MeshSurface();
    MeshSurface(const MeshSurface&) = delete;
    MeshSurface& operator=(const MeshSurface&) = delete;

    /// Signed distance from `p` to the surface, metres (negative inside), and the outward unit normal
    /// there (the pseudonormal of the nearest point; from the nearest point towards `p` where that is
    /// well defined). A point the grid (or the bounds) puts farther than `reach` outside returns a positive
    /// lower bound instead, without a query: pass a large reach for the exact distance everywhere.
    double signedDistance(const Vec3& p, Vec3& normal, double reach = 0.0) const;

    const Mesh& mesh() const { return m_mesh; }
    const Bounds& bounds() const { return m_bounds; }
    /// Radius of a sphere around the bounds' centre that holds every vertex and every point the surface calls
    /// inside (for a one-sided surface, its back region too).
    double boundingRadius() const { return m_radius + m_backDepth; }
    const std::string& source() const { return m_source; }
    SurfaceSides sides() const { return m_sides; }
    /// How deep behind a one-sided surface inside reaches, metres: its bounds' diagonal (a body that went
    /// through it within a step, however fast, is still caught). 0 for the others.
    double backDepth() const { return m_backDepth; }
    const MeshTopology& topology() const { return m_topology; }

private:
    MeshSurface() = default;
    struct Hierarchy;
    Mesh m_mesh;
    std::string m_source;
    SurfaceSides m_sides = SurfaceSides::Closed;
    MeshTopology m_topology;
    Bounds m_bounds;
    double m_radius = 0.0;                             ///< Of the vertices about the bounds' centre.
    double m_backDepth = 0.0;
    std::vector<Vec3> m_faceNormals;
    std::vector<Vec3> m_vertexNormals;                 ///< Angle-weighted pseudonormals, per vertex.
    std::vector<Vec3> m_edgeNormals;                   ///< Per triangle t, edge e = (corner e, corner e+1): 3t + e.
    std::vector<std::uint8_t> m_rim;                   ///< One-sided: per triangle, bit e set when edge e is
                                                       ///< open, bit 3 + c when corner c lies on an open edge.
    Vec3 m_gridOrigin = Vec3::Zero();                  ///< Corner of the distance grid (the bounds, padded).
    Vec3 m_gridStep = Vec3::Ones();                    ///< Node spacing per axis, metres.
    std::array<int, 3> m_gridNodes{};                  ///< Nodes per axis.
    std::vector<float> m_gridDistance;                 ///< Signed distance at each node, x fastest (empty:
                                                       ///< no grid, every point within reach is queried).
    /// The exact query (FCL, then the nearest triangle's feature and pseudonormal).
    double exactDistance(const Vec3& p, Vec3& normal) const;
    std::unique_ptr<Hierarchy> m_hierarchy;
};

}  // namespace softtouch

#pragma once
/// A triangle mesh as the engine sees it: plain arrays, no file format. io/ fills it.

#include "core/base/result.h"
#include "core/base/types.h"

#include <array>
#include <memory>
#include <string>
#include <span>
#include <vector>

namespace softtouch {

/// A named range of a mesh (one imported mesh, e.g. "body" or "eye_left").
struct MeshPart {
    std::string name;              ///< Name from the source file; may be empty.
    std::uint32_t firstVertex = 0; ///< Index of the part's first vertex.
    std::uint32_t vertexCount = 0; ///< Number of vertices in the part.
};

/// Axis-aligned bounds of a set of points.
struct Bounds {
    Vec3 min = Vec3::Zero(); ///< Smallest coordinates.
    Vec3 max = Vec3::Zero(); ///< Largest coordinates.
    /// Length of the diagonal (metres).
    double diagonal() const { return (max - min).norm(); }
    /// The bounds holding both these and `other`.
    Bounds united(const Bounds& other) const { return {min.cwiseMin(other.min), max.cwiseMax(other.max)}; }
};

/// Bounds of points; zero bounds for none.
Bounds boundsOf(std::span<const Vec3> points);

/// Indexed triangle mesh. Vertex order is the order every vertex cache uses.
/// Unit vertex normals from the triangles around each vertex, weighted by their areas (+z where none).
void areaWeightedNormals(std::span<const Vec3f> positions, std::span<const std::array<std::uint32_t, 3>> triangles,
                         std::span<Vec3f> normals);

struct Mesh {
    std::vector<Vec3f> positions;                      ///< Rest positions (metres).
    std::vector<Vec3f> normals;                        ///< Unit rest normals, one per vertex (or empty).
    std::vector<std::array<std::uint32_t, 3>> triangles; ///< Counter-clockwise triangles.
    std::vector<MeshPart> parts;                       ///< Parts in vertex order (may be empty).

    /// Checks that the mesh is usable: non-empty, finite, indices in range, normals sized.
    Status validate() const;
    /// Area-weighted vertex normals from the triangles (fills `normals`).
    void computeNormals();
    /// Bounds of the positions; zero bounds for an empty mesh.
    Bounds bounds() const;
};

/// A rest mesh as a scene holds it: shared and immutable. Copying a scene (an undo step, a simulation, the
/// editor's document) copies a pointer, and whether an edit kept an object's mesh is a pointer comparison.
/// Made from a Mesh (implicitly: `object.mesh = std::move(mesh)`); read through `->`, `*` or as a
/// `const Mesh&`. A change is a new mesh.
class SharedMesh {
public:
    /// The empty mesh.
    SharedMesh();
    SharedMesh(Mesh mesh);  // NOLINT(google-explicit-constructor): a scene object is given a Mesh
    const Mesh& operator*() const { return *m_mesh; }
    const Mesh* operator->() const { return m_mesh.get(); }
    operator const Mesh&() const { return *m_mesh; }  // NOLINT(google-explicit-constructor)
    /// The same mesh object, not only equal values (then everything made from one holds for the other).
    bool sameAs(const SharedMesh& other) const { return m_mesh == other.m_mesh; }

private:
    std::shared_ptr<const Mesh> m_mesh;
};

}  // namespace softtouch

#pragma once
/// A triangle mesh as the engine sees it: plain arrays, no file format. io/ fills it.

#include "core/result.h"
#include "core/types.h"

#include <array>
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

}  // namespace softtouch

#pragma once
/// A mass-spring body on the mesh itself: a node per vertex, a spring per unique triangle edge. This
/// is the "global mass-spring" the paper compares against (and, restricted to a region, the "local"
/// one). Its cost grows with the mesh, which is exactly what the lattice avoids.

#include "core/body/body_model.h"
#include "core/geometry/mesh.h"

namespace softtouch {

/// Settings of a mesh body.
struct MeshBodySettings {
    double stiffness = 80.0;   ///< Per edge spring, N/m.
    double damping = 0.9;      ///< Per edge spring, N·s/m.
    double totalMass = 1.0;    ///< Spread evenly over the vertices, kg.
    std::vector<std::uint32_t> anchors; ///< Vertices pinned in place.
    /// When non-empty, only these vertices are simulated; every other vertex is pinned (the local
    /// mass-spring: a region around the interaction, the rest of the mesh static).
    std::vector<std::uint8_t> simulated;
};

/// The body description of a mesh (build it with buildBodyModel()).
BodyDescription describeMeshBody(const Mesh& mesh, const MeshBodySettings& settings);

/// Unique undirected edges of the triangles, each as (lower index, higher index), sorted.
std::vector<std::array<std::uint32_t, 2>> uniqueEdges(const Mesh& mesh);

}  // namespace softtouch

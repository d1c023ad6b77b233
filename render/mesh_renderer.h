#pragma once
/// Draws lattice-deformed meshes with OpenGL 3.3 core. Only the lattice node positions are uploaded per
/// frame; the vertex shader evaluates the Bezier / B-spline map and the normals (render/shaders.cpp), so
/// a mesh costs the CPU nothing per frame beyond its lattice. No Qt: works in any current context (Qt's
/// QOpenGLWidget, or render::EglContext with no X server).
///
/// Every call except the helpers in camera.h needs the context that initialize() ran in to be current.

#include "core/base/result.h"
#include "core/body/forces.h"
#include "core/geometry/lattice.h"
#include "core/geometry/mesh.h"
#include "core/scene/scene.h"
#include "render/camera.h"

#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

namespace softtouch::render {

/// How a mesh is drawn.
enum class ShadeMode {
    Shaded,    ///< Opaque, two-light Lambert + rim.
    Wireframe, ///< Triangle edges only (glPolygonMode lines), in the mesh colour.
    XRay,      ///< Shaded, translucent, no depth writes: the lattice shows through.
};

/// Per-object look.
struct MeshStyle {
    ShadeMode mode = ShadeMode::Shaded;            ///< Drawing mode.
    Eigen::Vector3f colour{0.95f, 0.55f, 0.2f};    ///< Base colour, linear RGB, each in [0,1].
};

/// What the lattice overlay shows; one entry per lattice node unless said otherwise. Shorter vectors
/// (empty in particular) mean "default" for the missing nodes.
struct LatticeOverlay {
    std::vector<float> nodeValue;        ///< Painted value in [0,1], colour-mapped blue -> red; empty: neutral.
    std::vector<std::uint8_t> anchor;    ///< 0 free, 1 pinned (black-and-white), 2 heavy (dark purple).
    std::vector<std::uint8_t> isVoid;    ///< Non-zero: drawn as a hollow grey ring.
    std::vector<std::uint8_t> selected;  ///< Non-zero: drawn larger, in yellow.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> springs; ///< Node pairs drawn as lines.
    std::vector<float> springStrain;     ///< Per spring, (|r|-L)/L: compressed blue, rest grey, stretched red (saturates at ±0.25).
    float nodeSizePixels = 9.0f;         ///< Node disc diameter, pixels. Range [1, 64].
};

/// GPU renderer of lattice-deformed meshes, lattice overlays and collision planes.
class MeshRenderer {
public:
    MeshRenderer();
    ~MeshRenderer();
    MeshRenderer(const MeshRenderer&) = delete;
    MeshRenderer& operator=(const MeshRenderer&) = delete;

    /// Compiles the shaders and creates the shared GL objects. Needs a current OpenGL >= 3.3 core
    /// context; errors name the program and carry the shader log.
    Status initialize();
    /// Frees every GL object (context current). Safe to call twice, and before initialize().
    void release();
    /// True between a successful initialize() and release().
    bool isInitialized() const;

    /// Uploads one object: each vertex's lattice parameters (u,v,w) in the box, its rest normal mapped
    /// by cof(A) (computed once, in double), the triangles, and the lattice kind, counts and degrees
    /// (Bezier degree <= 7 per axis, clamped cubic B-spline up to 64 nodes per axis). The nodes start
    /// at the lattice's rest positions (the mesh drawn undeformed). Rest normals are computed from the
    /// triangles when the mesh has none. Returns the object id (>= 0).
    Result<int> addObject(const Mesh& mesh, const Lattice& lattice);
    /// Removes every object (their ids become invalid).
    void clearObjects();
    /// Number of objects added since the last clearObjects().
    int objectCount() const;

    /// Per frame: the object's lattice node positions (nodeCount() of its lattice), the only per-frame
    /// upload. Ignored (asserted in debug) when the count is wrong.
    void setNodes(int object, std::span<const Vec3> nodes);
    /// Per frame, instead of setNodes(): the object's deformed positions and unit normals computed on the
    /// CPU (a body on a base animation, whose rig moves the mesh in ways its lattice cannot; core/animation/base_motion.h).
    /// From the first call on the object draws these; `nodes` (its lattice as shown) places the overlay.
    void setDeformed(int object, std::span<const Vec3f> positions, std::span<const Vec3f> normals,
                     std::span<const Vec3> nodes);
    /// Drawing mode and colour of an object.
    void setStyle(int object, const MeshStyle& style);
    /// Overlay contents; nodes are drawn at the positions given to setNodes().
    void setOverlay(int object, const LatticeOverlay& overlay);
    /// Shows or hides an object's overlay (hidden by default).
    void setOverlayVisible(int object, bool visible);
    /// Collision planes drawn as translucent square quads of the given half-size (metres), centred on
    /// each CollisionPlane::point.
    void setPlanes(std::span<const CollisionPlane> planes, float halfSize);
    /// Colliders (spheres, capsules, boxes) drawn as opaque faceted stone, lit from the view's key light.
    void setColliders(std::span<const Collider> colliders);

    /// Draws everything into the currently bound framebuffer of the given pixel size, which it first
    /// clears to a mid-grey gradient. Afterwards depth test is enabled, blending disabled, polygon mode
    /// GL_FILL and no program or vertex array bound.
    void draw(const Camera& camera, int widthPixels, int heightPixels);

    /// Deformed world positions and unit normals, in mesh order, computed by the drawing vertex shader
    /// itself and read back with transform feedback (for tests and exact GPU/CPU comparisons).
    Status readDeformed(int object, std::vector<Vec3f>& positions, std::vector<Vec3f>& normals);

private:
    struct Object;
    struct Shared;
    Object* find(int object);
    void uploadOverlay(Object& object);
    std::unique_ptr<Shared> m_shared;               ///< Programs and shared buffers; null until initialize().
    std::vector<std::unique_ptr<Object>> m_objects; ///< Index = object id.
};

/// Shows object i of `sim` (renderer object `id`) with lattice nodes `nodes` at scene time `seconds`: the GPU
/// deforms it from the nodes, or, on a base animation, it is deformed on the CPU (base + turned deviation,
/// SceneSimulation::evaluateNodes) into the scratch buffers and drawn as is, its overlay where it is shown.
void showSceneObject(MeshRenderer& renderer, int id, const SceneSimulation& sim, std::size_t i, std::span<const Vec3> nodes,
                     double seconds, std::vector<Vec3f>& positions, std::vector<Vec3f>& normals);

}  // namespace softtouch::render

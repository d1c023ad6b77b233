#include "render/mesh_renderer.h"

#include "core/geometry/mesh_surface.h"
#include "core/geometry/primitives.h"

#include "render/gl.h"
#include "render/gl_program.h"
#include "render/shaders.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <string>

namespace softtouch::render {
namespace {

/// Widest node texture row; 64^3 B-spline nodes then need 256 rows (GL 3.3 guarantees 1024 per side).
constexpr int kNodeTextureMaxWidth = 1024;
/// Floats per vertex of the flat program: position (3), colour RGBA (4), point size + hollow flag (2).
constexpr int kFlatStride = 9;

void pushFlat(std::vector<float>& out, const Eigen::Vector3f& p, const Eigen::Vector4f& colour, float size = 1.0f,
              float hollow = 0.0f) {
    out.insert(out.end(), {p.x(), p.y(), p.z(), colour.x(), colour.y(), colour.z(), colour.w(), size, hollow});
}

/// Moreland's cool-warm diverging map: 0 blue, 0.5 light grey, 1 red.
Eigen::Vector3f coolWarm(float t) {
    t = std::clamp(std::isfinite(t) ? t : 0.5f, 0.0f, 1.0f);
    const Eigen::Vector3f blue(0.23f, 0.30f, 0.75f), mid(0.87f, 0.87f, 0.87f), red(0.71f, 0.02f, 0.15f);
    return t < 0.5f ? Eigen::Vector3f(blue + (mid - blue) * (2.0f * t))
                    : Eigen::Vector3f(mid + (red - mid) * (2.0f * t - 1.0f));
}

/// Strain colour: compressed blue, at rest grey, stretched red; saturates at ±25 %.
Eigen::Vector4f strainColour(float strain) {
    const float s = std::clamp(std::isfinite(strain) ? strain / 0.25f : 0.0f, -1.0f, 1.0f);
    const Eigen::Vector3f grey(0.7f, 0.7f, 0.72f);
    const Eigen::Vector3f target = s < 0.0f ? Eigen::Vector3f(0.15f, 0.35f, 1.0f) : Eigen::Vector3f(1.0f, 0.15f, 0.1f);
    const Eigen::Vector3f c = grey + (target - grey) * std::abs(s);
    return {c.x(), c.y(), c.z(), 0.85f};
}

template <typename T>
T entry(const std::vector<T>& values, std::size_t i, T fallback) {
    return i < values.size() ? values[i] : fallback;
}

void setFlatLayout() {
    const GLsizei stride = GLsizei(kFlatStride * sizeof(float));
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(3 * sizeof(float)));
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(7 * sizeof(float)));
}

}  // namespace

/// GL objects shared by every object.
struct MeshRenderer::Shared {
    /// Triangles for the flat program, rebuilt on the CPU and uploaded before the next draw that needs them
    /// (the collision planes; the colliders).
    struct FlatTriangles {
        GLuint vao = 0;
        GLuint buffer = 0;
        std::vector<float> vertices;  ///< kFlatStride floats per vertex; uploaded when `dirty`.
        GLsizei count = 0;            ///< Vertices uploaded or pending.
        bool dirty = false;

        void create() {
            glGenVertexArrays(1, &vao);
            glGenBuffers(1, &buffer);
            glBindVertexArray(vao);
            glBindBuffer(GL_ARRAY_BUFFER, buffer);
            setFlatLayout();
        }
        void release() {
            glDeleteVertexArrays(1, &vao);
            glDeleteBuffers(1, &buffer);
        }
        /// After `vertices` was rebuilt.
        void changed() {
            count = GLsizei(vertices.size() / kFlatStride);
            dirty = true;
        }
        /// Uploads if changed and draws, with the flat program already in use.
        void draw() {
            if (dirty) {
                glBindBuffer(GL_ARRAY_BUFFER, buffer);
                glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertices.size() * sizeof(float)), vertices.data(),
                             GL_DYNAMIC_DRAW);
                glBindBuffer(GL_ARRAY_BUFFER, 0);
                dirty = false;
            }
            if (count > 0) {
                glBindVertexArray(vao);
                glDrawArrays(GL_TRIANGLES, 0, count);
            }
        }
    };

    GlProgram mesh;              ///< Deforming vertex shader + shading; also the transform feedback source.
    GlProgram flat;              ///< Overlay points and lines, planes.
    GlProgram background;        ///< Gradient.
    GLuint emptyVao = 0;         ///< For attribute-less draws (background).
    FlatTriangles planes;        ///< Plane quads, translucent.
    FlatTriangles colliders;     ///< Collider triangles, opaque.
};

/// One uploaded mesh and its lattice.
struct MeshRenderer::Object {
    GLuint vao = 0;             ///< Mesh attributes + triangles.
    GLuint attributeBuffer = 0; ///< (u,v,w), cof(A) n_rest per vertex: 6 floats.
    GLuint indexBuffer = 0;
    GLuint nodeTexture = 0;     ///< RGBA32F, node positions relative to `origin`.
    GLuint feedbackBuffer = 0;  ///< Created by the first readDeformed().
    GLuint overlayVao = 0;
    GLuint overlayBuffer = 0;
    GLsizei vertexCount = 0;
    GLsizei indexCount = 0;
    std::array<int, 3> counts{};   ///< Nodes per axis.
    std::array<int, 3> degrees{};  ///< Basis degree per axis.
    int textureWidth = 1;
    int textureHeight = 1;
    std::vector<float> staging;    ///< Texture contents, RGBA per texel.
    Eigen::Vector3f origin = Eigen::Vector3f::Zero(); ///< Node centroid (world, metres).
    std::vector<Vec3> nodes;       ///< Latest node positions (overlay).
    MeshStyle style;
    LatticeOverlay overlay;
    bool overlayVisible = false;
    bool overlayDirty = true;
    bool direct = false;           ///< The attributes hold CPU-deformed positions and normals (setDeformed).
    std::vector<float> directStaging;
    GLsizei overlayLineVertices = 0;
    GLsizei overlayPoints = 0;

    void release() {
        const GLuint buffers[] = {attributeBuffer, indexBuffer, feedbackBuffer, overlayBuffer};
        glDeleteBuffers(4, buffers);
        const GLuint arrays[] = {vao, overlayVao};
        glDeleteVertexArrays(2, arrays);
        glDeleteTextures(1, &nodeTexture);
        vao = overlayVao = attributeBuffer = indexBuffer = feedbackBuffer = overlayBuffer = nodeTexture = 0;
    }
};

MeshRenderer::MeshRenderer() = default;

MeshRenderer::~MeshRenderer() {
    // GL objects need the context; the owner calls release() while it is current. Without it they are
    // left to the context's destruction, which frees them anyway.
}

bool MeshRenderer::isInitialized() const { return m_shared != nullptr; }

Status MeshRenderer::initialize() {
    release();
    const char* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    if (version == nullptr)
        return Status::error("OpenGL: no current context (initialize() needs a current OpenGL 3.3 core context)");
    GLint major = 0, minor = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    if (major * 10 + minor < 33)
        return Status::error(std::string("OpenGL 3.3 core is needed; the current context is ") + version);

    auto shared = std::make_unique<Shared>();
    auto mesh = buildProgram("mesh", shaders::meshVertex(), shaders::meshFragment(), {"vWorldPosition", "vWorldNormal"});
    if (!mesh)
        return Status::error(mesh.message());
    shared->mesh = mesh.value();
    auto flat = buildProgram("overlay", shaders::flatVertex(), shaders::flatFragment());
    if (!flat) {
        shared->mesh.release();
        return Status::error(flat.message());
    }
    shared->flat = flat.value();
    auto background = buildProgram("background", shaders::backgroundVertex(), shaders::backgroundFragment());
    if (!background) {
        shared->mesh.release();
        shared->flat.release();
        return Status::error(background.message());
    }
    shared->background = background.value();
    glUseProgram(shared->mesh.id);
    glUniform1i(shared->mesh.uniform("uNodes"), 0);
    glUseProgram(0);

    glGenVertexArrays(1, &shared->emptyVao);
    shared->planes.create();
    shared->colliders.create();
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    m_shared = std::move(shared);
    if (const GLenum error = glGetError(); error != GL_NO_ERROR)
        return Status::error("OpenGL error " + std::to_string(error) + " while creating the renderer's objects");
    return Status::success();
}

void MeshRenderer::release() {
    clearObjects();
    if (!m_shared)
        return;
    m_shared->mesh.release();
    m_shared->flat.release();
    m_shared->background.release();
    glDeleteVertexArrays(1, &m_shared->emptyVao);
    m_shared->planes.release();
    m_shared->colliders.release();
    m_shared.reset();
}

MeshRenderer::Object* MeshRenderer::find(int object) {
    if (object < 0 || std::size_t(object) >= m_objects.size())
        return nullptr;
    return m_objects[std::size_t(object)].get();
}

int MeshRenderer::objectCount() const { return int(m_objects.size()); }

void MeshRenderer::clearObjects() {
    for (auto& object : m_objects)
        if (object)
            object->release();
    m_objects.clear();
}

Result<int> MeshRenderer::addObject(const Mesh& mesh, const Lattice& lattice) {
    if (!m_shared)
        return Status::error("MeshRenderer::addObject before initialize()");
    if (Status valid = mesh.validate(); !valid)
        return Status::error("cannot draw the mesh: " + valid.message());
    std::vector<Vec3f> computedNormals;
    std::span<const Vec3f> restNormals = mesh.normals;
    if (mesh.normals.size() != mesh.positions.size()) {
        Mesh copy = mesh;
        copy.computeNormals();
        computedNormals = std::move(copy.normals);
        restNormals = computedNormals;
    }

    auto object = std::make_unique<Object>();
    for (int a = 0; a < 3; ++a) {
        object->counts[std::size_t(a)] = lattice.count(a);
        object->degrees[std::size_t(a)] = lattice.axis(a).degree();
    }
    const int nodeCount = lattice.nodeCount();
    object->textureWidth = std::min(nodeCount, kNodeTextureMaxWidth);
    object->textureHeight = (nodeCount + object->textureWidth - 1) / object->textureWidth;
    GLint maxTexture = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTexture);
    if (object->textureHeight > maxTexture)
        return Status::error("the lattice has " + std::to_string(nodeCount) + " nodes; this OpenGL allows textures of " +
                             std::to_string(maxTexture) + " texels per side only");

    // Per vertex: (u,v,w) and m = cof(A) n_rest, normalised, both in double first as core/geometry/binding.cpp.
    const OrientedBox& box = lattice.box();
    const Mat3 A = box.parameterJacobian();
    const Mat3 cofactorA = A.determinant() * A.inverse().transpose();
    std::vector<float> attributes;
    attributes.reserve(mesh.positions.size() * 6);
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const Vec3 uvw = box.toParameters(mesh.positions[v].cast<double>());
        Vec3 m = cofactorA * restNormals[v].cast<double>();
        if (const double len = m.norm(); len > 0.0)
            m /= len;
        attributes.insert(attributes.end(), {float(uvw.x()), float(uvw.y()), float(uvw.z()), float(m.x()),
                                             float(m.y()), float(m.z())});
    }
    object->vertexCount = GLsizei(mesh.positions.size());
    object->indexCount = GLsizei(mesh.triangles.size() * 3);

    glGenVertexArrays(1, &object->vao);
    glGenBuffers(1, &object->attributeBuffer);
    glGenBuffers(1, &object->indexBuffer);
    glBindVertexArray(object->vao);
    glBindBuffer(GL_ARRAY_BUFFER, object->attributeBuffer);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(attributes.size() * sizeof(float)), attributes.data(), GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<const void*>(3 * sizeof(float)));
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, object->indexBuffer);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(mesh.triangles.size() * sizeof(mesh.triangles[0])),
                 mesh.triangles.data(), GL_STATIC_DRAW);
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);

    glGenTextures(1, &object->nodeTexture);
    glBindTexture(GL_TEXTURE_2D, object->nodeTexture);
    // texelFetch ignores filtering, but a texture with mipmap filtering and no mipmaps is incomplete.
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, object->textureWidth, object->textureHeight, 0, GL_RGBA, GL_FLOAT, nullptr);
    glBindTexture(GL_TEXTURE_2D, 0);

    glGenVertexArrays(1, &object->overlayVao);
    glGenBuffers(1, &object->overlayBuffer);
    glBindVertexArray(object->overlayVao);
    glBindBuffer(GL_ARRAY_BUFFER, object->overlayBuffer);
    setFlatLayout();
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);

    if (const GLenum error = glGetError(); error != GL_NO_ERROR) {
        object->release();
        return Status::error("OpenGL error " + std::to_string(error) + " while uploading a mesh of " +
                             std::to_string(mesh.positions.size()) + " vertices");
    }
    m_objects.push_back(std::move(object));
    const int id = int(m_objects.size()) - 1;
    const std::vector<Vec3> rest = lattice.restNodes();
    setNodes(id, rest);
    return id;
}

void MeshRenderer::setNodes(int id, std::span<const Vec3> nodes) {
    Object* object = find(id);
    if (object == nullptr)
        return;
    const std::size_t count = std::size_t(object->counts[0]) * std::size_t(object->counts[1]) * std::size_t(object->counts[2]);
    assert(nodes.size() == count);
    if (nodes.size() != count)
        return;
    // Relative to the centroid, like Binding::evaluate: float keeps its precision far from the origin.
    Vec3 centre = Vec3::Zero();
    for (const Vec3& n : nodes)
        centre += n;
    centre /= double(nodes.size());
    object->origin = centre.cast<float>();
    object->staging.assign(std::size_t(object->textureWidth) * std::size_t(object->textureHeight) * 4, 0.0f);
    for (std::size_t i = 0; i < count; ++i) {
        const Vec3 local = nodes[i] - centre;
        object->staging[4 * i + 0] = float(local.x());
        object->staging[4 * i + 1] = float(local.y());
        object->staging[4 * i + 2] = float(local.z());
    }
    object->nodes.assign(nodes.begin(), nodes.end());
    object->overlayDirty = true;
    glBindTexture(GL_TEXTURE_2D, object->nodeTexture);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, object->textureWidth, object->textureHeight, GL_RGBA, GL_FLOAT,
                    object->staging.data());
    glBindTexture(GL_TEXTURE_2D, 0);
}

void MeshRenderer::setDeformed(int id, std::span<const Vec3f> positions, std::span<const Vec3f> normals,
                               std::span<const Vec3> nodes) {
    Object* object = find(id);
    if (object == nullptr || positions.size() != std::size_t(object->vertexCount) || normals.size() != positions.size())
        return;
    object->directStaging.resize(positions.size() * 6);
    for (std::size_t v = 0; v < positions.size(); ++v) {
        float* out = object->directStaging.data() + 6 * v;
        out[0] = positions[v].x(), out[1] = positions[v].y(), out[2] = positions[v].z();
        out[3] = normals[v].x(), out[4] = normals[v].y(), out[5] = normals[v].z();
    }
    glBindBuffer(GL_ARRAY_BUFFER, object->attributeBuffer);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(object->directStaging.size() * sizeof(float)), object->directStaging.data(),
                 GL_DYNAMIC_DRAW);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    object->direct = true;
    if (nodes.size() == object->nodes.size()) {
        object->nodes.assign(nodes.begin(), nodes.end());
        object->overlayDirty = true;
    }
}

void MeshRenderer::setStyle(int id, const MeshStyle& style) {
    if (Object* object = find(id))
        object->style = style;
}

void MeshRenderer::setOverlay(int id, const LatticeOverlay& overlay) {
    if (Object* object = find(id)) {
        object->overlay = overlay;
        object->overlayDirty = true;
    }
}

void MeshRenderer::setOverlayVisible(int id, bool visible) {
    if (Object* object = find(id))
        object->overlayVisible = visible;
}

void MeshRenderer::uploadOverlay(Object& object) {
    const LatticeOverlay& o = object.overlay;
    std::vector<float> vertices;
    const std::size_t nodeCount = object.nodes.size();
    vertices.reserve((o.springs.size() * 2 + nodeCount) * kFlatStride);
    GLsizei lines = 0;
    for (std::size_t s = 0; s < o.springs.size(); ++s) {
        const auto [a, b] = o.springs[s];
        if (a >= nodeCount || b >= nodeCount)
            continue;
        const Eigen::Vector4f colour = strainColour(entry(o.springStrain, s, 0.0f));
        pushFlat(vertices, object.nodes[a].cast<float>(), colour);
        pushFlat(vertices, object.nodes[b].cast<float>(), colour);
        lines += 2;
    }
    const float size = std::clamp(std::isfinite(o.nodeSizePixels) ? o.nodeSizePixels : 9.0f, 1.0f, 64.0f);
    for (std::size_t i = 0; i < nodeCount; ++i) {
        Eigen::Vector3f colour = o.nodeValue.empty() ? Eigen::Vector3f(0.82f, 0.86f, 0.92f) : coolWarm(entry(o.nodeValue, i, 0.5f));
        float pointSize = size;
        float hollow = 0.0f;
        switch (entry<std::uint8_t>(o.anchor, i, 0)) {
        case 1: colour = Eigen::Vector3f(0.02f, 0.02f, 0.02f); pointSize = size * 1.25f; break;  // pinned
        case 2: colour = Eigen::Vector3f(0.85f, 0.1f, 0.75f); pointSize = size * 1.25f; break;   // heavy
        default: break;
        }
        if (entry<std::uint8_t>(o.isVoid, i, 0) != 0) {
            colour = Eigen::Vector3f(0.6f, 0.6f, 0.6f);
            hollow = 1.0f;
        }
        if (entry<std::uint8_t>(o.selected, i, 0) != 0) {
            colour = Eigen::Vector3f(1.0f, 0.85f, 0.1f);
            pointSize *= 1.4f;
        }
        pushFlat(vertices, object.nodes[i].cast<float>(), {colour.x(), colour.y(), colour.z(), 1.0f}, pointSize, hollow);
    }
    glBindBuffer(GL_ARRAY_BUFFER, object.overlayBuffer);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertices.size() * sizeof(float)), vertices.data(), GL_DYNAMIC_DRAW);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    object.overlayLineVertices = lines;
    object.overlayPoints = GLsizei(nodeCount);
    object.overlayDirty = false;
}

void MeshRenderer::setColliders(std::span<const Collider> colliders) {
    if (!m_shared)
        return;
    std::vector<float>& out = m_shared->colliders.vertices;
    out.clear();
    // A dark slate: it reads against the light grey background the renders use.
    const Eigen::Vector3f stone(0.38f, 0.35f, 0.31f), light = Eigen::Vector3f(-0.5f, 0.7f, 0.6f).normalized();
    // Faceted: each triangle shaded by its own normal, so the shape reads without a lighting program.
    auto triangle = [&](const Vec3& a, const Vec3& b, const Vec3& c) {
        const Eigen::Vector3f n = (b - a).cross(c - a).cast<float>().normalized();
        const float shade = 0.35f + 0.65f * std::max(0.0f, n.allFinite() ? n.dot(light) : 0.0f);
        const Eigen::Vector4f colour(stone.x() * shade, stone.y() * shade, stone.z() * shade, 1.0f);
        for (const Vec3* p : {&a, &b, &c})
            pushFlat(out, p->cast<float>(), colour);
    };
    // Spheres and capsules start from a unit sphere with its poles on y (an odd ring count: no vertex on the
    // equator), scaled by the radius, each half moved out along the axis by the capsule's half length, and
    // turned onto the axis.
    const Mesh unit = makeUvEllipsoid(13, 24, Vec3::Ones());
    for (const Collider& c : colliders) {
        if (c.shape == ColliderShape::Box) {
            Vec3 corner[8];
            for (int k = 0; k < 8; ++k)
                corner[k] = c.centre + c.axes * Vec3((k & 1 ? 1 : -1) * c.halfExtents.x(), (k & 2 ? 1 : -1) * c.halfExtents.y(),
                                                     (k & 4 ? 1 : -1) * c.halfExtents.z());
            const int faces[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
            for (const auto& f : faces) {
                triangle(corner[f[0]], corner[f[1]], corner[f[2]]);
                triangle(corner[f[0]], corner[f[2]], corner[f[3]]);
            }
            continue;
        }
        if (c.shape == ColliderShape::Mesh) {  // the rock itself, placed, turned and scaled
            const Mesh& mesh = c.surface->mesh();
            std::vector<Vec3> p(mesh.positions.size());
            for (std::size_t i = 0; i < p.size(); ++i)
                p[i] = c.centre + c.axes * (c.scale * mesh.positions[i].cast<double>());
            for (const auto& t : mesh.triangles)
                triangle(p[t[0]], p[t[1]], p[t[2]]);
            continue;
        }
        const Vec3 axis = c.shape == ColliderShape::Capsule ? c.axis.normalized() : Vec3::UnitY();
        const Mat3 turn = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitY(), axis).toRotationMatrix();
        std::vector<Vec3> p(unit.positions.size());
        for (std::size_t i = 0; i < p.size(); ++i) {
            const Vec3 u = unit.positions[i].cast<double>();
            const double offset = c.shape == ColliderShape::Capsule ? (u.y() >= 0.0 ? c.halfLength : -c.halfLength) : 0.0;
            p[i] = c.centre + turn * (c.radius * u + offset * Vec3::UnitY());
        }
        for (const auto& t : unit.triangles)
            triangle(p[t[0]], p[t[1]], p[t[2]]);
    }
    m_shared->colliders.changed();
}

void MeshRenderer::setPlanes(std::span<const CollisionPlane> planes, float halfSize) {
    if (!m_shared)
        return;
    std::vector<float>& out = m_shared->planes.vertices;
    out.clear();
    const Eigen::Vector4f colour(0.55f, 0.75f, 0.95f, 0.28f);
    for (const CollisionPlane& plane : planes) {
        const Eigen::Vector3f n = plane.normal.cast<float>().normalized();
        if (!n.allFinite())
            continue;
        const Eigen::Vector3f helper = std::abs(n.y()) < 0.9f ? Eigen::Vector3f::UnitY() : Eigen::Vector3f::UnitX();
        const Eigen::Vector3f t1 = n.cross(helper).normalized() * halfSize;
        const Eigen::Vector3f t2 = n.cross(t1);
        const Eigen::Vector3f c = plane.point.cast<float>();
        const Eigen::Vector3f corners[4] = {c - t1 - t2, c + t1 - t2, c + t1 + t2, c - t1 + t2};
        for (int k : {0, 1, 2, 0, 2, 3})
            pushFlat(out, corners[k], colour);
    }
    m_shared->planes.changed();
}

void MeshRenderer::draw(const Camera& camera, int widthPixels, int heightPixels) {
    if (!m_shared)
        return;
    Shared& sh = *m_shared;
    glViewport(0, 0, widthPixels, heightPixels);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glDepthMask(GL_TRUE);
    glClearColor(0.4f, 0.4f, 0.42f, 1.0f);
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

    glDisable(GL_DEPTH_TEST);
    glUseProgram(sh.background.id);
    glBindVertexArray(sh.emptyVao);
    glDrawArrays(GL_TRIANGLES, 0, 3);

    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    glUseProgram(sh.mesh.id);
    glUniformMatrix4fv(sh.mesh.uniform("uView"), 1, GL_FALSE, camera.view.data());
    glUniformMatrix4fv(sh.mesh.uniform("uProjection"), 1, GL_FALSE, camera.projection.data());
    const GLint colourLocation = sh.mesh.uniform("uColour");
    const GLint alphaLocation = sh.mesh.uniform("uAlpha");
    const GLint flatLocation = sh.mesh.uniform("uFlat");
    glActiveTexture(GL_TEXTURE0);
    auto drawObject = [&](const Object& object, float alpha, bool flat) {
        glUniform1i(sh.mesh.uniform("uNodeTextureWidth"), object.textureWidth);
        glUniform3i(sh.mesh.uniform("uCount"), object.counts[0], object.counts[1], object.counts[2]);
        glUniform3i(sh.mesh.uniform("uDegree"), object.degrees[0], object.degrees[1], object.degrees[2]);
        glUniform3fv(sh.mesh.uniform("uOrigin"), 1, object.origin.data());
        glUniform1i(sh.mesh.uniform("uDirect"), object.direct ? 1 : 0);
        glUniform3fv(colourLocation, 1, object.style.colour.data());
        glUniform1f(alphaLocation, alpha);
        glUniform1i(flatLocation, flat ? 1 : 0);
        glBindTexture(GL_TEXTURE_2D, object.nodeTexture);
        glBindVertexArray(object.vao);
        glDrawElements(GL_TRIANGLES, object.indexCount, GL_UNSIGNED_INT, nullptr);
    };
    // Opaque first, then the translucent planes and X-ray meshes without depth writes.
    for (const auto& object : m_objects) {
        if (object->style.mode == ShadeMode::Shaded) {
            drawObject(*object, 1.0f, false);
        } else if (object->style.mode == ShadeMode::Wireframe) {
            glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
            drawObject(*object, 1.0f, true);
            glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
        }
    }
    // Colliders are opaque: drawn with the meshes, before anything translucent.
    if (sh.colliders.count > 0) {
        glUseProgram(sh.flat.id);
        glUniformMatrix4fv(sh.flat.uniform("uView"), 1, GL_FALSE, camera.view.data());
        glUniformMatrix4fv(sh.flat.uniform("uProjection"), 1, GL_FALSE, camera.projection.data());
        glUniform1i(sh.flat.uniform("uPoints"), 0);
        sh.colliders.draw();
        glUseProgram(sh.mesh.id);
    }
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glDepthMask(GL_FALSE);
    for (const auto& object : m_objects)
        if (object->style.mode == ShadeMode::XRay)
            drawObject(*object, 0.35f, false);

    glUseProgram(sh.flat.id);
    glUniformMatrix4fv(sh.flat.uniform("uView"), 1, GL_FALSE, camera.view.data());
    glUniformMatrix4fv(sh.flat.uniform("uProjection"), 1, GL_FALSE, camera.projection.data());
    const GLint pointsLocation = sh.flat.uniform("uPoints");
    glUniform1i(pointsLocation, 0);
    sh.planes.draw();
    // The lattice overlay stays visible through the mesh: it is what the animator edits.
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_PROGRAM_POINT_SIZE);
    for (const auto& object : m_objects) {
        if (!object->overlayVisible)
            continue;
        if (object->overlayDirty)
            uploadOverlay(*object);
        glBindVertexArray(object->overlayVao);
        glUniform1i(pointsLocation, 0);
        glDrawArrays(GL_LINES, 0, object->overlayLineVertices);
        glUniform1i(pointsLocation, 1);
        glDrawArrays(GL_POINTS, object->overlayLineVertices, object->overlayPoints);
    }
    glDisable(GL_PROGRAM_POINT_SIZE);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glBindVertexArray(0);
    glBindTexture(GL_TEXTURE_2D, 0);
    glUseProgram(0);
}

Status MeshRenderer::readDeformed(int id, std::vector<Vec3f>& positions, std::vector<Vec3f>& normals) {
    Object* object = find(id);
    if (!m_shared || object == nullptr)
        return Status::error("readDeformed: no object " + std::to_string(id));
    const Shared& sh = *m_shared;
    const GLsizeiptr bytes = GLsizeiptr(object->vertexCount) * 6 * GLsizeiptr(sizeof(float));
    if (object->feedbackBuffer == 0) {
        glGenBuffers(1, &object->feedbackBuffer);
        glBindBuffer(GL_TRANSFORM_FEEDBACK_BUFFER, object->feedbackBuffer);
        glBufferData(GL_TRANSFORM_FEEDBACK_BUFFER, bytes, nullptr, GL_STREAM_READ);
    }
    glUseProgram(sh.mesh.id);
    const Eigen::Matrix4f identity = Eigen::Matrix4f::Identity();
    glUniformMatrix4fv(sh.mesh.uniform("uView"), 1, GL_FALSE, identity.data());
    glUniformMatrix4fv(sh.mesh.uniform("uProjection"), 1, GL_FALSE, identity.data());
    glUniform1i(sh.mesh.uniform("uNodeTextureWidth"), object->textureWidth);
    glUniform3i(sh.mesh.uniform("uCount"), object->counts[0], object->counts[1], object->counts[2]);
    glUniform3i(sh.mesh.uniform("uDegree"), object->degrees[0], object->degrees[1], object->degrees[2]);
    glUniform3fv(sh.mesh.uniform("uOrigin"), 1, object->origin.data());
    glUniform1i(sh.mesh.uniform("uDirect"), object->direct ? 1 : 0);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, object->nodeTexture);
    glBindVertexArray(object->vao);
    glEnable(GL_RASTERIZER_DISCARD);
    glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, object->feedbackBuffer);
    glBeginTransformFeedback(GL_POINTS);
    glDrawArrays(GL_POINTS, 0, object->vertexCount);
    glEndTransformFeedback();
    glDisable(GL_RASTERIZER_DISCARD);
    glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, 0);
    std::vector<float> data(std::size_t(object->vertexCount) * 6);
    glBindBuffer(GL_TRANSFORM_FEEDBACK_BUFFER, object->feedbackBuffer);
    glGetBufferSubData(GL_TRANSFORM_FEEDBACK_BUFFER, 0, bytes, data.data());
    glBindBuffer(GL_TRANSFORM_FEEDBACK_BUFFER, 0);
    glBindVertexArray(0);
    glBindTexture(GL_TEXTURE_2D, 0);
    glUseProgram(0);
    if (const GLenum error = glGetError(); error != GL_NO_ERROR)
        return Status::error("OpenGL error " + std::to_string(error) + " while reading back deformed vertices");
    positions.resize(std::size_t(object->vertexCount));
    normals.resize(std::size_t(object->vertexCount));
    for (std::size_t v = 0; v < positions.size(); ++v) {
        positions[v] = Vec3f(data[6 * v + 0], data[6 * v + 1], data[6 * v + 2]);
        normals[v] = Vec3f(data[6 * v + 3], data[6 * v + 4], data[6 * v + 5]);
    }
    return Status::success();
}

void showSceneObject(MeshRenderer& renderer, int id, const SceneSimulation& sim, std::size_t i, std::span<const Vec3> nodes,
                     double seconds, std::vector<Vec3f>& positions, std::vector<Vec3f>& normals) {
    if (!sim.followsBaseAnimation(i)) {
        renderer.setNodes(id, nodes);
        return;
    }
    const std::size_t n = sim.object(i).mesh->positions.size();
    positions.resize(n);
    normals.resize(n);
    sim.evaluateNodes(i, nodes, seconds, positions, normals);
    renderer.setDeformed(id, positions, normals, sim.shownNodes(i, nodes, seconds));
}

}  // namespace softtouch::render

// The shaders SoftTouch ships for game engines (io/shaders/*.glsl) run, not only compiled: in a headless
// OpenGL context (EGL), fed from the exported files alone (the lattice cache's .lattice.glb and .bin; the
// VAT's mesh, EXRs and JSON), their outputs captured by transform feedback and compared with the PC2 and
// the normals of the same bake.
#include "io/documents/project_file.h"
#include "io/export/lattice_cache.h"
#include "io/export/vertex_cache.h"
#include "io/pipeline/bake.h"
#include "render/egl_context.h"
#include "render/gl.h"
#include "render/gl_program.h"

#include "helpers/gltf_read.h"

#include <ImfRgbaFile.h>
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include <QTemporaryDir>
#include <QtTest>

#include <cstring>
#include <fstream>
#include <iterator>

using namespace softtouch;
using softtouch::test::accessorFloats;
using softtouch::test::loadGlb;
namespace fs = std::filesystem;

namespace {

const fs::path kSource = SOFTTOUCH_SOURCE_DIR;
constexpr int kFrames = 6;

std::string readText(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void bakeTo(const Scene& scene, std::string_view format, const fs::path& out) {
    io::BakeOptions options;
    options.output = out;
    options.format = io::findExportFormat(format);
    options.frames = kFrames;
    options.threads = 1;
    const Result<io::BakeResult> result = io::bake(scene, options);
    if (!result)
        qFatal("bake failed: %s", result.message().c_str());
}

/// A fragment stage for linking only: the vertex outputs are captured before rasterisation, which is off.
constexpr const char* kFragment = "#version 430 core\nin vec3 vNormal;\nout vec4 colour;\nvoid main() { colour = vec4(vNormal, 1.0); }\n";

}  // namespace

class TestShippedShaders : public QObject {
    Q_OBJECT
private slots:
    void latticeShaderReproducesTheBake();
    void vatShaderReproducesTheBake();
};

void TestShippedShaders::latticeShaderReproducesTheBake() {
    if (Status s = render::EglContext::probeDriver(); !s)
        QSKIP(qPrintable("no EGL driver: " + QString::fromStdString(s.message())));
    auto created = render::EglContext::create(16, 16, 0);
    QVERIFY2(created, created.message().c_str());
    const std::unique_ptr<render::EglContext> context = std::move(created.value());
    GLint major = 0, minor = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    if (major * 10 + minor < 43)
        QSKIP(qPrintable(QString("the shader needs OpenGL 4.3 (storage buffers); this context has %1.%2").arg(major).arg(minor)));

    // The painted angelfish swims for a few frames; the lattice cache, the PC2 and the GLB (for the
    // bake's own normals) of the same bake.
    QTemporaryDir dir;
    const fs::path folder = dir.path().toStdString();
    const Result<io::Project> project = io::loadProject(kSource / "presets/scenes/angelfish-swim.softtouch");
    QVERIFY2(project, project.message().c_str());
    bakeTo(project->scene, "lattice", folder / "clip");
    bakeTo(project->scene, "pc2", folder / "clip.pc2");
    bakeTo(project->scene, "glb", folder / "normals.glb");
    const Result<io::VertexCache> pc2 = io::readPc2(folder / "clip.pc2");
    QVERIFY2(pc2, pc2.message().c_str());
    const Result<io::LatticeCache> cache = io::readLatticeCache(folder / "clip.lattice.bin");
    QVERIFY2(cache, cache.message().c_str());
    const tinygltf::Model mesh = loadGlb(folder / cache->mesh);
    const tinygltf::Model morphs = loadGlb(folder / "normals.glb");
    const tinygltf::Primitive& morphed = morphs.meshes.at(0).primitives.at(0);
    const std::vector<float> restNormalsAll = accessorFloats(morphs, morphed.attributes.at("NORMAL"));

    const std::string source = readText(kSource / "io/shaders/lattice_deform.glsl");
    QVERIFY(!source.empty());
    auto program = render::buildProgram("lattice_deform", source, kFragment, {"gl_Position", "vNormal"});
    QVERIFY2(program, program.message().c_str());
    const GLuint id = program->id;
    glUseProgram(id);

    // The .bin's node floats, every frame, as the shader's storage buffer (what an engine uploads as is).
    std::vector<float> nodes;
    for (const auto& frame : cache->frames)
        for (const Vec3f& p : frame)
            nodes.insert(nodes.end(), p.data(), p.data() + 3);
    GLuint buffers[4] = {};
    glGenBuffers(4, buffers);
    const GLuint nodeBuffer = buffers[0], uvwBuffer = buffers[1], normalBuffer = buffers[2], captured = buffers[3];
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, nodeBuffer);
    glBufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(nodes.size() * sizeof(float)), nodes.data(), GL_STATIC_DRAW);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, nodeBuffer);
    GLuint vao = 0;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glEnable(GL_RASTERIZER_DISCARD);
    const float identity4[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    const float identity3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    glUniformMatrix4fv(glGetUniformLocation(id, "uModelViewProjection"), 1, GL_FALSE, identity4);
    glUniformMatrix3fv(glGetUniformLocation(id, "uNormalMatrix"), 1, GL_FALSE, identity3);
    glUniform1i(glGetUniformLocation(id, "uNodesPerFrame"), GLint(cache->frames.front().size()));

    double diagonal = 0.0;
    {
        Vec3f lo = Vec3f::Constant(1e30f), hi = -lo;
        for (const auto& frame : pc2->frames)
            for (const Vec3f& p : frame) {
                lo = lo.cwiseMin(p);
                hi = hi.cwiseMax(p);
            }
        diagonal = double((hi - lo).norm());
    }
    double worst = 0.0, worstBlend = 0.0, worstNormal = 0.0, motion = 0.0;
    int firstNode = 0;
    for (std::size_t o = 0; o < cache->objects.size(); ++o) {
        const io::LatticeCacheObject& object = cache->objects[o];
        const std::vector<float> uvw = accessorFloats(mesh, mesh.meshes[0].primitives[o].attributes.at("_LATTICE_UVW"));
        const std::vector<float> normals = accessorFloats(mesh, mesh.meshes[0].primitives[o].attributes.at("NORMAL"));
        const GLsizei count = GLsizei(object.vertexCount);
        glBindBuffer(GL_ARRAY_BUFFER, uvwBuffer);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(uvw.size() * sizeof(float)), uvw.data(), GL_STATIC_DRAW);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
        glEnableVertexAttribArray(0);
        glBindBuffer(GL_ARRAY_BUFFER, normalBuffer);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(normals.size() * sizeof(float)), normals.data(), GL_STATIC_DRAW);
        glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
        glEnableVertexAttribArray(1);
        glBindBuffer(GL_TRANSFORM_FEEDBACK_BUFFER, captured);
        glBufferData(GL_TRANSFORM_FEEDBACK_BUFFER, GLsizeiptr(count) * 7 * GLsizeiptr(sizeof(float)), nullptr, GL_DYNAMIC_READ);
        glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, captured);

        glUniform3i(glGetUniformLocation(id, "uNodeCount"), object.nodes[0], object.nodes[1], object.nodes[2]);
        glUniform3i(glGetUniformLocation(id, "uDegree"), object.degrees[0], object.degrees[1], object.degrees[2]);
        glUniform1i(glGetUniformLocation(id, "uFirstNode"), firstNode);
        const Mat3 axes = object.box.axes;
        const float axesColumns[9] = {float(axes(0, 0)), float(axes(1, 0)), float(axes(2, 0)), float(axes(0, 1)), float(axes(1, 1)),
                                      float(axes(2, 1)), float(axes(0, 2)), float(axes(1, 2)), float(axes(2, 2))};
        glUniformMatrix3fv(glGetUniformLocation(id, "uBoxAxes"), 1, GL_FALSE, axesColumns);
        const Vec3 size = object.box.size;
        glUniform3f(glGetUniformLocation(id, "uBoxSize"), float(size.x()), float(size.y()), float(size.z()));

        // Runs the shader at frames a, b blended by t; returns x y z w nx ny nz per vertex.
        auto run = [&](int a, int b, float t) {
            glUniform1i(glGetUniformLocation(id, "uFrameA"), a);
            glUniform1i(glGetUniformLocation(id, "uFrameB"), b);
            glUniform1f(glGetUniformLocation(id, "uBlend"), t);
            glBeginTransformFeedback(GL_POINTS);
            glDrawArrays(GL_POINTS, 0, count);
            glEndTransformFeedback();
            std::vector<float> out(std::size_t(count) * 7);
            glGetBufferSubData(GL_TRANSFORM_FEEDBACK_BUFFER, 0, GLsizeiptr(out.size() * sizeof(float)), out.data());
            return out;
        };
        for (int f = 0; f < kFrames; ++f) {
            const std::vector<float> out = run(f, f, 0.0f);
            const std::vector<float> normalDeltas = accessorFloats(morphs, morphed.targets.at(std::size_t(f)).at("NORMAL"));
            for (std::size_t v = 0; v < std::size_t(count); ++v) {
                const Vec3f x(out[7 * v], out[7 * v + 1], out[7 * v + 2]);
                QCOMPARE(out[7 * v + 3], 1.0f);
                const Vec3f& expected = pc2->frames[std::size_t(f)][object.firstVertex + v];
                worst = std::max(worst, double((x - expected).norm()));
                motion = std::max(motion, double((expected - pc2->frames[0][object.firstVertex + v]).norm()));
                const std::size_t g = 3 * (object.firstVertex + v);
                const Vec3f baked(restNormalsAll[g] + normalDeltas[g], restNormalsAll[g + 1] + normalDeltas[g + 1],
                                  restNormalsAll[g + 2] + normalDeltas[g + 2]);
                worstNormal = std::max(worstNormal, double((Vec3f(out[7 * v + 4], out[7 * v + 5], out[7 * v + 6]) - baked.normalized()).norm()));
            }
            if (f + 1 < kFrames) {  // halfway to the next frame: the mesh is linear in the nodes
                const std::vector<float> between = run(f, f + 1, 0.5f);
                for (std::size_t v = 0; v < std::size_t(count); ++v) {
                    const Vec3f expected = 0.5f * (pc2->frames[std::size_t(f)][object.firstVertex + v] +
                                                   pc2->frames[std::size_t(f) + 1][object.firstVertex + v]);
                    worstBlend = std::max(worstBlend, double((Vec3f(between[7 * v], between[7 * v + 1], between[7 * v + 2]) - expected).norm()));
                }
            }
        }
        firstNode += object.nodeCount();
    }
    glDeleteVertexArrays(1, &vao);
    glDeleteBuffers(4, buffers);
    program->release();
    qInfo("%s: lattice_deform.glsl against the bake: positions %.3g, halfway blends %.3g of the diagonal; normals %.3g",
          context->description().c_str(), worst / diagonal, worstBlend / diagonal, worstNormal);
    QVERIFY2(motion > 1e-3 * diagonal, "the clip does not move: the comparison would be between rest poses");
    QVERIFY2(worst <= 1e-5 * diagonal, qPrintable(QString("position error %1 of the diagonal").arg(worst / diagonal)));
    QVERIFY2(worstBlend <= 1e-5 * diagonal, qPrintable(QString("blend error %1 of the diagonal").arg(worstBlend / diagonal)));
    QVERIFY2(worstNormal <= 1e-4, qPrintable(QString("normal error %1").arg(worstNormal)));
}

void TestShippedShaders::vatShaderReproducesTheBake() {
    if (Status s = render::EglContext::probeDriver(); !s)
        QSKIP(qPrintable("no EGL driver: " + QString::fromStdString(s.message())));
    auto created = render::EglContext::create(16, 16, 0);
    QVERIFY2(created, created.message().c_str());
    const std::unique_ptr<render::EglContext> context = std::move(created.value());

    QTemporaryDir dir;
    const fs::path folder = dir.path().toStdString();
    const Result<io::Project> project = io::loadProject(kSource / "presets/scenes/angelfish-swim.softtouch");
    QVERIFY2(project, project.message().c_str());
    // Wrapped rows (1,000 texels wide: 4 rows a frame) as well as the default one row per frame.
    for (const int width : {8192, 1000}) {
        io::BakeOptions options;
        options.output = folder / ("clip" + std::to_string(width));
        options.format = io::findExportFormat("vat");
        options.frames = kFrames;
        options.threads = 1;
        options.exportOptions.vatMaxWidth = width;
        QVERIFY(io::bake(project->scene, options));
        const std::string base = options.output.string();
        bakeTo(project->scene, "pc2", folder / "clip.pc2");
        const Result<io::VertexCache> pc2 = io::readPc2(folder / "clip.pc2");
        QVERIFY2(pc2, pc2.message().c_str());
        const nlohmann::json sidecar = nlohmann::json::parse(readText(base + ".vat.json"));
        const int texWidth = sidecar["textureWidth"], texHeight = sidecar["textureHeight"];
        const tinygltf::Model mesh = loadGlb(folder / sidecar["mesh"].get<std::string>());
        const tinygltf::Primitive& primitive = mesh.meshes.at(0).primitives.at(0);
        const std::vector<float> rest = accessorFloats(mesh, primitive.attributes.at("POSITION"));
        const std::vector<float> lookup = accessorFloats(mesh, primitive.attributes.at("TEXCOORD_1"));
        const GLsizei count = GLsizei(rest.size() / 3);
        QCOMPARE(std::size_t(count), pc2->info.pointCount);

        // Each EXR as a float texture, scanline 0 first (GL's t = 0 is glTF's v = 0), nearest, no mipmaps.
        GLuint textures[2] = {};
        glGenTextures(2, textures);
        const std::string names[2] = {base + ".vat-position.exr", base + ".vat-normal.exr"};
        for (int t = 0; t < 2; ++t) {
            Imf::RgbaInputFile file(names[t].c_str());
            const Imath::Box2i window = file.dataWindow();
            QCOMPARE(window.max.x - window.min.x + 1, texWidth);
            QCOMPARE(window.max.y - window.min.y + 1, texHeight);
            std::vector<Imf::Rgba> pixels(std::size_t(texWidth) * std::size_t(texHeight));
            file.setFrameBuffer(pixels.data(), 1, std::size_t(texWidth));
            file.readPixels(window.min.y, window.max.y);
            std::vector<float> rgb;
            rgb.reserve(pixels.size() * 3);
            for (const Imf::Rgba& p : pixels)
                rgb.insert(rgb.end(), {float(p.r), float(p.g), float(p.b)});
            glActiveTexture(GLenum(GL_TEXTURE0 + t));
            glBindTexture(GL_TEXTURE_2D, textures[t]);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
            glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
            glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB32F, texWidth, texHeight, 0, GL_RGB, GL_FLOAT, rgb.data());
        }

        auto program = render::buildProgram("vat_deform", readText(kSource / "io/shaders/vat_deform.glsl"), kFragment,
                                            {"gl_Position", "vNormal"});
        QVERIFY2(program, program.message().c_str());
        const GLuint id = program->id;
        glUseProgram(id);
        glUniform1i(glGetUniformLocation(id, "uOffsets"), 0);
        glUniform1i(glGetUniformLocation(id, "uNormals"), 1);
        glUniform1f(glGetUniformLocation(id, "uFrameRowStep"), sidecar["frameRowStep"].get<float>());
        const float identity4[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
        const float identity3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
        glUniformMatrix4fv(glGetUniformLocation(id, "uModelViewProjection"), 1, GL_FALSE, identity4);
        glUniformMatrix3fv(glGetUniformLocation(id, "uNormalMatrix"), 1, GL_FALSE, identity3);
        GLuint buffers[3] = {}, vao = 0;
        glGenBuffers(3, buffers);
        glGenVertexArrays(1, &vao);
        glBindVertexArray(vao);
        glBindBuffer(GL_ARRAY_BUFFER, buffers[0]);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(rest.size() * sizeof(float)), rest.data(), GL_STATIC_DRAW);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
        glEnableVertexAttribArray(0);
        glBindBuffer(GL_ARRAY_BUFFER, buffers[1]);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(lookup.size() * sizeof(float)), lookup.data(), GL_STATIC_DRAW);
        glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
        glEnableVertexAttribArray(1);
        glBindBuffer(GL_TRANSFORM_FEEDBACK_BUFFER, buffers[2]);
        glBufferData(GL_TRANSFORM_FEEDBACK_BUFFER, GLsizeiptr(count) * 7 * GLsizeiptr(sizeof(float)), nullptr, GL_DYNAMIC_READ);
        glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, buffers[2]);
        glEnable(GL_RASTERIZER_DISCARD);

        double worst = 0.0, allowed = 0.0, motion = 0.0, worstNormalLength = 0.0;
        for (int f = 0; f < kFrames; ++f) {
            glUniform1i(glGetUniformLocation(id, "uFrameA"), f);
            glUniform1i(glGetUniformLocation(id, "uFrameB"), f);
            glUniform1f(glGetUniformLocation(id, "uBlend"), 0.0f);
            glBeginTransformFeedback(GL_POINTS);
            glDrawArrays(GL_POINTS, 0, count);
            glEndTransformFeedback();
            std::vector<float> out(std::size_t(count) * 7);
            glGetBufferSubData(GL_TRANSFORM_FEEDBACK_BUFFER, 0, GLsizeiptr(out.size() * sizeof(float)), out.data());
            for (std::size_t v = 0; v < std::size_t(count); ++v) {
                const Vec3f x(out[7 * v], out[7 * v + 1], out[7 * v + 2]);
                const Vec3f& expected = pc2->frames[std::size_t(f)][v];
                const Vec3f restPosition(rest[3 * v], rest[3 * v + 1], rest[3 * v + 2]);
                // Half precision of the offset (2^-11 relative, 2^-25 m subnormal) plus float rounding.
                const double bound = double((expected - restPosition).norm()) * 1e-3 + 1e-6;
                worst = std::max(worst, double((x - expected).norm()) / bound);
                allowed = std::max(allowed, bound);
                motion = std::max(motion, double((expected - pc2->frames[0][v]).norm()));
                worstNormalLength = std::max(worstNormalLength, std::abs(double(Vec3f(out[7 * v + 4], out[7 * v + 5], out[7 * v + 6]).norm()) - 1.0));
            }
        }
        qInfo("vat_deform.glsl, texture %dx%d: worst position error %.3g of its half-precision bound (at most %.3g m); "
              "normals unit within %.2g", texWidth, texHeight, worst, allowed, worstNormalLength);
        QVERIFY2(motion > 1e-3, "the clip does not move");
        QVERIFY2(worst <= 1.0, qPrintable(QString("a vertex is %1 times its bound away from the bake").arg(worst)));
        QVERIFY(worstNormalLength <= 1e-5);
        glDeleteVertexArrays(1, &vao);
        glDeleteBuffers(3, buffers);
        glDeleteTextures(2, textures);
        program->release();
    }
}

QTEST_GUILESS_MAIN(TestShippedShaders)
#include "test_shipped_shaders.moc"

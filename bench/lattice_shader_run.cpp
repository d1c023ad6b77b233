// lattice-shader-run: plays an exported lattice cache through the shipped engine shader
// (io/shaders/lattice_deform.glsl) on whatever GPU EGL finds, with no window, no Qt and no file
// library but nlohmann-json: a real game's path, runnable on a bare GPU machine. It checks the result
// against the PC2 of the same bake and times the shader at scale (the mesh tiled to millions of vertices).
//
//   lattice-shader-run BASE PC2 [--shader FILE] [--tile T] [--frames-timed N]
//
// BASE.lattice.bin and BASE.lattice.glb as `softtouch-cli bake --format lattice` writes them; PC2 of the
// same bake. Prints the GPU, the worst position error (fraction of the clip's diagonal) and the shader's
// time per frame (GL_TIME_ELAPSED) for BASE's vertices x T. Exit 1 when the error exceeds 1e-5.
#include "render/egl_context.h"
#include "render/gl.h"
#include "render/gl_program.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace {

std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::uint32_t u32(const std::string& bytes, std::size_t at) {
    std::uint32_t v = 0;
    std::memcpy(&v, bytes.data() + at, 4);  // little-endian files, little-endian hosts
    return v;
}

/// The floats of a tightly packed FLOAT accessor of a GLB (JSON chunk, then BIN chunk).
std::vector<float> glbFloats(const std::string& glb, const nlohmann::json& gltf, int accessorIndex) {
    const auto& accessor = gltf["accessors"][std::size_t(accessorIndex)];
    const auto& view = gltf["bufferViews"][accessor["bufferView"].get<std::size_t>()];
    const std::size_t jsonBytes = u32(glb, 12);
    const std::size_t bin = 20 + jsonBytes + 8;
    const std::size_t components = accessor["type"] == "VEC3" ? 3 : accessor["type"] == "VEC2" ? 2 : 1;
    const std::size_t offset = bin + view.value("byteOffset", std::size_t(0)) + accessor.value("byteOffset", std::size_t(0));
    std::vector<float> out(accessor["count"].get<std::size_t>() * components);
    std::memcpy(out.data(), glb.data() + offset, out.size() * sizeof(float));
    return out;
}

constexpr const char* kFragment = "#version 430 core\nin vec3 vNormal;\nout vec4 colour;\nvoid main() { colour = vec4(vNormal, 1.0); }\n";

int fail(const std::string& message) {
    std::fprintf(stderr, "lattice-shader-run: %s\n", message.c_str());
    return 1;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 3)
        return fail("usage: lattice-shader-run BASE PC2 [--shader FILE] [--tile T] [--frames-timed N]");
    const std::string base = argv[1], pc2Path = argv[2];
    std::string shaderPath = SOFTTOUCH_SHADER_DIR "/lattice_deform.glsl";
    int tile = 1, framesTimed = 20;
    for (int i = 3; i + 1 < argc; i += 2) {
        const std::string a = argv[i];
        if (a == "--shader")
            shaderPath = argv[i + 1];
        else if (a == "--tile")
            tile = std::clamp(std::atoi(argv[i + 1]), 1, 100000);
        else if (a == "--frames-timed")
            framesTimed = std::clamp(std::atoi(argv[i + 1]), 1, 100000);
        else
            return fail("unknown option " + a);
    }

    // The cache: header and nodes of the .bin, (u,v,w) and normals of the .glb.
    const std::string bin = readFile(base + ".lattice.bin");
    if (bin.size() < 12 || bin.compare(0, 6, "STLATC") != 0)
        return fail(base + ".lattice.bin is not a lattice cache");
    const std::size_t headerBytes = u32(bin, 8);
    const nlohmann::json header = nlohmann::json::parse(bin.substr(12, headerBytes));
    const std::size_t nodesPerFrame = header["nodesPerFrame"], frames = header["frameCount"];
    std::vector<float> nodes((bin.size() - 12 - headerBytes) / 4);
    std::memcpy(nodes.data(), bin.data() + 12 + headerBytes, nodes.size() * 4);
    const std::string glb = readFile(base + ".lattice.glb");
    const nlohmann::json gltf = nlohmann::json::parse(glb.substr(20, u32(glb, 12)));
    const std::string pc2 = readFile(pc2Path);
    if (pc2.size() < 32 || pc2.compare(0, 11, "POINTCACHE2") != 0)
        return fail(pc2Path + " is not a PC2 file");
    const std::size_t points = u32(pc2, 16);

    auto created = softtouch::render::EglContext::create(16, 16, 0);
    if (!created)
        return fail(created.message());
    const auto context = std::move(created.value());
    auto program = softtouch::render::buildProgram("lattice_deform", readFile(shaderPath), kFragment, {"gl_Position", "vNormal"});
    if (!program)
        return fail(program.message());
    const GLuint id = program->id;
    glUseProgram(id);
    GLuint buffers[4] = {}, vao = 0, query = 0;
    glGenBuffers(4, buffers);
    glGenVertexArrays(1, &vao);
    glGenQueries(1, &query);
    glBindVertexArray(vao);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffers[0]);
    glBufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(nodes.size() * 4), nodes.data(), GL_STATIC_DRAW);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffers[0]);
    glEnable(GL_RASTERIZER_DISCARD);
    const float identity4[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, identity3[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    glUniformMatrix4fv(glGetUniformLocation(id, "uModelViewProjection"), 1, GL_FALSE, identity4);
    glUniformMatrix3fv(glGetUniformLocation(id, "uNormalMatrix"), 1, GL_FALSE, identity3);
    glUniform1i(glGetUniformLocation(id, "uNodesPerFrame"), GLint(nodesPerFrame));

    float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
    for (std::size_t f = 0; f < frames; ++f)
        for (std::size_t v = 0; v < points; ++v)
            for (int c = 0; c < 3; ++c) {
                float x = 0.0f;
                std::memcpy(&x, pc2.data() + 32 + 4 * (3 * (f * points + v) + std::size_t(c)), 4);
                lo[c] = std::min(lo[c], x);
                hi[c] = std::max(hi[c], x);
            }
    const double diagonal = std::sqrt(double(hi[0] - lo[0]) * (hi[0] - lo[0]) + double(hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                      double(hi[2] - lo[2]) * (hi[2] - lo[2]));
    double worst = 0.0;
    std::vector<double> milliseconds, wallMilliseconds;
    std::size_t tiledVertices = 0;
    for (std::size_t o = 0; o < header["objects"].size(); ++o) {
        const nlohmann::json& object = header["objects"][o];
        const auto& attributes = gltf["meshes"][0]["primitives"][o]["attributes"];
        const std::vector<float> uvw = glbFloats(glb, gltf, attributes["_LATTICE_UVW"].get<int>());
        const std::vector<float> normals = glbFloats(glb, gltf, attributes["NORMAL"].get<int>());
        const std::size_t count = uvw.size() / 3, first = object["firstVertex"];
        // Tiled: the same vertices T times over, to time the shader on a mesh T times larger.
        std::vector<float> tiledUvw, tiledNormals;
        for (int t = 0; t < tile; ++t) {
            tiledUvw.insert(tiledUvw.end(), uvw.begin(), uvw.end());
            tiledNormals.insert(tiledNormals.end(), normals.begin(), normals.end());
        }
        const GLsizei n = GLsizei(count * std::size_t(tile));
        tiledVertices += std::size_t(n);
        glBindBuffer(GL_ARRAY_BUFFER, buffers[1]);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(tiledUvw.size() * 4), tiledUvw.data(), GL_STATIC_DRAW);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
        glEnableVertexAttribArray(0);
        glBindBuffer(GL_ARRAY_BUFFER, buffers[2]);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(tiledNormals.size() * 4), tiledNormals.data(), GL_STATIC_DRAW);
        glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
        glEnableVertexAttribArray(1);
        glBindBuffer(GL_TRANSFORM_FEEDBACK_BUFFER, buffers[3]);
        glBufferData(GL_TRANSFORM_FEEDBACK_BUFFER, GLsizeiptr(n) * 7 * 4, nullptr, GL_DYNAMIC_READ);
        glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, buffers[3]);
        const auto& nodeCount = object["nodes"];
        const auto& degree = object["degrees"];
        glUniform3i(glGetUniformLocation(id, "uNodeCount"), nodeCount[0], nodeCount[1], nodeCount[2]);
        glUniform3i(glGetUniformLocation(id, "uDegree"), degree[0], degree[1], degree[2]);
        glUniform1i(glGetUniformLocation(id, "uFirstNode"), object["firstNode"].get<int>());
        float axes[9], size[3];
        for (int c = 0; c < 3; ++c) {
            for (int r = 0; r < 3; ++r)
                axes[3 * c + r] = object["box"]["axes"][std::size_t(c)][std::size_t(r)].get<float>();
            size[c] = object["box"]["size"][std::size_t(c)].get<float>();
        }
        glUniformMatrix3fv(glGetUniformLocation(id, "uBoxAxes"), 1, GL_FALSE, axes);
        glUniform3f(glGetUniformLocation(id, "uBoxSize"), size[0], size[1], size[2]);
        std::vector<float> out(std::size_t(count) * 7);
        for (std::size_t run = 0; run < std::max<std::size_t>(frames, std::size_t(framesTimed)); ++run) {
            const int f = int(run % frames);
            glUniform1i(glGetUniformLocation(id, "uFrameA"), f);
            glUniform1i(glGetUniformLocation(id, "uFrameB"), f);
            glUniform1f(glGetUniformLocation(id, "uBlend"), 0.0f);
            glFinish();
            const auto start = std::chrono::steady_clock::now();
            glBeginQuery(GL_TIME_ELAPSED, query);
            glBeginTransformFeedback(GL_POINTS);
            glDrawArrays(GL_POINTS, 0, n);
            glEndTransformFeedback();
            glEndQuery(GL_TIME_ELAPSED);
            glFinish();
            const double wall = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
            GLuint64 nanoseconds = 0;
            glGetQueryObjectui64v(query, GL_QUERY_RESULT, &nanoseconds);
            if (run >= 2) {  // the first runs include the driver's shader compilation and uploads
                milliseconds.push_back(double(nanoseconds) * 1e-6);
                wallMilliseconds.push_back(wall);
            }
            if (run >= frames)
                continue;
            glGetBufferSubData(GL_TRANSFORM_FEEDBACK_BUFFER, 0, GLsizeiptr(out.size() * 4), out.data());  // first tile
            for (std::size_t v = 0; v < count; ++v) {
                double e2 = 0.0;
                for (int c = 0; c < 3; ++c) {
                    float expected = 0.0f;
                    std::memcpy(&expected, pc2.data() + 32 + 4 * (3 * (std::size_t(f) * points + first + v) + std::size_t(c)), 4);
                    const double d = double(out[7 * v + std::size_t(c)]) - double(expected);
                    e2 += d * d;
                }
                worst = std::max(worst, std::sqrt(e2));
            }
        }
    }
    std::sort(milliseconds.begin(), milliseconds.end());
    std::sort(wallMilliseconds.begin(), wallMilliseconds.end());
    const double median = milliseconds.empty() ? 0.0 : milliseconds[milliseconds.size() / 2];
    const double wallMedian = wallMilliseconds.empty() ? 0.0 : wallMilliseconds[wallMilliseconds.size() / 2];
    std::printf("%s\n", context->description().c_str());
    std::printf("frames %zu, worst position error %.3g of the diagonal\n", frames, worst / diagonal);
    std::printf("%zu vertices (x%d tiles): shader %.3f ms per frame on the GPU's clock (GL_TIME_ELAPSED), %.3f ms from submit "
                "to finish (median of %zu), %.3g million vertices/s by the wall clock\n",
                tiledVertices, tile, median, wallMedian, milliseconds.size(),
                wallMedian > 0 ? double(tiledVertices) / wallMedian * 1e-3 : 0.0);
    return worst <= 1e-5 * diagonal ? 0 : 1;
}

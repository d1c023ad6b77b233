// glTF 2.0 / GLB morph-target animation, written with tinygltf (no hand-written JSON).
//
// One mesh, one primitive: the rest mesh (POSITION, NORMAL, indices) of every object concatenated
// in cache order, and one morph target per frame holding POSITION deltas (frame - rest) and, by
// default, NORMAL deltas. A weights animation on the mesh's node drives the targets: key f at time
// f / fps is target f at weight 1 and every other at 0, with a LINEAR sampler (two targets active
// between keys) or STEP (one active). The deformation at frame f is therefore exactly
// rest + delta_f, which is what the round-trip test re-imports with assimp.
//
// Compressed morphs (ClipExportOptions::gltfMorphError > 0): the frames' deltas are kept until finish(),
// then fitted as their mean (target 0, weight 1 in every key) plus the fewest principal components that
// keep every frame within the error (core/fitting/morph_basis.h); key f holds [1, w_f1 … w_fK]. Normal deltas get
// components fitted to the same weights. The base mesh is the rest mesh, as in every other export.
//
// glTF cannot be streamed: the JSON (written first in a GLB) must know every accessor, so the
// whole binary buffer stays in memory until finish(): about pointCount x 24 bytes per frame
// (12 with normals off). The weights are frames x frames floats. docs/formats.md has the numbers.

#include "core/fitting/morph_basis.h"
#include "io/export/clip_writer_internal.h"
#include "io/export/export_formats.h"
#include "io/export/vertex_cache_internal.h"
#include "io/import/gltf_meshopt.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <sstream>

namespace softtouch::io {

namespace detail {

int addRawAccessor(tinygltf::Model& model, const void* bytes, std::size_t byteCount, std::size_t count, int componentType,
                   int type, int target) {
    std::vector<unsigned char>& data = model.buffers.front().data;
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = data.size();
    view.byteLength = byteCount;
    if (target != 0)
        view.target = target;
    data.resize(data.size() + byteCount);
    if (byteCount != 0)
        std::memcpy(data.data() + view.byteOffset, bytes, byteCount);
    // Every view starts on 4 bytes, so every accessor is aligned to its component size: pad after this one
    // (16-bit indices of an odd number of triangles end on 2).
    data.resize((data.size() + 3) / 4 * 4, 0);
    model.bufferViews.push_back(view);
    tinygltf::Accessor accessor;
    accessor.bufferView = int(model.bufferViews.size() - 1);
    accessor.byteOffset = 0;
    accessor.componentType = componentType;
    accessor.count = count;
    accessor.type = type;
    model.accessors.push_back(accessor);
    return int(model.accessors.size() - 1);
}

int addKeyTimes(tinygltf::Model& model, const ClipSetup& setup, tinygltf::Animation& animation) {
    const std::size_t keys = animationKeys(setup);
    std::vector<float> times(keys);
    for (std::size_t f = 0; f < keys; ++f)
        times[f] = float(double(f) / setup.info.fps);
    if (setup.loops) {
        tinygltf::Value::Object extras;
        extras["loopClosingKey"] = tinygltf::Value(true);
        animation.extras = tinygltf::Value(extras);
    }
    return addFloatAccessor(model, times.data(), keys, 1, false, true);
}

int addFloatAccessor(tinygltf::Model& model, const float* values, std::size_t count, int components,
                     bool vertexAttribute, bool bounds) {
    const int type = components == 1   ? TINYGLTF_TYPE_SCALAR
                     : components == 2 ? TINYGLTF_TYPE_VEC2
                     : components == 3 ? TINYGLTF_TYPE_VEC3
                                       : TINYGLTF_TYPE_VEC4;
    const int index = addRawAccessor(model, values, count * std::size_t(components) * sizeof(float), count,
                                     TINYGLTF_COMPONENT_TYPE_FLOAT, type, vertexAttribute ? TINYGLTF_TARGET_ARRAY_BUFFER : 0);
    tinygltf::Accessor& accessor = model.accessors[std::size_t(index)];
    if (bounds && count > 0) {
        accessor.minValues.assign(std::size_t(components), std::numeric_limits<double>::infinity());
        accessor.maxValues.assign(std::size_t(components), -std::numeric_limits<double>::infinity());
        for (std::size_t i = 0; i < count; ++i) {
            for (std::size_t c = 0; c < std::size_t(components); ++c) {
                const double v = values[i * std::size_t(components) + c];
                accessor.minValues[c] = std::min(accessor.minValues[c], v);
                accessor.maxValues[c] = std::max(accessor.maxValues[c], v);
            }
        }
    }
    return index;
}

int addIndexAccessor(tinygltf::Model& model, std::span<const std::array<std::uint32_t, 3>> triangles,
                     std::uint32_t baseVertex) {
    // 16-bit indices wherever every index lies below 65535 (glTF reserves the type's largest value), as game
    // exporters write them: half the bytes. A fish of 3,656 vertices needs no more.
    std::uint32_t largest = 0;
    for (const auto& t : triangles)
        for (std::uint32_t index : t)
            largest = std::max(largest, index - baseVertex);
    const bool narrow = largest < 65535;
    const std::size_t size = narrow ? sizeof(std::uint16_t) : sizeof(std::uint32_t);
    std::vector<unsigned char> bytes(triangles.size() * 3 * size);
    unsigned char* out = bytes.data();
    for (const auto& t : triangles) {
        for (std::uint32_t index : t) {
            // glTF is little-endian, like every host we build on.
            const std::uint32_t local = index - baseVertex;
            const std::uint16_t local16 = std::uint16_t(local);
            if (narrow)
                std::memcpy(out, &local16, sizeof local16);
            else
                std::memcpy(out, &local, sizeof local);
            out += size;
        }
    }
    return addRawAccessor(model, bytes.data(), bytes.size(), triangles.size() * 3,
                          narrow ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT : TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                          TINYGLTF_TYPE_SCALAR, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
}

Result<std::string> serializeGltf(const tinygltf::Model& model, bool binary, const std::filesystem::path& path,
                                  bool compress, double* targetChange) {
    tinygltf::TinyGLTF gltf;
    std::ostringstream out(std::ios::binary);
    if (!gltf.WriteGltfSceneToStream(&model, out, false, binary))
        return Status::error("cannot write " + quoted(path) + ": tinygltf could not serialise the model");
    if (!compress)
        return out.str();
    auto packed = compressGlb(out.str(), "cannot write " + quoted(path));
    if (!packed)
        return packed.status();
    if (targetChange)
        *targetChange = packed->largestChange;
    return std::move(packed->glb);
}

Status checkCompressible(const std::filesystem::path& path, bool binary, const ClipExportOptions& options) {
    if (options.gltfCompress && !binary)
        return Status::error("cannot write " + quoted(path) + ": --compress packs a GLB's binary chunk; give a .glb path");
    return Status::success();
}

}  // namespace detail

namespace {

/// Spec-guaranteed simultaneously active targets; more may be ignored by some viewers.
constexpr std::size_t kGuaranteedActiveTargets = 8;
/// Targets per mesh above which some runtimes refuse or truncate (Bevy's loader takes at most 64,
/// bevyengine/bevy#8158).
constexpr std::size_t kCommonTargetLimit = 64;

class GltfWriter final : public ClipWriter {
public:
    GltfWriter(bool binary, const ClipExportOptions& options) : m_binary(binary), m_options(options) {}

    Status begin(const std::filesystem::path& path, const ClipSetup& setup) override {
        abort();
        m_warnings.clear();
        if (Status s = detail::checkCacheInfo(path, setup.info); !s)
            return s;
        if (setup.restMesh.positions.size() != setup.info.pointCount ||
            setup.restMesh.normals.size() != setup.info.pointCount)
            return Status::error("cannot write " + detail::quoted(path) + ": the rest mesh has " +
                                 std::to_string(setup.restMesh.positions.size()) + " positions and " +
                                 std::to_string(setup.restMesh.normals.size()) + " normals, expected " +
                                 std::to_string(setup.info.pointCount) + " of each");
        if (setup.info.pointCount > std::numeric_limits<std::uint32_t>::max())
            return Status::error("cannot write " + detail::quoted(path) + ": glTF indices hold at most 2^32 vertices");
        if (Status s = detail::checkCompressible(path, m_binary, m_options); !s)
            return s;
        if (Status s = detail::checkWritable(path); !s)
            return s;
        {
            // One target per frame: the deltas and a frames x frames weight table. Compressed: the deltas
            // twice (kept, then centred) and the frames' Gram matrix.
            const double f = double(setup.info.frameCount), perFrame = double(setup.info.pointCount) * (m_options.gltfNormals ? 24.0 : 12.0);
            const double bytes = compressed() ? 2.0 * f * perFrame + 8.0 * f * f : f * perFrame + 4.0 * f * f;
            if (Status s = detail::checkExportMemory(path, bytes, compressed() ? "a compressed-morph glTF" : "a glTF morph export"); !s)
                return s;
        }
        m_path = path;
        m_setup = setup;
        m_model = std::make_unique<tinygltf::Model>();
        m_model->asset.version = "2.0";
        m_model->asset.generator = "SoftTouch";
        m_model->buffers.emplace_back();

        // One mesh and node per object, each with its own targets, so a DCC or engine sees the objects by
        // name; compressed morphs share one basis over the whole clip: one mesh.
        m_parts.clear();
        if (setup.objects.size() > 1 && !compressed()) {
            for (const ClipObject& o : setup.objects)
                m_parts.push_back({o.name, o.firstVertex, o.vertexCount, o.firstTriangle, o.triangleCount});
        } else {
            m_parts.push_back({setup.objects.size() == 1 ? setup.objects.front().name : std::string("clip"), 0,
                               std::uint32_t(setup.info.pointCount), 0, std::uint32_t(setup.restMesh.triangles.size())});
        }
        for (const Part& part : m_parts) {
            tinygltf::Primitive primitive;
            primitive.mode = TINYGLTF_MODE_TRIANGLES;
            primitive.attributes["POSITION"] = detail::addFloatAccessor(
                *m_model, setup.restMesh.positions[part.firstVertex].data(), part.vertexCount, 3, true, true);
            primitive.attributes["NORMAL"] = detail::addFloatAccessor(
                *m_model, setup.restMesh.normals[part.firstVertex].data(), part.vertexCount, 3, true, false);
            primitive.indices = detail::addIndexAccessor(
                *m_model, std::span(setup.restMesh.triangles).subspan(part.firstTriangle, part.triangleCount), part.firstVertex);
            tinygltf::Mesh mesh;
            mesh.name = part.name;
            mesh.primitives.push_back(primitive);
            m_model->meshes.push_back(mesh);
        }
        m_delta.resize(setup.info.pointCount);
        m_framesWritten = 0;
        m_notes.clear();
        m_positionDeltas.clear();
        m_normalDeltas.clear();
        if (compressed()) {
            const std::size_t values = 3 * setup.info.pointCount;
            if (setup.info.frameCount > std::numeric_limits<std::size_t>::max() / 4 / values / 2)
                return Status::error("cannot write " + detail::quoted(path) + ": the clip is too large to compress in memory");
            m_positionDeltas.reserve(setup.info.frameCount * values);
            if (m_options.gltfNormals)
                m_normalDeltas.reserve(setup.info.frameCount * values);
        }
        return Status::success();
    }

    Status writeFrame(const FrameData& frame) override {
        if (!m_model)
            return Status::error("no glTF is being written: begin() was not called or the write failed");
        if (Status s = checkFrameData(m_path, m_framesWritten, m_setup, frame, m_options.gltfNormals, false); !s) {
            abort();
            return s;
        }
        const Mesh& rest = m_setup.restMesh;
        if (compressed()) {  // kept until finish(), where the basis is fitted to every frame
            for (std::size_t v = 0; v < m_delta.size(); ++v) {
                const Vec3f d = frame.positions[v] - rest.positions[v];
                m_positionDeltas.insert(m_positionDeltas.end(), d.data(), d.data() + 3);
                if (m_options.gltfNormals) {
                    const Vec3f n = frame.normals[v] - rest.normals[v];
                    m_normalDeltas.insert(m_normalDeltas.end(), n.data(), n.data() + 3);
                }
            }
            ++m_framesWritten;
            return Status::success();
        }
        for (std::size_t p = 0; p < m_parts.size(); ++p) {
            const Part& part = m_parts[p];
            std::map<std::string, int> target;
            for (std::size_t v = part.firstVertex; v < part.firstVertex + part.vertexCount; ++v)
                m_delta[v] = frame.positions[v] - rest.positions[v];
            target["POSITION"] = detail::addFloatAccessor(*m_model, m_delta[part.firstVertex].data(), part.vertexCount, 3, true, true);
            if (m_options.gltfNormals) {
                for (std::size_t v = part.firstVertex; v < part.firstVertex + part.vertexCount; ++v)
                    m_delta[v] = frame.normals[v] - rest.normals[v];
                target["NORMAL"] = detail::addFloatAccessor(*m_model, m_delta[part.firstVertex].data(), part.vertexCount, 3, true, false);
            }
            m_model->meshes[p].primitives.front().targets.push_back(std::move(target));
        }
        ++m_framesWritten;
        return Status::success();
    }

    Status finish() override {
        if (!m_model)
            return Status::error("no glTF is being written: begin() was not called or the write failed");
        const std::size_t frames = m_setup.info.frameCount;
        if (m_framesWritten != frames) {
            Status s = detail::frameCountMismatch(m_path, m_framesWritten, frames);
            abort();
            return s;
        }
        // Key f's weights, one row per key: frame f's target alone, or [1, w_f1 … w_fK] when compressed.
        std::vector<float> weights;
        std::size_t targets = frames;
        tinygltf::Value::Array names;
        if (compressed()) {
            targets = addCompressedTargets(weights, names);
        } else {
            weights.assign(frames * frames, 0.0f);
            for (std::size_t f = 0; f < frames; ++f) {
                weights[f * frames + f] = 1.0f;
                std::string number = std::to_string(f);
                names.emplace_back(std::string("frame_") + std::string(number.size() < 4 ? 4 - number.size() : 0, '0') + number);
            }
        }
        tinygltf::Scene scene;
        for (std::size_t p = 0; p < m_model->meshes.size(); ++p) {
            tinygltf::Mesh& mesh = m_model->meshes[p];
            mesh.weights.assign(weights.begin(), weights.begin() + std::ptrdiff_t(targets));  // shown without the animation: frame 0
            tinygltf::Value::Object extras;
            extras["targetNames"] = tinygltf::Value(names);  // the de-facto convention Blender and three.js read
            mesh.extras = tinygltf::Value(extras);
            tinygltf::Node node;
            node.mesh = int(p);
            node.name = mesh.name;
            m_model->nodes.push_back(node);
            scene.nodes.push_back(int(p));
        }
        m_model->scenes.push_back(scene);
        m_model->defaultScene = 0;

        // Key f at f / fps; a loop closes with key `frames` = key 0 (ClipSetup::loops).
        warnAboutTargets(weights, targets);
        if (m_setup.loops)
            weights.insert(weights.end(), weights.begin(), weights.begin() + std::ptrdiff_t(targets));
        tinygltf::Animation animation;
        animation.name = "clip";
        tinygltf::AnimationSampler sampler;
        sampler.input = detail::addKeyTimes(*m_model, m_setup, animation);
        sampler.output = detail::addFloatAccessor(*m_model, weights.data(), weights.size(), 1, false, false);
        sampler.interpolation = m_options.gltfLinear ? "LINEAR" : "STEP";
        animation.samplers.push_back(sampler);
        for (std::size_t p = 0; p < m_model->nodes.size(); ++p) {  // every object keys the same frames
            tinygltf::AnimationChannel channel;
            channel.sampler = 0;
            channel.target_node = int(p);
            channel.target_path = "weights";
            animation.channels.push_back(channel);
        }
        m_model->animations.push_back(animation);

        double targetChange = 0.0;
        Result<std::string> bytes = detail::serializeGltf(*m_model, m_binary, m_path, m_options.gltfCompress, &targetChange);
        m_model.reset();
        if (!bytes)
            return Status::error(bytes.message());
        if (targetChange > 0.0) {
            // A vertex moves by Σ weight × delta, so packing moves it by at most √3 × the heaviest key's Σ|weight| ×
            // the largest change of a delta component.
            double heaviest = 0.0;
            for (std::size_t f = 0; f < frames; ++f) {
                double sum = 0.0;
                for (std::size_t t = 0; t < targets; ++t)
                    sum += std::abs(double(weights[f * targets + t]));
                heaviest = std::max(heaviest, sum);
            }
            const double diagonal = std::max(1e-12, m_setup.restMesh.bounds().diagonal());
            char line[200];
            std::snprintf(line, sizeof line, "packed: morph-target deltas within %.2g m (16-bit mantissas), so every vertex "
                          "within %.2g of the diagonal of the unpacked file", targetChange, std::sqrt(3.0) * heaviest * targetChange / diagonal);
            m_notes.push_back(detail::quoted(m_path) + ": " + line);
        }
        std::vector<std::unique_ptr<detail::StagedFile>> files;
        files.push_back(std::make_unique<detail::StagedFile>(m_path));
        if (Status s = files.front()->write(bytes.value()); !s)
            return s;
        if (compressed() || m_options.gltfCompress) {
            const double pc2Bytes = 32.0 + double(frames) * double(m_setup.info.pointCount) * 12.0;
            char line[200];
            std::snprintf(line, sizeof line, "%zu bytes, %.1f%% of a PC2 of the same clip (%.0f bytes)", bytes.value().size(),
                          100.0 * double(bytes.value().size()) / pc2Bytes, pc2Bytes);
            m_notes.push_back(detail::quoted(m_path) + ": " + line);
        }
        return detail::publishAll(files);
    }

    void abort() override {
        m_model.reset();
        m_framesWritten = 0;
        m_positionDeltas.clear();
        m_positionDeltas.shrink_to_fit();
        m_normalDeltas.clear();
        m_normalDeltas.shrink_to_fit();
        m_delta.clear();
        m_delta.shrink_to_fit();
    }

    bool needsNormals() const override { return m_options.gltfNormals; }

private:
    /// One object's range of the rest mesh: its own glTF mesh and node.
    struct Part {
        std::string name;
        std::uint32_t firstVertex, vertexCount, firstTriangle, triangleCount;
    };

    bool compressed() const { return m_options.gltfMorphError > 0.0; }

    /// Fits the compressed basis to the kept frames and adds its targets (mean first); fills the keys'
    /// weights and the targets' names, and returns the number of targets.
    std::size_t addCompressedTargets(std::vector<float>& weights, tinygltf::Value::Array& names) {
        const std::size_t frames = m_setup.info.frameCount, values = 3 * m_setup.info.pointCount;
        const double diagonal = std::max(1e-12, m_setup.restMesh.bounds().diagonal());
        MorphBasis basis = fitMorphBasis(m_positionDeltas, frames, values, m_options.gltfMorphError * diagonal,
                                               std::size_t(std::max(1, m_options.gltfMaxMorphs)));
        m_positionDeltas.clear();
        m_positionDeltas.shrink_to_fit();
        MorphBasis normals;
        if (m_options.gltfNormals) {
            normals = fitMorphComponentsFor(basis, m_normalDeltas, frames, values);
            m_normalDeltas.clear();
            m_normalDeltas.shrink_to_fit();
        }
        // Weights in [0, 1]: each component's lowest weight goes into the mean target and its range into
        // the target, w' = (w − lo) / (hi − lo). The motion is the same; importers that clamp negative
        // weights (assimp 5.2 reads them as 0) or sliders that start at 0 (Blender's shape keys) play it.
        for (std::size_t k = 0; k < basis.components.size(); ++k) {
            float low = basis.weights[0][k], high = low;
            for (const auto& row : basis.weights) {
                low = std::min(low, row[k]);
                high = std::max(high, row[k]);
            }
            const float range = high > low ? high - low : 1.0f;
            for (MorphBasis* b : {&basis, m_options.gltfNormals ? &normals : nullptr}) {
                if (!b)
                    continue;
                for (std::size_t j = 0; j < values; ++j) {
                    b->mean[j] += low * b->components[k][j];
                    b->components[k][j] *= range;
                }
            }
            for (auto& row : basis.weights)
                row[k] = (row[k] - low) / range;
        }
        auto addTarget = [&](const std::vector<float>& position, const std::vector<float>* normal) {
            std::map<std::string, int> target;
            target["POSITION"] = detail::addFloatAccessor(*m_model, position.data(), m_setup.info.pointCount, 3, true, true);
            if (normal)
                target["NORMAL"] = detail::addFloatAccessor(*m_model, normal->data(), m_setup.info.pointCount, 3, true, false);
            m_model->meshes.front().primitives.front().targets.push_back(std::move(target));
        };
        addTarget(basis.mean, m_options.gltfNormals ? &normals.mean : nullptr);
        names.emplace_back(std::string("mean"));
        for (std::size_t k = 0; k < basis.components.size(); ++k) {
            addTarget(basis.components[k], m_options.gltfNormals ? &normals.components[k] : nullptr);
            names.emplace_back("component_" + std::to_string(k + 1));
        }
        const std::size_t targets = basis.components.size() + 1;
        weights.assign(frames * targets, 0.0f);
        for (std::size_t f = 0; f < frames; ++f) {
            weights[f * targets] = 1.0f;
            for (std::size_t k = 0; k + 1 < targets; ++k)
                weights[f * targets + k + 1] = basis.weights[f][k];
        }
        char line[300];
        std::snprintf(line, sizeof line,
                      "compressed morphs: the mean and %zu component%s for %zu frames (weights in [0, 1]); worst frame RMS "
                      "error %.3g, worst vertex error %.3g of the diagonal (target %.3g)",
                      basis.components.size(), basis.components.size() == 1 ? "" : "s", frames, basis.worstFrameRms / diagonal, basis.worstVertexError / diagonal,
                      m_options.gltfMorphError);
        m_notes.push_back(detail::quoted(m_path) + ": " + line);
        if (basis.worstFrameRms > m_options.gltfMorphError * diagonal)
            m_warnings.push_back(detail::quoted(m_path) + ": " + std::to_string(basis.components.size()) +
                                 " components (the most allowed) miss the error target; allow more with --targets or raise --error");
        return targets;
    }

    /// Counts the targets the sampler makes active at once (a key's non-zero weights, and with
    /// LINEAR the union of two neighbouring keys) and warns past what engines guarantee.
    void warnAboutTargets(const std::vector<float>& weights, std::size_t targets) {
        std::size_t mostActive = 0;
        const std::size_t keys = targets > 0 ? weights.size() / targets : 0;
        for (std::size_t k = 0; k < keys; ++k) {
            std::size_t active = 0;
            for (std::size_t t = 0; t < targets; ++t) {
                const bool here = weights[k * targets + t] != 0.0f;
                const bool next = m_options.gltfLinear && k + 1 < keys && weights[(k + 1) * targets + t] != 0.0f;
                active += (here || next) ? 1 : 0;
            }
            mostActive = std::max(mostActive, active);
        }
        const std::string file = detail::quoted(m_path);
        if (mostActive > kGuaranteedActiveTargets)
            m_warnings.push_back(file + ": up to " + std::to_string(mostActive) +
                                 " morph targets are active at once; glTF viewers only guarantee " +
                                 std::to_string(kGuaranteedActiveTargets) + ", so some will drop targets");
        if (targets > kCommonTargetLimit)
            m_warnings.push_back(file + ": " + std::to_string(targets) + " morph targets (one per frame) in one mesh; " +
                                 "at most " + std::to_string(mostActive) + " are active at once, but some runtimes load only " +
                                 std::to_string(kCommonTargetLimit) + " targets per mesh (Bevy), so prefer VAT or the " +
                                 "lattice cache for long clips");
    }

    bool m_binary;
    ClipExportOptions m_options;
    std::filesystem::path m_path;
    ClipSetup m_setup;                         ///< Copied by begin().
    std::unique_ptr<tinygltf::Model> m_model;  ///< The whole file until finish() (glTF cannot stream).
    std::vector<Vec3f> m_delta;                ///< One frame's deltas, reused.
    std::vector<Part> m_parts;                 ///< The meshes written: one per object, or the whole rest mesh.
    std::vector<float> m_positionDeltas;       ///< Compressed morphs: every frame's position deltas until finish().
    std::vector<float> m_normalDeltas;         ///< Compressed morphs: every frame's normal deltas until finish().
    std::size_t m_framesWritten = 0;
};

}  // namespace

namespace detail {

std::unique_ptr<ClipWriter> makeGltfWriter(bool binary, const ClipExportOptions& options) {
    return std::make_unique<GltfWriter>(binary, options);
}

namespace {

/// glTF options that ask for bones (skinError or skinBones) get the skinned writer.
std::unique_ptr<ClipWriter> gltfOrSkin(bool binary, const ClipExportOptions& options) {
    if (options.skinError > 0.0 || options.skinBones > 0)
        return makeSkinWriter(binary, options);
    return makeGltfWriter(binary, options);
}

}  // namespace

/// The "gltf" and "glb" exports (io/export/export_formats.cpp): named, the name decides the file kind.
std::unique_ptr<ClipWriter> makeGltfExport(const std::filesystem::path&, const ClipExportOptions& options) {
    return gltfOrSkin(false, options);
}
std::unique_ptr<ClipWriter> makeGlbExport(const std::filesystem::path&, const ClipExportOptions& options) {
    return gltfOrSkin(true, options);
}
/// The "pca" export: glTF JSON for a .gltf path, GLB otherwise.
std::unique_ptr<ClipWriter> makeCompressedMorphExport(const std::filesystem::path& path, const ClipExportOptions& options) {
    return gltfOrSkin(!writesGltfJson(path), options);
}

}  // namespace detail

}  // namespace softtouch::io

// glTF 2.0 / GLB skinned export: the clip as linear blend skinning with rigid bones (core/fitting/skin_fit.h),
// the path every engine plays. Written with tinygltf.
//
// One mesh, one primitive: the rest mesh (POSITION, NORMAL, indices, the same bytes as the other
// exports' rest mesh) plus JOINTS_0 (UNSIGNED_SHORT x 4) and WEIGHTS_0 (FLOAT x 4, ≥ 0, summing to 1);
// compressed (--compress, io/import/gltf_meshopt.h), UNSIGNED_BYTE x 4 both, the weights normalized.
// Node 0 holds the mesh and the skin; nodes 1..K are the bones, flat under the scene, each with a
// translation and rotation channel sampled at every frame (LINEAR: slerp between keys). The inverse
// bind matrices are identities, because each bone's transform maps the rest pose itself: vertex =
// Σ w_j (R_j rest + T_j). Bone nodes hold frame 0's transform, so a viewer that ignores the animation
// shows frame 0.
//
// The frames stay in memory until finish(), where the bones are fitted: 12 bytes per vertex per frame.

#include "core/fitting/skin_fit.h"
#include "io/export/clip_writer_internal.h"
#include "io/export/export_formats.h"
#include "io/export/vertex_cache_internal.h"

#include <tiny_gltf.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

namespace softtouch::io {

namespace {

/// Levels of the 8-bit normalized weights a compressed file stores.
constexpr int kWeightSteps = 255;

class SkinWriter final : public ClipWriter {
public:
    SkinWriter(bool binary, const ClipExportOptions& options) : m_binary(binary), m_options(options) {}

    Status begin(const std::filesystem::path& path, const ClipSetup& setup) override {
        abort();
        m_warnings.clear();
        m_notes.clear();
        if (Status s = detail::checkCacheInfo(path, setup.info); !s)
            return s;
        if (setup.restMesh.positions.size() != setup.info.pointCount || setup.restMesh.normals.size() != setup.info.pointCount)
            return Status::error("cannot write " + detail::quoted(path) + ": the rest mesh does not match the clip's vertex count");
        if (setup.info.frameCount > std::numeric_limits<std::size_t>::max() / 16 / std::max<std::size_t>(1, setup.info.pointCount))
            return Status::error("cannot write " + detail::quoted(path) + ": the clip is too large to fit bones to in memory");
        if (Status s = detail::checkCompressible(path, m_binary, m_options); !s)
            return s;
        if (Status s = detail::checkWritable(path); !s)
            return s;
        if (Status s = detail::checkExportMemory(path, double(setup.info.frameCount) * double(setup.info.pointCount) * 12.0,
                                                 "a skinned glTF export");
            !s)
            return s;
        m_path = path;
        m_setup = setup;
        m_frames.clear();
        m_frames.reserve(setup.info.frameCount);
        m_started = true;
        return Status::success();
    }

    Status writeFrame(const FrameData& frame) override {
        if (!m_started)
            return Status::error("no skinned glTF is being written: begin() was not called or the write failed");
        if (Status s = checkFrameData(m_path, m_frames.size(), m_setup, frame, false, false); !s) {
            abort();
            return s;
        }
        m_frames.emplace_back(frame.positions.begin(), frame.positions.end());
        return Status::success();
    }

    Status finish() override {
        if (!m_started)
            return Status::error("no skinned glTF is being written: begin() was not called or the write failed");
        const std::size_t frames = m_setup.info.frameCount, n = m_setup.info.pointCount;
        if (m_frames.size() != frames) {
            Status s = detail::frameCountMismatch(m_path, m_frames.size(), frames);
            abort();
            return s;
        }
        const std::vector<Vec3f>& rest = m_setup.restMesh.positions;
        const double diagonal = std::max(1e-12, m_setup.restMesh.bounds().diagonal());

        // The bones: a fixed count, or the fewest of 8, 16, 32, 64 that meet the error target. A compressed
        // file stores 8-bit weights, and its error is measured with them.
        auto fit = [&](int bones) {
            SkinFit fitted = fitRigidSkin(rest, m_frames, bones);
            if (m_options.gltfCompress) {
                roundSkinWeights(fitted, kWeightSteps);
                measureSkinError(fitted, rest, m_frames);
            }
            return fitted;
        };
        SkinFit skin;
        if (m_options.skinBones > 0) {
            skin = fit(m_options.skinBones);
        } else {
            for (int bones : {8, 16, 32, 64}) {
                skin = fit(bones);
                if (skin.rmsError <= m_options.skinError * diagonal)
                    break;
            }
            if (skin.rmsError > m_options.skinError * diagonal)
                m_warnings.push_back(detail::quoted(m_path) + ": 64 bones miss the error target (RMS " +
                                     std::to_string(skin.rmsError / diagonal) + " of the diagonal); the clip bends more "
                                     "finely than rigid bones follow: use PCA morphs, VAT or the lattice cache");
        }
        m_frames.clear();
        m_frames.shrink_to_fit();
        const std::size_t k = std::size_t(skin.bones);

        tinygltf::Model model;
        model.asset.version = "2.0";
        model.asset.generator = "SoftTouch";
        model.buffers.emplace_back();
        tinygltf::Primitive primitive;
        primitive.mode = TINYGLTF_MODE_TRIANGLES;
        primitive.attributes["POSITION"] = detail::addFloatAccessor(model, rest.front().data(), n, 3, true, true);
        primitive.attributes["NORMAL"] = detail::addFloatAccessor(model, m_setup.restMesh.normals.front().data(), n, 3, true, false);
        primitive.indices = detail::addIndexAccessor(model, m_setup.restMesh.triangles, 0);
        std::vector<std::uint16_t> joints(4 * n);
        std::vector<float> weights(4 * n);
        for (std::size_t i = 0; i < n; ++i) {
            // Unused slots: joint 0 at weight 0. Weights renormalised in float so they sum to 1 there.
            float sum = 0.0f;
            for (std::size_t s = 0; s < 4; ++s)
                sum += skin.weights[i][s];
            for (std::size_t s = 0; s < 4; ++s) {
                const float w = skin.weights[i][s] / sum;
                joints[4 * i + s] = w > 0.0f ? skin.joints[i][s] : std::uint16_t(0);
                weights[4 * i + s] = w;
            }
        }
        if (m_options.gltfCompress && k <= 256) {
            // Bytes, as engines ship them: joints exactly, weights as the multiples of 1/255 the fit was
            // measured with (roundSkinWeights), summing to exactly 255.
            std::vector<std::uint8_t> joint8(4 * n), weight8(4 * n);
            for (std::size_t e = 0; e < 4 * n; ++e) {
                joint8[e] = std::uint8_t(joints[e]);
                weight8[e] = std::uint8_t(std::lround(double(skin.weights[e / 4][e % 4]) * kWeightSteps));
            }
            primitive.attributes["JOINTS_0"] = detail::addRawAccessor(model, joint8.data(), joint8.size(), n,
                                                              TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_VEC4,
                                                              TINYGLTF_TARGET_ARRAY_BUFFER);
            primitive.attributes["WEIGHTS_0"] = detail::addRawAccessor(model, weight8.data(), weight8.size(), n,
                                                               TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_VEC4,
                                                               TINYGLTF_TARGET_ARRAY_BUFFER);
            model.accessors.back().normalized = true;
        } else {
            primitive.attributes["JOINTS_0"] = detail::addRawAccessor(model, joints.data(), joints.size() * 2, n,
                                                              TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_VEC4,
                                                              TINYGLTF_TARGET_ARRAY_BUFFER);
            primitive.attributes["WEIGHTS_0"] = detail::addFloatAccessor(model, weights.data(), n, 4, true, false);
        }
        tinygltf::Mesh mesh;
        mesh.name = m_setup.objects.size() == 1 ? m_setup.objects.front().name : std::string("clip");
        mesh.primitives.push_back(primitive);
        model.meshes.push_back(mesh);

        tinygltf::Node meshNode;
        meshNode.name = mesh.name;
        meshNode.mesh = 0;
        meshNode.skin = 0;
        model.nodes.push_back(meshNode);
        tinygltf::Skin gltfSkin;
        gltfSkin.name = "bones";
        std::vector<float> identities(16 * k, 0.0f);
        for (std::size_t j = 0; j < k; ++j)
            for (int d = 0; d < 4; ++d)
                identities[16 * j + std::size_t(5 * d)] = 1.0f;
        gltfSkin.inverseBindMatrices = detail::addRawAccessor(model, identities.data(), identities.size() * 4, k,
                                                      TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_MAT4, 0);

        // Per bone: translations and rotations at every frame, quaternions kept in one hemisphere so
        // that slerp between keys takes the short way.
        // Key f at f / fps; a loop closes with key `frames` = key 0 (ClipSetup::loops).
        const std::size_t keys = detail::animationKeys(m_setup);
        tinygltf::Animation animation;
        animation.name = "clip";
        const int timeAccessor = detail::addKeyTimes(model, m_setup, animation);
        tinygltf::Scene scene;
        scene.nodes.push_back(0);
        // The bones hang under one still root, so the joints have a common root (the Khronos validator's
        // SKIN_NO_COMMON_ROOT is an error, and pipelines that gate on it reject the file) and an importer
        // builds one armature. The root is the identity, so each bone's keys stay world transforms.
        tinygltf::Node root;
        root.name = "softtouch_skeleton";
        model.nodes.push_back(root);
        const int rootNode = int(model.nodes.size() - 1);
        scene.nodes.push_back(rootNode);
        gltfSkin.skeleton = rootNode;
        for (std::size_t j = 0; j < k; ++j) {
            std::vector<float> translation(3 * keys), rotation(4 * keys);
            Eigen::Quaterniond previous = Eigen::Quaterniond::Identity();
            for (std::size_t f = 0; f < keys; ++f) {
                const BoneTransform& t = skin.transforms[f % frames][j];
                Eigen::Quaterniond q(t.rotation);
                q.normalize();
                if (f > 0 && q.dot(previous) < 0.0)
                    q.coeffs() = -q.coeffs();
                previous = q;
                for (int a = 0; a < 3; ++a)
                    translation[3 * f + std::size_t(a)] = float(t.translation[a]);
                rotation[4 * f + 0] = float(q.x());
                rotation[4 * f + 1] = float(q.y());
                rotation[4 * f + 2] = float(q.z());
                rotation[4 * f + 3] = float(q.w());
            }
            tinygltf::Node bone;
            char name[32];
            std::snprintf(name, sizeof name, "bone_%02zu", j + 1);
            bone.name = name;
            bone.translation = {translation[0], translation[1], translation[2]};
            bone.rotation = {rotation[0], rotation[1], rotation[2], rotation[3]};
            model.nodes.push_back(bone);
            const int node = int(model.nodes.size() - 1);
            gltfSkin.joints.push_back(node);
            model.nodes[std::size_t(rootNode)].children.push_back(node);
            for (const auto& [path, values, components] :
                 {std::tuple<const char*, const std::vector<float>*, int>{"translation", &translation, 3},
                  {"rotation", &rotation, 4}}) {
                tinygltf::AnimationSampler sampler;
                sampler.input = timeAccessor;
                sampler.output = detail::addFloatAccessor(model, values->data(), keys, components, false, false);
                sampler.interpolation = "LINEAR";
                animation.samplers.push_back(sampler);
                tinygltf::AnimationChannel channel;
                channel.sampler = int(animation.samplers.size() - 1);
                channel.target_node = node;
                channel.target_path = path;
                animation.channels.push_back(channel);
            }
        }
        model.skins.push_back(gltfSkin);
        model.animations.push_back(animation);
        model.scenes.push_back(scene);
        model.defaultScene = 0;

        Result<std::string> bytes = detail::serializeGltf(model, m_binary, m_path, m_options.gltfCompress);
        m_started = false;
        if (!bytes)
            return Status::error(bytes.message());
        std::vector<std::unique_ptr<detail::StagedFile>> files;
        files.push_back(std::make_unique<detail::StagedFile>(m_path));
        if (Status s = files.front()->write(bytes.value()); !s)
            return s;
        const double pc2Bytes = 32.0 + double(frames) * double(n) * 12.0;
        char line[300];
        std::snprintf(line, sizeof line,
                      "skinned: %zu rigid bones, at most 4 weights a vertex; RMS error %.3g, worst vertex error %.3g of the "
                      "diagonal (target %.3g); %zu bytes, %.1f%% of a PC2 of the same clip",
                      k, skin.rmsError / diagonal, skin.maxError / diagonal, m_options.skinBones > 0 ? 0.0 : m_options.skinError,
                      bytes.value().size(), 100.0 * double(bytes.value().size()) / pc2Bytes);
        m_notes.push_back(detail::quoted(m_path) + ": " + line);
        return detail::publishAll(files);
    }

    void abort() override {
        m_started = false;
        m_frames.clear();
        m_frames.shrink_to_fit();
    }

private:
    bool m_binary;
    ClipExportOptions m_options;
    std::filesystem::path m_path;
    ClipSetup m_setup;
    std::vector<std::vector<Vec3f>> m_frames;  ///< Every frame's positions until finish().
    bool m_started = false;
};

}  // namespace

namespace detail {

std::unique_ptr<ClipWriter> makeSkinWriter(bool binary, const ClipExportOptions& options) {
    return std::make_unique<SkinWriter>(binary, options);
}

/// The "skin" export (io/export/export_formats.cpp): glTF JSON for a .gltf path, GLB otherwise.
std::unique_ptr<ClipWriter> makeSkinExport(const std::filesystem::path& path, const ClipExportOptions& options) {
    return makeSkinWriter(!writesGltfJson(path), options);
}

}  // namespace detail

}  // namespace softtouch::io

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
// On the source rig (ClipSetup::sourceRig: the one object came skinned to a skeleton, and the bake kept it):
// the file's skeleton instead, with its node names, hierarchy, rest transforms and inverse bind matrices as
// the file has them and its keyed nodes sampled at every frame; POSITION is the file's bind mesh, and at
// most a few rigid helper bones (core/fitting/skin_fit.h, fitHelperBones) hang under the source joints
// that weigh most where they act, carrying what the rig does not do (the wobble).
//
// The frames stay in memory until finish(), where the bones are fitted: 12 bytes per vertex per frame.

#include "core/fitting/skin_fit.h"
#include "io/export/clip_writer_internal.h"
#include "io/export/export_formats.h"
#include "io/export/vertex_cache_internal.h"

#include <tiny_gltf.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string_view>
#include <tuple>

namespace softtouch::io {

namespace {

/// Levels of the 8-bit normalized weights a compressed file stores.
constexpr int kWeightSteps = 255;

/// JOINTS_0 and WEIGHTS_0 of `skin` on `primitive`: unsigned shorts and floats, or for a compressed file the bytes
/// engines ship (joints exactly, weights the multiples of 1/255 the fit was measured with, summing to 255).
void addSkinAttributes(tinygltf::Model& model, tinygltf::Primitive& primitive, const SkinFit& skin, bool compress) {
    const std::size_t n = skin.weights.size();
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
    if (compress && skin.bones <= 256) {
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
}

/// A node's local transforms at every key: translations, rotations (kept in one hemisphere so that slerp
/// between keys takes the short way) and scales, as the channels store them.
struct NodeKeys {
    std::vector<float> translation, rotation, scale;
    void add(const NodeTransform& t) {
        Eigen::Quaterniond q = t.rotation.normalized();
        if (rotation.size() >= 4) {
            const std::size_t at = rotation.size() - 4;
            const Eigen::Quaterniond previous(rotation[at + 3], rotation[at], rotation[at + 1], rotation[at + 2]);
            if (q.dot(previous) < 0.0)
                q.coeffs() = -q.coeffs();
        }
        for (int a = 0; a < 3; ++a) {
            translation.push_back(float(t.translation[a]));
            scale.push_back(float(t.scale[a]));
        }
        for (double c : {q.x(), q.y(), q.z(), q.w()})
            rotation.push_back(float(c));
    }
};

/// Channels playing `keys` on `node` (LINEAR), the scale only when `withScale`.
void addNodeChannels(tinygltf::Model& model, tinygltf::Animation& animation, int timeAccessor, int node,
                     const NodeKeys& keys, bool withScale) {
    const std::size_t count = keys.rotation.size() / 4;
    for (const auto& [path, values, components] :
         {std::tuple<const char*, const std::vector<float>*, int>{"translation", &keys.translation, 3},
          {"rotation", &keys.rotation, 4},
          {"scale", &keys.scale, 3}}) {
        if (std::string_view(path) == "scale" && !withScale)
            continue;
        tinygltf::AnimationSampler sampler;
        sampler.input = timeAccessor;
        sampler.output = detail::addFloatAccessor(model, values->data(), count, components, false, false);
        sampler.interpolation = "LINEAR";
        animation.samplers.push_back(sampler);
        tinygltf::AnimationChannel channel;
        channel.sampler = int(animation.samplers.size() - 1);
        channel.target_node = node;
        channel.target_path = path;
        animation.channels.push_back(channel);
    }
}

/// Sets a node's translation, rotation and scale (those that are not the identity's).
void setNodeTransform(tinygltf::Node& node, const NodeTransform& t) {
    if (!t.translation.isZero())
        node.translation = {t.translation.x(), t.translation.y(), t.translation.z()};
    const Eigen::Quaterniond q = t.rotation.normalized();
    if (!q.isApprox(Eigen::Quaterniond::Identity(), 0.0))
        node.rotation = {q.x(), q.y(), q.z(), q.w()};
    if (!t.scale.isOnes())
        node.scale = {t.scale.x(), t.scale.y(), t.scale.z()};
}

/// An affine transform as translation, rotation and scale (its linear part taken as R·diag(scale); a shear,
/// which no node can hold, is dropped).
NodeTransform decompose(const Eigen::Affine3d& m) {
    NodeTransform t;
    t.translation = m.translation();
    const Mat3 linear = m.linear();
    for (int a = 0; a < 3; ++a)
        t.scale[a] = linear.col(a).norm();
    if (linear.determinant() < 0.0)
        t.scale[0] = -t.scale[0];
    Mat3 rotation = linear * t.scale.cwiseInverse().asDiagonal();
    const Eigen::JacobiSVD<Mat3> svd(rotation, Eigen::ComputeFullU | Eigen::ComputeFullV);
    rotation = svd.matrixU() * svd.matrixV().transpose();
    t.rotation = Eigen::Quaterniond(rotation).normalized();
    return t;
}

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
        if (m_setup.sourceRig)
            return finishOnRig(*m_setup.sourceRig);
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
        addSkinAttributes(model, primitive, skin, m_options.gltfCompress);
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
            NodeKeys boneKeys;
            for (std::size_t f = 0; f < keys; ++f) {
                const BoneTransform& t = skin.transforms[f % frames][j];
                NodeTransform key;
                key.translation = t.translation;
                key.rotation = Eigen::Quaterniond(t.rotation);
                boneKeys.add(key);
            }
            tinygltf::Node bone;
            char name[32];
            std::snprintf(name, sizeof name, "bone_%02zu", j + 1);
            bone.name = name;
            bone.translation = {boneKeys.translation[0], boneKeys.translation[1], boneKeys.translation[2]};
            bone.rotation = {boneKeys.rotation[0], boneKeys.rotation[1], boneKeys.rotation[2], boneKeys.rotation[3]};
            model.nodes.push_back(bone);
            const int node = int(model.nodes.size() - 1);
            gltfSkin.joints.push_back(node);
            model.nodes[std::size_t(rootNode)].children.push_back(node);
            addNodeChannels(model, animation, timeAccessor, node, boneKeys, false);
        }
        model.skins.push_back(gltfSkin);
        model.animations.push_back(animation);
        model.scenes.push_back(scene);
        model.defaultScene = 0;

        char line[300];
        std::snprintf(line, sizeof line,
                      "skinned: %zu rigid bones, at most 4 weights a vertex; RMS error %.3g, worst vertex error %.3g of the "
                      "diagonal (target %.3g)",
                      k, skin.rmsError / diagonal, skin.maxError / diagonal, m_options.skinBones > 0 ? 0.0 : m_options.skinError);
        return publish(model, line);
    }
    void abort() override {
        m_started = false;
        m_frames.clear();
        m_frames.shrink_to_fit();
    }

private:
    /// Writes `model` to the path, noting `what` the file holds with its size against a PC2 of the same clip.
    Status publish(const tinygltf::Model& model, const std::string& what) {
        Result<std::string> bytes = detail::serializeGltf(model, m_binary, m_path, m_options.gltfCompress);
        m_started = false;
        if (!bytes)
            return Status::error(bytes.message());
        std::vector<std::unique_ptr<detail::StagedFile>> files;
        files.push_back(std::make_unique<detail::StagedFile>(m_path));
        if (Status s = files.front()->write(bytes.value()); !s)
            return s;
        const double pc2Bytes = 32.0 + double(m_setup.info.frameCount) * double(m_setup.info.pointCount) * 12.0;
        char size[120];
        std::snprintf(size, sizeof size, "; %zu bytes, %.1f%% of a PC2 of the same clip", bytes.value().size(),
                      100.0 * double(bytes.value().size()) / pc2Bytes);
        m_notes.push_back(detail::quoted(m_path) + ": " + what + size);
        return detail::publishAll(files);
    }

    /// The clip on the skeleton it came skinned to: the source nodes as the file has them, plus the fewest
    /// helper bones (0, 2, 4, 8, 16, up to the most allowed) that meet the error target.
    Status finishOnRig(const SourceRig& rig) {
        const std::size_t frames = m_setup.info.frameCount, n = m_setup.info.pointCount;
        const Skeleton& skeleton = rig.skeleton;
        const double diagonal = std::max(1e-12, m_setup.restMesh.bounds().diagonal());
        const SourceSkin source = sourceSkin(skeleton, rig.mesh);
        auto fit = [&](int helpers) {
            RigSkinFit fitted = fitHelperBones(rig.mesh.bind, m_frames, source, helpers);
            if (m_options.gltfCompress) {
                roundSkinWeights(fitted.skin, kWeightSteps);
                measureSkinError(fitted.skin, rig.mesh.bind, m_frames);
            }
            return fitted;
        };
        const int most = m_options.skinBones > 0 ? m_options.skinBones : ClipExportOptions::kDefaultHelperBones;
        RigSkinFit fitted;
        if (m_options.skinBones > 0) {
            fitted = fit(most);
        } else {
            for (int helpers : {0, 2, 4, 8, 16, most}) {
                if (helpers > most)
                    continue;
                fitted = fit(helpers);
                if (fitted.skin.rmsError <= m_options.skinError * diagonal)
                    break;
            }
            if (fitted.skin.rmsError > m_options.skinError * diagonal)
                m_warnings.push_back(detail::quoted(m_path) + ": the source rig and " + std::to_string(most) +
                                     " helper bones miss the error target (RMS " + std::to_string(fitted.skin.rmsError / diagonal) +
                                     " of the diagonal); raise --bones, or use fitted bones (--rig fitted), PCA morphs or VAT");
        }
        m_frames.clear();
        m_frames.shrink_to_fit();
        const SkinFit& skin = fitted.skin;
        const std::size_t joints = skeleton.joints.size(), helpers = std::size_t(skin.bones) - joints;

        tinygltf::Model model;
        model.asset.version = "2.0";
        model.asset.generator = "SoftTouch";
        model.buffers.emplace_back();
        // The bind mesh the inverse bind matrices undo, with its own normals.
        Mesh bind;
        bind.positions = rig.mesh.bind;
        bind.triangles = m_setup.restMesh.triangles;
        bind.computeNormals();
        tinygltf::Primitive primitive;
        primitive.mode = TINYGLTF_MODE_TRIANGLES;
        primitive.attributes["POSITION"] = detail::addFloatAccessor(model, bind.positions.front().data(), n, 3, true, true);
        primitive.attributes["NORMAL"] = detail::addFloatAccessor(model, bind.normals.front().data(), n, 3, true, false);
        primitive.indices = detail::addIndexAccessor(model, bind.triangles, 0);
        addSkinAttributes(model, primitive, skin, m_options.gltfCompress);
        tinygltf::Mesh mesh;
        mesh.name = rig.meshName.empty() ? m_setup.objects.front().name : rig.meshName;
        mesh.primitives.push_back(primitive);
        model.meshes.push_back(mesh);
        tinygltf::Node meshNode;
        meshNode.name = mesh.name;
        meshNode.mesh = 0;
        meshNode.skin = 0;
        model.nodes.push_back(meshNode);
        tinygltf::Scene scene;
        scene.nodes.push_back(0);

        // The source nodes as the file has them: node s at model node 1 + s.
        const int firstSource = 1;
        for (std::size_t s = 0; s < skeleton.nodes.size(); ++s) {
            tinygltf::Node node;
            node.name = skeleton.nodes[s].name;
            setNodeTransform(node, skeleton.nodes[s].rest);
            model.nodes.push_back(node);
            if (skeleton.nodes[s].parent < 0)
                scene.nodes.push_back(firstSource + int(s));
            else
                model.nodes[std::size_t(firstSource + skeleton.nodes[s].parent)].children.push_back(firstSource + int(s));
        }
        tinygltf::Skin gltfSkin;
        gltfSkin.name = "skeleton";
        std::vector<float> inverseBind;
        auto addInverseBind = [&](const Eigen::Matrix4d& m) {
            for (int c = 0; c < 4; ++c)  // column-major, as glTF stores matrices
                for (int r = 0; r < 4; ++r)
                    inverseBind.push_back(float(m(r, c)));
        };
        for (std::size_t j = 0; j < joints; ++j) {
            gltfSkin.joints.push_back(firstSource + skeleton.joints[j]);
            addInverseBind(skeleton.inverseBind[j]);
        }
        // The joints' common root, when they have one, is the skin's skeleton.
        auto topOf = [&](int s) {
            while (skeleton.nodes[std::size_t(s)].parent >= 0)
                s = skeleton.nodes[std::size_t(s)].parent;
            return s;
        };
        const int top = topOf(skeleton.joints.front());
        if (std::all_of(skeleton.joints.begin(), skeleton.joints.end(), [&](int j) { return topOf(j) == top; }))
            gltfSkin.skeleton = firstSource + top;

        // Helpers: bind pose at the centre of where each acts, unturned, under its parent joint; per frame its
        // local transform is the parent's world inverted times its own world (the fitted transform of the bind
        // mesh, composed with its bind pose).
        const std::size_t keys = detail::animationKeys(m_setup);
        std::vector<std::vector<Eigen::Affine3d>> world(frames);
        for (std::size_t f = 0; f < frames; ++f)
            world[f] = skeleton.world(f);
        tinygltf::Animation animation;
        animation.name = "clip";
        const int timeAccessor = detail::addKeyTimes(model, m_setup, animation);
        for (std::size_t h = 0; h < helpers; ++h) {
            const std::size_t parentJoint = std::size_t(fitted.helperParent[h]);
            const int parentNode = skeleton.joints[parentJoint];
            Eigen::Affine3d bindPose = Eigen::Affine3d::Identity();
            bindPose.translate(fitted.helperCentre[h]);
            const Eigen::Affine3d parentBind(skeleton.inverseBind[parentJoint].inverse());
            tinygltf::Node node;
            node.name = skeleton.nodes[std::size_t(parentNode)].name + "_wobble_" + std::to_string(h + 1);
            setNodeTransform(node, decompose(parentBind.inverse() * bindPose));
            NodeKeys helperKeys;
            for (std::size_t f = 0; f < keys; ++f) {
                const BoneTransform& t = skin.transforms[f % frames][joints + h];
                Eigen::Affine3d own = Eigen::Affine3d::Identity();
                own.linear() = t.rotation;
                own.translation() = t.translation;
                helperKeys.add(decompose(world[f % frames][std::size_t(parentNode)].inverse() * own * bindPose));
            }
            model.nodes.push_back(node);
            const int index = int(model.nodes.size() - 1);
            model.nodes[std::size_t(firstSource + parentNode)].children.push_back(index);
            gltfSkin.joints.push_back(index);
            addInverseBind(bindPose.inverse().matrix());
            addNodeChannels(model, animation, timeAccessor, index, helperKeys, true);
        }
        // The source's keyed nodes, sampled at every frame (the file's own keys at the clip's times).
        for (std::size_t s = 0; s < skeleton.nodes.size(); ++s) {
            if (!skeleton.nodes[s].animated)
                continue;
            NodeKeys nodeKeys;
            for (std::size_t f = 0; f < keys; ++f)
                nodeKeys.add(skeleton.poses[f % frames][s]);
            addNodeChannels(model, animation, timeAccessor, firstSource + int(s), nodeKeys, true);
        }
        gltfSkin.inverseBindMatrices = detail::addRawAccessor(model, inverseBind.data(), inverseBind.size() * 4,
                                                              gltfSkin.joints.size(), TINYGLTF_COMPONENT_TYPE_FLOAT,
                                                              TINYGLTF_TYPE_MAT4, 0);
        model.skins.push_back(gltfSkin);
        if (!animation.channels.empty())
            model.animations.push_back(animation);
        model.scenes.push_back(scene);
        model.defaultScene = 0;

        char line[300];
        std::snprintf(line, sizeof line,
                      "skinned onto the source rig: its %zu joints kept (names, hierarchy, bind pose, animation) and %zu "
                      "helper bones added; RMS error %.3g, worst vertex error %.3g of the diagonal (target %.3g)",
                      joints, helpers, skin.rmsError / diagonal, skin.maxError / diagonal,
                      m_options.skinBones > 0 ? 0.0 : m_options.skinError);
        return publish(model, line);
    }

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

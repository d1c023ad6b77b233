#pragma once
// Test data for animated imports: small GLB files with a known motion, written with tinygltf, and that
// motion computed here independently of assimp and of SoftTouch's importer.
//   - keyed: a box under a node whose translation and rotation are keyed;
//   - skinned: a bar along x with two joints, the second bending about z;
//   - morph: a box with one blend shape whose weight is keyed.
// Keys are at every 1/24 s over one second, so a bake at 24 fps (or samples at 120/s) land on keys, where
// the motion is exactly the keyed value whatever the interpolation.

#include "core/base/types.h"

#include <tiny_gltf.h>

#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace softtouch::test {

enum class RigKind { Keyed, Skinned, Morph };

struct RiggedFile {
    std::vector<Vec3f> rest;                      ///< Vertex positions as written (mesh space), file order.
    std::vector<std::array<std::uint32_t, 3>> triangles;
    /// Where vertex v is at key k (t = k/24 s), metres, world space.
    std::vector<std::vector<Vec3f>> expected;
};

namespace rigged_detail {

inline constexpr int kKeys = 25;  // 0 .. 1 s at 24 keys/s

/// A box of n×n×n vertices per face grid (a closed, watertight surface: 6 faces sharing edges is not needed
/// for these tests, so each face has its own vertices).
inline void box(const Vec3& size, const Vec3& centre, int n, RiggedFile& out) {
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) {
            const auto first = std::uint32_t(out.rest.size());
            const int u = (axis + 1) % 3, w = (axis + 2) % 3;
            for (int j = 0; j <= n; ++j)
                for (int i = 0; i <= n; ++i) {
                    Vec3 p = Vec3::Zero();
                    p[axis] = side ? 0.5 : -0.5;
                    p[u] = -0.5 + double(i) / n;
                    p[w] = -0.5 + double(j) / n;
                    out.rest.push_back((centre + p.cwiseProduct(size)).cast<float>());
                }
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i) {
                    const std::uint32_t a = first + std::uint32_t(j * (n + 1) + i), b = a + 1,
                                        c = a + std::uint32_t(n + 1), d = c + 1;
                    if (side)
                        out.triangles.push_back({a, b, d}), out.triangles.push_back({a, d, c});
                    else
                        out.triangles.push_back({a, d, b}), out.triangles.push_back({a, c, d});
                }
        }
}

inline int addBuffer(tinygltf::Model& model, const void* data, std::size_t bytes, int target = 0) {
    auto& buffer = model.buffers.front().data;
    while (buffer.size() % 4)
        buffer.push_back(0);
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = buffer.size();
    view.byteLength = bytes;
    if (target)
        view.target = target;
    const auto* b = static_cast<const unsigned char*>(data);
    buffer.insert(buffer.end(), b, b + bytes);
    model.bufferViews.push_back(view);
    return int(model.bufferViews.size() - 1);
}

inline int addAccessor(tinygltf::Model& model, const void* data, std::size_t count, int type, int componentType,
                       std::size_t componentBytes, int components, int target = 0,
                       std::vector<double> minValues = {}, std::vector<double> maxValues = {}) {
    tinygltf::Accessor a;
    a.bufferView = addBuffer(model, data, count * componentBytes * std::size_t(components), target);
    a.count = count;
    a.type = type;
    a.componentType = componentType;
    a.minValues = std::move(minValues);
    a.maxValues = std::move(maxValues);
    model.accessors.push_back(a);
    return int(model.accessors.size() - 1);
}

inline int addVec3(tinygltf::Model& model, const std::vector<Vec3f>& v, bool bounds = false) {
    std::vector<double> lo, hi;
    if (bounds) {
        Vec3f a = v.front(), b = v.front();
        for (const Vec3f& p : v)
            a = a.cwiseMin(p), b = b.cwiseMax(p);
        lo = {a.x(), a.y(), a.z()};
        hi = {b.x(), b.y(), b.z()};
    }
    return addAccessor(model, v.data(), v.size(), TINYGLTF_TYPE_VEC3, TINYGLTF_COMPONENT_TYPE_FLOAT, 4, 3,
                       TINYGLTF_TARGET_ARRAY_BUFFER, lo, hi);
}

/// The quaternion last appended to glTF's (x, y, z, w) list, as the file holds it (float).
inline Eigen::Quaterniond lastQuaternion(const std::vector<float>& q) {
    const std::size_t n = q.size();
    return Eigen::Quaterniond(double(q[n - 1]), double(q[n - 4]), double(q[n - 3]), double(q[n - 2]));
}

inline void addSampler(tinygltf::Model& model, tinygltf::Animation& animation, int node, const std::string& path,
                       const std::vector<float>& values, int type) {
    std::vector<float> times(kKeys);
    for (int k = 0; k < kKeys; ++k)
        times[std::size_t(k)] = float(k) / 24.0f;
    tinygltf::AnimationSampler sampler;
    sampler.input = addAccessor(model, times.data(), times.size(), TINYGLTF_TYPE_SCALAR, TINYGLTF_COMPONENT_TYPE_FLOAT, 4,
                                1, 0, {0.0}, {1.0});
    const int components = type == TINYGLTF_TYPE_VEC4 ? 4 : type == TINYGLTF_TYPE_VEC3 ? 3 : 1;
    sampler.output = addAccessor(model, values.data(), values.size() / std::size_t(components), type,
                                 TINYGLTF_COMPONENT_TYPE_FLOAT, 4, components);
    sampler.interpolation = "LINEAR";
    animation.samplers.push_back(sampler);
    tinygltf::AnimationChannel channel;
    channel.sampler = int(animation.samplers.size() - 1);
    channel.target_node = node;
    channel.target_path = path;
    animation.channels.push_back(channel);
}

}  // namespace rigged_detail

/// Writes one of the rigs as a GLB at `path` and returns its geometry and expected motion.
inline RiggedFile writeRiggedGlb(RigKind kind, const std::string& path) {
    using namespace rigged_detail;
    RiggedFile out;
    tinygltf::Model model;
    model.asset.version = "2.0";
    model.buffers.emplace_back();
    tinygltf::Animation animation;
    animation.name = "take";
    tinygltf::Mesh mesh;
    tinygltf::Primitive primitive;
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    const double pi = 3.14159265358979323846;
    if (kind == RigKind::Skinned)
        box(Vec3(0.6, 0.08, 0.08), Vec3(0.3, 0, 0), 8, out);
    else
        box(Vec3(0.3, 0.2, 0.1), Vec3::Zero(), 4, out);
    primitive.attributes["POSITION"] = addVec3(model, out.rest, true);
    primitive.indices = addAccessor(model, out.triangles.data(), out.triangles.size() * 3, TINYGLTF_TYPE_SCALAR,
                                    TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, 4, 1, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    out.expected.assign(kKeys, std::vector<Vec3f>(out.rest.size()));
    tinygltf::Scene scene;
    if (kind == RigKind::Keyed) {
        // The mesh's node moves along x and turns about y.
        tinygltf::Node node;
        node.mesh = 0;
        model.nodes.push_back(node);
        scene.nodes = {0};
        std::vector<float> translation, rotation;
        for (int k = 0; k < kKeys; ++k) {
            const double t = k / 24.0;
            const Vec3 shift(0.4 * std::sin(2 * pi * t), 0.1 * t, 0);
            const Eigen::Quaterniond turn(Eigen::AngleAxisd(0.8 * std::sin(2 * pi * t), Vec3::UnitY()));
            translation.insert(translation.end(), {float(shift.x()), float(shift.y()), float(shift.z())});
            rotation.insert(rotation.end(), {float(turn.x()), float(turn.y()), float(turn.z()), float(turn.w())});
            const Eigen::Quaterniond asWritten = lastQuaternion(rotation);
            for (std::size_t v = 0; v < out.rest.size(); ++v)
                out.expected[std::size_t(k)][v] =
                    (asWritten.normalized() * out.rest[v].cast<double>() + shift.cast<float>().cast<double>()).cast<float>();
        }
        addSampler(model, animation, 0, "translation", translation, TINYGLTF_TYPE_VEC3);
        addSampler(model, animation, 0, "rotation", rotation, TINYGLTF_TYPE_VEC4);
    } else if (kind == RigKind::Skinned) {
        // Joint 0 at the origin, joint 1 (its child) at x = 0.3 bending about z; weights blend over x in
        // [0.2, 0.4]. The mesh node has no transform (glTF skins ignore it).
        tinygltf::Node meshNode, root, elbow;
        meshNode.mesh = 0;
        meshNode.skin = 0;
        root.children = {2};
        elbow.translation = {0.3, 0.0, 0.0};
        model.nodes = {meshNode, root, elbow};
        scene.nodes = {0, 1};
        tinygltf::Skin skin;
        skin.joints = {1, 2};
        const std::array<float, 16> identity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
        std::array<float, 16> elbowInverse = identity;
        elbowInverse[12] = -0.3f;  // column-major: the translation of the inverse bind matrix
        std::vector<float> ibm(identity.begin(), identity.end());
        ibm.insert(ibm.end(), elbowInverse.begin(), elbowInverse.end());
        skin.inverseBindMatrices = addAccessor(model, ibm.data(), 2, TINYGLTF_TYPE_MAT4, TINYGLTF_COMPONENT_TYPE_FLOAT, 4, 16);
        model.skins.push_back(skin);
        std::vector<std::uint16_t> joints;
        std::vector<float> weights;
        std::vector<float> elbowWeight;
        for (const Vec3f& p : out.rest) {
            const float w = std::clamp((p.x() - 0.2f) / 0.2f, 0.0f, 1.0f);
            joints.insert(joints.end(), {0, 1, 0, 0});
            weights.insert(weights.end(), {1.0f - w, w, 0.0f, 0.0f});
            elbowWeight.push_back(w);
        }
        primitive.attributes["JOINTS_0"] = addAccessor(model, joints.data(), out.rest.size(), TINYGLTF_TYPE_VEC4,
                                                       TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, 2, 4, TINYGLTF_TARGET_ARRAY_BUFFER);
        primitive.attributes["WEIGHTS_0"] = addAccessor(model, weights.data(), out.rest.size(), TINYGLTF_TYPE_VEC4,
                                                        TINYGLTF_COMPONENT_TYPE_FLOAT, 4, 4, TINYGLTF_TARGET_ARRAY_BUFFER);
        std::vector<float> rotation;
        for (int k = 0; k < kKeys; ++k) {
            const double angle = 0.6 * std::sin(2 * pi * k / 24.0);
            const Eigen::Quaterniond bend(Eigen::AngleAxisd(angle, Vec3::UnitZ()));
            rotation.insert(rotation.end(), {float(bend.x()), float(bend.y()), float(bend.z()), float(bend.w())});
            const Eigen::Quaterniond asWritten = lastQuaternion(rotation);
            for (std::size_t v = 0; v < out.rest.size(); ++v) {
                const Vec3 p = out.rest[v].cast<double>();
                const Vec3 bent = asWritten.normalized() * (p - Vec3(0.3, 0, 0)) + Vec3(0.3, 0, 0);
                out.expected[std::size_t(k)][v] = ((1.0 - elbowWeight[v]) * p + elbowWeight[v] * bent).cast<float>();
            }
        }
        addSampler(model, animation, 2, "rotation", rotation, TINYGLTF_TYPE_VEC4);
    } else {
        // One blend shape: the top face rises and the box bulges in z; its weight is keyed.
        std::vector<Vec3f> delta(out.rest.size());
        for (std::size_t v = 0; v < out.rest.size(); ++v)
            delta[v] = Vec3f(0.0f, out.rest[v].y() > 0.09f ? 0.08f : 0.0f, 0.3f * out.rest[v].z() * (0.2f + out.rest[v].y()));
        primitive.targets.push_back({{"POSITION", addVec3(model, delta, true)}});
        mesh.weights = {0.0};
        tinygltf::Node node;
        node.mesh = 0;
        model.nodes.push_back(node);
        scene.nodes = {0};
        std::vector<float> weight;
        for (int k = 0; k < kKeys; ++k) {
            weight.push_back(float(std::pow(std::sin(pi * k / 24.0), 2)));
            for (std::size_t v = 0; v < out.rest.size(); ++v)
                out.expected[std::size_t(k)][v] = out.rest[v] + weight.back() * delta[v];
        }
        addSampler(model, animation, 0, "weights", weight, TINYGLTF_TYPE_SCALAR);
    }
    mesh.primitives.push_back(primitive);
    model.meshes.push_back(mesh);
    model.animations.push_back(animation);
    model.scenes.push_back(scene);
    model.defaultScene = 0;
    tinygltf::TinyGLTF writer;
    writer.WriteGltfSceneToFile(&model, path, false, true, false, true);
    return out;
}

/// Writes `to`: the GLB `from` (its first animation) with a second take named `name` that plays the first
/// `speed` times as fast (its key times divided by `speed`), as a rig exported with a run beside its walk.
inline bool writeWithSecondTake(const std::string& from, const std::string& to, const std::string& name, double speed) {
    tinygltf::TinyGLTF io;
    tinygltf::Model model;
    std::string error, warning;
    if (!io.LoadBinaryFromFile(&model, &error, &warning, from) || model.animations.empty())
        return false;
    tinygltf::Animation second = model.animations.front();
    second.name = name;
    for (tinygltf::AnimationSampler& sampler : second.samplers) {
        const tinygltf::Accessor& input = model.accessors.at(std::size_t(sampler.input));
        const tinygltf::BufferView& view = model.bufferViews.at(std::size_t(input.bufferView));
        const auto* times = reinterpret_cast<const float*>(model.buffers.at(std::size_t(view.buffer)).data.data() +
                                                           view.byteOffset + input.byteOffset);
        std::vector<float> faster(times, times + input.count);
        for (float& t : faster)
            t = float(t / speed);
        sampler.input = rigged_detail::addAccessor(model, faster.data(), faster.size(), TINYGLTF_TYPE_SCALAR,
                                                   TINYGLTF_COMPONENT_TYPE_FLOAT, 4, 1, 0, {double(faster.front())},
                                                   {double(faster.back())});
    }
    model.animations.push_back(second);
    return io.WriteGltfSceneToFile(&model, to, false, true, false, true);
}

}  // namespace softtouch::test

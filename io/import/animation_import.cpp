#include "io/import/animation_import.h"

#include "io/import/assimp_read.h"
#include "io/import/isolated_import.h"
#include "io/import/scene_units.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <map>
#include <optional>
#include <sstream>

namespace softtouch::io {

namespace {

/// The key pair around `ticks` and how far between them: (index, fraction); past either end, that end.
template <typename Key>
std::pair<unsigned, double> bracket(const Key* keys, unsigned count, double ticks) {
    if (count <= 1 || ticks <= keys[0].mTime)
        return {0u, 0.0};
    if (ticks >= keys[count - 1].mTime)
        return {count - 1, 0.0};
    unsigned lo = 0, hi = count - 1;
    while (hi - lo > 1) {
        const unsigned mid = (lo + hi) / 2;
        (keys[mid].mTime <= ticks ? lo : hi) = mid;
    }
    const double span = keys[hi].mTime - keys[lo].mTime;
    return {lo, span > 0.0 ? (ticks - keys[lo].mTime) / span : 0.0};
}

/// A node's transform at `ticks`: its channel's keys (positions and scales linear, rotations slerped), or
/// its own transform where the take does not key it.
aiMatrix4x4 localTransform(const aiNode& node, const aiNodeAnim* channel, double ticks) {
    if (!channel)
        return node.mTransformation;
    aiVector3D scaling(1, 1, 1), position(0, 0, 0);
    aiQuaternion rotation;
    aiVector3D nodeScaling, nodePosition;
    aiQuaternion nodeRotation;
    node.mTransformation.Decompose(nodeScaling, nodeRotation, nodePosition);
    auto vectorAt = [&](const aiVectorKey* keys, unsigned count, const aiVector3D& otherwise) {
        if (count == 0)
            return otherwise;
        const auto [k, f] = bracket(keys, count, ticks);
        if (f == 0.0)
            return keys[k].mValue;
        return keys[k].mValue + ai_real(f) * (keys[k + 1].mValue - keys[k].mValue);
    };
    position = vectorAt(channel->mPositionKeys, channel->mNumPositionKeys, nodePosition);
    scaling = vectorAt(channel->mScalingKeys, channel->mNumScalingKeys, nodeScaling);
    if (channel->mNumRotationKeys == 0) {
        rotation = nodeRotation;
    } else {
        const auto [k, f] = bracket(channel->mRotationKeys, channel->mNumRotationKeys, ticks);
        if (f == 0.0)
            rotation = channel->mRotationKeys[k].mValue;
        else
            aiQuaternion::Interpolate(rotation, channel->mRotationKeys[k].mValue, channel->mRotationKeys[k + 1].mValue,
                                      ai_real(f));
        rotation.Normalize();
    }
    return aiMatrix4x4(scaling, rotation, position);
}

/// One placement of a mesh in the node hierarchy.
struct Instance {
    unsigned mesh = 0;
    int node = 0;
    std::uint32_t firstVertex = 0;
    const aiMeshMorphAnim* morph = nullptr;  ///< The take's blend-shape weights for it, if it keys them.
};

/// The file's node hierarchy flattened depth first, its triangle meshes as placed, and one take.
class Rig {
public:
    Rig(const aiScene& scene, const aiAnimation* take, double metresPerUnit)
        : m_scene(scene), m_take(take), m_scale(ai_real(metresPerUnit)) {
        flatten(scene.mRootNode);
        m_channel.assign(m_nodes.size(), nullptr);
        if (take)
            for (unsigned c = 0; c < take->mNumChannels; ++c)
                if (auto it = m_byName.find(take->mChannels[c]->mNodeName.C_Str()); it != m_byName.end())
                    m_channel[std::size_t(it->second)] = take->mChannels[c];
        // Placements stop once a single sample would hold more than kMaxSampledPositions: the count refuses
        // it then, and a node that lists one mesh a million times is not walked to its end.
        std::uint64_t vertices = 0;
        for (std::size_t n = 0; n < m_nodes.size() && vertices <= kMaxSampledPositions; ++n) {
            const aiMeshMorphAnim* morph = m_nodes[n]->mNumMeshes ? morphChannel(*m_nodes[n]) : nullptr;
            for (unsigned i = 0; i < m_nodes[n]->mNumMeshes && vertices <= kMaxSampledPositions; ++i) {
                const aiMesh* mesh = scene.mMeshes[m_nodes[n]->mMeshes[i]];
                if (!(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) || mesh->mNumFaces == 0)
                    continue;
                m_instances.push_back({m_nodes[n]->mMeshes[i], int(n), std::uint32_t(vertices), morph});
                vertices += mesh->mNumVertices;
                m_operations += sampleOperations(*mesh, morph);
                m_mostBones = std::max<std::size_t>(m_mostBones, mesh->mNumBones);
            }
        }
        m_vertexCount = std::size_t(vertices);
        m_operations += double(m_nodes.size());
    }

    std::size_t vertexCount() const { return m_vertexCount; }
    /// What positionsAt() costs (kMaxSampledOperations): one per node, plus sampleOperations() per placed mesh.
    double operationsPerSample() const { return m_operations; }
    /// The most joints (bones) one mesh is skinned to.
    std::size_t mostBones() const { return m_mostBones; }
    const std::vector<Instance>& instances() const { return m_instances; }

    /// Every vertex at `seconds` of the take, metres.
    void positionsAt(double seconds, std::vector<Vec3f>& out) const {
        const double ticksPerSecond = m_take && m_take->mTicksPerSecond > 0.0 ? m_take->mTicksPerSecond : 25.0;
        const double ticks = seconds * ticksPerSecond;
        std::vector<aiMatrix4x4> global(m_nodes.size());
        for (std::size_t n = 0; n < m_nodes.size(); ++n) {
            const aiMatrix4x4 local = localTransform(*m_nodes[n], m_channel[n], ticks);
            global[n] = m_parent[n] < 0 ? local : global[std::size_t(m_parent[n])] * local;
        }
        out.resize(m_vertexCount);
        std::vector<aiVector3D> morphed;
        for (const Instance& instance : m_instances) {
            const aiMesh& mesh = *m_scene.mMeshes[instance.mesh];
            morphed.assign(mesh.mVertices, mesh.mVertices + mesh.mNumVertices);
            applyMorphs(mesh, instance.morph, ticks, morphed);
            Vec3f* target = out.data() + instance.firstVertex;
            if (!mesh.HasBones()) {
                const aiMatrix4x4& m = global[std::size_t(instance.node)];
                for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
                    const aiVector3D p = m * morphed[v];
                    target[v] = Vec3f(p.x, p.y, p.z) * float(m_scale);
                }
                continue;
            }
            // Skinning: p = Σ_b w_b (bone's global transform × its offset, the inverse bind matrix) p_mesh.
            std::vector<aiVector3D> sum(mesh.mNumVertices, aiVector3D(0, 0, 0));
            std::vector<ai_real> weight(mesh.mNumVertices, 0);
            for (unsigned b = 0; b < mesh.mNumBones; ++b) {
                const aiBone& bone = *mesh.mBones[b];
                const auto it = m_byName.find(bone.mName.C_Str());
                if (it == m_byName.end())
                    continue;
                const aiMatrix4x4 skin = global[std::size_t(it->second)] * bone.mOffsetMatrix;
                for (unsigned w = 0; w < bone.mNumWeights; ++w) {
                    const aiVertexWeight& vw = bone.mWeights[w];
                    if (vw.mVertexId >= mesh.mNumVertices)
                        continue;
                    sum[vw.mVertexId] += vw.mWeight * (skin * morphed[vw.mVertexId]);
                    weight[vw.mVertexId] += vw.mWeight;
                }
            }
            const aiMatrix4x4& rigid = global[std::size_t(instance.node)];
            for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
                // Weights are meant to sum to 1; a vertex no bone holds follows its node.
                const aiVector3D p = weight[v] > ai_real(1e-6) ? sum[v] / weight[v] : rigid * morphed[v];
                target[v] = Vec3f(p.x, p.y, p.z) * float(m_scale);
            }
        }
    }

    /// The skeleton of the one placed mesh, which must be skinned, evaluated at `seconds` of the take.
    Result<SourceRig> sourceRig(const std::vector<double>& seconds, const std::string& name) const {
        if (m_instances.size() != 1)
            return Status::error("mesh file " + name + " places " + std::to_string(m_instances.size()) +
                                 " triangle meshes; a skin onto its rig needs exactly one");
        const aiMesh& mesh = *m_scene.mMeshes[m_instances.front().mesh];
        if (!mesh.HasBones())
            return Status::error("mesh file " + name + ": its mesh is not skinned to a skeleton");
        SourceRig rig;
        rig.meshName = mesh.mName.C_Str();
        Skeleton& skeleton = rig.skeleton;
        // Joints and their ancestors, in the flattened order (parents first). The file's root is left out when
        // it is neither a joint nor moves anything (assimp's own root over a glTF scene's top-level nodes).
        std::vector<int> jointNode;
        std::vector<bool> keep(m_nodes.size(), false);
        for (unsigned b = 0; b < mesh.mNumBones; ++b) {
            const auto it = m_byName.find(mesh.mBones[b]->mName.C_Str());
            if (it == m_byName.end())
                return Status::error("mesh file " + name + ": skin joint '" + mesh.mBones[b]->mName.C_Str() +
                                     "' is not a node of the file");
            jointNode.push_back(it->second);
            for (int n = it->second; n >= 0 && !keep[std::size_t(n)]; n = m_parent[std::size_t(n)])
                keep[std::size_t(n)] = true;
        }
        if (keep[0] && std::find(jointNode.begin(), jointNode.end(), 0) == jointNode.end() &&
            m_nodes[0]->mTransformation.IsIdentity() && !m_channel[0])
            keep[0] = false;
        std::vector<int> index(m_nodes.size(), -1);
        for (std::size_t n = 0; n < m_nodes.size(); ++n) {
            if (!keep[n])
                continue;
            index[n] = int(skeleton.nodes.size());
            Skeleton::Node node;
            node.name = m_nodes[n]->mName.C_Str();
            node.parent = m_parent[n] < 0 ? -1 : index[std::size_t(m_parent[n])];
            node.rest = nodeTransform(m_nodes[n]->mTransformation);
            node.animated = m_channel[n] != nullptr;
            skeleton.nodes.push_back(std::move(node));
        }
        for (unsigned b = 0; b < mesh.mNumBones; ++b) {
            skeleton.joints.push_back(index[std::size_t(jointNode[b])]);
            const aiMatrix4x4& m = mesh.mBones[b]->mOffsetMatrix;
            Eigen::Matrix4d ibm;
            ibm << m.a1, m.a2, m.a3, m.a4 * m_scale, m.b1, m.b2, m.b3, m.b4 * m_scale, m.c1, m.c2, m.c3, m.c4 * m_scale,
                m.d1, m.d2, m.d3, m.d4;
            skeleton.inverseBind.push_back(ibm);
        }
        // The bind mesh and each vertex's four heaviest weights, renormalised.
        SkinnedMesh& skinned = rig.mesh;
        std::vector<std::vector<std::pair<float, std::uint16_t>>> held(mesh.mNumVertices);
        for (unsigned b = 0; b < mesh.mNumBones; ++b)
            for (unsigned w = 0; w < mesh.mBones[b]->mNumWeights; ++w) {
                const aiVertexWeight& vw = mesh.mBones[b]->mWeights[w];
                if (vw.mVertexId < mesh.mNumVertices && vw.mWeight > 0.0f)
                    held[vw.mVertexId].push_back({vw.mWeight, std::uint16_t(b)});
            }
        for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
            skinned.bind.push_back(Vec3f(mesh.mVertices[v].x, mesh.mVertices[v].y, mesh.mVertices[v].z) * float(m_scale));
            auto& weights = held[v];
            if (weights.empty())
                return Status::error("mesh file " + name + ": vertex " + std::to_string(v) +
                                     " of its skinned mesh has no joint weights");
            std::sort(weights.begin(), weights.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
            weights.resize(std::min<std::size_t>(weights.size(), 4));
            float sum = 0.0f;
            for (const auto& w : weights)
                sum += w.first;
            std::array<std::uint16_t, 4> joints{};
            std::array<float, 4> share{};
            for (std::size_t s = 0; s < 4; ++s) {
                joints[s] = s < weights.size() ? weights[s].second : weights.front().second;
                share[s] = s < weights.size() ? weights[s].first / sum : 0.0f;
            }
            skinned.joints.push_back(joints);
            skinned.weights.push_back(share);
        }
        const double ticksPerSecond = m_take && m_take->mTicksPerSecond > 0.0 ? m_take->mTicksPerSecond : 25.0;
        for (double at : seconds) {
            std::vector<NodeTransform>& pose = skeleton.poses.emplace_back();
            for (std::size_t n = 0; n < m_nodes.size(); ++n)
                if (keep[n])
                    pose.push_back(nodeTransform(localTransform(*m_nodes[n], m_channel[n], at * ticksPerSecond)));
            reportImportProgress();
        }
        return rig;
    }

private:
    /// A node transform in metres: the file's translation scaled as its positions are.
    NodeTransform nodeTransform(const aiMatrix4x4& m) const {
        aiVector3D scaling, position;
        aiQuaternion rotation;
        m.Decompose(scaling, rotation, position);
        NodeTransform t;
        t.translation = Vec3(position.x, position.y, position.z) * double(m_scale);
        t.rotation = Eigen::Quaterniond(rotation.w, rotation.x, rotation.y, rotation.z).normalized();
        t.scale = Vec3(scaling.x, scaling.y, scaling.z);
        return t;
    }

    /// What positionsAt() does for one placed `mesh` a sample: a pass over its vertices, one more for each
    /// blend-shape target some sample weighs (applyMorphs skips a weight of 0) and its weights' bookkeeping,
    /// one per skin weight and bone.
    static double sampleOperations(const aiMesh& mesh, const aiMeshMorphAnim* channel) {
        double operations = double(mesh.mNumVertices) + mesh.mNumAnimMeshes;
        std::vector<bool> weighed(mesh.mNumAnimMeshes, false);
        if (channel) {  // the keyed weights replace the defaults
            unsigned mostValues = 0;
            for (unsigned k = 0; k < channel->mNumKeys; ++k) {
                const aiMeshMorphKey& key = channel->mKeys[k];
                mostValues = std::max(mostValues, key.mNumValuesAndWeights);
                for (unsigned i = 0; i < key.mNumValuesAndWeights; ++i)
                    if (key.mValues[i] < weighed.size() && key.mWeights[i] != 0.0)
                        weighed[key.mValues[i]] = true;
            }
            operations += 2.0 * mostValues;  // a sample blends two keys
        } else {
            for (unsigned t = 0; t < mesh.mNumAnimMeshes; ++t)
                weighed[t] = mesh.mAnimMeshes[t]->mWeight != 0.0f;
        }
        for (unsigned t = 0; t < mesh.mNumAnimMeshes; ++t)
            if (weighed[t])
                operations += mesh.mNumVertices;
        for (unsigned b = 0; b < mesh.mNumBones; ++b)
            operations += 1.0 + mesh.mBones[b]->mNumWeights;
        return operations;
    }

    /// Flattens the hierarchy under `root` depth first, parents before children, without recursion: a chain of
    /// kMaxRigNodes joints is no deeper on the stack than one.
    void flatten(const aiNode* root) {
        std::vector<std::pair<const aiNode*, int>> pending{{root, -1}};  // (node, its parent's index)
        while (!pending.empty()) {
            const auto [node, parent] = pending.back();
            pending.pop_back();
            const int index = int(m_nodes.size());
            m_nodes.push_back(node);
            m_parent.push_back(parent);
            m_byName.emplace(node->mName.C_Str(), index);
            for (unsigned c = node->mNumChildren; c-- > 0;)  // the first child is taken first
                pending.emplace_back(node->mChildren[c], index);
        }
    }

    /// Blend shapes: p + Σ_k w_k (target_k − p), the weights keyed by the take (channel named after the mesh's
    /// node) or each target's own default.
    void applyMorphs(const aiMesh& mesh, const aiMeshMorphAnim* channel, double ticks, std::vector<aiVector3D>& p) const {
        if (mesh.mNumAnimMeshes == 0)
            return;
        std::vector<double> weights(mesh.mNumAnimMeshes, 0.0);
        for (unsigned k = 0; k < mesh.mNumAnimMeshes; ++k)
            weights[k] = mesh.mAnimMeshes[k]->mWeight;
        if (channel) {
            std::fill(weights.begin(), weights.end(), 0.0);
            const auto [k, f] = bracket(channel->mKeys, channel->mNumKeys, ticks);
            auto addKey = [&](const aiMeshMorphKey& key, double share) {
                for (unsigned i = 0; i < key.mNumValuesAndWeights; ++i)
                    if (key.mValues[i] < weights.size())
                        weights[key.mValues[i]] += share * key.mWeights[i];
            };
            addKey(channel->mKeys[k], 1.0 - f);
            if (f > 0.0)
                addKey(channel->mKeys[k + 1], f);
        }
        const std::vector<aiVector3D> base = p;
        for (unsigned k = 0; k < mesh.mNumAnimMeshes; ++k) {
            const aiAnimMesh& target = *mesh.mAnimMeshes[k];
            if (weights[k] == 0.0 || !target.mVertices || target.mNumVertices != mesh.mNumVertices)
                continue;
            for (unsigned v = 0; v < mesh.mNumVertices; ++v)
                p[v] += ai_real(weights[k]) * (target.mVertices[v] - base[v]);
        }
    }

    const aiMeshMorphAnim* morphChannel(const aiNode& placed) const {
        if (!m_take)
            return nullptr;
        const std::string name = placed.mName.C_Str();
        for (unsigned c = 0; c < m_take->mNumMorphMeshChannels; ++c) {
            const std::string channel = m_take->mMorphMeshChannels[c]->mName.C_Str();
            // glTF names the channel after the node, some writers add "*index".
            if (channel == name || channel.rfind(name + "*", 0) == 0)
                return m_take->mMorphMeshChannels[c];
        }
        return nullptr;
    }

    const aiScene& m_scene;
    const aiAnimation* m_take;
    ai_real m_scale;
    std::vector<const aiNode*> m_nodes;
    std::vector<int> m_parent;
    std::map<std::string, int> m_byName;
    std::vector<const aiNodeAnim*> m_channel;  ///< Per node: the take's keys for it, or null.
    std::vector<Instance> m_instances;
    std::size_t m_vertexCount = 0;
    double m_operations = 0.0;
    std::size_t m_mostBones = 0;
};

std::string formatSeconds(double s) {
    std::ostringstream out;
    out << s;
    return out.str();
}

/// Reads `path` into `importer` as every animated import does; fails naming the file.
Result<const aiScene*> readAnimatedScene(Assimp::Importer& importer, const std::filesystem::path& path, const std::string& name) {
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    const unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType |
                           aiProcess_ValidateDataStructure;
    std::string problem;
    const aiScene* scene = readAssimpScene(importer, path, flags, problem);
    if (!scene || !scene->mRootNode)
        return Status::error("cannot read mesh " + name + ": " + (scene ? std::string("it has no scene") : problem));
    return scene;
}

/// The scene's takes; fails when it has none.
Result<TakeList> sceneTakes(const aiScene& scene, const std::string& name) {
    TakeList takes;
    for (unsigned a = 0; a < scene.mNumAnimations; ++a) {
        const aiAnimation& take = *scene.mAnimations[a];
        const double tps = take.mTicksPerSecond > 0.0 ? take.mTicksPerSecond : 25.0;
        takes.emplace_back(take.mName.C_Str(), take.mDuration / tps);
    }
    if (takes.empty())
        return Status::error("mesh file " + name + " has no animation (no keyed transforms, skeleton or blend-shape "
                             "weights): import it as a still mesh");
    return takes;
}

/// Nodes in the hierarchy under `root`, counted without recursion and only up to `most` + 1: a file may
/// hold far more, or nest them deeper than a recursive walk's stack.
std::size_t countNodes(const aiNode* root, std::size_t most) {
    std::vector<const aiNode*> pending{root};
    std::size_t count = 0;
    while (!pending.empty() && count <= most) {
        const aiNode* node = pending.back();
        pending.pop_back();
        ++count;
        for (unsigned c = 0; c < node->mNumChildren; ++c)
            pending.push_back(node->mChildren[c]);
    }
    return count;
}

std::string formatCount(double n) {
    std::ostringstream out;
    out << std::setprecision(n < 1e9 ? 10 : 3) << n;
    return out.str();
}

Result<AnimatedMesh> readAnimated(const std::filesystem::path& path, const std::string& name, const AnimationRequest& request) {
    // The request first: nothing of it may reach a count or a time before it is known to be finite.
    if (!std::isfinite(request.start) || !std::isfinite(request.end))
        return Status::error("mesh file " + name + ": the animation's range must be finite numbers of seconds, got " +
                             formatSeconds(request.start) + " to " + formatSeconds(request.end));
    if (!(request.rate >= 1.0 && request.rate <= 1000.0))
        return Status::error("mesh file " + name + ": the animation's sample rate must be in [1, 1000] per second, "
                             "got " + formatSeconds(request.rate));
    Assimp::Importer importer;
    const auto read = readAnimatedScene(importer, path, name);
    if (!read)
        return read.status();
    const aiScene* scene = read.value();
    AnimatedMesh result;
    auto takes = sceneTakes(*scene, name);
    if (!takes)
        return takes.status();
    result.takes = std::move(takes.value());
    int chosen = request.take.empty() ? 0 : -1;
    for (std::size_t a = 0; a < result.takes.size() && chosen < 0; ++a)
        if (result.takes[a].first == request.take)
            chosen = int(a);
    if (chosen < 0) {
        std::string names;
        for (const auto& [takeName, seconds] : result.takes)
            names += (names.empty() ? "\"" : ", \"") + takeName + "\" (" + formatSeconds(seconds) + " s)";
        return Status::error("mesh file " + name + " has no take \"" + request.take + "\"; it has " + names);
    }
    const std::string& takeName = result.takes[std::size_t(chosen)].first;
    const double length = result.takes[std::size_t(chosen)].second;
    // A take of 1e30 s or of infinite length used to become 2 samples (its sample count overflowed), or to abort
    // the import allocating them; no count is computed here before the range is known to be at most an hour.
    if (!std::isfinite(length))
        return Status::error("mesh file " + name + ": take \"" + takeName + "\" is " + formatSeconds(length) +
                             " s long; its key times are not finite numbers");
    const double end = request.end < 0.0 ? length : request.end;
    if (!(request.start >= 0.0 && end > request.start && end <= length * (1.0 + 1e-9) + 1e-9))
        return Status::error("mesh file " + name + ": the range " + formatSeconds(request.start) + " to " +
                             formatSeconds(end) + " s is not inside take \"" + takeName + "\" (0 to " +
                             formatSeconds(length) + " s)");
    if (end > kMaxAnimationSeconds)
        return Status::error("mesh file " + name + ": the range " + formatSeconds(request.start) + " to " +
                             formatSeconds(end) + " s of take \"" + takeName + "\" (" + formatSeconds(length) + " s) ends past " +
                             formatSeconds(kMaxAnimationSeconds) + " s, the furthest into a take SoftTouch samples: " +
                             "give it an end of at most " + formatSeconds(kMaxAnimationSeconds) + " s");
    const std::size_t nodes = countNodes(scene->mRootNode, kMaxRigNodes);
    if (nodes > kMaxRigNodes)
        return Status::error("mesh file " + name + ": its rig has more than " + formatCount(double(kMaxRigNodes)) +
                             " nodes (joints and others), the most SoftTouch samples");
    const SceneUnit unit = sceneUnit(*scene, path.string());
    result.unit = unit.description;
    const Rig rig(*scene, scene->mAnimations[chosen], unit.metresPerUnit);
    if (rig.vertexCount() == 0)
        return Status::error("mesh file " + name + " has no triangles");
    if (rig.mostBones() > kMaxRigNodes)
        return Status::error("mesh file " + name + ": a mesh is skinned to " + formatCount(double(rig.mostBones())) +
                             " joints, more than the " + formatCount(double(kMaxRigNodes)) + " SoftTouch samples");
    // At most an hour at 1000 samples/s: the count fits any integer type from here on.
    const double span = (end - request.start) * request.rate;
    const auto count = request.loop ? std::max<long long>(2, std::llround(span)) : (long long)(std::floor(span + 1e-9)) + 1;
    const double positions = double(count) * double(rig.vertexCount());
    if (positions > kMaxSampledPositions)
        return Status::error("mesh file " + name + ": " + std::to_string(count) + " samples of " +
                             std::to_string(rig.vertexCount()) + " vertices is " + formatCount(positions) +
                             " positions, more than SoftTouch keeps (" + formatCount(kMaxSampledPositions) +
                             "): sample a shorter range or at a lower rate");
    const double operations = double(count) * rig.operationsPerSample();
    if (operations > kMaxSampledOperations)
        return Status::error("mesh file " + name + ": " + std::to_string(count) + " samples of this rig is " +
                             formatCount(operations) + " rig operations (" + formatCount(rig.operationsPerSample()) +
                             " a sample: its vertices, weighed blend-shape targets, skin weights and nodes), " +
                             "more than SoftTouch evaluates in one import (" + formatCount(kMaxSampledOperations) +
                             "): sample a shorter range or at a lower rate");
    BaseAnimation& animation = result.animation;
    animation.take = result.takes[std::size_t(chosen)].first;
    animation.start = request.start;
    animation.rate = request.rate;
    animation.loop = request.loop;
    animation.samples.resize(std::size_t(count));
    for (long long k = 0; k < count; ++k) {
        rig.positionsAt(std::min(end, request.start + double(k) / request.rate), animation.samples[std::size_t(k)]);
        reportImportProgress();  // a long take is work, not a hang (io/import/isolated_import.h)
    }
    // The rest mesh: the first sample, with the file's triangles.
    Mesh& mesh = result.mesh;
    mesh.positions = animation.samples.front();
    for (const Instance& instance : rig.instances()) {
        const aiMesh& source = *scene->mMeshes[instance.mesh];
        MeshPart part;
        part.name = source.mName.C_Str();
        part.firstVertex = instance.firstVertex;
        part.vertexCount = source.mNumVertices;
        mesh.parts.push_back(part);
        for (unsigned f = 0; f < source.mNumFaces; ++f) {
            const aiFace& face = source.mFaces[f];
            if (face.mNumIndices == 3)
                mesh.triangles.push_back({instance.firstVertex + face.mIndices[0], instance.firstVertex + face.mIndices[1],
                                          instance.firstVertex + face.mIndices[2]});
        }
    }
    mesh.computeNormals();
    if (Status s = mesh.validate(); !s)
        return Status::error("mesh file " + name + ": " + s.message());
    if (Status s = animation.validate(mesh.positions.size()); !s)
        return Status::error("mesh file " + name + ": " + s.message());
    return result;
}

void putTakes(std::string& out, const TakeList& takes) {
    put(out, std::uint64_t(takes.size()));
    for (const auto& [takeName, seconds] : takes) {
        putString(out, takeName);
        put(out, seconds);
    }
}

bool readTakesBytes(Decoder& in, TakeList& takes) {
    std::uint64_t count = 0;
    if (!in.get(count))
        return false;
    for (std::uint64_t t = 0; t < count; ++t) {
        std::string takeName;
        double seconds = 0.0;
        if (!in.getBytes(takeName) || !in.get(seconds))
            return false;
        takes.emplace_back(std::move(takeName), seconds);
    }
    return true;
}

void putAnimated(std::string& out, const AnimatedMesh& a) {
    // Up to kMaxSampledPositions (384 MiB): reserved once, not grown by doubling and copying.
    std::size_t sampleBytes = 0;
    for (const auto& sample : a.animation.samples)
        sampleBytes += sizeof(std::uint64_t) + sample.size() * sizeof(Vec3f);
    out.reserve(out.size() + sampleBytes + 2 * a.mesh.positions.size() * sizeof(Vec3f) +
                a.mesh.triangles.size() * sizeof(a.mesh.triangles[0]) + (1 << 16));
    putMesh(out, a.mesh);
    putString(out, a.animation.take);
    put(out, a.animation.start);
    put(out, a.animation.rate);
    put(out, std::uint8_t(a.animation.loop));
    put(out, std::uint64_t(a.animation.samples.size()));
    for (const auto& sample : a.animation.samples)
        putVector(out, sample);
    putTakes(out, a.takes);
    putString(out, a.unit);
}

bool readAnimatedBytes(Decoder& in, AnimatedMesh& a) {
    std::uint64_t samples = 0;
    std::uint8_t loop = 0;
    if (!getMesh(in, a.mesh) || !in.getBytes(a.animation.take) || !in.get(a.animation.start) || !in.get(a.animation.rate) ||
        !in.get(loop) || !in.get(samples))
        return false;
    a.animation.loop = loop != 0;
    for (std::uint64_t k = 0; k < samples; ++k) {
        std::vector<Vec3f> sample;
        if (!in.getVector(sample))
            return false;
        a.animation.samples.push_back(std::move(sample));
    }
    return readTakesBytes(in, a.takes) && in.getBytes(a.unit);
}

/// Everything importSourceRig() sends back through the importer's pipe.
void putTransform(std::string& out, const NodeTransform& t) {
    for (double x : {t.translation.x(), t.translation.y(), t.translation.z(), t.rotation.w(), t.rotation.x(), t.rotation.y(),
                     t.rotation.z(), t.scale.x(), t.scale.y(), t.scale.z()})
        put(out, x);
}
bool getTransform(Decoder& in, NodeTransform& t) {
    double x[10];
    for (double& v : x)
        if (!in.get(v))
            return false;
    t.translation = Vec3(x[0], x[1], x[2]);
    t.rotation = Eigen::Quaterniond(x[3], x[4], x[5], x[6]);
    t.scale = Vec3(x[7], x[8], x[9]);
    return true;
}
void putSourceRig(std::string& out, const SourceRig& rig) {
    const Skeleton& s = rig.skeleton;
    put(out, std::uint64_t(s.nodes.size()));
    for (const Skeleton::Node& node : s.nodes) {
        putString(out, node.name);
        put(out, std::int32_t(node.parent));
        putTransform(out, node.rest);
        put(out, std::uint8_t(node.animated));
    }
    putVector(out, s.joints);
    putVector(out, s.inverseBind);
    put(out, std::uint64_t(s.poses.size()));
    for (const auto& pose : s.poses)
        for (const NodeTransform& t : pose)
            putTransform(out, t);
    putVector(out, rig.mesh.bind);
    putVector(out, rig.mesh.joints);
    putVector(out, rig.mesh.weights);
    putString(out, rig.meshName);
}
bool readSourceRigBytes(Decoder& in, SourceRig& rig) {
    Skeleton& s = rig.skeleton;
    std::uint64_t count = 0, poses = 0;
    if (!in.get(count))
        return false;
    for (std::uint64_t n = 0; n < count; ++n) {
        Skeleton::Node node;
        std::int32_t parent = -1;
        std::uint8_t animated = 0;
        if (!in.getBytes(node.name) || !in.get(parent) || !getTransform(in, node.rest) || !in.get(animated))
            return false;
        node.parent = parent;
        node.animated = animated != 0;
        s.nodes.push_back(std::move(node));
    }
    if (!in.getVector(s.joints) || !in.getVector(s.inverseBind) || !in.get(poses))
        return false;
    for (std::uint64_t f = 0; f < poses; ++f) {
        std::vector<NodeTransform>& pose = s.poses.emplace_back(s.nodes.size());
        for (NodeTransform& t : pose)
            if (!getTransform(in, t))
                return false;
    }
    return in.getVector(rig.mesh.bind) && in.getVector(rig.mesh.joints) && in.getVector(rig.mesh.weights) &&
           in.getBytes(rig.meshName);
}

/// The skeleton of `path`'s skinned mesh at `takeSeconds` of take `take` (importSourceRig()).
Result<SourceRig> readSourceRig(const std::filesystem::path& path, const std::string& name, const std::string& take,
                                const std::vector<double>& takeSeconds) {
    Assimp::Importer importer;
    const auto read = readAnimatedScene(importer, path, name);
    if (!read)
        return read.status();
    const aiScene& scene = *read.value();
    if (countNodes(scene.mRootNode, kMaxRigNodes) > kMaxRigNodes)
        return Status::error("mesh file " + name + ": its rig has more than " + formatCount(double(kMaxRigNodes)) +
                             " nodes (joints and others), the most SoftTouch samples");
    const aiAnimation* chosen = nullptr;
    for (unsigned a = 0; a < scene.mNumAnimations && !chosen; ++a)
        if (take.empty() || take == scene.mAnimations[a]->mName.C_Str())
            chosen = scene.mAnimations[a];
    if (!chosen)
        return Status::error("mesh file " + name + " has no take \"" + take + "\"");
    for (double at : takeSeconds)
        if (!std::isfinite(at))
            return Status::error("mesh file " + name + ": a rig time is not a finite number");
    const Rig rig(scene, chosen, sceneUnit(scene, path.string()).metresPerUnit);
    return rig.sourceRig(takeSeconds, name);
}

}  // namespace

std::string answerAnimated(const std::filesystem::path& path, const std::string& name, const AnimationRequest& request) {
    return encodeResult(readAnimated(path, name, request), putAnimated);
}

std::string answerTakes(const std::filesystem::path& path, const std::string& name) {
    Assimp::Importer importer;
    const auto scene = readAnimatedScene(importer, path, name);
    return encodeResult(scene ? sceneTakes(*scene.value(), name) : Result<TakeList>(scene.status()), putTakes);
}

std::string answerSourceRig(const std::filesystem::path& path, const std::string& name, const std::string& take,
                            const std::vector<double>& takeSeconds) {
    return encodeResult(readSourceRig(path, name, take, takeSeconds), putSourceRig);
}

bool getAnimated(Decoder& in, AnimatedMesh& a) { return readAnimatedBytes(in, a); }
bool getTakes(Decoder& in, TakeList& takes) { return readTakesBytes(in, takes); }
bool getSourceRig(Decoder& in, SourceRig& rig) { return readSourceRigBytes(in, rig); }

Result<AnimatedMesh> importAnimatedMesh(const std::filesystem::path& path, const AnimationRequest& request) {
    ImportRequest asked;
    asked.kind = ImportRequest::Kind::Animated;
    asked.paths = {path};
    asked.animation = request;
    return importIsolated<AnimatedMesh>(asked, getAnimated);
}

Result<TakeList> animationTakes(const std::filesystem::path& path) {
    ImportRequest asked;
    asked.kind = ImportRequest::Kind::Takes;
    asked.paths = {path};
    return importIsolated<TakeList>(asked, getTakes);
}

Result<SourceRig> importSourceRig(const std::filesystem::path& path, const std::string& take,
                                  const std::vector<double>& takeSeconds) {
    ImportRequest asked;
    asked.kind = ImportRequest::Kind::SourceRig;
    asked.paths = {path};
    asked.take = take;
    asked.takeSeconds = takeSeconds;
    return importIsolated<SourceRig>(asked, getSourceRig);
}

}  // namespace softtouch::io

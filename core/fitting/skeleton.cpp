#include "core/fitting/skeleton.h"

namespace softtouch {

Eigen::Affine3d NodeTransform::matrix() const {
    Eigen::Affine3d m = Eigen::Affine3d::Identity();
    m.translate(translation);
    m.rotate(rotation);
    m.scale(scale);
    return m;
}

std::vector<Eigen::Affine3d> Skeleton::world(std::size_t frame) const {
    std::vector<Eigen::Affine3d> out(nodes.size());
    for (std::size_t n = 0; n < nodes.size(); ++n) {
        const Eigen::Affine3d local = poses[frame][n].matrix();
        out[n] = nodes[n].parent < 0 ? local : out[std::size_t(nodes[n].parent)] * local;
    }
    return out;
}

SourceSkin sourceSkin(const Skeleton& skeleton, const SkinnedMesh& mesh) {
    SourceSkin skin;
    skin.joints = mesh.joints;
    skin.weights = mesh.weights;
    skin.transforms.resize(skeleton.poses.size());
    for (std::size_t f = 0; f < skeleton.poses.size(); ++f) {
        const std::vector<Eigen::Affine3d> world = skeleton.world(f);
        for (std::size_t j = 0; j < skeleton.joints.size(); ++j) {
            const Eigen::Matrix4d m = world[std::size_t(skeleton.joints[j])].matrix() * skeleton.inverseBind[j];
            skin.transforms[f].push_back({m.topLeftCorner<3, 3>(), m.topRightCorner<3, 1>()});
        }
    }
    return skin;
}

}  // namespace softtouch

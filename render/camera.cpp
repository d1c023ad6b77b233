#include "render/camera.h"

#include <algorithm>
#include <cmath>

namespace softtouch::render {

Eigen::Matrix4f lookAt(const Eigen::Vector3f& eye, const Eigen::Vector3f& centre, const Eigen::Vector3f& up) {
    Eigen::Vector3f forward = centre - eye;
    if (forward.squaredNorm() == 0.0f)
        forward = -Eigen::Vector3f::UnitZ();
    forward.normalize();
    Eigen::Vector3f side = forward.cross(up);
    if (side.squaredNorm() < 1e-12f)  // up parallel to the view: any perpendicular axis will do
        side = forward.cross(std::abs(forward.y()) < 0.9f ? Eigen::Vector3f::UnitY() : Eigen::Vector3f::UnitZ());
    side.normalize();
    const Eigen::Vector3f trueUp = side.cross(forward);
    Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
    m.block<1, 3>(0, 0) = side.transpose();
    m.block<1, 3>(1, 0) = trueUp.transpose();
    m.block<1, 3>(2, 0) = -forward.transpose();
    m(0, 3) = -side.dot(eye);
    m(1, 3) = -trueUp.dot(eye);
    m(2, 3) = forward.dot(eye);
    return m;
}

Eigen::Matrix4f perspective(float fovYRadians, float aspect, float nearPlane, float farPlane) {
    const float f = 1.0f / std::tan(0.5f * fovYRadians);
    Eigen::Matrix4f m = Eigen::Matrix4f::Zero();
    m(0, 0) = f / aspect;
    m(1, 1) = f;
    m(2, 2) = (farPlane + nearPlane) / (nearPlane - farPlane);
    m(2, 3) = 2.0f * farPlane * nearPlane / (nearPlane - farPlane);
    m(3, 2) = -1.0f;
    return m;
}

Camera cameraFor(const CameraPlacement& placement, float aspect) {
    Camera camera;
    camera.view = lookAt(placement.eye, placement.centre, placement.up);
    camera.projection = perspective(placement.fovY, aspect > 0.0f ? aspect : 1.0f, placement.nearPlane, placement.farPlane);
    return camera;
}

Camera frameBounds(const Bounds& bounds, const Eigen::Vector3f& viewDirection, float aspect) {
    return cameraFor(framePlacement(bounds, viewDirection, aspect), aspect);
}

CameraPlacement framePlacement(const Bounds& bounds, const Eigen::Vector3f& viewDirection, float aspect) {
    aspect = aspect > 0.0f ? aspect : 1.0f;
    const Eigen::Vector3f centre = (0.5 * (bounds.min + bounds.max)).cast<float>();
    const float radius = std::max(0.5f * float(bounds.diagonal()), 1e-3f);
    Eigen::Vector3f dir = viewDirection.squaredNorm() > 0.0f ? viewDirection.normalized() : Eigen::Vector3f(-Eigen::Vector3f::UnitZ());
    // The sphere fits when its radius subtends at most half of the narrower field of view.
    const float halfY = 0.5f * kDefaultFovY;
    const float halfX = std::atan(std::tan(halfY) * aspect);
    const float distance = radius / std::sin(std::min(halfX, halfY)) * 1.05f;
    CameraPlacement placement;
    placement.eye = centre - dir * distance;
    placement.centre = centre;
    placement.up = std::abs(dir.y()) > 0.99f ? Eigen::Vector3f::UnitZ() : Eigen::Vector3f::UnitY();
    placement.fovY = kDefaultFovY;
    placement.nearPlane = std::max(distance - 4.0f * radius, distance * 0.01f);
    placement.farPlane = distance + 4.0f * radius;
    return placement;
}

Eigen::Vector3d toPixels(const Camera& camera, const Vec3& world, int width, int height) {
    const Eigen::Vector4d clip =
        (camera.projection * camera.view).cast<double>() * Eigen::Vector4d(world.x(), world.y(), world.z(), 1.0);
    const Eigen::Vector3d ndc = clip.head<3>() / clip.w();
    return {0.5 * (ndc.x() + 1.0) * width, 0.5 * (1.0 - ndc.y()) * height, ndc.z()};
}

}  // namespace softtouch::render

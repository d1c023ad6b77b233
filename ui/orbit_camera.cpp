#include "ui/orbit_camera.h"

#include <algorithm>
#include <cmath>

namespace softtouch::ui {

namespace {
constexpr double kPitchLimit = 1.55;  // just short of straight up/down, so "up" stays defined
}

Vec3 OrbitCamera::forward() const {
    return Vec3(-std::sin(yaw) * std::cos(pitch), std::sin(pitch), -std::cos(yaw) * std::cos(pitch));
}

Vec3 OrbitCamera::eye() const { return target - distance * forward(); }

render::Camera OrbitCamera::camera(int widthPixels, int heightPixels) const {
    return render::cameraFor(placement(), float(std::max(widthPixels, 1)) / float(std::max(heightPixels, 1)));
}

render::CameraPlacement OrbitCamera::placement() const {
    render::CameraPlacement p;
    p.eye = eye().cast<float>();
    p.centre = target.cast<float>();
    p.up = Eigen::Vector3f::UnitY();
    p.fovY = float(fovY);
    p.nearPlane = float(distance * 0.01);
    p.farPlane = float(distance * 100.0);
    return p;
}

void OrbitCamera::orbit(double dxPixels, double dyPixels) {
    yaw -= 0.01 * dxPixels;
    pitch = std::clamp(pitch - 0.01 * dyPixels, -kPitchLimit, kPitchLimit);
}

void OrbitCamera::pan(double dxPixels, double dyPixels, int heightPixels) {
    const Vec3 f = forward();
    const Vec3 right = f.cross(Vec3::UnitY()).normalized();
    const Vec3 up = right.cross(f);
    const double metresPerPixel = 2.0 * distance * std::tan(fovY / 2.0) / std::max(heightPixels, 1);
    target += (-dxPixels * right + dyPixels * up) * metresPerPixel;
}

void OrbitCamera::dolly(double factor) { distance = std::clamp(distance * factor, 1e-4, 1e6); }

void OrbitCamera::frame(const Bounds& bounds) {
    target = 0.5 * (bounds.min + bounds.max);
    const double radius = std::max(0.5 * bounds.diagonal(), 1e-3);
    distance = 1.15 * radius / std::sin(fovY / 2.0);
}

void OrbitCamera::viewFront() { yaw = 0.0; pitch = 0.0; }
void OrbitCamera::viewSide() { yaw = 1.5707963267948966; pitch = 0.0; }
void OrbitCamera::viewTop() { yaw = 0.0; pitch = -kPitchLimit; }

Eigen::Vector3d OrbitCamera::project(const Vec3& world, int widthPixels, int heightPixels) const {
    const render::Camera c = camera(widthPixels, heightPixels);
    const Eigen::Vector4d clip = (c.projection * c.view).cast<double>() * world.homogeneous();
    const Eigen::Vector3d ndc = clip.head<3>() / clip.w();
    return {(ndc.x() + 1.0) * 0.5 * widthPixels, (1.0 - ndc.y()) * 0.5 * heightPixels, clip.w() > 0 ? ndc.z() : 2.0};
}

Ray OrbitCamera::rayThrough(double xPixels, double yPixels, int widthPixels, int heightPixels) const {
    const render::Camera c = camera(widthPixels, heightPixels);
    const Eigen::Matrix4d inverse = (c.projection * c.view).cast<double>().inverse();
    const double nx = 2.0 * xPixels / std::max(widthPixels, 1) - 1.0;
    const double ny = 1.0 - 2.0 * yPixels / std::max(heightPixels, 1);
    const Eigen::Vector4d nearPoint = inverse * Eigen::Vector4d(nx, ny, -1.0, 1.0);
    const Eigen::Vector4d farPoint = inverse * Eigen::Vector4d(nx, ny, 1.0, 1.0);
    Ray r;
    r.origin = nearPoint.head<3>() / nearPoint.w();
    r.direction = (farPoint.head<3>() / farPoint.w() - r.origin).normalized();
    return r;
}

Vec3 OrbitCamera::pointOnViewPlane(double xPixels, double yPixels, int widthPixels, int heightPixels,
                                   const Vec3& reference) const {
    const Ray r = rayThrough(xPixels, yPixels, widthPixels, heightPixels);
    const Vec3 f = forward();
    const double denom = r.direction.dot(f);
    if (std::abs(denom) < 1e-12)
        return reference;
    const double t = (reference - r.origin).dot(f) / denom;
    return r.origin + t * r.direction;
}

}  // namespace softtouch::ui

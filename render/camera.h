#pragma once
/// View and projection matrices for the renderer (column-major, OpenGL conventions: the camera looks
/// down -z in view space, clip space z in [-w, w]).

#include "core/mesh.h"

#include <Eigen/Dense>

namespace softtouch::render {

/// A camera as the two matrices the shaders take.
struct Camera {
    Eigen::Matrix4f view = Eigen::Matrix4f::Identity();       ///< World to view (rigid). Filled by lookAt().
    Eigen::Matrix4f projection = Eigen::Matrix4f::Identity(); ///< View to clip. Filled by perspective().
};

/// World-to-view matrix of a camera at `eye` looking at `centre`, `up` roughly up (not parallel to the
/// viewing direction; a parallel `up` is replaced by another axis).
Eigen::Matrix4f lookAt(const Eigen::Vector3f& eye, const Eigen::Vector3f& centre, const Eigen::Vector3f& up);

/// Perspective projection (as gluPerspective): vertical field of view in radians (0, pi), aspect =
/// width / height (> 0), 0 < nearPlane < farPlane (metres).
Eigen::Matrix4f perspective(float fovYRadians, float aspect, float nearPlane, float farPlane);

/// Vertical field of view frameBounds() uses, radians (35 degrees).
constexpr float kDefaultFovY = 0.6108652f;

/// A camera looking along `viewDirection` (need not be unit; zero means -z) at the centre of `bounds`,
/// far enough that the bounds' bounding sphere fits the view at the given aspect (width / height),
/// with +y up (or +z when looking along y).
Camera frameBounds(const Bounds& bounds, const Eigen::Vector3f& viewDirection, float aspect);

/// Where a world point lands in a picture of the given size drawn with `camera`: pixels from the top-left
/// corner (x right, y down) and the normalised depth in [-1, 1] (outside: clipped).
Eigen::Vector3d toPixels(const Camera& camera, const Vec3& world, int width, int height);

}  // namespace softtouch::render

#pragma once
/// View and projection matrices for the renderer (column-major, OpenGL conventions: the camera looks
/// down -z in view space, clip space z in [-w, w]).

#include "core/geometry/mesh.h"

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

/// Where a camera stands and what it sees, as other renderers take it (the preview page's three.js camera
/// is built from these, so it draws what render/ draws).
struct CameraPlacement {
    Eigen::Vector3f eye = Eigen::Vector3f::Zero();     ///< Camera position, metres.
    Eigen::Vector3f centre = -Eigen::Vector3f::UnitZ(); ///< Point looked at.
    Eigen::Vector3f up = Eigen::Vector3f::UnitY();     ///< Roughly up (lookAt() makes it orthogonal).
    float fovY = kDefaultFovY;                         ///< Vertical field of view, radians.
    float nearPlane = 0.01f;                           ///< Near clipping distance, metres.
    float farPlane = 100.0f;                           ///< Far clipping distance, metres.
};

/// The matrices of a placement at the given aspect (width / height).
Camera cameraFor(const CameraPlacement& placement, float aspect);

/// A camera looking along `viewDirection` (need not be unit; zero means -z) at the centre of `bounds`,
/// far enough that the bounds' bounding sphere fits the view at the given aspect (width / height),
/// with +y up (or +z when looking along y).
CameraPlacement framePlacement(const Bounds& bounds, const Eigen::Vector3f& viewDirection, float aspect);

/// cameraFor(framePlacement(bounds, viewDirection, aspect), aspect).
Camera frameBounds(const Bounds& bounds, const Eigen::Vector3f& viewDirection, float aspect);

/// Where a world point lands in a picture of the given size drawn with `camera`: pixels from the top-left
/// corner (x right, y down) and the normalised depth in [-1, 1] (outside: clipped).
Eigen::Vector3d toPixels(const Camera& camera, const Vec3& world, int width, int height);

}  // namespace softtouch::render

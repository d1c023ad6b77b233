#pragma once
/// The viewport camera as animators drive it: it orbits a target (yaw, pitch), pans in the view
/// plane and dollies towards the target; plus the projections the tools need (world to pixels,
/// pixels to a ray).

#include "core/geometry/mesh.h"
#include "render/camera.h"

#include <Eigen/Dense>

namespace softtouch::ui {

/// A ray in world space.
struct Ray {
    Vec3 origin = Vec3::Zero();      ///< Metres.
    Vec3 direction = Vec3::UnitZ();  ///< Unit.
};

/// Orbiting perspective camera.
class OrbitCamera {
public:
    Vec3 target = Vec3::Zero();   ///< Point orbited, metres.
    double yaw = 0.6;             ///< Radians about +y; 0 looks along -z.
    double pitch = -0.35;         ///< Radians; negative looks down. (-pi/2, pi/2).
    double distance = 3.0;        ///< Eye to target, metres, > 0.
    double fovY = 0.6108652;      ///< Vertical field of view, radians (35 degrees).

    /// Eye position.
    Vec3 eye() const;
    /// Unit viewing direction (eye to target).
    Vec3 forward() const;
    /// Matrices for a viewport of the given pixel size.
    render::Camera camera(int widthPixels, int heightPixels) const;
    /// Where this camera stands, for a render of the same view at another size (Render video).
    render::CameraPlacement placement() const;

    /// Turns by pixel deltas (0.01 rad per pixel).
    void orbit(double dxPixels, double dyPixels);
    /// Moves target and eye in the view plane so the point under the cursor follows it.
    void pan(double dxPixels, double dyPixels, int heightPixels);
    /// Multiplies the distance (factor < 1 moves closer).
    void dolly(double factor);
    /// Fits bounds into view from the current direction.
    void frame(const Bounds& bounds);
    /// Standard views: front (looking along -z), side (along -x), top (down -y).
    void viewFront();
    void viewSide();
    void viewTop();

    /// Pixel position (x right, y down, origin top-left) and NDC depth of a world point; depth outside
    /// [-1, 1] means clipped.
    Eigen::Vector3d project(const Vec3& world, int widthPixels, int heightPixels) const;
    /// The ray from the eye through a pixel.
    Ray rayThrough(double xPixels, double yPixels, int widthPixels, int heightPixels) const;
    /// The world point under a pixel at the same view depth as `reference` (drags move in the view plane).
    Vec3 pointOnViewPlane(double xPixels, double yPixels, int widthPixels, int heightPixels, const Vec3& reference) const;
};

}  // namespace softtouch::ui

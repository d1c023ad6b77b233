#pragma once
/// The lattice's rest frame: an oriented box. Parameters (u,v,w) in [0,1]^3 map to
/// origin + axes * (size .* uvw), so the box corner `origin` is (0,0,0) and the opposite corner (1,1,1).

#include "core/base/result.h"
#include "core/base/types.h"

#include <span>

namespace softtouch {

/// An oriented box in world space.
struct OrientedBox {
    Vec3 origin = Vec3::Zero();      ///< World position of the (0,0,0) corner (metres).
    Mat3 axes = Mat3::Identity();    ///< Columns: unit, orthonormal, right-handed box axes.
    Vec3 size = Vec3::Ones();        ///< Edge lengths along the three axes (metres, > 0).

    /// World point to box parameters (u,v,w); inside the box they lie in [0,1].
    Vec3 toParameters(const Vec3& world) const;
    /// Box parameters (u,v,w) to world point.
    Vec3 toWorld(const Vec3& uvw) const;
    /// The constant derivative d(u,v,w)/d(world), a 3x3 matrix (rows: u, v, w).
    Mat3 parameterJacobian() const;
    /// Length of the box diagonal (metres).
    double diagonal() const { return size.norm(); }
    /// Checks sizes are finite and positive and the axes orthonormal.
    Status validate() const;
};

/// How a box is fitted to points.
struct BoxFitSettings {
    bool oriented = false;      ///< false: world axes (what animators expect for modelled assets); true: principal axes.
    double padding = 0.02;      ///< Extra room on each side, as a fraction of the largest extent. Range [0, 1].
    double minThickness = 0.05; ///< Smallest extent, as a fraction of the largest: flat meshes stay valid. Range (0, 1].
};

/// Fits a box around points. Flat and degenerate inputs (a plane, a line, a single point) still give a
/// valid box; an empty or non-finite input gives an error.
Result<OrientedBox> fitBox(std::span<const Vec3f> points, const BoxFitSettings& settings = {});

}  // namespace softtouch

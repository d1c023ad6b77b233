#pragma once
/// Basic vector types of the engine. Physics runs in double (tiny state, extreme stiffness and mass
/// ratios); mesh data and deformation run in float (large arrays, exported as float anyway).

#include <Eigen/Dense>
#include <cstdint>

namespace softtouch {

using Vec3 = Eigen::Vector3d;   ///< Physics-side vector (metres, m/s, newtons).
using Vec3f = Eigen::Vector3f;  ///< Mesh-side vector (metres).
using Mat3 = Eigen::Matrix3d;   ///< 3x3 matrix (rotations, Jacobians).

/// True when all three components are finite (neither NaN nor infinite).
template <typename Derived>
inline bool isFinite(const Eigen::MatrixBase<Derived>& v) {
    return v.allFinite();
}

}  // namespace softtouch

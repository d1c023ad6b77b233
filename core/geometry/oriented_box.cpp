#include "core/geometry/oriented_box.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace softtouch {

Vec3 OrientedBox::toParameters(const Vec3& world) const {
    return (axes.transpose() * (world - origin)).cwiseQuotient(size);
}

Vec3 OrientedBox::toWorld(const Vec3& uvw) const {
    return origin + axes * uvw.cwiseProduct(size);
}

Mat3 OrientedBox::parameterJacobian() const {
    return size.cwiseInverse().asDiagonal() * axes.transpose();
}

Status OrientedBox::validate() const {
    if (!isFinite(origin) || !axes.allFinite() || !isFinite(size))
        return Status::error("the lattice box has a non-finite value");
    if ((size.array() <= 0.0).any())
        return Status::error("the lattice box has a zero or negative size; every size must be > 0");
    if (!(axes.transpose() * axes).isIdentity(1e-6) || axes.determinant() < 0.0)
        return Status::error("the lattice box axes are not a right-handed orthonormal rotation");
    return Status::success();
}

Result<OrientedBox> fitBox(std::span<const Vec3f> points, const BoxFitSettings& settings) {
    if (points.empty())
        return Status::error("cannot fit a lattice box around an empty mesh");
    for (const Vec3f& p : points) {
        if (!isFinite(p))
            return Status::error("cannot fit a lattice box: the mesh has a non-finite vertex");
    }
    OrientedBox box;
    if (settings.oriented && points.size() >= 3) {
        Vec3 mean = Vec3::Zero();
        for (const Vec3f& p : points)
            mean += p.cast<double>();
        mean /= double(points.size());
        Mat3 covariance = Mat3::Zero();
        for (const Vec3f& p : points) {
            const Vec3 d = p.cast<double>() - mean;
            covariance += d * d.transpose();
        }
        Eigen::SelfAdjointEigenSolver<Mat3> solver(covariance);
        // Largest variance first, so u runs along the long axis (a fish's spine).
        Mat3 axes = solver.eigenvectors().rowwise().reverse();
        if (axes.determinant() < 0.0)
            axes.col(2) = -axes.col(2);
        box.axes = axes;
    }
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::max());
    Vec3 hi = -lo;
    for (const Vec3f& p : points) {
        const Vec3 local = box.axes.transpose() * p.cast<double>();
        lo = lo.cwiseMin(local);
        hi = hi.cwiseMax(local);
    }
    Vec3 extent = hi - lo;
    double largest = extent.maxCoeff();
    if (largest <= 0.0) {
        // A single point: give it a unit-scale box around itself relative to its magnitude.
        largest = std::max(1e-3, 1e-3 * lo.cwiseAbs().maxCoeff());
    }
    const double thinnest = settings.minThickness * largest;
    for (int a = 0; a < 3; ++a) {
        if (extent[a] < thinnest) {
            const double grow = 0.5 * (thinnest - extent[a]);
            lo[a] -= grow;
            hi[a] += grow;
        }
    }
    const double pad = settings.padding * largest;
    lo.array() -= pad;
    hi.array() += pad;
    box.size = hi - lo;
    box.origin = box.axes * lo;
    return box;
}

}  // namespace softtouch

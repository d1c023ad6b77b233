#include "core/body/network_elasticity.h"

#include <Eigen/Cholesky>

namespace softtouch {

NetworkElasticity networkElasticity(const Lattice& lattice, const LatticeMaterial& material) {
    NetworkElasticity out;
    const Mat3 axes = lattice.box().axes;
    const std::vector<Vec3> rest = lattice.restNodes();
    for (const Spring& s : latticeSprings(lattice, material)) {
        if (material.isVoid[s.a] || material.isVoid[s.b])
            continue;
        const Vec3 n = axes.transpose() * (rest[s.b] - rest[s.a]) / s.restLength;
        Eigen::Matrix<double, 6, 1> m;
        m << n.x() * n.x(), n.y() * n.y(), n.z() * n.z(), n.y() * n.z(), n.x() * n.z(), n.x() * n.y();
        out.stiffness += s.stiffness * s.restLength * s.restLength * m * m.transpose();
    }
    out.stiffness /= lattice.box().size.prod();
    const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(out.stiffness);
    const double scale = out.stiffness.diagonal().maxCoeff();
    out.resistsEveryStrain = scale > 0.0 && ldlt.info() == Eigen::Success && ldlt.isPositive() &&
                             ldlt.vectorD().minCoeff() > 1e-12 * scale;
    if (!out.resistsEveryStrain)
        return out;
    // Compliance S = C⁻¹: uniaxial stress σ along u gives ε_uu = S_11 σ, so E_u = 1/S_11; likewise shear.
    const Eigen::Matrix<double, 6, 6> compliance = ldlt.solve(Eigen::Matrix<double, 6, 6>::Identity());
    for (int a = 0; a < 3; ++a) {
        out.youngsModulus[a] = 1.0 / compliance(a, a);
        out.shearModulus[a] = 1.0 / compliance(a + 3, a + 3);
    }
    return out;
}

}  // namespace softtouch

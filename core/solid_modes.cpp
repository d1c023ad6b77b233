#include "core/solid_modes.h"

#include "core/axis_basis.h"
#include "core/modes.h"
#include "core/network_elasticity.h"
#include "core/scene.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

namespace softtouch {

namespace {

/// Gauss-Legendre points and weights of `n` points on [0,1] (exact for polynomials of degree 2n-1).
/// Newton's iteration on P_n from the Chebyshev-like first guess converges in a few steps for n <= 16.
void gaussLegendre(int n, std::vector<double>& points, std::vector<double>& weights) {
    points.assign(std::size_t(n), 0.0);
    weights.assign(std::size_t(n), 0.0);
    for (int i = 0; i < n; ++i) {
        double x = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5));
        double slope = 1.0;
        for (int iteration = 0; iteration < 100; ++iteration) {
            double p0 = 1.0, p1 = x;  // P_0, P_1; the recurrence climbs to P_n and P_{n-1}
            for (int k = 2; k <= n; ++k) {
                const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            slope = n * (x * p1 - p0) / (x * x - 1.0);
            const double step = p1 / slope;
            x -= step;
            if (std::abs(step) < 1e-15)
                break;
        }
        // On [-1,1]: w = 2 / ((1 - x²) P_n'(x)²); mapped to [0,1] both halve.
        points[std::size_t(i)] = 0.5 * (1.0 - x);
        weights[std::size_t(i)] = 1.0 / ((1.0 - x * x) * slope * slope);
    }
}

/// T = Pᵀ C P: the 9x9 elasticity acting on displacement gradients, columns (α, k) = 3α + k meaning
/// ∂u_α/∂x_k, P the map from gradients to Voigt strain (ε_uu, ε_vv, ε_ww, 2ε_vw, 2ε_uw, 2ε_uv).
Eigen::Matrix<double, 9, 9> gradientElasticity(const Eigen::Matrix<double, 6, 6>& c) {
    Eigen::Matrix<double, 6, 9> p = Eigen::Matrix<double, 6, 9>::Zero();
    const auto g = [](int alpha, int k) { return 3 * alpha + k; };
    p(0, g(0, 0)) = 1.0;
    p(1, g(1, 1)) = 1.0;
    p(2, g(2, 2)) = 1.0;
    p(3, g(1, 2)) = p(3, g(2, 1)) = 1.0;
    p(4, g(0, 2)) = p(4, g(2, 0)) = 1.0;
    p(5, g(0, 1)) = p(5, g(1, 0)) = 1.0;
    return p.transpose() * c * p;
}

}  // namespace

Result<SolidModes> solidModes(const SolidField& solid, int degree, int count) {
    if (degree < 1 || degree > kMaxSolidDegree)
        return Status::error("the reference solid's degree must be 1 to " + std::to_string(kMaxSolidDegree) + ", not " +
                             std::to_string(degree));
    if (!solid.size.allFinite() || solid.size.minCoeff() <= 0.0)
        return Status::error("the solid's box has a side that is not a positive length");
    if (!solid.modulus || !solid.density)
        return Status::error("the solid has no modulus or density field");
    const int n1 = degree + 1;
    const int nodes = n1 * n1 * n1;
    if (!solid.pinned.empty() && int(solid.pinned.size()) != nodes)
        return Status::error("the solid's pinned flags name " + std::to_string(solid.pinned.size()) + " nodes, not " +
                             std::to_string(nodes));

    // Quadrature: degree + 3 points per axis integrate N_i N_j (degree 2·degree) times a cubic density exactly.
    const int q1 = degree + 3;
    std::vector<double> qx, qw;
    gaussLegendre(q1, qx, qw);
    const AxisBasis basis = AxisBasis::bezier(n1);
    std::vector<BasisSample> samples;
    for (double x : qx)
        samples.push_back(basis.sample(x));

    const int points = q1 * q1 * q1;
    Eigen::MatrixXd value(points, nodes);
    std::array<Eigen::MatrixXd, 3> gradient{Eigen::MatrixXd(points, nodes), Eigen::MatrixXd(points, nodes),
                                            Eigen::MatrixXd(points, nodes)};
    Eigen::VectorXd massWeight(points), stiffnessWeight(points);
    const double volume = solid.size.prod();
    for (int c = 0, q = 0; c < q1; ++c) {
        for (int b = 0; b < q1; ++b) {
            for (int a = 0; a < q1; ++a, ++q) {
                const Vec3 s(qx[std::size_t(a)], qx[std::size_t(b)], qx[std::size_t(c)]);
                const double w = qw[std::size_t(a)] * qw[std::size_t(b)] * qw[std::size_t(c)] * volume;
                const double rho = solid.density(s), e = solid.modulus(s);
                if (!std::isfinite(rho) || rho <= 0.0 || !std::isfinite(e) || e < 0.0)
                    return Status::error("the solid's density or modulus is not positive and finite at (" +
                                         std::to_string(s.x()) + ", " + std::to_string(s.y()) + ", " + std::to_string(s.z()) + ")");
                massWeight[q] = w * rho;
                stiffnessWeight[q] = w * e;
                const BasisSample& su = samples[std::size_t(a)];
                const BasisSample& sv = samples[std::size_t(b)];
                const BasisSample& sw = samples[std::size_t(c)];
                for (int k = 0; k < n1; ++k) {
                    for (int j = 0; j < n1; ++j) {
                        for (int i = 0; i < n1; ++i) {
                            const int node = i + n1 * (j + n1 * k);
                            const double nu = su.value[std::size_t(i)], nv = sv.value[std::size_t(j)], nw = sw.value[std::size_t(k)];
                            value(q, node) = nu * nv * nw;
                            gradient[0](q, node) = su.slope[std::size_t(i)] * nv * nw / solid.size.x();
                            gradient[1](q, node) = nu * sv.slope[std::size_t(j)] * nw / solid.size.y();
                            gradient[2](q, node) = nu * nv * sw.slope[std::size_t(k)] / solid.size.z();
                        }
                    }
                }
            }
        }
    }

    // Scalar matrices: mass ∫ρ N_i N_j and G^(kl) = ∫ e ∂_k N_i ∂_l N_j.
    const Eigen::MatrixXd mass = value.transpose() * massWeight.asDiagonal() * value;
    std::array<std::array<Eigen::MatrixXd, 3>, 3> g;
    for (int k = 0; k < 3; ++k) {
        for (int l = k; l < 3; ++l) {
            g[std::size_t(k)][std::size_t(l)] = gradient[std::size_t(k)].transpose() * stiffnessWeight.asDiagonal() *
                                                gradient[std::size_t(l)];
            if (l != k)
                g[std::size_t(l)][std::size_t(k)] = g[std::size_t(k)][std::size_t(l)].transpose();
        }
    }
    const Eigen::Matrix<double, 9, 9> t = gradientElasticity(solid.elasticity);

    std::vector<int> slot(std::size_t(nodes), -1);
    int free = 0;
    for (int i = 0; i < nodes; ++i) {
        if (solid.pinned.empty() || !solid.pinned[std::size_t(i)])
            slot[std::size_t(i)] = free++;
    }
    if (free == 0)
        return Status::error("every node of the reference solid is pinned, so it has no modes");
    const int dof = 3 * free;
    Eigen::MatrixXd stiffness = Eigen::MatrixXd::Zero(dof, dof), consistentMass = Eigen::MatrixXd::Zero(dof, dof);
    for (int i = 0; i < nodes; ++i) {
        const int si = slot[std::size_t(i)];
        if (si < 0)
            continue;
        for (int j = 0; j < nodes; ++j) {
            const int sj = slot[std::size_t(j)];
            if (sj < 0)
                continue;
            for (int alpha = 0; alpha < 3; ++alpha) {
                consistentMass(3 * si + alpha, 3 * sj + alpha) = mass(i, j);
                for (int beta = 0; beta < 3; ++beta) {
                    double sum = 0.0;
                    for (int k = 0; k < 3; ++k) {
                        for (int l = 0; l < 3; ++l)
                            sum += t(3 * alpha + k, 3 * beta + l) * g[std::size_t(k)][std::size_t(l)](i, j);
                    }
                    stiffness(3 * si + alpha, 3 * sj + beta) = sum;
                }
            }
        }
    }

    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(stiffness, consistentMass, Eigen::EigenvaluesOnly);
    if (solver.info() != Eigen::Success)
        return Status::error("the eigenvalue solver did not converge on the reference solid");
    const Eigen::VectorXd& lambda = solver.eigenvalues();  // ascending
    SolidModes result;
    result.degree = degree;
    result.unknowns = dof;
    const int first = rigidModeCount(lambda);
    result.rigidModes = first;
    for (int m = first; m < dof && int(result.frequencyHz.size()) < count; ++m)
        result.frequencyHz.push_back(std::sqrt(lambda[m]) / (2.0 * std::numbers::pi));
    return result;
}

namespace {

/// The elasticity a Continuum material's painted values mean: the springs' on a uniform cell of the lattice's
/// mean spacing (box size / (nodes - 1) along each axis). Every cell of a Bezier lattice is that cell, so it is
/// the lattice's own network; a clamped B-spline's end cells are a third and two thirds as wide and make
/// another solid, which is the lattice's error, not the material's (docs/lattice.md). A lone cell gives it
/// exactly, since each spring's coefficient sums its cells' shares. The legacy spring model (a stiffness per
/// spring, whatever the cells) means nothing beyond its own network.
NetworkElasticity paintedElasticity(const Lattice& lattice, const LatticeMaterial& unit) {
    if (unit.model != MaterialModel::Continuum || lattice.shape().kind == LatticeKind::Bezier)
        return networkElasticity(lattice, unit);
    OrientedBox cell = lattice.box();
    for (int a = 0; a < 3; ++a)
        cell.size[a] /= double(lattice.count(a) - 1);
    const Lattice one = Lattice::create({LatticeKind::Bezier, {2, 2, 2}}, cell).value();  // a sub-box of a valid box
    LatticeMaterial cellMaterial = continuumMaterial(one, 1.0, 1.0, 0.0);
    cellMaterial.kindScale = unit.kindScale;
    cellMaterial.anisotropy = unit.anisotropy;
    return networkElasticity(one, cellMaterial);
}

}  // namespace

Result<SolidField> materialSolid(const Lattice& lattice, const LatticeMaterial& material, int degree) {
    if (degree < 1 || degree > kMaxSolidDegree)
        return Status::error("the reference solid's degree must be 1 to " + std::to_string(kMaxSolidDegree) + ", not " +
                             std::to_string(degree));
    const std::size_t n = std::size_t(lattice.nodeCount());
    if (std::any_of(material.isVoid.begin(), material.isVoid.end(), [](std::uint8_t v) { return v != 0; }))
        return Status::error("the body has void nodes; the reference solid fills the whole lattice box");
    if (material.stiffness.size() != n || material.mass.size() != n)
        return Status::error("the material has " + std::to_string(material.stiffness.size()) + " stiffness values for " +
                             std::to_string(n) + " nodes");

    // The springs' elasticity per unit of the painted stiffness: every spring's k is linear in its two nodes'.
    LatticeMaterial unit = material;
    std::fill(unit.stiffness.begin(), unit.stiffness.end(), 1.0);
    const NetworkElasticity network = paintedElasticity(lattice, unit);
    if (!network.resistsEveryStrain)
        return Status::error("the springs do not resist every uniform strain (a spring kind scaled to 0), so they "
                             "describe no solid");

    auto reference = Lattice::create({LatticeKind::Bezier, {degree + 1, degree + 1, degree + 1}}, lattice.box());
    if (!reference)
        return reference.status();
    const LatticeMaterial carried = resampleMaterial(lattice, material, reference.value(), true);

    const std::vector<double> masses = nodeMasses(lattice, material);
    const std::vector<double> volumes = nodeVolumes(lattice);
    std::vector<double> density(n);
    for (std::size_t i = 0; i < n; ++i)
        density[i] = masses[i] / volumes[i];
    const auto interpolate = [lattice](std::vector<double> values) {
        return [lattice, values = std::move(values)](const Vec3& s) {
            double sum = 0.0;
            for (const NodeWeight& w : lattice.weights(s))
                sum += w.weight * values[w.node];
            return sum;
        };
    };

    SolidField solid;
    solid.size = lattice.box().size;
    solid.elasticity = network.stiffness;
    solid.modulus = interpolate(material.stiffness);
    solid.density = interpolate(std::move(density));
    solid.pinned.resize(std::size_t(reference->nodeCount()), 0);
    for (std::size_t i = 0; i < carried.anchor.size() && i < solid.pinned.size(); ++i)
        solid.pinned[i] = carried.anchor[i] != AnchorMode::Free;
    return solid;
}

Result<SolidModes> materialSolidModes(const Lattice& lattice, const LatticeMaterial& material, int degree, int count) {
    auto solid = materialSolid(lattice, material, degree);
    if (!solid)
        return solid.status();
    auto modes = solidModes(solid.value(), degree, count);
    if (!modes || degree < 2)
        return modes;
    auto lowerSolid = materialSolid(lattice, material, degree - 1);
    auto lower = lowerSolid ? solidModes(lowerSolid.value(), degree - 1, count) : Result<SolidModes>(lowerSolid.status());
    if (!lower)
        return modes;  // spread stays unknown (-1): not converged
    modes->spread = 0.0;
    for (std::size_t m = 0; m < modes->frequencyHz.size(); ++m) {
        // A mode the coarser solid lacks counts as moved entirely.
        const double change = m < lower->frequencyHz.size() ? std::abs(lower->frequencyHz[m] / modes->frequencyHz[m] - 1.0) : 1.0;
        modes->spread = std::max(modes->spread, change);
    }
    return modes;
}

Result<SolidComparison> compareWithSolid(const Lattice& lattice, const LatticeMaterial& material, int degree, int count) {
    auto modes = objectModes(lattice, material, nullptr, count);  // the material alone: no goal springs
    if (!modes)
        return modes.status();
    auto solid = materialSolidModes(lattice, material, degree, count);
    if (!solid)
        return solid.status();
    SolidComparison out;
    out.solid = std::move(solid.value());
    for (const VibrationMode& mode : modes->modes)
        out.latticeHz.push_back(mode.frequencyHz);
    if (out.solid.converged()) {
        for (std::size_t m = 0; m < out.latticeHz.size() && m < out.solid.frequencyHz.size(); ++m)
            out.error.push_back(out.latticeHz[m] / out.solid.frequencyHz[m] - 1.0);
    }
    return out;
}

std::string describeModeErrors(const std::vector<double>& errors) {
    std::string text;
    for (double e : errors) {
        char part[32];
        std::snprintf(part, sizeof part, "%s%+.1f%%", text.empty() ? "" : " / ", 100.0 * e);
        text += part;
    }
    return text;
}

}  // namespace softtouch

#include "core/modes/solid_modes.h"

#include "core/body/network_elasticity.h"
#include "core/geometry/axis_basis.h"
#include "core/geometry/axis_quadrature.h"
#include "core/modes/modes.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

namespace softtouch {

Result<SolidModes> solidModes(const SolidField& solid, int degree, int count) {
    if (degree < 1 || degree > kMaxSolidDegree)
        return Status::error("the reference solid's degree must be 1 to " + std::to_string(kMaxSolidDegree) + ", not " +
                             std::to_string(degree));
    return solidModes(solid, bernsteinElement(degree), count);
}

namespace {

/// Basis values (or, with `axis` 0..2, slopes along that axis in 1/m) at every point of a tensor quadrature,
/// one row per point (u fastest), one column per node; sparse, since a B-spline point sees (degree + 1)^3 nodes.
Eigen::SparseMatrix<double> basisAtPoints(const std::array<AxisQuadrature, 3>& q, const std::array<int, 3>& count,
                                          const Vec3& size, int axis) {
    const int points = int(q[0].sample.size() * q[1].sample.size() * q[2].sample.size());
    std::vector<Eigen::Triplet<double>> entries;
    int row = 0;
    for (const BasisSample& sw : q[2].sample) {
        for (const BasisSample& sv : q[1].sample) {
            for (const BasisSample& su : q[0].sample) {
                for (int k = 0; k < sw.order; ++k) {
                    for (int j = 0; j < sv.order; ++j) {
                        for (int i = 0; i < su.order; ++i) {
                            const int node = (su.first + i) + count[0] * ((sv.first + j) + count[1] * (sw.first + k));
                            const std::size_t ui = std::size_t(i), vj = std::size_t(j), wk = std::size_t(k);
                            // The factor along `axis` is its slope (per metre: d/dx = d/ds / size).
                            const double nu = axis == 0 ? su.slope[ui] / size.x() : su.value[ui];
                            const double nv = axis == 1 ? sv.slope[vj] / size.y() : sv.value[vj];
                            const double nw = axis == 2 ? sw.slope[wk] / size.z() : sw.value[wk];
                            entries.emplace_back(row, node, nu * nv * nw);
                        }
                    }
                }
                ++row;
            }
        }
    }
    Eigen::SparseMatrix<double> out(points, count[0] * count[1] * count[2]);
    out.setFromTriplets(entries.begin(), entries.end());
    return out;
}

/// The field `f` at every point of the tensor quadrature times its weight and the box volume; fails on a value
/// that is negative or not finite (or zero, when `positive`).
Result<Eigen::VectorXd> weightedField(const std::array<AxisQuadrature, 3>& q, const Vec3& size,
                                      const std::function<double(const Vec3&)>& f, bool positive) {
    Eigen::VectorXd out(Eigen::Index(q[0].weight.size() * q[1].weight.size() * q[2].weight.size()));
    Eigen::Index row = 0;
    for (std::size_t c = 0; c < q[2].weight.size(); ++c) {
        for (std::size_t b = 0; b < q[1].weight.size(); ++b) {
            for (std::size_t a = 0; a < q[0].weight.size(); ++a, ++row) {
                const Vec3 s(q[0].point[a], q[1].point[b], q[2].point[c]);
                const double value = f(s);
                if (!std::isfinite(value) || value < 0.0 || (positive && value == 0.0))
                    return Status::error("the solid's density or modulus is not positive and finite at (" +
                                         std::to_string(s.x()) + ", " + std::to_string(s.y()) + ", " +
                                         std::to_string(s.z()) + ")");
                out[row] = value * q[0].weight[a] * q[1].weight[b] * q[2].weight[c] * size.prod();
            }
        }
    }
    return out;
}

}  // namespace

namespace {

/// A solid's stiffness and consistent mass over the free nodes' unknowns (3 per node), and each node's share of the
/// mass ∫ρ N_i over all nodes, pinned ones included (what a uniform acceleration loads it with).
struct Assembled {
    Eigen::MatrixXd stiffness, mass;
    Eigen::VectorXd nodeMass;
    int degree = 0;
};

Result<Assembled> assemble(const SolidField& solid, const SolidElement& element) {
    if (!solid.size.allFinite() || solid.size.minCoeff() <= 0.0)
        return Status::error("the solid's box has a side that is not a positive length");
    if (!solid.modulus || !solid.density)
        return Status::error("the solid has no modulus or density field");
    std::array<int, 3> counts{};
    int degree = 0;
    for (int a = 0; a < 3; ++a) {
        counts[std::size_t(a)] = element.axes[std::size_t(a)].count();
        degree = std::max(degree, element.axes[std::size_t(a)].degree());
        if (counts[std::size_t(a)] < 2)
            return Status::error("the element has no basis along axis " + std::to_string(a));
    }
    const int nodes = counts[0] * counts[1] * counts[2];
    if (!solid.pinned.empty() && int(solid.pinned.size()) != nodes)
        return Status::error("the solid's pinned flags name " + std::to_string(solid.pinned.size()) + " nodes, not " +
                             std::to_string(nodes));
    if (element.stiffnessPoints < 0)
        return Status::error("the element's stiffness quadrature has a negative number of points");

    // degree + 3 points per span integrate N_i N_j (degree 2·degree) times a cubic density exactly, and
    // ∂N_i ∂N_j times a cubic modulus.
    std::array<AxisQuadrature, 3> massPoints, stiffnessPoints;
    for (int a = 0; a < 3; ++a) {
        const AxisBasis& basis = element.axes[std::size_t(a)];
        massPoints[std::size_t(a)] = axisQuadrature(basis, basis.degree() + 3);
        const int perSpan = element.reduced ? basis.degree() : element.stiffnessPoints > 0 ? element.stiffnessPoints : basis.degree() + 3;
        stiffnessPoints[std::size_t(a)] = axisQuadrature(basis, perSpan);
    }
    const auto massWeight = weightedField(massPoints, solid.size, solid.density, true);
    if (!massWeight)
        return massWeight.status();
    if (!(element.exactShare >= 0.0 && element.exactShare <= 1.0))
        return Status::error("the element's exact share must be 0 to 1");
    const Eigen::SparseMatrix<double> value = basisAtPoints(massPoints, counts, solid.size, -1);

    // Scalar matrices: mass ∫ρ N_i N_j (lumped: its row sums ∫ρ N_i, since the basis sums to 1) and
    // G^(kl) = ∫ e ∂_k N_i ∂_l N_j.
    Eigen::MatrixXd mass = weightedProduct(value, massWeight.value(), value);
    if (element.mass == SolidMass::Lumped)
        mass = Eigen::MatrixXd(mass.rowwise().sum().asDiagonal());
    std::array<std::array<Eigen::MatrixXd, 3>, 3> g;
    const auto addGradientProducts = [&](const std::array<AxisQuadrature, 3>& points, double share) -> Status {
        const auto weight = weightedField(points, solid.size, solid.modulus, false);
        if (!weight)
            return weight.status();
        const std::array<Eigen::SparseMatrix<double>, 3> gradient{basisAtPoints(points, counts, solid.size, 0),
                                                                  basisAtPoints(points, counts, solid.size, 1),
                                                                  basisAtPoints(points, counts, solid.size, 2)};
        for (int k = 0; k < 3; ++k) {
            for (int l = 0; l < 3; ++l) {
                Eigen::MatrixXd product = share * weightedProduct(gradient[std::size_t(k)], weight.value(), gradient[std::size_t(l)]);
                Eigen::MatrixXd& sum = g[std::size_t(k)][std::size_t(l)];
                if (sum.size() == 0)
                    sum = std::move(product);
                else
                    sum += product;
            }
        }
        return Status::success();
    };
    const bool blended = element.reduced && element.exactShare > 0.0;
    if (Status s = addGradientProducts(stiffnessPoints, blended ? 1.0 - element.exactShare : 1.0); !s)
        return s;
    if (blended) {
        std::array<AxisQuadrature, 3> exact;
        for (int a = 0; a < 3; ++a)
            exact[std::size_t(a)] = axisQuadrature(element.axes[std::size_t(a)], element.axes[std::size_t(a)].degree() + 1);
        if (Status s = addGradientProducts(exact, element.exactShare); !s)
            return s;
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
    Assembled out;
    out.degree = degree;
    out.nodeMass = mass.rowwise().sum();
    Eigen::MatrixXd& stiffness = out.stiffness;
    Eigen::MatrixXd& massMatrix = out.mass;
    stiffness = Eigen::MatrixXd::Zero(dof, dof);
    massMatrix = Eigen::MatrixXd::Zero(dof, dof);
    for (int i = 0; i < nodes; ++i) {
        const int si = slot[std::size_t(i)];
        if (si < 0)
            continue;
        for (int j = 0; j < nodes; ++j) {
            const int sj = slot[std::size_t(j)];
            if (sj < 0)
                continue;
            for (int alpha = 0; alpha < 3; ++alpha) {
                massMatrix(3 * si + alpha, 3 * sj + alpha) = mass(i, j);
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
    return out;
}

}  // namespace

Result<SolidModes> solidModes(const SolidField& solid, const SolidElement& element, int count) {
    auto assembled = assemble(solid, element);
    if (!assembled)
        return assembled.status();
    const Eigen::MatrixXd& stiffness = assembled->stiffness;
    const Eigen::MatrixXd& massMatrix = assembled->mass;
    const int dof = int(stiffness.rows());
    const int degree = assembled->degree;
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(stiffness, massMatrix, Eigen::EigenvaluesOnly);
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

Result<Vec3> solidSag(const SolidField& solid, const SolidElement& element, const Vec3& gravity) {
    if (!gravity.allFinite())
        return Status::error("gravity is not a finite vector");
    auto assembled = assemble(solid, element);
    if (!assembled)
        return assembled.status();
    // The load ∫ρ N_i g is the mass row sums times g (the basis sums to 1); the centre of mass moves by
    // Σ_i (∫ρ N_i) u_i / ∫ρ, pinned nodes not moving.
    std::vector<double> freeMass;  // the free nodes' shares, in the order of their unknowns
    for (Eigen::Index i = 0; i < assembled->nodeMass.size(); ++i)
        if (solid.pinned.empty() || !solid.pinned[std::size_t(i)])
            freeMass.push_back(assembled->nodeMass[i]);
    Eigen::VectorXd load(assembled->stiffness.rows());
    for (std::size_t s = 0; s < freeMass.size(); ++s)
        load.segment<3>(Eigen::Index(3 * s)) = freeMass[s] * gravity;
    const Eigen::LDLT<Eigen::MatrixXd> factor(assembled->stiffness);
    if (factor.info() != Eigen::Success || !(factor.vectorD().array() > 0.0).all())
        return Status::error("the solid is not held: it has no static rest under gravity");
    const Eigen::VectorXd u = factor.solve(load);
    Vec3 moved = Vec3::Zero();
    for (std::size_t s = 0; s < freeMass.size(); ++s)
        moved += freeMass[s] * Vec3(u.segment<3>(Eigen::Index(3 * s)));
    return Vec3(moved / assembled->nodeMass.sum());
}

double SpringDeparture::largest() const {
    double worst = 0.0;
    for (double r : relative)
        worst = std::max(worst, std::abs(r));
    return worst;
}

std::string SpringDeparture::describe() const {
    static constexpr std::array<const char*, 6> kNames{"E_u", "E_v", "E_w", "G_vw", "G_uw", "G_uv"};
    std::array<int, 6> order{0, 1, 2, 3, 4, 5};
    std::stable_sort(order.begin(), order.end(),
                     [this](int a, int b) { return std::abs(relative[std::size_t(a)]) > std::abs(relative[std::size_t(b)]); });
    std::string text;
    for (int i : order) {
        const double r = relative[std::size_t(i)];
        if (std::abs(r) <= kSpringDepartureTolerance)
            continue;
        char part[32];
        std::snprintf(part, sizeof part, "%s%s %+.0f%%", text.empty() ? "" : ", ", kNames[std::size_t(i)], 100.0 * r);
        text += part;
    }
    return text;
}

std::optional<SpringDeparture> springDeparture(const Lattice& lattice, const LatticeMaterial& material) {
    if (material.model != MaterialModel::Continuum)
        return std::nullopt;
    const NetworkElasticity springs = networkElasticity(lattice, material);
    const NetworkElasticity solid = materialElasticity(lattice, material);
    if (!springs.resistsEveryStrain || !solid.resistsEveryStrain)
        return std::nullopt;
    SpringDeparture departure;
    for (int a = 0; a < 3; ++a) {
        departure.relative[std::size_t(a)] = springs.youngsModulus[a] / solid.youngsModulus[a] - 1.0;
        departure.relative[std::size_t(a + 3)] = springs.shearModulus[a] / solid.shearModulus[a] - 1.0;
    }
    return departure;
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
    auto body = buildLatticeBody(lattice, material);
    if (!body)
        return body.status();
    auto modes = analyseModes(*body.value(), count);  // the material alone: no goal springs
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

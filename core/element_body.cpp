#include "core/element_body.h"

#include "core/axis_quadrature.h"
#include "core/lattice.h"
#include "core/lattice_body.h"
#include "core/solid_modes.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCore>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

namespace softtouch {

namespace {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

/// Voigt strain (uu, vv, ww, 2vw, 2uw, 2uv) of a symmetric tensor.
Vec6 voigtStrain(const Mat3& e) {
    Vec6 v;
    v << e(0, 0), e(1, 1), e(2, 2), e(1, 2) + e(2, 1), e(0, 2) + e(2, 0), e(0, 1) + e(1, 0);
    return v;
}

/// The symmetric tensor of a Voigt stress.
Mat3 stressTensor(const Vec6& s) {
    Mat3 t;
    t << s[0], s[5], s[4], s[5], s[1], s[3], s[4], s[3], s[2];
    return t;
}

/// The stretch of F: FᵀF − I = V diag(g) Vᵀ, so S − I = V diag(g / (1 + √(1 + g))) Vᵀ with no cancellation
/// for small strains, and the singular values s = √(1 + g).
struct Stretch {
    Mat3 basis;     ///< V.
    Vec3 singular;  ///< s.
    Mat3 strain;    ///< S − I.
};

Stretch stretchOf(const Mat3& f) {
    const Mat3 green = f.transpose() * f - Mat3::Identity();
    Eigen::SelfAdjointEigenSolver<Mat3> eigen;
    eigen.computeDirect(green);
    Stretch out;
    out.basis = eigen.eigenvectors();
    Vec3 change;
    for (int a = 0; a < 3; ++a) {
        const double g = std::max(eigen.eigenvalues()[a], -1.0 + 1e-12);  // a collapsed direction keeps a tiny length
        out.singular[a] = std::sqrt(1.0 + g);
        change[a] = g / (1.0 + out.singular[a]);
    }
    out.strain = out.basis * change.asDiagonal() * out.basis.transpose();
    return out;
}

/// P = 2 F Y with S Y + Y S = σ: the exact gradient of ½ εᵀ C ε in F (S's eigenbasis makes the Sylvester
/// equation diagonal).
Mat3 firstPiola(const Mat3& f, const Stretch& stretch, const Mat3& sigma) {
    Mat3 y = stretch.basis.transpose() * sigma * stretch.basis;
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            y(a, b) /= stretch.singular[a] + stretch.singular[b];
    return 2.0 * f * (stretch.basis * y * stretch.basis.transpose());
}

/// The rotation of F's polar decomposition, F S⁻¹.
Mat3 rotationOf(const Mat3& f, const Stretch& stretch) {
    return f * (stretch.basis * stretch.singular.cwiseInverse().asDiagonal() * stretch.basis.transpose());
}

Mat3 gradientAt(const ElementBody& body, const ElementPoint& p, std::span<const Vec3> field) {
    Mat3 f = Mat3::Zero();
    for (std::uint32_t e = p.first; e < p.first + p.count; ++e)
        f.noalias() += field[body.supportNode[e]] * body.supportGradient[e].transpose();
    return f;
}

/// Subtracts P ∇N_i from each free support node's force.
void scatter(const ElementBody& body, const ElementPoint& p, const Mat3& stress, std::span<Vec3> force) {
    for (std::uint32_t e = p.first; e < p.first + p.count; ++e) {
        const std::uint32_t node = body.supportNode[e];
        if (body.slot[node] >= 0)
            force[node] -= stress * body.supportGradient[e];
    }
}

/// The rotated Kelvin-Voigt stress R η C sym(Rᵀ Ḟ) at a point (its viscosity factor included).
Mat3 viscousStress(const ElementBody& body, const ElementPoint& p, const Mat3& rotation, std::span<const Vec3> velocity) {
    const Mat3 rate = rotation.transpose() * gradientAt(body, p, velocity);
    const Vec6 sigma = p.viscosity * (body.elasticity * voigtStrain(0.5 * (rate + rate.transpose())));
    return rotation * stressTensor(sigma);
}

void addNodeDamping(const ElementBody& body, std::span<const Vec3> velocity, std::span<Vec3> force) {
    const std::size_t n = body.nodeCount();
    for (const std::uint32_t i : body.freeNodes) {
        Vec3 sum = Vec3::Zero();
        for (std::size_t j = 0; j < n; ++j)
            sum += body.nodeDamping(Eigen::Index(i), Eigen::Index(j)) * velocity[j];
        force[i] -= sum;
    }
}

/// Visits every point of a tensor quadrature with its parameters, weight and the three axes' basis samples.
template <typename Visit>
void forEachTensorPoint(const std::array<AxisQuadrature, 3>& q, Visit&& visit) {
    for (std::size_t c = 0; c < q[2].point.size(); ++c)
        for (std::size_t b = 0; b < q[1].point.size(); ++b)
            for (std::size_t a = 0; a < q[0].point.size(); ++a)
                visit(Vec3(q[0].point[a], q[1].point[b], q[2].point[c]), q[0].weight[a] * q[1].weight[b] * q[2].weight[c],
                      q[0].sample[a], q[1].sample[b], q[2].sample[c]);
}

/// Visits the nodes whose basis is non-zero at a point: node, value, gradient per unit parameter.
template <typename Visit>
void forEachSupport(const Lattice& lattice, const BasisSample& su, const BasisSample& sv, const BasisSample& sw,
                    Visit&& visit) {
    for (int k = 0; k < sw.order; ++k)
        for (int j = 0; j < sv.order; ++j)
            for (int i = 0; i < su.order; ++i) {
                const auto ui = std::size_t(i), vj = std::size_t(j), wk = std::size_t(k);
                const Vec3 slope(su.slope[ui] * sv.value[vj] * sw.value[wk], su.value[ui] * sv.slope[vj] * sw.value[wk],
                                 su.value[ui] * sv.value[vj] * sw.slope[wk]);
                visit(std::uint32_t(lattice.index(su.first + i, sv.first + j, sw.first + k)),
                      su.value[ui] * sv.value[vj] * sw.value[wk], slope);
            }
}

/// A per-node field interpolated by the lattice's basis at a point.
double interpolate(const Lattice& lattice, const std::vector<double>& values, const BasisSample& su, const BasisSample& sv,
                   const BasisSample& sw) {
    double sum = 0.0;
    forEachSupport(lattice, su, sv, sw, [&](std::uint32_t node, double value, const Vec3&) { sum += value * values[node]; });
    return sum;
}

}  // namespace

Result<std::shared_ptr<const ElementBody>> buildElementBody(const Lattice& lattice, const LatticeMaterial& material,
                                                            std::span<const std::uint8_t> held) {
    if (material.model != MaterialModel::Continuum)
        return Status::error("the solid element needs a continuum material (density, modulus); upgrade the project's "
                             "lattice-springs material first");
    auto solid = materialSolid(lattice, material, 1);  // its fields; the reference net's anchors are not used here
    if (!solid)
        return solid.status();
    const std::size_t n = std::size_t(lattice.nodeCount());
    if (held.size() != n)
        return Status::error("the element's held flags name " + std::to_string(held.size()) + " nodes, not " +
                             std::to_string(n));

    auto body = std::make_shared<ElementBody>();
    body->elasticity = solid->elasticity;
    body->slot.assign(n, -1);
    for (std::size_t i = 0; i < n; ++i) {
        if (!held[i]) {
            body->slot[i] = int(body->freeNodes.size());
            body->freeNodes.push_back(std::uint32_t(i));
        }
    }
    if (body->freeNodes.empty())
        return Status::error("every node is held, so the solid element has nothing to move");

    // Node fields the points interpolate: density as materialSolid() takes it (node mass over node volume).
    const std::vector<double> masses = nodeMasses(lattice, material);
    const std::vector<double> volumes = nodeVolumes(lattice);
    std::vector<double> density(n), dampedDensity(n);
    for (std::size_t i = 0; i < n; ++i) {
        density[i] = masses[i] / volumes[i];
        dampedDensity[i] = material.nodeDamping[i] * density[i];
        if (held[i])
            continue;
        body->maxNodeDampingRate = std::max(body->maxNodeDampingRate, material.nodeDamping[i]);
        if (material.stiffness[i] > 0.0)
            body->maxDampingRatio = std::max(body->maxDampingRatio, material.damping[i] / material.stiffness[i]);
    }
    const Vec3 size = lattice.box().size;
    const double volume = size.prod();

    // Stiffness points: the reduced rule with 1 − share, the exact one (degree + 1 a span) with share.
    const SolidElement element = simulatedElement(lattice);
    for (const auto& [share, extra] : {std::pair{1.0 - element.exactShare, 0}, std::pair{element.exactShare, 1}}) {
        if (share <= 0.0)
            continue;
        std::array<AxisQuadrature, 3> q;
        for (int a = 0; a < 3; ++a)
            q[std::size_t(a)] = axisQuadrature(lattice.axis(a), lattice.axis(a).degree() + extra);
        forEachTensorPoint(q, [&](const Vec3&, double weight, const BasisSample& su, const BasisSample& sv, const BasisSample& sw) {
            ElementPoint p;
            const double w = share * weight * volume;
            p.stiffness = w * interpolate(lattice, material.stiffness, su, sv, sw);
            p.viscosity = w * interpolate(lattice, material.damping, su, sv, sw);
            p.first = std::uint32_t(body->supportNode.size());
            forEachSupport(lattice, su, sv, sw, [&](std::uint32_t node, double, const Vec3& slope) {
                body->supportNode.push_back(node);
                body->supportGradient.push_back(slope.cwiseQuotient(size));
            });
            p.count = std::uint32_t(body->supportNode.size()) - p.first;
            body->viscous = body->viscous || p.viscosity > 0.0;
            body->points.push_back(p);
        });
    }

    // Mass and node damping, consistent: degree + 3 points a span, as the reference's. M = Vᵀ diag(wρ) V with V the
    // basis at the points (one row each), as a product rather than point by point: a Bezier 8x8x8 has 1,000 points
    // that each see all 512 nodes.
    std::array<AxisQuadrature, 3> q;
    for (int a = 0; a < 3; ++a)
        q[std::size_t(a)] = axisQuadrature(lattice.axis(a), lattice.axis(a).degree() + 3);
    std::vector<Eigen::Triplet<double>> entries;
    std::vector<double> rho, gammaRho;
    forEachTensorPoint(q, [&](const Vec3&, double weight, const BasisSample& su, const BasisSample& sv, const BasisSample& sw) {
        const int row = int(rho.size());
        forEachSupport(lattice, su, sv, sw, [&](std::uint32_t node, double value, const Vec3&) { entries.emplace_back(row, int(node), value); });
        rho.push_back(weight * volume * interpolate(lattice, density, su, sv, sw));
        gammaRho.push_back(weight * volume * interpolate(lattice, dampedDensity, su, sv, sw));
    });
    Eigen::SparseMatrix<double> values(Eigen::Index(rho.size()), Eigen::Index(n));
    values.setFromTriplets(entries.begin(), entries.end());
    body->mass = weightedProduct(values, Eigen::Map<const Eigen::VectorXd>(rho.data(), Eigen::Index(rho.size())), values);
    body->nodeDamping = weightedProduct(values, Eigen::Map<const Eigen::VectorXd>(gammaRho.data(), Eigen::Index(gammaRho.size())), values);
    body->nodeDamped = body->nodeDamping.cwiseAbs().maxCoeff() > 0.0;

    const Eigen::Index free = Eigen::Index(body->freeNodes.size());
    Eigen::MatrixXd freeMass(free, free);
    for (Eigen::Index a = 0; a < free; ++a)
        for (Eigen::Index b = 0; b < free; ++b)
            freeMass(a, b) = body->mass(body->freeNodes[std::size_t(a)], body->freeNodes[std::size_t(b)]);
    body->massFactor.compute(freeMass);
    if (body->massFactor.info() != Eigen::Success)
        return Status::error("the solid element's mass matrix is not positive definite (is the density positive everywhere?)");
    return std::shared_ptr<const ElementBody>(std::move(body));
}

void addElementForces(const ElementBody& body, std::span<const Vec3> position, std::span<const Vec3> velocity,
                      std::span<Vec3> force, bool viscous, bool nodeDamping) {
    for (const ElementPoint& p : body.points) {
        const Mat3 f = gradientAt(body, p, position);
        const Stretch stretch = stretchOf(f);
        const Vec6 sigma = p.stiffness * (body.elasticity * voigtStrain(stretch.strain));
        Mat3 stress = firstPiola(f, stretch, stressTensor(sigma));
        if (viscous && p.viscosity > 0.0)
            stress += viscousStress(body, p, rotationOf(f, stretch), velocity);
        scatter(body, p, stress, force);
    }
    if (nodeDamping && body.nodeDamped)
        addNodeDamping(body, velocity, force);
}

void addElementDampingForces(const ElementBody& body, std::span<const Vec3> position, std::span<const Vec3> velocity,
                             std::span<Vec3> force) {
    if (body.viscous) {
        for (const ElementPoint& p : body.points) {
            if (p.viscosity <= 0.0)
                continue;
            const Mat3 f = gradientAt(body, p, position);
            scatter(body, p, viscousStress(body, p, rotationOf(f, stretchOf(f)), velocity), force);
        }
    }
    if (body.nodeDamped)
        addNodeDamping(body, velocity, force);
}

double elementEnergy(const ElementBody& body, std::span<const Vec3> position) {
    double energy = 0.0;
    for (const ElementPoint& p : body.points) {
        const Vec6 strain = voigtStrain(stretchOf(gradientAt(body, p, position)).strain);
        energy += 0.5 * p.stiffness * strain.dot(body.elasticity * strain);
    }
    return energy;
}

double elementKineticEnergy(const ElementBody& body, std::span<const Vec3> velocity) {
    double energy = 0.0;
    for (const std::uint32_t i : body.freeNodes)
        for (const std::uint32_t j : body.freeNodes)
            energy += body.mass(i, j) * velocity[i].dot(velocity[j]);
    return 0.5 * energy;
}

void solveElementMass(const ElementBody& body, std::span<const Vec3> force, std::span<Vec3> acceleration,
                      Eigen::MatrixXd& work) {
    const Eigen::Index free = Eigen::Index(body.freeNodes.size());
    work.resize(free, 3);
    for (Eigen::Index s = 0; s < free; ++s)
        work.row(s) = force[body.freeNodes[std::size_t(s)]].transpose();
    body.massFactor.solveInPlace(work);
    for (Eigen::Index s = 0; s < free; ++s)
        acceleration[body.freeNodes[std::size_t(s)]] = work.row(s).transpose();
}

namespace {

/// Σ_q w_q Bᵀ C B over the free nodes at rest, B the Voigt strain of the support's displacements, each point's
/// factor from `factor` (its stiffness or its viscosity). At rest every point's rotation is the box's (the rest
/// nodes are the box's grid), so the matrix is the box frame's turned by it, and the box frame's is nine weighted
/// products of the gradients, G^(kl) = Σ_q w_q ∂_k N_i ∂_l N_j, combined through T = Pᵀ C P (as the reference).
template <typename Factor>
Eigen::MatrixXd restMatrix(const ElementBody& body, std::span<const Vec3> rest, Factor&& factor) {
    const Eigen::Index dof = Eigen::Index(3 * body.freeNodes.size());
    Eigen::MatrixXd out = Eigen::MatrixXd::Zero(dof, dof);
    if (body.points.empty())
        return out;
    const Eigen::Index points = Eigen::Index(body.points.size());
    std::array<std::vector<Eigen::Triplet<double>>, 3> entries;
    Eigen::VectorXd weight(points);
    for (Eigen::Index q = 0; q < points; ++q) {
        const ElementPoint& p = body.points[std::size_t(q)];
        weight[q] = factor(p);
        for (std::uint32_t e = p.first; e < p.first + p.count; ++e)
            for (int k = 0; k < 3; ++k)
                entries[std::size_t(k)].emplace_back(int(q), int(body.supportNode[e]), body.supportGradient[e][k]);
    }
    std::array<Eigen::SparseMatrix<double>, 3> gradient;
    for (int k = 0; k < 3; ++k) {
        gradient[std::size_t(k)].resize(points, Eigen::Index(body.nodeCount()));
        gradient[std::size_t(k)].setFromTriplets(entries[std::size_t(k)].begin(), entries[std::size_t(k)].end());
    }
    std::array<std::array<Eigen::MatrixXd, 3>, 3> g;
    for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l)
            g[std::size_t(k)][std::size_t(l)] = weightedProduct(gradient[std::size_t(k)], weight, gradient[std::size_t(l)]);
    const Eigen::Matrix<double, 9, 9> t = gradientElasticity(body.elasticity);
    const Mat3 f = gradientAt(body, body.points.front(), rest);
    const Mat3 r = rotationOf(f, stretchOf(f));
    for (std::size_t a = 0; a < body.freeNodes.size(); ++a) {
        const Eigen::Index i = body.freeNodes[a];
        for (std::size_t b = 0; b < body.freeNodes.size(); ++b) {
            const Eigen::Index j = body.freeNodes[b];
            Mat3 block;
            for (int alpha = 0; alpha < 3; ++alpha)
                for (int beta = 0; beta < 3; ++beta) {
                    double sum = 0.0;
                    for (int k = 0; k < 3; ++k)
                        for (int l = 0; l < 3; ++l)
                            sum += t(3 * alpha + k, 3 * beta + l) * g[std::size_t(k)][std::size_t(l)](i, j);
                    block(alpha, beta) = sum;
                }
            out.block<3, 3>(Eigen::Index(3 * a), Eigen::Index(3 * b)) = r * block * r.transpose();
        }
    }
    return out;
}

}  // namespace

Eigen::MatrixXd elementRestStiffness(const ElementBody& body, std::span<const Vec3> restPosition) {
    return restMatrix(body, restPosition, [](const ElementPoint& p) { return p.stiffness; });
}

Eigen::MatrixXd elementRestViscosity(const ElementBody& body, std::span<const Vec3> restPosition) {
    return restMatrix(body, restPosition, [](const ElementPoint& p) { return p.viscosity; });
}

}  // namespace softtouch

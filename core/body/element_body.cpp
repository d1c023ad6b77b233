#include "core/body/element_body.h"

#include "core/body/element_stress.h"
#include "core/body/lattice_body.h"
#include "core/body/solid_element.h"
#include "core/geometry/axis_quadrature.h"
#include "core/geometry/lattice.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCore>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

namespace softtouch {

namespace {

/// The points' scratch, the calling thread's (a body is stepped by one thread at a time, and several bodies may
/// step at once on different threads).
struct PointScratch {
    std::array<std::vector<double>, 3> gradient;  ///< elementGradients()' columns.
    std::array<std::vector<double>, 3> stress;    ///< The stresses' columns, elementScatter()'s.
};
PointScratch& pointScratch() {
    thread_local PointScratch s;
    return s;
}

/// Points [first, first + kStressLanes) of one field's matrix in columns laid out as elementGradients() writes
/// them (`width` doubles a point, the field's three from 3 × `field`), as lanes (entry 3c + α the column c's
/// component α); lanes past `count` hold the identity, or zero with `identity` false.
std::array<Lanes, 9> loadLanes(const std::array<std::vector<double>, 3>& columns, std::size_t width, std::size_t field,
                               std::size_t first, std::size_t count, bool identity) {
    std::array<Lanes, 9> out;
    for (int l = 0; l < kStressLanes; ++l) {
        const std::size_t p = first + std::size_t(l);
        for (int c = 0; c < 3; ++c)
            for (int a = 0; a < 3; ++a)
                out[std::size_t(3 * c + a)][std::size_t(l)] =
                    p < count ? columns[std::size_t(c)][p * width + 3 * field + std::size_t(a)] : (identity && a == c ? 1.0 : 0.0);
    }
    return out;
}

/// Points [first, first + kStressLanes) of a per-point value; lanes past `count` hold zero.
Lanes loadLanes(const std::vector<double>& values, std::size_t first, std::size_t count) {
    Lanes out{};
    for (int l = 0; l < kStressLanes; ++l)
        if (first + std::size_t(l) < count)
            out[std::size_t(l)] = values[first + std::size_t(l)];
    return out;
}

/// The lanes below `count` of a matrix at each lane, back into columns laid out as loadLanes() reads them
/// (negated with `negate`).
void storeLanes(const std::array<Lanes, 9>& m, std::size_t first, std::size_t count, std::array<std::vector<double>, 3>& columns,
                std::size_t width, std::size_t field, bool negate = false) {
    for (std::size_t c = 0; c < 3; ++c)
        if (columns[c].size() < count * width)
            columns[c].resize(count * width);
    for (int l = 0; l < kStressLanes && first + std::size_t(l) < count; ++l)
        for (int c = 0; c < 3; ++c)
            for (int a = 0; a < 3; ++a) {
                const double value = m[std::size_t(3 * c + a)][std::size_t(l)];
                columns[std::size_t(c)][(first + std::size_t(l)) * width + 3 * field + std::size_t(a)] = negate ? -value : value;
            }
}

/// A per-node field interpolated by the lattice's basis at parameters s.
double interpolate(const Lattice& lattice, const std::vector<double>& values, const Vec3& s) {
    double sum = 0.0;
    for (const NodeWeight& w : lattice.weights(s))
        sum += w.weight * values[w.node];
    return sum;
}

/// The rule of degree + `extraPoints` Gauss points a span on every axis, each point weighted by `share` × its
/// weight × the box volume × the painted modulus (and viscosity) there.
ElementRule makeRule(const Lattice& lattice, const LatticeMaterial& material, double share, int extraPoints) {
    ElementRule rule;
    std::array<AxisQuadrature, 3> q;
    const Vec3 size = lattice.box().size;
    for (int a = 0; a < 3; ++a) {
        const AxisBasis& basis = lattice.axis(a);
        q[std::size_t(a)] = axisQuadrature(basis, basis.degree() + extraPoints);
        ElementAxisRule& axis = rule.axes[std::size_t(a)];
        const Eigen::Index points = Eigen::Index(q[std::size_t(a)].point.size());
        axis.value = Eigen::MatrixXd::Zero(points, basis.count());
        axis.slope = Eigen::MatrixXd::Zero(points, basis.count());
        for (Eigen::Index p = 0; p < points; ++p) {
            const BasisSample& sample = q[std::size_t(a)].sample[std::size_t(p)];
            for (int r = 0; r < sample.order; ++r) {
                axis.value(p, sample.first + r) = sample.value[std::size_t(r)];
                axis.slope(p, sample.first + r) = sample.slope[std::size_t(r)] / size[a];
            }
        }
        axis.finishAxis();
    }
    for (std::size_t c = 0; c < q[2].point.size(); ++c)  // u fastest, as elementRulePoint()
        for (std::size_t b = 0; b < q[1].point.size(); ++b)
            for (std::size_t a = 0; a < q[0].point.size(); ++a) {
                const Vec3 s(q[0].point[a], q[1].point[b], q[2].point[c]);
                const double w = share * q[0].weight[a] * q[1].weight[b] * q[2].weight[c] * size.prod();
                rule.stiffness.push_back(w * interpolate(lattice, material.stiffness, s));
                rule.viscosity.push_back(w * interpolate(lattice, material.damping, s));
            }
    return rule;
}

}  // namespace

Eigen::MatrixXd elementFreeBlock(const ElementBody& body, const Eigen::MatrixXd& nodeMatrix) {
    const Eigen::Index free = Eigen::Index(body.freeNodes.size());
    Eigen::MatrixXd out(free, free);
    for (Eigen::Index a = 0; a < free; ++a)
        for (Eigen::Index b = 0; b < free; ++b)
            out(a, b) = nodeMatrix(body.freeNodes[std::size_t(a)], body.freeNodes[std::size_t(b)]);
    return out;
}

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
    body->frame = lattice.box().axes;
    body->counts = {lattice.count(0), lattice.count(1), lattice.count(2)};
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
    }

    // Stiffness: the reduced rule (degree points a span) with 1 − share, the exact one (degree + 1) with share.
    const SolidElement element = simulatedElement(lattice);
    if (element.exactShare < 1.0)
        body->rules.push_back(makeRule(lattice, material, 1.0 - element.exactShare, 0));
    if (element.exactShare > 0.0)
        body->rules.push_back(makeRule(lattice, material, element.exactShare, 1));
    for (const ElementRule& rule : body->rules)
        body->viscous = body->viscous || *std::max_element(rule.viscosity.begin(), rule.viscosity.end()) > 0.0;

    // Mass and node damping, consistent: degree + 3 points a span, as the reference's. M = Vᵀ diag(wρ) V with V the
    // basis at the points (one row each), as a product rather than point by point: a Bezier 8x8x8 has 1,000 points
    // that each see all 512 nodes.
    const Vec3 size = lattice.box().size;
    std::array<AxisQuadrature, 3> q;
    for (int a = 0; a < 3; ++a)
        q[std::size_t(a)] = axisQuadrature(lattice.axis(a), lattice.axis(a).degree() + 3);
    std::vector<Eigen::Triplet<double>> entries;
    std::vector<double> rho, gammaRho;
    for (std::size_t c = 0; c < q[2].point.size(); ++c)
        for (std::size_t b = 0; b < q[1].point.size(); ++b)
            for (std::size_t a = 0; a < q[0].point.size(); ++a) {
                const int row = int(rho.size());
                const Vec3 s(q[0].point[a], q[1].point[b], q[2].point[c]);
                double d = 0.0, g = 0.0;
                for (const NodeWeight& w : lattice.weights(s)) {
                    entries.emplace_back(row, int(w.node), w.weight);
                    d += w.weight * density[w.node];
                    g += w.weight * dampedDensity[w.node];
                }
                const double weight = q[0].weight[a] * q[1].weight[b] * q[2].weight[c] * size.prod();
                rho.push_back(weight * d);
                gammaRho.push_back(weight * g);
            }
    Eigen::SparseMatrix<double> values(Eigen::Index(rho.size()), Eigen::Index(n));
    values.setFromTriplets(entries.begin(), entries.end());
    body->mass = weightedProduct(values, Eigen::Map<const Eigen::VectorXd>(rho.data(), Eigen::Index(rho.size())), values);
    body->nodeDamping = weightedProduct(values, Eigen::Map<const Eigen::VectorXd>(gammaRho.data(), Eigen::Index(gammaRho.size())), values);
    body->nodeDamped = body->nodeDamping.cwiseAbs().maxCoeff() > 0.0;

    const Eigen::Index free = Eigen::Index(body->freeNodes.size());
    body->massFactor.compute(elementFreeBlock(*body, body->mass));
    if (body->massFactor.info() != Eigen::Success)
        return Status::error("the solid element's mass matrix is not positive definite (is the density positive everywhere?)");
    body->inverseFactor = body->massFactor.matrixL().solve(Eigen::MatrixXd::Identity(free, free));
    if (body->viscous)
        body->viscosityBound = elementViscosityBound(*body);
    return std::shared_ptr<const ElementBody>(std::move(body));
}

void addElementForces(const ElementBody& body, std::span<const Vec3> position, std::span<const Vec3> velocity,
                      std::span<Vec3> force, bool viscous, bool nodeDamping, std::span<Vec3> dampingOut) {
    PointScratch& t = pointScratch();
    const bool withViscosity = viscous && body.viscous;
    const bool measure = !dampingOut.empty();
    if (measure)
        std::fill(dampingOut.begin(), dampingOut.end(), Vec3::Zero());
    // One contraction for the positions and velocities together, and one back for the stresses and, when they
    // are measured, the viscous stresses alone.
    const std::array<std::span<const Vec3>, 2> fields = {position, velocity};
    const std::size_t inWidth = withViscosity ? 6 : 3, outWidth = withViscosity && measure ? 6 : 3;
    const std::array<std::span<Vec3>, 2> forces = {force, dampingOut};
    for (const ElementRule& rule : body.rules) {
        elementGradients(rule, body.counts, std::span(fields).first(inWidth / 3), t.gradient);
        const std::size_t points = rule.pointCount();
        for (std::size_t first = 0; first < points; first += kStressLanes) {
            const std::array<Lanes, 9> f = loadLanes(t.gradient, inWidth, 0, first, points, true);
            StretchLanes stretch;
            stretchLanes(f, stretch);
            std::array<Lanes, 9> stress;
            elasticStressLanes(body.elasticity, loadLanes(rule.stiffness, first, points), f, stretch, stress);
            if (withViscosity) {
                std::array<Lanes, 9> rotation, damping;
                rotationLanes(f, stretch, rotation);
                corotatedStressLanes(body.elasticity, loadLanes(rule.viscosity, first, points), rotation,
                                     loadLanes(t.gradient, inWidth, 1, first, points, false), damping);
                for (int e = 0; e < 9; ++e)
                    for (int l = 0; l < kStressLanes; ++l)
                        stress[std::size_t(e)][std::size_t(l)] += damping[std::size_t(e)][std::size_t(l)];
                if (measure)
                    storeLanes(damping, first, points, t.stress, outWidth, 1);
            }
            storeLanes(stress, first, points, t.stress, outWidth, 0);
        }
        elementScatter(rule, body.counts, t.stress, body.slot, std::span(forces).first(outWidth / 3));
    }
    if (nodeDamping && body.nodeDamped) {
        addElementMatrixTimes(body, body.nodeDamping, -1.0, velocity, force);
        if (measure)
            addElementMatrixTimes(body, body.nodeDamping, -1.0, velocity, dampingOut);
    }
}

void elementRotations(const ElementBody& body, std::span<const Vec3> position, std::vector<Mat3>& rotations) {
    PointScratch& t = pointScratch();
    rotations.clear();
    for (const ElementRule& rule : body.rules) {
        elementGradients(rule, body.counts, std::span(&position, 1), t.gradient);
        const std::size_t points = rule.pointCount();
        for (std::size_t first = 0; first < points; first += kStressLanes) {
            const std::array<Lanes, 9> f = loadLanes(t.gradient, 3, 0, first, points, true);
            StretchLanes stretch;
            stretchLanes(f, stretch);
            std::array<Lanes, 9> rotation;
            rotationLanes(f, stretch, rotation);
            for (int l = 0; l < kStressLanes && first + std::size_t(l) < points; ++l) {
                Mat3 r;
                for (int e = 0; e < 9; ++e)
                    r(e) = rotation[std::size_t(e)][std::size_t(l)];  // column-major, as Mat3
                rotations.push_back(r);
            }
        }
    }
}

void addElementTangent(const ElementBody& body, const std::vector<Mat3>& rotations, double a, double b,
                       std::span<const Vec3> p, std::span<Vec3> y) {
    PointScratch& t = pointScratch();
    std::size_t first = 0;
    for (const ElementRule& rule : body.rules) {
        elementGradients(rule, body.counts, std::span(&p, 1), t.gradient);
        const std::size_t points = rule.pointCount();
        for (std::size_t q = 0; q < points; q += kStressLanes) {
            std::array<Lanes, 9> rotation{};
            Lanes factor{};
            for (int l = 0; l < kStressLanes && q + std::size_t(l) < points; ++l) {
                const Mat3& r = rotations[first + q + std::size_t(l)];
                for (int e = 0; e < 9; ++e)
                    rotation[std::size_t(e)][std::size_t(l)] = r(e);
                factor[std::size_t(l)] = a * rule.stiffness[q + std::size_t(l)] + b * rule.viscosity[q + std::size_t(l)];
            }
            std::array<Lanes, 9> stress;
            corotatedStressLanes(body.elasticity, factor, rotation, loadLanes(t.gradient, 3, 0, q, points, false), stress);
            storeLanes(stress, q, points, t.stress, 3, 0, true);  // elementScatter() subtracts
        }
        elementScatter(rule, body.counts, t.stress, body.slot, std::span(&y, 1));
        first += points;
    }
}

double elementEnergy(const ElementBody& body, std::span<const Vec3> position) {
    PointScratch& t = pointScratch();
    double energy = 0.0;
    for (const ElementRule& rule : body.rules) {
        elementGradients(rule, body.counts, std::span(&position, 1), t.gradient);
        const std::size_t points = rule.pointCount();
        Lanes lanes{};
        for (std::size_t first = 0; first < points; first += kStressLanes) {
            const std::array<Lanes, 9> f = loadLanes(t.gradient, 3, 0, first, points, true);
            StretchLanes stretch;
            stretchLanes(f, stretch);
            std::array<Lanes, 9> stress;
            elasticStressLanes(body.elasticity, loadLanes(rule.stiffness, first, points), f, stretch, stress, &lanes);
        }
        for (const double e : lanes)
            energy += e;
    }
    return energy;
}

double elementMassProduct(const ElementBody& body, std::span<const Vec3> a, std::span<const Vec3> b) {
    double sum = 0.0;
    for (const std::uint32_t i : body.freeNodes)
        for (const std::uint32_t j : body.freeNodes)
            sum += body.mass(i, j) * a[i].dot(b[j]);
    return sum;
}

void addElementMatrixTimes(const ElementBody& body, const Eigen::MatrixXd& nodeMatrix, double scale,
                           std::span<const Vec3> in, std::span<Vec3> out) {
    // Column by column: the matrix is column-major, so a column's rows are read in order; a node that does not
    // move (a held one, in a product over the free nodes) is skipped.
    const std::size_t n = body.nodeCount();
    for (std::size_t j = 0; j < n; ++j) {
        if (in[j].isZero(0.0))
            continue;
        const Vec3 x = scale * in[j];
        const double* column = nodeMatrix.data() + j * n;
        for (const std::uint32_t i : body.freeNodes)
            out[i] += column[i] * x;
    }
}

Eigen::MatrixXd elementFreeMatrix(const ElementBody& body, const Eigen::MatrixXd& nodeMatrix) {
    const Eigen::MatrixXd block = elementFreeBlock(body, nodeMatrix);
    Eigen::MatrixXd out = Eigen::MatrixXd::Zero(3 * block.rows(), 3 * block.cols());
    for (Eigen::Index a = 0; a < block.rows(); ++a)
        for (Eigen::Index b = 0; b < block.cols(); ++b)
            out.block<3, 3>(3 * a, 3 * b).diagonal().setConstant(block(a, b));
    return out;
}

ElementViscosityModes elementViscosityModes(const ElementBody& body) {
    ElementViscosityModes out;
    if (!body.viscous)
        return out;
    // K̃ φ = k M φ over the free nodes (every component alike), φ M-normalised: K̃ = M Φ diag(k) Φᵀ M.
    const Eigen::MatrixXd mass = elementFreeBlock(body, body.mass);
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> modes(elementFreeBlock(body, body.viscosityBound), mass);
    out.massModes = mass * modes.eigenvectors();
    out.rates = modes.eigenvalues();
    return out;
}

Eigen::MatrixXd elementStepViscosity(const ElementBody& body, const ElementViscosityModes& modes, double h) {
    const Eigen::Index free = Eigen::Index(body.freeNodes.size());
    if (modes.rates.size() != free)
        return Eigen::MatrixXd::Zero(free, free);
    const Eigen::VectorXd kept = (modes.rates.array() - kExplicitViscosityShare / h).max(0.0).matrix();
    return modes.massModes * kept.asDiagonal() * modes.massModes.transpose();
}

double elementStepViscosityProduct(const ElementBody& body, const ElementViscosityModes& modes, double h,
                                   std::span<const Vec3> v) {
    // Σ_j kept_j |φ_jᵀ M v|², mode by mode (no scratch: the energy account calls it inside a step).
    const double floor = kExplicitViscosityShare / h;
    double sum = 0.0;
    for (Eigen::Index j = 0; j < modes.rates.size(); ++j) {
        const double kept = modes.rates[j] - floor;
        if (!(kept > 0.0))
            continue;
        Vec3 projected = Vec3::Zero();
        for (std::size_t s = 0; s < body.freeNodes.size(); ++s)
            projected += modes.massModes(Eigen::Index(s), j) * v[body.freeNodes[s]];
        sum += kept * projected.squaredNorm();
    }
    return sum;
}

void applyElementFreeMatrix(const ElementBody& body, const Eigen::MatrixXd& matrix, std::span<const Vec3> in,
                            std::span<Vec3> out, Eigen::MatrixXd& work) {
    // A product with the inverse rather than two triangular solves with a factor: the same arithmetic, and on
    // small lattices a product Eigen runs faster than the solves.
    const Eigen::Index free = Eigen::Index(body.freeNodes.size());
    work.resize(free, 6);
    for (Eigen::Index s = 0; s < free; ++s)
        work.row(s).head<3>() = in[body.freeNodes[std::size_t(s)]].transpose();
    work.rightCols<3>().noalias() = matrix * work.leftCols<3>();
    for (Eigen::Index s = 0; s < free; ++s)
        out[body.freeNodes[std::size_t(s)]] = work.row(s).tail<3>().transpose();
}

namespace {

using GradientProducts = std::array<std::array<Eigen::MatrixXd, 3>, 3>;

/// G^(kl) = Σ_q w_q ∂_k N_i ∂_l N_j over every node, each point's w_q from `factor` (a rule's stiffness or
/// viscosity); with `diagonalOnly` only G^(kk) (the others stay empty).
template <typename Factor>
GradientProducts gradientProducts(const ElementBody& body, Factor&& factor, bool diagonalOnly) {
    const Eigen::Index n = Eigen::Index(body.nodeCount());
    GradientProducts g;
    for (int k = 0; k < 3; ++k)
        for (int l = 0; l < 3; ++l)
            if (!diagonalOnly || k == l)
                g[std::size_t(k)][std::size_t(l)] = Eigen::MatrixXd::Zero(n, n);
    const auto [nu, nv, nw] = body.counts;
    for (const ElementRule& rule : body.rules) {
        const Eigen::Index points = Eigen::Index(rule.pointCount());
        std::array<std::vector<Eigen::Triplet<double>>, 3> entries;
        Eigen::VectorXd weight(points);
        const ElementAxisRule& u = rule.axes[0];
        const ElementAxisRule& v = rule.axes[1];
        const ElementAxisRule& w = rule.axes[2];
        const int pu = int(u.value.rows()), pv = int(v.value.rows()), pw = int(w.value.rows());
        for (int r = 0; r < pw; ++r)
            for (int q = 0; q < pv; ++q)
                for (int p = 0; p < pu; ++p) {
                    const int point = int(elementRulePoint(rule, p, q, r));
                    weight[point] = factor(rule, std::size_t(point));
                    for (int k = 0; k < nw; ++k)
                        for (int j = 0; j < nv; ++j)
                            for (int i = 0; i < nu; ++i) {
                                const Vec3 slope(u.slope(p, i) * v.value(q, j) * w.value(r, k),
                                                 u.value(p, i) * v.slope(q, j) * w.value(r, k),
                                                 u.value(p, i) * v.value(q, j) * w.slope(r, k));
                                if (slope.isZero(0.0))
                                    continue;
                                const int node = i + nu * (j + nv * k);
                                for (int c = 0; c < 3; ++c)
                                    entries[std::size_t(c)].emplace_back(point, node, slope[c]);
                            }
                }
        std::array<Eigen::SparseMatrix<double>, 3> gradient;
        for (int c = 0; c < 3; ++c) {
            gradient[std::size_t(c)].resize(points, n);
            gradient[std::size_t(c)].setFromTriplets(entries[std::size_t(c)].begin(), entries[std::size_t(c)].end());
        }
        for (int k = 0; k < 3; ++k)
            for (int l = 0; l < 3; ++l)
                if (!diagonalOnly || k == l)
                    g[std::size_t(k)][std::size_t(l)] += weightedProduct(gradient[std::size_t(k)], weight, gradient[std::size_t(l)]);
    }
    return g;
}

/// Σ_q w_q Bᵀ C B over the free nodes at rest, B the Voigt strain of the nodes' displacements, each point's
/// factor from `factor` (a rule's stiffness or viscosity). At rest every point's rotation is the box's, so the
/// matrix is the box frame's turned by it, and the box frame's is the nine gradient products combined through
/// T = Pᵀ C P (as the reference's).
template <typename Factor>
Eigen::MatrixXd restMatrix(const ElementBody& body, Factor&& factor) {
    const Eigen::Index dof = Eigen::Index(3 * body.freeNodes.size());
    const GradientProducts g = gradientProducts(body, factor, false);
    const Eigen::Matrix<double, 9, 9> t = gradientElasticity(body.elasticity);
    const Mat3& r = body.frame;
    Eigen::MatrixXd out(dof, dof);
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

Eigen::MatrixXd elementRestStiffness(const ElementBody& body) {
    return restMatrix(body, [](const ElementRule& rule, std::size_t p) { return rule.stiffness[p]; });
}

Eigen::MatrixXd elementRestViscosity(const ElementBody& body) {
    return restMatrix(body, [](const ElementRule& rule, std::size_t p) { return rule.viscosity[p]; });
}

Eigen::MatrixXd elementViscosityBound(const ElementBody& body) {
    // A point's viscous power is η εᵀ C ε with ε = sym(Rᵀ Ḟ) in Voigt form; in Mandel form (shears times √2,
    // so that |ε| is the Frobenius norm) it is at most η λ |ε|² ≤ η λ |Ḟ|², λ the largest eigenvalue of C
    // there, and |Ḟ|² = Σ_k |Σ_i v_i ∂_k N_i|² is the same for every component and rotation.
    Eigen::Matrix<double, 6, 1> mandel;
    mandel << 1.0, 1.0, 1.0, std::sqrt(2.0), std::sqrt(2.0), std::sqrt(2.0);
    const Eigen::Matrix<double, 6, 6> c = mandel.asDiagonal() * body.elasticity * mandel.asDiagonal();
    const double lambda = Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>>(c, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff();
    const GradientProducts g = gradientProducts(body, [](const ElementRule& rule, std::size_t p) { return rule.viscosity[p]; }, true);
    return 0.5 * lambda * (g[0][0] + g[1][1] + g[2][2]);
}

}  // namespace softtouch

#include "core/body/element_body.h"

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

using Vec6 = Eigen::Matrix<double, 6, 1>;

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

/// Scratch of the contractions, the calling thread's (a body is stepped by one thread at a time, and several
/// bodies may step at once on different threads).
struct Contraction {
    std::array<std::vector<Vec3>, 2> a, d;
    std::array<std::vector<Vec3>, 3> b, c, gradient, rate, stress;
};
Contraction& scratch() {
    thread_local Contraction c;
    return c;
}

void fit(std::vector<Vec3>& v, std::size_t size) {
    if (v.size() < size)
        v.resize(size);
}

/// The columns of the deformation gradient (∂x/∂X_u, ∂x/∂X_v, ∂x/∂X_w; box frame) of the node field `x` at every
/// point of `rule` (index p + P_u (q + P_v r)), by three one-axis contractions.
void gradients(const ElementBody& body, const ElementRule& rule, std::span<const Vec3> x, std::array<std::vector<Vec3>*, 3> out) {
    const auto [nu, nv, nw] = body.counts;
    const ElementAxisRule& u = rule.axes[0];
    const ElementAxisRule& v = rule.axes[1];
    const ElementAxisRule& w = rule.axes[2];
    const int pu = int(u.value.rows()), pv = int(v.value.rows()), pw = int(w.value.rows());
    Contraction& t = scratch();
    // Along u: A_V[p, j, k] = Σ_i V_u(p, i) x[i, j, k], A_S likewise with the slope.
    const std::size_t sizeA = std::size_t(pu * nv * nw), sizeB = std::size_t(pu * pv * nw), sizeP = rule.pointCount();
    fit(t.a[0], sizeA);
    fit(t.a[1], sizeA);
    for (int k = 0; k < nw; ++k)
        for (int j = 0; j < nv; ++j) {
            const Vec3* row = x.data() + nu * (j + nv * k);
            for (int p = 0; p < pu; ++p) {
                Vec3 value = Vec3::Zero(), slope = Vec3::Zero();
                for (int i = 0; i < nu; ++i) {
                    value += u.value(p, i) * row[i];
                    slope += u.slope(p, i) * row[i];
                }
                t.a[0][std::size_t(p + pu * (j + nv * k))] = value;
                t.a[1][std::size_t(p + pu * (j + nv * k))] = slope;
            }
        }
    // Along v: B_VV = V_v A_V, B_VS = S_v A_V, B_SV = V_v A_S, at [p, q, k].
    for (auto& b : t.b)
        fit(b, sizeB);
    for (int k = 0; k < nw; ++k)
        for (int q = 0; q < pv; ++q)
            for (int p = 0; p < pu; ++p) {
                Vec3 vv = Vec3::Zero(), vs = Vec3::Zero(), sv = Vec3::Zero();
                for (int j = 0; j < nv; ++j) {
                    const std::size_t from = std::size_t(p + pu * (j + nv * k));
                    vv += v.value(q, j) * t.a[0][from];
                    vs += v.slope(q, j) * t.a[0][from];
                    sv += v.value(q, j) * t.a[1][from];
                }
                const std::size_t to = std::size_t(p + pu * (q + pv * k));
                t.b[0][to] = vv;
                t.b[1][to] = vs;
                t.b[2][to] = sv;
            }
    // Along w: the u column from B_SV, the v column from B_VS, the w column from B_VV with the slope.
    for (auto* o : out)
        fit(*o, sizeP);
    for (int r = 0; r < pw; ++r)
        for (int q = 0; q < pv; ++q)
            for (int p = 0; p < pu; ++p) {
                Vec3 cu = Vec3::Zero(), cv = Vec3::Zero(), cw = Vec3::Zero();
                for (int k = 0; k < nw; ++k) {
                    const std::size_t from = std::size_t(p + pu * (q + pv * k));
                    cu += w.value(r, k) * t.b[2][from];
                    cv += w.value(r, k) * t.b[1][from];
                    cw += w.slope(r, k) * t.b[0][from];
                }
                const std::size_t point = std::size_t(p + pu * (q + pv * r));
                (*out[0])[point] = cu;
                (*out[1])[point] = cv;
                (*out[2])[point] = cw;
            }
}

/// The transpose of gradients(): the node forces −Σ_q P_q ∇N_i(q) of the stresses whose columns (weights
/// included) are `column[c]` per point, subtracted from `force` on the free nodes.
void scatter(const ElementBody& body, const ElementRule& rule, std::array<const std::vector<Vec3>*, 3> column,
             std::span<Vec3> force) {
    const auto [nu, nv, nw] = body.counts;
    const ElementAxisRule& u = rule.axes[0];
    const ElementAxisRule& v = rule.axes[1];
    const ElementAxisRule& w = rule.axes[2];
    const int pu = int(u.value.rows()), pv = int(v.value.rows()), pw = int(w.value.rows());
    Contraction& t = scratch();
    const std::size_t sizeC = std::size_t(pu * pv * nw), sizeD = std::size_t(pu * nv * nw);
    // Along w: C_SV = V_wᵀ G_u, C_VS = V_wᵀ G_v, C_VV = S_wᵀ G_w, at [p, q, k].
    for (auto& c : t.c)
        fit(c, sizeC);
    for (int k = 0; k < nw; ++k)
        for (int q = 0; q < pv; ++q)
            for (int p = 0; p < pu; ++p) {
                Vec3 sv = Vec3::Zero(), vs = Vec3::Zero(), vv = Vec3::Zero();
                for (int r = 0; r < pw; ++r) {
                    const std::size_t point = std::size_t(p + pu * (q + pv * r));
                    sv += w.value(r, k) * (*column[0])[point];
                    vs += w.value(r, k) * (*column[1])[point];
                    vv += w.slope(r, k) * (*column[2])[point];
                }
                const std::size_t to = std::size_t(p + pu * (q + pv * k));
                t.c[0][to] = sv;
                t.c[1][to] = vs;
                t.c[2][to] = vv;
            }
    // Along v: D_S = V_vᵀ C_SV (still to meet the u slope), D_V = S_vᵀ C_VS + V_vᵀ C_VV, at [p, j, k].
    fit(t.d[0], sizeD);
    fit(t.d[1], sizeD);
    for (int k = 0; k < nw; ++k)
        for (int j = 0; j < nv; ++j)
            for (int p = 0; p < pu; ++p) {
                Vec3 ds = Vec3::Zero(), dv = Vec3::Zero();
                for (int q = 0; q < pv; ++q) {
                    const std::size_t from = std::size_t(p + pu * (q + pv * k));
                    ds += v.value(q, j) * t.c[0][from];
                    dv += v.slope(q, j) * t.c[1][from] + v.value(q, j) * t.c[2][from];
                }
                t.d[0][std::size_t(p + pu * (j + nv * k))] = ds;
                t.d[1][std::size_t(p + pu * (j + nv * k))] = dv;
            }
    // Along u: f[i, j, k] = Σ_p S_u(p, i) D_S + V_u(p, i) D_V.
    for (int k = 0; k < nw; ++k)
        for (int j = 0; j < nv; ++j)
            for (int i = 0; i < nu; ++i) {
                const std::size_t node = std::size_t(i + nu * (j + nv * k));
                if (body.slot[node] < 0)
                    continue;
                Vec3 f = Vec3::Zero();
                for (int p = 0; p < pu; ++p) {
                    const std::size_t from = std::size_t(p + pu * (j + nv * k));
                    f += u.slope(p, i) * t.d[0][from] + u.value(p, i) * t.d[1][from];
                }
                force[node] -= f;
            }
}

Mat3 columnsAt(const std::array<std::vector<Vec3>, 3>& columns, std::size_t point) {
    Mat3 f;
    f << columns[0][point], columns[1][point], columns[2][point];
    return f;
}

/// The rotated Kelvin-Voigt stress R η C sym(Rᵀ Ḟ) of a point (its viscosity factor included).
Mat3 viscousStress(const ElementBody& body, double viscosity, const Mat3& rotation, const Mat3& rate) {
    const Mat3 turned = rotation.transpose() * rate;
    const Vec6 sigma = viscosity * (body.elasticity * voigtStrain(0.5 * (turned + turned.transpose())));
    return rotation * stressTensor(sigma);
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
    }
    for (std::size_t c = 0; c < q[2].point.size(); ++c)
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
    Contraction& t = scratch();
    const bool withViscosity = viscous && body.viscous;
    const bool measure = !dampingOut.empty();
    if (measure)
        std::fill(dampingOut.begin(), dampingOut.end(), Vec3::Zero());
    for (const ElementRule& rule : body.rules) {
        gradients(body, rule, position, {&t.gradient[0], &t.gradient[1], &t.gradient[2]});
        if (withViscosity)
            gradients(body, rule, velocity, {&t.rate[0], &t.rate[1], &t.rate[2]});
        const std::size_t points = rule.pointCount();
        for (auto& s : t.stress)
            fit(s, points);
        // Node forces come from the stress columns; the viscous part also goes to dampingOut, through its own
        // scatter, so t.c/t.d are reused after this loop and the columns are kept apart until then.
        for (std::size_t p = 0; p < points; ++p) {
            const Mat3 f = columnsAt(t.gradient, p);
            const Stretch stretch = stretchOf(f);
            const Vec6 sigma = rule.stiffness[p] * (body.elasticity * voigtStrain(stretch.strain));
            Mat3 stress = firstPiola(f, stretch, stressTensor(sigma));
            if (withViscosity) {
                const Mat3 damping = viscousStress(body, rule.viscosity[p], rotationOf(f, stretch), columnsAt(t.rate, p));
                stress += damping;
                if (measure)  // keep the viscous columns where the rates were (no longer needed)
                    for (int c = 0; c < 3; ++c)
                        t.rate[std::size_t(c)][p] = damping.col(c);
            }
            for (int c = 0; c < 3; ++c)
                t.stress[std::size_t(c)][p] = stress.col(c);
        }
        scatter(body, rule, {&t.stress[0], &t.stress[1], &t.stress[2]}, force);
        if (withViscosity && measure)
            scatter(body, rule, {&t.rate[0], &t.rate[1], &t.rate[2]}, dampingOut);
    }
    if (nodeDamping && body.nodeDamped) {
        addElementMatrixTimes(body, body.nodeDamping, -1.0, velocity, force);
        if (measure)
            addElementMatrixTimes(body, body.nodeDamping, -1.0, velocity, dampingOut);
    }
}

void elementRotations(const ElementBody& body, std::span<const Vec3> position, std::vector<Mat3>& rotations) {
    Contraction& t = scratch();
    rotations.clear();
    for (const ElementRule& rule : body.rules) {
        gradients(body, rule, position, {&t.gradient[0], &t.gradient[1], &t.gradient[2]});
        for (std::size_t p = 0; p < rule.pointCount(); ++p) {
            const Mat3 f = columnsAt(t.gradient, p);
            rotations.push_back(rotationOf(f, stretchOf(f)));
        }
    }
}

void addElementTangent(const ElementBody& body, const std::vector<Mat3>& rotations, double a, double b,
                       std::span<const Vec3> p, std::span<Vec3> y) {
    Contraction& t = scratch();
    std::size_t first = 0;
    for (const ElementRule& rule : body.rules) {
        gradients(body, rule, p, {&t.gradient[0], &t.gradient[1], &t.gradient[2]});
        const std::size_t points = rule.pointCount();
        for (auto& s : t.stress)
            fit(s, points);
        for (std::size_t q = 0; q < points; ++q) {
            const Mat3& r = rotations[first + q];
            const Mat3 turned = r.transpose() * columnsAt(t.gradient, q);
            const double factor = a * rule.stiffness[q] + b * rule.viscosity[q];
            const Mat3 stress = r * stressTensor(factor * (body.elasticity * voigtStrain(0.5 * (turned + turned.transpose()))));
            for (int c = 0; c < 3; ++c)
                t.stress[std::size_t(c)][q] = -stress.col(c);  // scatter() subtracts
        }
        scatter(body, rule, {&t.stress[0], &t.stress[1], &t.stress[2]}, y);
        first += points;
    }
}

double elementEnergy(const ElementBody& body, std::span<const Vec3> position) {
    Contraction& t = scratch();
    double energy = 0.0;
    for (const ElementRule& rule : body.rules) {
        gradients(body, rule, position, {&t.gradient[0], &t.gradient[1], &t.gradient[2]});
        for (std::size_t p = 0; p < rule.pointCount(); ++p) {
            const Vec6 strain = voigtStrain(stretchOf(columnsAt(t.gradient, p)).strain);
            energy += 0.5 * rule.stiffness[p] * strain.dot(body.elasticity * strain);
        }
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

void solveElementMass(const ElementBody& body, std::span<const Vec3> force, std::span<Vec3> acceleration,
                      Eigen::MatrixXd& work) {
    solveElementMass(body, body.massFactor, force, acceleration, work);
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

void solveElementMass(const ElementBody& body, const Eigen::LLT<Eigen::MatrixXd>& factor, std::span<const Vec3> force,
                      std::span<Vec3> acceleration, Eigen::MatrixXd& work) {
    const Eigen::Index free = Eigen::Index(body.freeNodes.size());
    work.resize(free, 3);
    for (Eigen::Index s = 0; s < free; ++s)
        work.row(s) = force[body.freeNodes[std::size_t(s)]].transpose();
    factor.solveInPlace(work);
    for (Eigen::Index s = 0; s < free; ++s)
        acceleration[body.freeNodes[std::size_t(s)]] = work.row(s).transpose();
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
                    const int point = p + pu * (q + pv * r);
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

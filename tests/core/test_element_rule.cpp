// The solid element's contractions (core/body/element_rule.h) against the sums they factorise: the gradient at
// every point is Σ_i x_i ⊗ ∇N_i summed node by node, and the scatter is its transpose, on lattices with a
// different node count per axis and on B-splines (whose zero coefficients the contractions skip), one field and
// two at once.

#include "core/body/element_body.h"
#include "core/body/lattice_body.h"
#include "core/geometry/lattice.h"

#include <QtTest>

#include <random>

using namespace softtouch;

namespace {

struct Case {
    const char* name;
    LatticeShape shape;
};

std::shared_ptr<const ElementBody> bodyOn(const LatticeShape& shape, std::vector<std::uint8_t> held = {}) {
    OrientedBox box;
    box.size = Vec3(1.3, 0.7, 0.4);
    const Lattice lattice = Lattice::create(shape, box).value();
    const LatticeMaterial material = continuumMaterial(lattice, 900.0, 2e5, 0.0);
    held.resize(std::size_t(lattice.nodeCount()), 0);
    return buildElementBody(lattice, material, held).value();
}

std::vector<Vec3> randomField(std::size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> x(-1.0, 1.0);
    std::vector<Vec3> out(n);
    for (Vec3& v : out)
        v = Vec3(x(rng), x(rng), x(rng));
    return out;
}

/// ∂x/∂X_c at the point (p, q, r), node by node.
Mat3 directGradient(const ElementBody& body, const ElementRule& rule, std::span<const Vec3> x, int p, int q, int r) {
    const auto [nu, nv, nw] = body.counts;
    const ElementAxisRule &u = rule.axes[0], &v = rule.axes[1], &w = rule.axes[2];
    Mat3 f = Mat3::Zero();
    for (int k = 0; k < nw; ++k)
        for (int j = 0; j < nv; ++j)
            for (int i = 0; i < nu; ++i) {
                const Vec3 slope(u.slope(p, i) * v.value(q, j) * w.value(r, k), u.value(p, i) * v.slope(q, j) * w.value(r, k),
                                 u.value(p, i) * v.value(q, j) * w.slope(r, k));
                f += x[std::size_t(i + nu * (j + nv * k))] * slope.transpose();
            }
    return f;
}

}  // namespace

class TestElementRule : public QObject {
    Q_OBJECT
private slots:
    void gradientsAreTheNodeSums();
    void scatterIsTheTransposeOnTheFreeNodes();
};

static const Case kCases[] = {
    {"Bezier 3x4x5", {LatticeKind::Bezier, {3, 4, 5}}},
    {"B-spline 8x4x6", {LatticeKind::BSpline, {8, 4, 6}}},
    {"B-spline 5x7x4", {LatticeKind::BSpline, {5, 7, 4}}},
};

void TestElementRule::gradientsAreTheNodeSums() {
    for (const Case& c : kCases) {
        const auto body = bodyOn(c.shape);
        const std::vector<Vec3> x = randomField(body->nodeCount(), 1), v = randomField(body->nodeCount(), 2);
        const std::array<std::span<const Vec3>, 2> fields = {x, v};
        for (const ElementRule& rule : body->rules) {
            for (std::size_t count : {1, 2}) {
                std::array<std::vector<double>, 3> columns;
                elementGradients(rule, body->counts, std::span(fields).first(count), columns);
                const std::size_t width = 3 * count;
                for (int r = 0; r < rule.axisPoints(2); ++r)
                    for (int q = 0; q < rule.axisPoints(1); ++q)
                        for (int p = 0; p < rule.axisPoints(0); ++p) {
                            const std::size_t point = elementRulePoint(rule, p, q, r);
                            for (std::size_t f = 0; f < count; ++f) {
                                const Mat3 expected = directGradient(*body, rule, fields[f], p, q, r);
                                Mat3 got;
                                for (int col = 0; col < 3; ++col)
                                    for (int a = 0; a < 3; ++a)
                                        got(a, col) = columns[std::size_t(col)][point * width + 3 * f + std::size_t(a)];
                                QVERIFY2((got - expected).norm() < 1e-12 * (1.0 + expected.norm()),
                                         qPrintable(QString("%1, point (%2, %3, %4), field %5").arg(c.name).arg(p).arg(q).arg(r).arg(f)));
                            }
                        }
            }
        }
    }
}

void TestElementRule::scatterIsTheTransposeOnTheFreeNodes() {
    // Σ_q P_q : ∇x(q) = −Σ_i f_i · x_i for any stresses P and node field x zero on the held nodes, f the scatter's
    // forces; the held nodes' forces are left alone, and a second field's forces are its own.
    for (const Case& c : kCases) {
        const auto probe = bodyOn(c.shape);
        std::vector<std::uint8_t> held(probe->nodeCount(), 0);
        for (std::size_t i = 0; i < held.size(); i += 5)
            held[i] = 1;
        const auto body = bodyOn(c.shape, held);
        const std::vector<Vec3> x = randomField(body->nodeCount(), 3);
        for (const ElementRule& rule : body->rules) {
            std::array<std::vector<double>, 3> stress;
            std::mt19937 rng(4);
            std::uniform_real_distribution<double> s(-1.0, 1.0);
            for (int col = 0; col < 3; ++col) {
                stress[std::size_t(col)].resize(2 * 3 * rule.pointCount());  // two fields: P, then 2P
                for (std::size_t point = 0; point < rule.pointCount(); ++point)
                    for (int a = 0; a < 3; ++a) {
                        const double value = s(rng);
                        stress[std::size_t(col)][6 * point + std::size_t(a)] = value;
                        stress[std::size_t(col)][6 * point + 3 + std::size_t(a)] = 2.0 * value;
                    }
            }
            const Vec3 untouched(7.0, 8.0, 9.0);
            std::vector<Vec3> force(body->nodeCount(), untouched), twice(body->nodeCount(), untouched);
            const std::array<std::span<Vec3>, 2> forces = {force, twice};
            elementScatter(rule, body->counts, stress, body->slot, forces);
            double free = 0.0;
            for (std::size_t i = 0; i < body->nodeCount(); ++i) {
                if (held[i]) {
                    QCOMPARE(force[i], untouched);
                    QCOMPARE(twice[i], untouched);
                    continue;
                }
                free += (force[i] - untouched).dot(x[i]);
                QVERIFY(((twice[i] - untouched) - 2.0 * (force[i] - untouched)).norm() < 1e-12 * (1.0 + force[i].norm()));
            }
            // The forces on the free nodes pair with x as the stresses do with the gradient of x on the free nodes.
            std::vector<Vec3> freeOnly = x;
            for (std::size_t i = 0; i < held.size(); ++i)
                if (held[i])
                    freeOnly[i] = Vec3::Zero();
            std::array<std::vector<double>, 3> freeGradient;
            elementGradients(rule, body->counts, std::array<std::span<const Vec3>, 1>{freeOnly}, freeGradient);
            double freeWork = 0.0;
            for (int col = 0; col < 3; ++col)
                for (std::size_t point = 0; point < rule.pointCount(); ++point)
                    for (int a = 0; a < 3; ++a)
                        freeWork += stress[std::size_t(col)][6 * point + std::size_t(a)] * freeGradient[std::size_t(col)][3 * point + std::size_t(a)];
            QVERIFY2(std::abs(free + freeWork) < 1e-10 * (1.0 + std::abs(freeWork)),
                     qPrintable(QString("%1: −Σ f·x %2, Σ P:∇x %3").arg(c.name).arg(-free).arg(freeWork)));
        }
    }
}

QTEST_GUILESS_MAIN(TestElementRule)
#include "test_element_rule.moc"

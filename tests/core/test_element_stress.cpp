// The solid element's point kernel (core/body/element_stress.h), points in SIMD lanes: the stretch is FᵀF's
// square root to round-off on every kind of deformation (rest, tiny and large strains, repeated stretches,
// flips and near-collapse), the stress is its energy's exact gradient and turns with the body, the corotated
// stress is linear elasticity turned by R, and no lane reads another's point.

#include "core/body/element_stress.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include <QtTest>

#include <random>
#include <vector>

using namespace softtouch;

namespace {

using Mat3 = Eigen::Matrix3d;
using Lane9 = std::array<Lanes, 9>;

Mat3 laneMatrix(const Lane9& m, int l) {
    Mat3 out;
    for (int e = 0; e < 9; ++e)
        out(e) = m[std::size_t(e)][std::size_t(l)];  // column-major, entry 3c + α
    return out;
}

Mat3 laneSymmetric(const std::array<Lanes, 6>& v, int l) {
    const auto x = [&](int i) { return v[std::size_t(i)][std::size_t(l)]; };
    Mat3 out;
    out << x(0), x(5), x(4), x(5), x(1), x(3), x(4), x(3), x(2);
    return out;
}

/// Fills lanes from matrices, repeating the last one past the end.
Lane9 lanes(const std::vector<Mat3>& matrices) {
    Lane9 out;
    for (int l = 0; l < kStressLanes; ++l) {
        const Mat3& m = matrices[std::min(std::size_t(l), matrices.size() - 1)];
        for (int e = 0; e < 9; ++e)
            out[std::size_t(e)][std::size_t(l)] = m(e);
    }
    return out;
}

Mat3 randomRotation(std::mt19937& rng) {
    std::normal_distribution<double> n;
    return Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
}

/// Deformations a body meets, and the ones that break eigensolvers: rest, a rotation alone, strains from 1e-9 to
/// 1 (random), stretches repeated along two and three axes, an exact and a near-repeated pair, a flip and a
/// near-collapse, each turned at random.
std::vector<Mat3> hardDeformations(std::mt19937& rng) {
    std::normal_distribution<double> n;
    std::vector<Mat3> out = {Mat3::Identity(), randomRotation(rng)};
    for (double scale : {1e-9, 1e-6, 1e-3, 0.05, 0.3, 1.0}) {
        Mat3 d;
        for (int e = 0; e < 9; ++e)
            d(e) = scale * n(rng);
        out.push_back(randomRotation(rng) * (Mat3::Identity() + d));
    }
    const auto turned = [&](const Eigen::Vector3d& stretches) {
        const Mat3 q = randomRotation(rng);
        return Mat3(randomRotation(rng) * q * stretches.asDiagonal() * q.transpose());
    };
    out.push_back(turned({1.2, 1.2, 1.2}));
    out.push_back(turned({1.0 + 1e-7, 1.0 + 1e-7, 1.0 + 1e-7}));
    out.push_back(turned({0.9, 1.3, 1.3}));
    out.push_back(turned({1.1, 1.1 + 1e-12, 0.7}));
    out.push_back(turned({2.5, 0.4, 1.0}));
    out.push_back(turned({1e-3, 1.0, 1.0}));
    out.push_back(Mat3(Eigen::Vector3d(1.0, 1.0, -1.0).asDiagonal()) * randomRotation(rng));  // inverted
    return out;
}

/// The energy ½ εᵀ σ of one F in lane 0 (the other lanes at rest).
double energyOf(const Eigen::Matrix<double, 6, 6>& c, const Mat3& f) {
    const Lane9 fl = lanes({f, Mat3::Identity()});
    StretchLanes stretch;
    stretchLanes(fl, stretch);
    Lanes modulus;
    modulus.fill(1.0);
    Lanes energy{};
    Lane9 stress;
    elasticStressLanes(c, modulus, fl, stretch, stress, &energy);
    return energy[0];
}

/// An orthotropic elasticity like the springs' solid (Voigt order uu, vv, ww, vw, uw, uv), unequal on every axis.
Eigen::Matrix<double, 6, 6> orthotropic() {
    Eigen::Matrix<double, 6, 6> c = Eigen::Matrix<double, 6, 6>::Zero();
    c.topLeftCorner<3, 3>() << 2.0, 0.6, 0.5, 0.6, 1.5, 0.4, 0.5, 0.4, 1.2;
    c.bottomRightCorner<3, 3>().diagonal() << 0.35, 0.45, 0.55;
    return c;
}

}  // namespace

class TestElementStress : public QObject {
    Q_OBJECT
private slots:
    void stretchIsTheSquareRootOfFtF();
    void stressIsTheEnergysGradient();
    void stressTurnsWithTheBodyAndBalancesMoments();
    void corotatedStressIsLinearElasticityTurned();
    void noLaneReadsAnothersPoint();
};

void TestElementStress::stretchIsTheSquareRootOfFtF() {
    std::mt19937 rng(11);
    for (int round = 0; round < 40; ++round) {
        const std::vector<Mat3> all = hardDeformations(rng);
        for (std::size_t first = 0; first < all.size(); first += std::size_t(kStressLanes)) {
            const std::vector<Mat3> block(all.begin() + long(first),
                                          all.begin() + long(std::min(all.size(), first + std::size_t(kStressLanes))));
            const Lane9 f = lanes(block);
            StretchLanes stretch;
            stretchLanes(f, stretch);
            Lane9 rotation;
            rotationLanes(f, stretch, rotation);
            for (int l = 0; l < int(block.size()); ++l) {
                const Mat3 v = laneMatrix(stretch.basis, l);
                const Mat3 e = laneSymmetric(stretch.strain, l);
                const Mat3 g = block[std::size_t(l)].transpose() * block[std::size_t(l)] - Mat3::Identity();
                const double scale = std::max(g.norm(), 1e-300);
                // V is orthonormal and diagonalises FᵀF − I, and (I + E)² = FᵀF, both to round-off of |FᵀF − I|.
                QVERIFY2((v.transpose() * v - Mat3::Identity()).norm() < 1e-14, qPrintable(QString("round %1 lane %2").arg(round).arg(first + l)));
                Mat3 turned = v.transpose() * g * v;
                const double off = turned.norm() > 0.0 ? (turned - Mat3(turned.diagonal().asDiagonal())).norm() / turned.norm() : 0.0;
                QVERIFY2(off < 1e-14, qPrintable(QString("deformation %1: off-diagonal %2").arg(first + l).arg(off)));
                const double residual = (2.0 * e + e * e - g).norm() / scale;
                // Round-off grows with the square of F's condition (the near-collapse's is 1000): a singular value
                // comes from 1 + g, g the eigenvalue of FᵀF − I.
                const Eigen::Vector3d sv = block[std::size_t(l)].jacobiSvd().singularValues();
                const double tolerance = 1e-14 * std::pow(sv.maxCoeff() / sv.minCoeff(), 2);
                QVERIFY2(residual < tolerance,
                         qPrintable(QString("deformation %1: (I + E)² − FᵀF = %2 of |FᵀF − I|").arg(first + l).arg(residual)));
                for (int k = 0; k < 3; ++k)
                    QVERIFY(stretch.singular[std::size_t(k)][std::size_t(l)] > 0.0);
                // R = F S⁻¹ is a rotation, turned inside out where F is.
                const Mat3 r = laneMatrix(rotation, l);
                const double orthogonality = (r.transpose() * r - Mat3::Identity()).norm();
                QVERIFY2(orthogonality < tolerance,
                         qPrintable(QString("deformation %1: |RᵀR − I| = %2").arg(first + l).arg(orthogonality)));
                QCOMPARE(r.determinant() > 0.0, block[std::size_t(l)].determinant() > 0.0);
            }
        }
    }
    // At rest nothing rotates and nothing is strained: exactly zero, not round-off.
    const Lane9 rest = lanes({Mat3::Identity()});
    StretchLanes stretch;
    stretchLanes(rest, stretch);
    for (const Lanes& e : stretch.strain)
        for (const double x : e)
            QCOMPARE(x, 0.0);
}

void TestElementStress::stressIsTheEnergysGradient() {
    // P = ∂Ψ/∂F by central differences, on strains from small to large (the difference's own error is about
    // 1e-10 of |P| here).
    std::mt19937 rng(5);
    std::normal_distribution<double> n;
    const Eigen::Matrix<double, 6, 6> c = orthotropic();
    for (double scale : {0.01, 0.1, 0.4}) {
        for (int round = 0; round < 8; ++round) {
            Mat3 d;
            for (int e = 0; e < 9; ++e)
                d(e) = scale * n(rng);
            const Mat3 f = randomRotation(rng) * (Mat3::Identity() + d);
            const Lane9 fl = lanes({f, Mat3::Identity()});
            StretchLanes stretch;
            stretchLanes(fl, stretch);
            Lanes modulus;
            modulus.fill(1.0);
            Lane9 stress;
            elasticStressLanes(c, modulus, fl, stretch, stress);
            const Mat3 p = laneMatrix(stress, 0);
            Mat3 numeric;
            const double h = 1e-6;
            for (int e = 0; e < 9; ++e) {
                Mat3 plus = f, minus = f;
                plus(e) += h;
                minus(e) -= h;
                numeric(e) = (energyOf(c, plus) - energyOf(c, minus)) / (2.0 * h);
            }
            QVERIFY2((p - numeric).norm() < 1e-6 * p.norm(),
                     qPrintable(QString("strain %1: |P − ∂Ψ/∂F| = %2 of |P|").arg(scale).arg((p - numeric).norm() / p.norm())));
        }
    }
}

void TestElementStress::stressTurnsWithTheBodyAndBalancesMoments() {
    // Frame indifference: turning the deformed body turns its stress, P(QF) = Q P(F); and P Fᵀ is symmetric, so
    // the element's forces carry no net moment.
    std::mt19937 rng(7);
    std::normal_distribution<double> n;
    const Eigen::Matrix<double, 6, 6> c = orthotropic();
    std::vector<Mat3> fs, turned;
    std::vector<Mat3> qs;
    for (int l = 0; l < kStressLanes; ++l) {
        Mat3 d;
        for (int e = 0; e < 9; ++e)
            d(e) = 0.2 * n(rng);
        fs.push_back(randomRotation(rng) * (Mat3::Identity() + d));
        qs.push_back(randomRotation(rng));
        turned.push_back(qs.back() * fs.back());
    }
    Lanes modulus;
    modulus.fill(3.0);
    const auto stressOf = [&](const std::vector<Mat3>& f) {
        const Lane9 fl = lanes(f);
        StretchLanes stretch;
        stretchLanes(fl, stretch);
        Lane9 stress;
        elasticStressLanes(c, modulus, fl, stretch, stress);
        return stress;
    };
    const Lane9 p = stressOf(fs), pt = stressOf(turned);
    for (int l = 0; l < kStressLanes; ++l) {
        const Mat3 pl = laneMatrix(p, l);
        QVERIFY((laneMatrix(pt, l) - qs[std::size_t(l)] * pl).norm() < 1e-12 * pl.norm());
        const Mat3 moment = pl * fs[std::size_t(l)].transpose();
        QVERIFY((moment - moment.transpose()).norm() < 1e-12 * pl.norm());
    }
}

void TestElementStress::corotatedStressIsLinearElasticityTurned() {
    // R (a C sym(Rᵀ G)), against the same written with Eigen in the test.
    std::mt19937 rng(3);
    std::normal_distribution<double> n;
    const Eigen::Matrix<double, 6, 6> c = orthotropic();
    std::vector<Mat3> rotations, gradients;
    Lanes factor;
    for (int l = 0; l < kStressLanes; ++l) {
        rotations.push_back(randomRotation(rng));
        Mat3 g;
        for (int e = 0; e < 9; ++e)
            g(e) = n(rng);
        gradients.push_back(g);
        factor[std::size_t(l)] = 0.5 + l;
    }
    Lane9 stress;
    corotatedStressLanes(c, factor, lanes(rotations), lanes(gradients), stress);
    for (int l = 0; l < kStressLanes; ++l) {
        const Mat3& r = rotations[std::size_t(l)];
        const Mat3 t = r.transpose() * gradients[std::size_t(l)];
        Eigen::Matrix<double, 6, 1> strain;
        strain << t(0, 0), t(1, 1), t(2, 2), t(1, 2) + t(2, 1), t(0, 2) + t(2, 0), t(0, 1) + t(1, 0);
        const Eigen::Matrix<double, 6, 1> s = factor[std::size_t(l)] * (c * strain);
        Mat3 sigma;
        sigma << s[0], s[5], s[4], s[5], s[1], s[3], s[4], s[3], s[2];
        const Mat3 expected = r * sigma;
        QVERIFY((laneMatrix(stress, l) - expected).norm() < 1e-13 * expected.norm());
    }
}

void TestElementStress::noLaneReadsAnothersPoint() {
    // One deformation in lane 0 beside rest, and beside the hardest ones: the same stress to round-off (a lane
    // may take one more Jacobi sweep with harder neighbours, never another's numbers).
    std::mt19937 rng(9);
    const std::vector<Mat3> hard = hardDeformations(rng);
    const Eigen::Matrix<double, 6, 6> c = orthotropic();
    Lanes modulus;
    modulus.fill(1.0);
    const Mat3 f = hard[5];
    const auto laneZero = [&](std::vector<Mat3> block) {
        block.insert(block.begin(), f);
        const Lane9 fl = lanes(block);
        StretchLanes stretch;
        stretchLanes(fl, stretch);
        Lane9 stress;
        elasticStressLanes(c, modulus, fl, stretch, stress);
        return laneMatrix(stress, 0);
    };
    const Mat3 alone = laneZero({Mat3::Identity()});
    QVERIFY(alone.norm() > 0.0);
    for (std::size_t first = 0; first + 1 < hard.size(); first += 3) {
        const Mat3 beside = laneZero({hard.begin() + long(first), hard.begin() + long(std::min(hard.size(), first + 7))});
        QVERIFY2((beside - alone).norm() < 1e-14 * alone.norm(), qPrintable(QString("beside %1").arg(first)));
    }
}

QTEST_GUILESS_MAIN(TestElementStress)
#include "test_element_stress.moc"

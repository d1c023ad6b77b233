// Rigid skinning decomposition (core/fitting/skin_fit.h) on clips whose answer is known.
#include "core/fitting/skin_fit.h"

#include <QtTest>

#include <Eigen/Geometry>

#include <cmath>

using namespace softtouch;

namespace {

/// A bar of points along x in [0, 2]; its half x < 1 turns about z by `angle` at the origin, the other half
/// moves rigidly by `shift`: two rigid parts.
std::vector<Vec3f> twoRigidParts(const std::vector<Vec3f>& rest, double angle, const Vec3& shift) {
    std::vector<Vec3f> moved;
    const Mat3 r = Eigen::AngleAxisd(angle, Vec3::UnitZ()).toRotationMatrix();
    for (const Vec3f& p : rest)
        moved.push_back(p.x() < 1.0f ? Vec3f((r * p.cast<double>()).cast<float>()) : Vec3f((p.cast<double>() + shift).cast<float>()));
    return moved;
}

}  // namespace

class TestSkinFit : public QObject {
    Q_OBJECT
private slots:
    void twoRigidPartsNeedTwoBones();
    void moreBonesNeverFitWorse();
};

void TestSkinFit::twoRigidPartsNeedTwoBones() {
    std::vector<Vec3f> rest;
    for (int i = 0; i < 40; ++i)
        for (int j = 0; j < 3; ++j)
            rest.emplace_back(float(i) / 20.0f + 0.025f, 0.1f * float(j), 0.05f * float((i + j) % 2));
    std::vector<std::vector<Vec3f>> frames;
    for (int f = 0; f < 10; ++f)
        frames.push_back(twoRigidParts(rest, 0.1 * f, Vec3(0.0, 0.02 * f, 0.01 * f)));
    const SkinFit one = fitRigidSkin(rest, frames, 1);
    const SkinFit two = fitRigidSkin(rest, frames, 2);
    QVERIFY2(one.rmsError > 1e-2, qPrintable(QString::number(one.rmsError)));
    QVERIFY2(two.rmsError < 1e-5, qPrintable(QString::number(two.rmsError)));
    for (std::size_t i = 0; i < rest.size(); ++i) {
        float sum = 0.0f;
        for (float w : two.weights[i]) {
            QVERIFY(w >= 0.0f);
            sum += w;
        }
        QVERIFY(std::abs(sum - 1.0f) < 1e-6f);
        // Each point follows its own part: the reconstruction at the last frame is exact.
        QVERIFY((skinnedPosition(two, rest, 9, i) - frames[9][i].cast<double>()).norm() < 1e-5);
    }
}

void TestSkinFit::moreBonesNeverFitWorse() {
    // A bar bending smoothly (a circular arc of growing curvature): no rigid split is exact, and more
    // bones fit it better.
    std::vector<Vec3f> rest;
    for (int i = 0; i <= 60; ++i)
        for (int j = -1; j <= 1; ++j)
            rest.emplace_back(float(i) / 30.0f, 0.05f * float(j), 0.0f);
    std::vector<std::vector<Vec3f>> frames;
    for (int f = 1; f <= 8; ++f) {
        const double curvature = 0.3 * f;
        std::vector<Vec3f> bent;
        for (const Vec3f& p : rest) {
            const double s = p.x(), r = 1.0 / curvature - p.y();
            bent.emplace_back(float(r * std::sin(s * curvature)), float(1.0 / curvature - r * std::cos(s * curvature)), 0.0f);
        }
        frames.push_back(bent);
    }
    double previous = 1e30;
    for (int bones : {2, 4, 8, 16}) {
        const SkinFit skin = fitRigidSkin(rest, frames, bones);
        qInfo("%2d bones: RMS %.3g m, worst %.3g m", bones, skin.rmsError, skin.maxError);
        QVERIFY2(skin.rmsError < previous, qPrintable(QString("%1 bones: %2 after %3").arg(bones).arg(skin.rmsError).arg(previous)));
        previous = skin.rmsError;
    }
    QVERIFY(previous < 5e-3);
}

QTEST_GUILESS_MAIN(TestSkinFit)
#include "test_skin_fit.moc"

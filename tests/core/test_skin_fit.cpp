// Rigid skinning decomposition (core/fitting/skin_fit.h) on clips whose answer is known.
#include "core/fitting/skeleton.h"
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

/// A two-joint chain along x: joint 0 at the origin, joint 1 at x = 1 under it, each turning about z; the
/// bar's points weighted to joint 0 below x = 0.8, to joint 1 above 1.2 and blended between.
struct Chain {
    Skeleton skeleton;
    SkinnedMesh mesh;
    std::vector<std::vector<Vec3f>> frames;  // what the rig alone does
};

Chain twoJointChain(int frameCount) {
    Chain chain;
    Skeleton& s = chain.skeleton;
    s.nodes = {{"root", -1, {}, true}, {"tip", 0, {}, true}};
    s.nodes[1].rest.translation = Vec3(1.0, 0.0, 0.0);
    s.joints = {0, 1};
    Eigen::Matrix4d tipInverse = Eigen::Matrix4d::Identity();
    tipInverse(0, 3) = -1.0;
    s.inverseBind = {Eigen::Matrix4d::Identity(), tipInverse};
    for (int i = 0; i <= 40; ++i)
        for (int j = -1; j <= 1; ++j)
            for (int k = -1; k <= 1; k += 2) {
                const float x = float(i) / 20.0f;
                chain.mesh.bind.emplace_back(x, 0.05f * float(j), 0.05f * float(k));
                const float toTip = std::clamp((x - 0.8f) / 0.4f, 0.0f, 1.0f);
                chain.mesh.joints.push_back({0, 1, 0, 0});
                chain.mesh.weights.push_back({1.0f - toTip, toTip, 0.0f, 0.0f});
            }
    for (int f = 0; f < frameCount; ++f) {
        std::vector<NodeTransform> pose(2);
        pose[0].rotation = Eigen::AngleAxisd(0.3 * std::sin(0.5 * f), Vec3::UnitZ());
        pose[1].translation = Vec3(1.0, 0.0, 0.0);
        pose[1].rotation = Eigen::AngleAxisd(0.5 * std::sin(0.5 * f - 0.7), Vec3::UnitZ());
        s.poses.push_back(pose);
    }
    const SourceSkin skin = sourceSkin(s, chain.mesh);
    SkinFit asFit;
    asFit.bones = 2;
    asFit.joints = chain.mesh.joints;
    asFit.weights = chain.mesh.weights;
    asFit.transforms = skin.transforms;
    for (int f = 0; f < frameCount; ++f) {
        std::vector<Vec3f> frame;
        for (std::size_t i = 0; i < chain.mesh.bind.size(); ++i)
            frame.push_back(skinnedPosition(asFit, chain.mesh.bind, std::size_t(f), i).cast<float>());
        chain.frames.push_back(frame);
    }
    return chain;
}

}  // namespace

class TestSkinFit : public QObject {
    Q_OBJECT
private slots:
    void twoRigidPartsNeedTwoBones();
    void moreBonesNeverFitWorse();
    void helperBonesCarryWhatTheRigMisses();
    void anExactRigGetsNoHelper();
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

void TestSkinFit::helperBonesCarryWhatTheRigMisses() {
    // The rig's motion plus a wobble it cannot make: the last quarter of the bar swings about y (out of the
    // chain's plane) and lags, a motion no turn about z gives.
    Chain chain = twoJointChain(16);
    std::vector<std::vector<Vec3f>> clip = chain.frames;
    for (std::size_t f = 0; f < clip.size(); ++f)
        for (std::size_t i = 0; i < clip[f].size(); ++i) {
            const double beyond = std::max(0.0, double(chain.mesh.bind[i].x()) - 1.5);
            clip[f][i].z() += float(0.4 * beyond * std::sin(0.9 * double(f)));
        }
    const SourceSkin source = sourceSkin(chain.skeleton, chain.mesh);
    const RigSkinFit none = fitHelperBones(chain.mesh.bind, clip, source, 0);
    const RigSkinFit four = fitHelperBones(chain.mesh.bind, clip, source, 4);
    qInfo("the rig alone: RMS %.3g m; with %d helpers: RMS %.3g m", none.skin.rmsError, four.skin.bones - 2,
          four.skin.rmsError);
    QCOMPARE(none.skin.bones, 2);
    QVERIFY2(none.skin.rmsError > 5e-3, qPrintable(QString::number(none.skin.rmsError)));
    QVERIFY(four.skin.bones > 2 && four.skin.bones <= 6);
    QVERIFY2(four.skin.rmsError < 0.2 * none.skin.rmsError, qPrintable(QString::number(four.skin.rmsError)));
    QCOMPARE(four.sourceJoints, 2);
    // The joints keep their motion exactly; only helpers move on their own.
    for (std::size_t f = 0; f < clip.size(); ++f)
        for (std::size_t j = 0; j < 2; ++j) {
            QCOMPARE(four.skin.transforms[f][j].rotation, source.transforms[f][j].rotation);
            QCOMPARE(four.skin.transforms[f][j].translation, source.transforms[f][j].translation);
        }
    // The helpers act on the tip, so they hang from the tip joint, and sit beyond x = 1.
    QCOMPARE(four.helperParent.size(), std::size_t(four.skin.bones - 2));
    for (std::size_t h = 0; h < four.helperParent.size(); ++h) {
        QCOMPARE(four.helperParent[h], 1);
        QVERIFY2(four.helperCentre[h].x() > 1.0, qPrintable(QString::number(four.helperCentre[h].x())));
    }
    for (const auto& w : four.skin.weights) {
        float sum = 0.0f;
        for (float x : w) {
            QVERIFY(x >= 0.0f);
            sum += x;
        }
        QVERIFY(std::abs(sum - 1.0f) < 1e-5f);
    }
}

void TestSkinFit::anExactRigGetsNoHelper() {
    const Chain chain = twoJointChain(12);
    const RigSkinFit fit = fitHelperBones(chain.mesh.bind, chain.frames, sourceSkin(chain.skeleton, chain.mesh), 8);
    QCOMPARE(fit.skin.bones, 2);
    QVERIFY(fit.helperParent.empty());
    QVERIFY2(fit.skin.rmsError < 1e-6, qPrintable(QString::number(fit.skin.rmsError)));
    QCOMPARE(fit.skin.weights, chain.mesh.weights);
}

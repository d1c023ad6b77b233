// End to end: 'softtouch-cli render' writes MP4, GIF and PNG sequences headless (no DISPLAY), and fails
// cleanly on bad input without touching existing files; 'softtouch-cli modes --pictures' draws the
// mode shapes headless.
#include "core/body/lattice_body.h"
#include "io/documents/project_file.h"
#include "io/export/video_encoder.h"
#include "render/mode_pictures.h"

#include "helpers/cli_run.h"

#include <QDir>
#include <QImage>
#include <QTemporaryDir>
#include <QtTest>

using namespace softtouch;

namespace {

using test::Run;
const QString kScene = QStringLiteral(SOFTTOUCH_SOURCE_DIR "/presets/scenes/angelfish-swim.softtouch");

/// Rendering must work without a window system: every run here is headless.
Run runCli(const QStringList& args) { return test::runCli(args, true); }

/// Width and height from a PNG's IHDR chunk (big-endian at bytes 16..23).
std::pair<int, int> pngSize(const QString& path) {
    QFile f(path);
    if (!f.open(QIODevice::ReadOnly))
        return {0, 0};
    const QByteArray head = f.read(24);
    if (head.size() < 24 || !head.startsWith("\x89PNG"))
        return {0, 0};
    auto be = [&](int at) {
        return (int(quint8(head[at])) << 24) | (int(quint8(head[at + 1])) << 16) | (int(quint8(head[at + 2])) << 8) |
               int(quint8(head[at + 3]));
    };
    return {be(16), be(20)};
}

}  // namespace

class TestCliRender : public QObject {
    Q_OBJECT
private slots:
    void mp4HasCodecSizeFpsAndFrames();
    void gifHasFrames();
    void pngSequenceHasFramesOfSize();
    void badInputFailsWithoutPartialFiles_data();
    void badInputFailsWithoutPartialFiles();
    void missingOutputFoldersAreMade();
    void modePicturesShowEachShape();
    void baseAnimationIsDrawn();
};

void TestCliRender::mp4HasCodecSizeFpsAndFrames() {
    QTemporaryDir dir;
    const QString out = dir.filePath("swim.mp4");
    const Run run = runCli({"render", kScene, "--out", out, "--size", "160x96", "--fps", "30", "--frames", "12",
                            "--crf", "28", "--quiet"});
    QVERIFY2(run.exitCode == 0, qPrintable(run.err));
    auto probe = io::probeVideo(out.toStdString());
    QVERIFY2(probe.ok(), probe.message().c_str());
    // H.264 unless this libavcodec lacks libx264, which the CLI must then say.
    const bool fallback = run.err.contains("libx264 is not available");
    QCOMPARE(QString::fromStdString(probe->codec), fallback ? QStringLiteral("mpeg4") : QStringLiteral("h264"));
    QCOMPARE(probe->width, 160);
    QCOMPARE(probe->height, 96);
    QVERIFY2(std::abs(probe->fps - 30.0) < 1e-6, qPrintable(QString::number(probe->fps)));
    QCOMPARE(probe->frames, 12);
    QCOMPARE(QDir(dir.path()).entryList(QDir::Files), QStringList{"swim.mp4"});  // no temporary left
}

void TestCliRender::gifHasFrames() {
    QTemporaryDir dir;
    const QString out = dir.filePath("swim.gif");
    const Run run = runCli({"render", kScene, "--out", out, "--size", "120x80", "--frames", "6", "--quiet"});
    QVERIFY2(run.exitCode == 0, qPrintable(run.err));
    auto probe = io::probeVideo(out.toStdString());
    QVERIFY2(probe.ok(), probe.message().c_str());
    QCOMPARE(QString::fromStdString(probe->codec), QStringLiteral("gif"));
    QCOMPARE(probe->width, 120);
    QCOMPARE(probe->height, 80);
    QCOMPARE(probe->frames, 6);
}

void TestCliRender::pngSequenceHasFramesOfSize() {
    QTemporaryDir dir;
    const QString out = dir.filePath("frames/");
    const Run run = runCli({"render", kScene, "--out", out, "--size", "100x60", "--frames", "4", "--quiet"});
    QVERIFY2(run.exitCode == 0, qPrintable(run.err));
    const QStringList files = QDir(out).entryList(QDir::Files, QDir::Name);
    QCOMPARE(files, (QStringList{"frame_0000.png", "frame_0001.png", "frame_0002.png", "frame_0003.png"}));
    for (const QString& f : files)
        QCOMPARE(pngSize(QDir(out).filePath(f)), (std::pair{100, 60}));
}

void TestCliRender::badInputFailsWithoutPartialFiles_data() {
    QTest::addColumn<QString>("name");    // output inside the temporary directory
    QTest::addColumn<QString>("size");
    QTest::addColumn<QString>("message"); // part of the error
    QTest::addColumn<int>("exitCode");    // 2 bad usage (with the usage line), 1 failure (one line)
    QTest::newRow("size without height") << "old.mp4" << "100x" << "--size: expects WIDTHxHEIGHT" << 2;
    QTest::newRow("size too small") << "old.mp4" << "8x8" << "--size: expects WIDTHxHEIGHT" << 2;
    QTest::newRow("odd size for yuv420p") << "old.mp4" << "161x96" << "even width and height" << 2;  // a usage error, as 0x0 is
    QTest::newRow("parent is a file") << "old.mp4/out.gif" << "160x96" << "old.mp4" << 1;
}

void TestCliRender::badInputFailsWithoutPartialFiles() {
    QFETCH(QString, name);
    QFETCH(QString, size);
    QFETCH(QString, message);
    QFETCH(int, exitCode);
    QTemporaryDir dir;
    QFile old(dir.filePath("old.mp4"));
    QVERIFY(old.open(QIODevice::WriteOnly));
    old.write("previous render");
    old.close();
    const Run run = runCli({"render", kScene, "--out", dir.filePath(name), "--size", size, "--frames", "3", "--quiet"});
    QCOMPARE(run.exitCode, exitCode);
    QVERIFY2(run.err.contains(message), qPrintable(run.err));
    QVERIFY2(run.err.count('\n') == (exitCode == 2 ? 3 : 1), qPrintable(run.err));  // one clear line (+ usage)
    QCOMPARE(QDir(dir.path()).entryList(QDir::AllEntries | QDir::NoDotAndDotDot), QStringList{"old.mp4"});
    QVERIFY(old.open(QIODevice::ReadOnly));
    QCOMPARE(old.readAll(), QByteArray("previous render"));
}

// `bake --out new/dir/fish.pc2` and `render --out new/dir/fish.mp4` make the folders, as a pipeline expects
// (they used to fail: "No such file or directory"); a command that fails after making them takes them away.
void TestCliRender::missingOutputFoldersAreMade() {
    QTemporaryDir dir;
    const Run render = runCli({"render", kScene, "--out", dir.filePath("shots/a/fish.mp4"), "--size", "160x96", "--frames",
                               "2", "--quiet"});
    QVERIFY2(render.exitCode == 0, qPrintable(render.err));
    QVERIFY(QFileInfo(dir.filePath("shots/a/fish.mp4")).size() > 0);
    const Run bake = runCli({"bake", kScene, "--out", dir.filePath("caches/b/fish.pc2"), "--frames", "2", "--quiet"});
    QVERIFY2(bake.exitCode == 0, qPrintable(bake.err));
    QVERIFY(QFileInfo(dir.filePath("caches/b/fish.pc2")).size() > 0);
    const Run failed = runCli({"bake", kScene, "--clip", "no-such-clip", "--out", dir.filePath("gone/c/fish.pc2"), "--quiet"});
    QCOMPARE(failed.exitCode, 1);
    QVERIFY2(failed.err.contains("no-such-clip"), qPrintable(failed.err));
    QVERIFY(!QFileInfo::exists(dir.filePath("gone")));
}

// A body on its base animation is drawn as its rig moves it: half a swim cycle apart the rigged guppy's
// tail is on the other side, so the two frames differ over much of the fish (drawing the lattice's
// deviation alone, the frames differ by the wobble only).
void TestCliRender::baseAnimationIsDrawn() {
    QTemporaryDir dir;
    const QString scene = QStringLiteral(SOFTTOUCH_SOURCE_DIR "/presets/scenes/guppy-rigged.softtouch");
    const Run run = runCli({"render", scene, "--clip", "swim", "--out", dir.filePath("frames") + "/", "--size", "320x180",
                            "--frames", "13", "--quiet"});
    QVERIFY2(run.exitCode == 0, qPrintable(run.err));
    const QImage first(dir.filePath("frames/frame_0000.png")), half(dir.filePath("frames/frame_0012.png"));
    QVERIFY(!first.isNull() && !half.isNull());
    int fish = 0, changed = 0;
    const QRgb background = first.pixel(2, first.height() / 2);
    for (int y = 0; y < first.height(); ++y)
        for (int x = 0; x < first.width(); ++x) {
            const QColor a = first.pixelColor(x, y), b = half.pixelColor(x, y);
            const QColor bg = first.pixelColor(0, y);
            const bool inA = std::abs(a.red() - bg.red()) + std::abs(a.green() - bg.green()) + std::abs(a.blue() - bg.blue()) > 60;
            const bool inB = std::abs(b.red() - bg.red()) + std::abs(b.green() - bg.green()) + std::abs(b.blue() - bg.blue()) > 60;
            fish += inA ? 1 : 0;
            changed += inA != inB ? 1 : 0;
        }
    (void)background;
    qInfo("the fish covers %d pixels; half a cycle later %d pixels changed between fish and background (%.0f%%)", fish,
          changed, 100.0 * changed / std::max(fish, 1));
    QVERIFY(fish > 500);
    QVERIFY(changed > fish / 5);
}

namespace {

/// Largest summed RGB difference between two pictures over the 3x3 patch around `at` (inside a node disc).
int patchDifference(const QImage& a, const QImage& b, const QPointF& at) {
    int worst = 0;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            const QPoint p(int(std::lround(at.x())) + dx, int(std::lround(at.y())) + dy);
            if (!a.rect().contains(p))
                continue;
            const QColor x = a.pixelColor(p), y = b.pixelColor(p);
            worst = std::max(worst, std::abs(x.red() - y.red()) + std::abs(x.green() - y.green()) +
                                        std::abs(x.blue() - y.blue()));
        }
    return worst;
}

/// Fraction of the pixels within `radius` of `centre` whose summed RGB difference exceeds 30.
double changedFraction(const QImage& a, const QImage& b, const QPointF& centre, double radius) {
    int changed = 0, total = 0;
    for (int y = int(centre.y() - radius); y <= int(centre.y() + radius); ++y)
        for (int x = int(centre.x() - radius); x <= int(centre.x() + radius); ++x) {
            if (!a.rect().contains(x, y) || QLineF(centre, QPointF(x, y)).length() > radius)
                continue;
            const QColor p = a.pixelColor(x, y), q = b.pixelColor(x, y);
            changed += std::abs(p.red() - q.red()) + std::abs(p.green() - q.green()) + std::abs(p.blue() - q.blue()) > 30;
            ++total;
        }
    return total > 0 ? double(changed) / total : 0.0;
}

}  // namespace

// The three lowest modes of the angelfish drawn headless: one picture per mode and a strip of them,
// of the asked size; against the same pictures at amplitude 0 (the rest pose, same camera), the free
// end has left its place and the pinned head has not.
void TestCliRender::modePicturesShowEachShape() {
    QTemporaryDir dir;
    const int W = 400, H = 260;
    const Run run = runCli({"modes", kScene, "--pictures", dir.filePath("fish"), "--size", "400x260"});
    QVERIFY2(run.exitCode == 0, qPrintable(run.err));
    QVERIFY2(run.out.contains("wrote " + dir.filePath("fish-modes.png")), qPrintable(run.out));
    const Run still = runCli({"modes", kScene, "--pictures", dir.filePath("rest"), "--size", "400x260", "--amplitude", "0"});
    QVERIFY2(still.exitCode == 0, qPrintable(still.err));
    QCOMPARE(pngSize(dir.filePath("fish-modes.png")), (std::pair{3 * W, H}));

    auto project = io::loadProject(kScene.toStdString());
    QVERIFY2(project.ok(), project.message().c_str());
    const SceneObject& fish = project->scene.objects[0];
    auto body = buildLatticeBody(fish.lattice, fish.material);
    QVERIFY(body.ok());
    const auto modes = analyseModes(*body.value(), 3);
    QVERIFY(modes.ok() && modes->modes.size() == 3);
    const std::vector<Vec3>& rest = body.value()->restPositions;
    const double amplitude = kModeDisplayFraction * fish.lattice.box().size.maxCoeff();
    for (int m = 1; m <= 3; ++m) {
        const QString name = QString("fish-%1.png").arg(m);
        QCOMPARE(pngSize(dir.filePath(name)), (std::pair{W, H}));
        const QImage shape(dir.filePath(name)), at0(dir.filePath(QString("rest-%1.png").arg(m)));
        QVERIFY(!shape.isNull() && !at0.isNull());
        const VibrationMode& mode = modes->modes[std::size_t(m - 1)];
        const render::Camera camera = render::modeCamera(fish, mode, amplitude, W, H);
        auto pixel = [&](const Vec3& x) {
            const Eigen::Vector3d p = render::toPixels(camera, x, W, H);
            return QPointF(p.x(), p.y());
        };
        // The nodes that travel furthest on screen (the free end): around where they were at rest, the
        // picture changed. The pinned head: its discs are where they were, pixel for pixel (apart from
        // those a moving node's disc may cover in either picture).
        auto travel = [&](std::size_t n) { return QLineF(pixel(rest[n]), pixel(rest[n] + amplitude * mode.shape[n])).length(); };
        double farthest = 0.0;
        for (std::size_t n = 0; n < rest.size(); ++n)
            farthest = std::max(farthest, travel(n));
        QVERIFY2(farthest > 12.0, qPrintable(QString("%1: the mode moves a node %2 px").arg(name).arg(farthest)));
        double changed = 0.0;
        int moving = 0, pinned = 0;
        for (std::size_t n = 0; n < rest.size(); ++n) {
            const QPointF p = pixel(rest[n]);
            if (travel(n) > 0.8 * farthest) {
                changed += changedFraction(shape, at0, p, 10.0);
                ++moving;
            }
            if (fish.material.anchor[n] != AnchorMode::Pinned)
                continue;
            bool covered = false;
            for (std::size_t k = 0; k < rest.size(); ++k)
                covered = covered || (fish.material.anchor[k] != AnchorMode::Pinned &&
                                      (QLineF(p, pixel(rest[k])).length() < 8.0 ||
                                       QLineF(p, pixel(rest[k] + amplitude * mode.shape[k])).length() < 8.0));
            if (covered)
                continue;
            ++pinned;
            QVERIFY2(patchDifference(shape, at0, p) < 30, qPrintable(QString("%1: pinned node %2 moved").arg(name).arg(n)));
        }
        QVERIFY2(moving >= 1 && pinned >= 4, qPrintable(QString("%1: %2 moving, %3 pinned nodes to compare").arg(name).arg(moving).arg(pinned)));
        QVERIFY2(changed / moving > 0.3, qPrintable(QString("%1: only %2 changed where the free end was").arg(name).arg(changed / moving)));
    }
    // Usage errors are refused before anything is drawn.
    const Run bad = runCli({"modes", kScene, "--pictures", dir.filePath("bad"), "--amplitude", "2"});
    QCOMPARE(bad.exitCode, 2);
    QVERIFY(bad.err.contains("--amplitude"));
    QVERIFY(!QFile::exists(dir.filePath("bad-1.png")));
}

QTEST_GUILESS_MAIN(TestCliRender)
#include "test_cli_render.moc"

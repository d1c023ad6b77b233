// End to end: 'softtouch-cli render' writes MP4, GIF and PNG sequences headless (no DISPLAY), and fails
// cleanly on bad input without touching existing files.
#include "io/video_encoder.h"

#include "cli_run.h"

#include <QDir>
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
    QTest::newRow("size without height") << "old.mp4" << "100x" << "--size expects WIDTHxHEIGHT";
    QTest::newRow("size too small") << "old.mp4" << "8x8" << "--size expects WIDTHxHEIGHT";
    QTest::newRow("odd size for yuv420p") << "old.mp4" << "161x96" << "even width and height";
    QTest::newRow("missing directory") << "missing/out.mp4" << "160x96" << "missing";
    QTest::newRow("parent is a file") << "old.mp4/out.gif" << "160x96" << "old.mp4";
}

void TestCliRender::badInputFailsWithoutPartialFiles() {
    QFETCH(QString, name);
    QFETCH(QString, size);
    QFETCH(QString, message);
    QTemporaryDir dir;
    QFile old(dir.filePath("old.mp4"));
    QVERIFY(old.open(QIODevice::WriteOnly));
    old.write("previous render");
    old.close();
    const Run run = runCli({"render", kScene, "--out", dir.filePath(name), "--size", size, "--frames", "3", "--quiet"});
    QCOMPARE(run.exitCode, 1);
    QVERIFY2(run.err.contains(message), qPrintable(run.err));
    QVERIFY2(run.err.count('\n') == 1, qPrintable(run.err));  // one clear line
    QCOMPARE(QDir(dir.path()).entryList(QDir::AllEntries | QDir::NoDotAndDotDot), QStringList{"old.mp4"});
    QVERIFY(old.open(QIODevice::ReadOnly));
    QCOMPARE(old.readAll(), QByteArray("previous render"));
}

QTEST_GUILESS_MAIN(TestCliRender)
#include "test_cli_render.moc"

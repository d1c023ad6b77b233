// io/export/video_encoder: streaming, atomic video files read back with libavformat.
#include "io/export/video_encoder.h"

#include <QDir>
#include <QTemporaryDir>
#include <QtTest>

using namespace softtouch;

namespace {

/// A frame with a moving square on a gradient: real content for the encoders.
std::vector<std::uint8_t> frameAt(int w, int h, int f) {
    std::vector<std::uint8_t> rgba(std::size_t(w) * std::size_t(h) * 4);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            std::uint8_t* p = &rgba[(std::size_t(y) * std::size_t(w) + std::size_t(x)) * 4];
            const bool square = x >= 4 * f && x < 4 * f + 16 && y >= 8 && y < 24;
            p[0] = square ? 240 : std::uint8_t(y * 255 / h);
            p[1] = square ? 120 : 100;
            p[2] = square ? 20 : std::uint8_t(255 - y * 255 / h);
            p[3] = 255;
        }
    return rgba;
}

QStringList entries(const QTemporaryDir& dir) { return QDir(dir.path()).entryList(QDir::AllEntries | QDir::NoDotAndDotDot); }

}  // namespace

class TestVideo : public QObject {
    Q_OBJECT
private slots:
    void formatFromPath();
    void mp4EncodersWriteEveryFrame_data();
    void mp4EncodersWriteEveryFrame();
    void abortKeepsPreviousFile();
    void pngAbortLeavesNothing();
    void badSettingsNameFileAndCodec();
};

void TestVideo::formatFromPath() {
    QCOMPARE(io::videoFormatFromPath("a/b.MP4"), std::optional(io::VideoFormat::Mp4));
    QCOMPARE(io::videoFormatFromPath("b.gif"), std::optional(io::VideoFormat::Gif));
    QCOMPARE(io::videoFormatFromPath("frames/"), std::optional(io::VideoFormat::PngSequence));
    QTemporaryDir dir;
    QCOMPARE(io::videoFormatFromPath(dir.path().toStdString()), std::optional(io::VideoFormat::PngSequence));
    QVERIFY(!io::videoFormatFromPath("movie.avi"));
}

void TestVideo::mp4EncodersWriteEveryFrame_data() {
    QTest::addColumn<QString>("encoder");
    QTest::addColumn<QString>("codec");
    QTest::newRow("libx264") << "libx264" << "h264";
    QTest::newRow("mpeg4 fallback") << "mpeg4" << "mpeg4";
}

void TestVideo::mp4EncodersWriteEveryFrame() {
    QFETCH(QString, encoder);
    QFETCH(QString, codec);
    QTemporaryDir dir;
    io::VideoSettings settings;
    settings.output = dir.filePath("clip.mp4").toStdString();
    settings.width = 64;
    settings.height = 32;
    settings.fps = 25.0;
    settings.mp4Encoder = encoder.toStdString();
    auto video = io::VideoEncoder::open(settings);
    if (!video && encoder == "libx264")
        QSKIP("this libavcodec has no libx264 (the CLI then falls back to mpeg4, tested in the next row)");
    QVERIFY2(video.ok(), video.message().c_str());
    for (int f = 0; f < 10; ++f) {
        Status s = video.value()->writeFrame(frameAt(64, 32, f));
        QVERIFY2(s.ok(), s.message().c_str());
        QVERIFY(!QFile::exists(dir.filePath("clip.mp4")));  // only the temporary exists until finish()
    }
    Status finished = video.value()->finish();
    QVERIFY2(finished.ok(), finished.message().c_str());
    QCOMPARE(entries(dir), QStringList{"clip.mp4"});
    auto probe = io::probeVideo(settings.output);
    QVERIFY2(probe.ok(), probe.message().c_str());
    QCOMPARE(QString::fromStdString(probe->codec), codec);
    QCOMPARE(probe->width, 64);
    QCOMPARE(probe->height, 32);
    QCOMPARE(probe->frames, 10);
    QVERIFY(std::abs(probe->fps - 25.0) < 1e-6);
}

void TestVideo::abortKeepsPreviousFile() {
    QTemporaryDir dir;
    const QString path = dir.filePath("keep.gif");
    QFile old(path);
    QVERIFY(old.open(QIODevice::WriteOnly));
    old.write("old bytes");
    old.close();
    io::VideoSettings settings;
    settings.output = path.toStdString();
    settings.format = io::VideoFormat::Gif;
    settings.width = 32;
    settings.height = 32;
    {
        auto video = io::VideoEncoder::open(settings);
        QVERIFY2(video.ok(), video.message().c_str());
        QVERIFY(video.value()->writeFrame(frameAt(32, 32, 0)).ok());
        QVERIFY(video.value()->writeFrame(frameAt(32, 32, 1)).ok());
        QVERIFY(!video.value()->writeFrame(std::vector<std::uint8_t>(7)).ok());  // wrong size: an error, no crash
        video.value()->abort();
    }
    {
        auto video = io::VideoEncoder::open(settings);  // destroyed without finish(): same as abort
        QVERIFY(video.ok());
        QVERIFY(video.value()->writeFrame(frameAt(32, 32, 0)).ok());
    }
    QCOMPARE(entries(dir), QStringList{"keep.gif"});
    QVERIFY(old.open(QIODevice::ReadOnly));
    QCOMPARE(old.readAll(), QByteArray("old bytes"));
}

void TestVideo::pngAbortLeavesNothing() {
    QTemporaryDir dir;
    io::VideoSettings settings;
    settings.output = dir.filePath("seq").toStdString();
    settings.format = io::VideoFormat::PngSequence;
    settings.width = 32;
    settings.height = 16;
    auto video = io::VideoEncoder::open(settings);
    QVERIFY2(video.ok(), video.message().c_str());
    for (int f = 0; f < 3; ++f)
        QVERIFY(video.value()->writeFrame(frameAt(32, 16, f)).ok());
    video.value()->abort();
    QCOMPARE(entries(dir), QStringList{});  // the directory it created is gone too
}

void TestVideo::badSettingsNameFileAndCodec() {
    io::VideoSettings settings;
    settings.output = "/tmp/softtouch-never-written.mp4";
    settings.width = 63;
    settings.height = 32;
    auto odd = io::VideoEncoder::open(settings);
    QVERIFY(!odd.ok());
    QVERIFY2(odd.message().find("softtouch-never-written.mp4") != std::string::npos, odd.message().c_str());
    QVERIFY2(odd.message().find("even") != std::string::npos, odd.message().c_str());
    settings.width = 64;
    settings.mp4Encoder = "no-such-encoder";
    auto unknown = io::VideoEncoder::open(settings);
    QVERIFY(!unknown.ok());
    QVERIFY2(unknown.message().find("no-such-encoder") != std::string::npos, unknown.message().c_str());
    settings.mp4Encoder.clear();
    settings.crf = 70;
    QVERIFY(!io::VideoEncoder::open(settings).ok());
    QVERIFY(!QFile::exists("/tmp/softtouch-never-written.mp4"));
}

QTEST_GUILESS_MAIN(TestVideo)
#include "test_video.moc"

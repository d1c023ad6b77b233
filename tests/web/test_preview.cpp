// The clip preview page (softtouch-cli preview) played in headless Chromium (SwiftShader's WebGL 2):
// every export kind a game plays (skinned, morph, VAT, lattice cache) is baked from the angelfish's swim
// clip, opened as a page at a frame, read back from the page's canvas, and compared with the project's
// own render of that frame (softtouch-cli render, the same camera).

#include "helpers/cli_run.h"
#include "io/pipeline/clip_preview.h"

#include <QDir>
#include <QImage>
#include <QJsonDocument>
#include <QJsonObject>
#include <QProcess>
#include <QRegularExpression>
#include <QStandardPaths>
#include <QTemporaryDir>
#include <QtTest>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <filesystem>
#include <vector>

#include <sys/stat.h>

using softtouch::test::runCli;

namespace {

const QString kScene = QStringLiteral(SOFTTOUCH_SOURCE_DIR "/presets/scenes/angelfish-swim.softtouch");
constexpr int kWidth = 960, kHeight = 540;
constexpr int kRenderedFrames = 13;  // 0..12: the frames checked and their neighbours

/// Pixels covered by the mesh in one picture.
using Mask = std::vector<bool>;

/// The page's matte: white on black.
Mask matteMask(const QImage& image) {
    Mask mask(std::size_t(image.width() * image.height()));
    for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x)
            mask[std::size_t(y * image.width() + x)] = qGray(image.pixel(x, y)) > 127;
    return mask;
}

/// The project's render: the background is a vertical gradient, so a row's background is its first
/// pixel (the mesh never reaches the edge); a pixel is the mesh's where it differs from that by more
/// than half the typical contrast of mesh pixels (edges are antialiased).
Mask renderMask(const QImage& image) {
    std::vector<int> contrast(std::size_t(image.width() * image.height()));
    std::vector<int> covered;
    for (int y = 0; y < image.height(); ++y) {
        const QRgb background = image.pixel(0, y);
        for (int x = 0; x < image.width(); ++x) {
            const QRgb p = image.pixel(x, y);
            const int d = std::abs(qRed(p) - qRed(background)) + std::abs(qGreen(p) - qGreen(background)) +
                          std::abs(qBlue(p) - qBlue(background));
            contrast[std::size_t(y * image.width() + x)] = d;
            if (d > 16)
                covered.push_back(d);
        }
    }
    std::nth_element(covered.begin(), covered.begin() + covered.size() / 2, covered.end());
    const int threshold = covered.empty() ? 16 : covered[covered.size() / 2] / 2;
    Mask mask(contrast.size());
    for (std::size_t i = 0; i < contrast.size(); ++i)
        mask[i] = contrast[i] > threshold;
    return mask;
}

double intersectionOverUnion(const Mask& a, const Mask& b) {
    std::size_t both = 0, either = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        both += a[i] && b[i];
        either += a[i] || b[i];
    }
    return either ? double(both) / double(either) : 0.0;
}

/// A one-triangle morph clip: one target, a weights animation of two keys at 24 fps; its data (88 bytes,
/// morphClipData) in buffer 0, a file beside it named "data.bin".
nlohmann::json morphClipGltf() {
    return nlohmann::json::parse(R"({
      "asset": {"version": "2.0"},
      "buffers": [{"uri": "data.bin", "byteLength": 88}],
      "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 36},
                      {"buffer": 0, "byteOffset": 72, "byteLength": 8}, {"buffer": 0, "byteOffset": 80, "byteLength": 8}],
      "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
        {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0.1], "max": [0, 0, 0.1]},
        {"bufferView": 2, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0], "max": [0.041666666666666664]},
        {"bufferView": 3, "componentType": 5126, "count": 2, "type": "SCALAR"}],
      "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "targets": [{"POSITION": 1}]}], "weights": [0]}],
      "nodes": [{"mesh": 0}],
      "scenes": [{"nodes": [0]}],
      "scene": 0,
      "animations": [{"samplers": [{"input": 2, "output": 3, "interpolation": "LINEAR"}],
                      "channels": [{"sampler": 0, "target": {"node": 0, "path": "weights"}}]}]})");
}

/// Positions, deltas (0.1 m along z), key times (0, 1/24 s) and weights (0, 1) of morphClipGltf.
QByteArray morphClipData() {
    const std::array<float, 22> v{0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0.1f, 0, 0, 0.1f, 0, 0, 0.1f, 0, 1 / 24.0f, 0, 1};
    return QByteArray(reinterpret_cast<const char*>(v.data()), int(sizeof v));
}

/// The GLB of `gltf` with `bin` as its binary chunk (buffer 0 without a URI).
QByteArray glbOf(nlohmann::json gltf, QByteArray bin) {
    gltf["buffers"][0].erase("uri");
    QByteArray text = QByteArray::fromStdString(gltf.dump());
    while (text.size() % 4)
        text += ' ';
    while (bin.size() % 4)
        bin += '\0';
    const auto u32 = [](QByteArray& out, int v) {
        for (int b = 0; b < 4; ++b)
            out += char((v >> (8 * b)) & 0xFF);
    };
    QByteArray out("glTF");
    u32(out, 2);
    u32(out, 12 + 8 + int(text.size()) + 8 + int(bin.size()));
    u32(out, int(text.size()));
    out += "JSON" + text;
    u32(out, int(bin.size()));
    out += QByteArray("BIN\0", 4) + bin;
    return out;
}

bool writeBytes(const QString& path, const QByteArray& bytes) {
    QFile file(path);
    return file.open(QIODevice::WriteOnly | QIODevice::Truncate) && file.write(bytes) == bytes.size();
}

/// softtouch-cli within `seconds`: a preview that blocks (a FIFO opened for reading waits for a writer)
/// fails the test instead of hanging the suite.
softtouch::test::Run runCliWithin(const QStringList& args, int seconds) {
    QProcess p;
    p.start(softtouch::test::kCli, args);
    if (!p.waitForFinished(seconds * 1000)) {
        p.kill();
        p.waitForFinished();
        return {-2, {}, QString("softtouch-cli %1 did not finish within %2 s").arg(args.join(' ')).arg(seconds)};
    }
    return {p.exitStatus() == QProcess::NormalExit ? p.exitCode() : -1, QString::fromUtf8(p.readAllStandardOutput()),
            QString::fromUtf8(p.readAllStandardError())};
}

}  // namespace

class TestPreview : public QObject {
    Q_OBJECT

private:
    QTemporaryDir m_dir;
    QString m_chromium;
    std::vector<Mask> m_rendered;  ///< The project's render of frames 0..kRenderedFrames-1.

    /// Opens `page` in headless Chromium with the address options `fragment`; returns the document.
    QString openPage(const QString& page, const QString& fragment) {
        QTemporaryDir profile;
        QProcess p;
        p.start(m_chromium, {"--headless", "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
                             "--user-data-dir=" + profile.path(), "--virtual-time-budget=30000", "--dump-dom",
                             QUrl::fromLocalFile(page).toString() + "#" + fragment});
        if (!p.waitForFinished(180000))
            return {};
        return QString::fromUtf8(p.readAllStandardOutput());
    }

    /// The project's own render of the first frames, once.
    void renderTheProject() {
        if (!m_rendered.empty())
            return;
        const auto render = runCli({"render", kScene, "--clip", "swim", "--size", QString("%1x%2").arg(kWidth).arg(kHeight),
                                    "--frames", QString::number(kRenderedFrames), "--out", m_dir.filePath("render/"), "--quiet"},
                                   true);
        QVERIFY2(render.exitCode == 0, qPrintable(render.err));
        for (int f = 0; f < kRenderedFrames; ++f) {
            const QImage image(m_dir.filePath(QString("render/frame_%1.png").arg(f, 4, 10, QChar('0'))));
            QCOMPARE(image.size(), QSize(kWidth, kHeight));
            m_rendered.push_back(renderMask(image));
        }
    }

    /// m_dir/hostile/: clip/ holds data.bin, sub/data.bin, a FIFO pipe.bin and link.bin, a link to
    /// ../secret.bin, a file outside clip/ that no page made from clip/ may hold.
    QString hostileFolder() {
        const QString root = m_dir.filePath("hostile");
        if (QDir(root).exists())
            return root;
        [&] {
            QVERIFY(QDir().mkpath(root + "/clip/sub"));
            QVERIFY(writeBytes(root + "/secret.bin", morphClipData()));
            QVERIFY(writeBytes(root + "/clip/data.bin", morphClipData()));
            QVERIFY(writeBytes(root + "/clip/sub/data.bin", morphClipData()));
            QCOMPARE(::mkfifo(QFile::encodeName(root + "/clip/pipe.bin").constData(), 0600), 0);
            std::error_code ec;
            std::filesystem::create_symlink("../secret.bin", (root + "/clip/link.bin").toStdString(), ec);
            QVERIFY2(!ec, ec.message().c_str());
        }();
        return root;
    }

    /// Writes morphClipGltf with the value at `pointer` replaced by `value` (JSON) as clip/NAME in
    /// hostileFolder() (a GLB with morphClipData as its binary chunk when `binary`), previews it and checks
    /// that the preview fails at once, naming the file and `expected`, with no page written.
    void checkRefused(bool binary, const QString& pointer, const QString& value, const QString& expected) {
        const QString folder = hostileFolder() + "/clip";
        nlohmann::json gltf = morphClipGltf();
        gltf[nlohmann::json::json_pointer(pointer.toStdString())] = nlohmann::json::parse(value.toStdString());
        const QString name = binary ? "evil.glb" : "evil.gltf";
        QVERIFY(writeBytes(folder + "/" + name, binary ? glbOf(gltf, morphClipData()) : QByteArray::fromStdString(gltf.dump())));
        const QString page = folder + "/page-" + QTest::currentDataTag();
        const auto run = runCliWithin({"preview", folder + "/" + name, "--out", page}, 60);
        QVERIFY2(run.exitCode == 1, qPrintable(QString("exit %1: %2").arg(run.exitCode).arg(run.err)));
        QVERIFY2(run.err.contains(folder + "/" + name) && run.err.contains(expected), qPrintable(run.err));
        QVERIFY(!QFile::exists(page + "/index.html"));
    }

private slots:
    void initTestCase() { QVERIFY(m_dir.isValid()); }

    void everyKindPlaysTheFramesTheProjectRenders_data() {
        QTest::addColumn<QString>("format");
        QTest::addColumn<QString>("out");   // as bake takes it
        QTest::addColumn<QString>("clip");  // as preview takes it
        QTest::addColumn<double>("minimumOverlap");
        QTest::addColumn<bool>("compress");  // bake --compress: three.js decodes EXT_meshopt_compression
        // pca keeps every frame within 0.5% of the diagonal (RMS), so its silhouette may move a pixel.
        QTest::newRow("skinned") << "skin" << "swim-skin.glb" << "swim-skin.glb" << 0.985 << false;
        QTest::newRow("skinned, compressed") << "skin" << "swim-packed.glb" << "swim-packed.glb" << 0.985 << true;
        QTest::newRow("morph") << "pca" << "swim-pca.glb" << "swim-pca.glb" << 0.975 << false;
        QTest::newRow("morph, compressed") << "pca" << "swim-packed.glb" << "swim-packed.glb" << 0.975 << true;
        QTest::newRow("vat") << "vat" << "swim" << "swim.vat.json" << 0.985 << false;
        QTest::newRow("lattice") << "lattice" << "swim" << "swim.lattice.bin" << 0.985 << false;
    }

    void everyKindPlaysTheFramesTheProjectRenders() {
        QFETCH(QString, format);
        QFETCH(QString, out);
        QFETCH(QString, clip);
        QFETCH(double, minimumOverlap);
        QFETCH(bool, compress);
        m_chromium = QStandardPaths::findExecutable("chromium");
        if (m_chromium.isEmpty())
            QSKIP("preview test skipped: chromium is not installed (scripts/install-deps.sh installs it)");
        renderTheProject();
        QCOMPARE(int(m_rendered.size()), kRenderedFrames);
        const QString folder = m_dir.filePath(format + (compress ? "-packed" : ""));
        QVERIFY(QDir().mkpath(folder));
        QStringList bakeArgs{"bake", kScene, "--clip", "swim", "--format", format, "--out", folder + "/" + out, "--quiet"};
        if (compress)
            bakeArgs << "--compress";
        const auto bake = runCli(bakeArgs);
        QVERIFY2(bake.exitCode == 0, qPrintable(bake.err));
        const auto preview = runCli({"preview", folder + "/" + clip, "--out", folder + "/page", "--size",
                                     QString("%1x%2").arg(kWidth).arg(kHeight)});
        QVERIFY2(preview.exitCode == 0, qPrintable(preview.err));
        QVERIFY2(preview.out.contains("24 frames at 24 fps"), qPrintable(preview.out));
        // One browser start for the clip: frames 6 and 12 shown still, then played, not only still: the page
        // plays from the start, a 60th of a second a step (a headless browser's clock does not keep time), and
        // stops 0.4 s in, then 1.3 s in, past the end of the one-second loop. The stops show different frames,
        // each the frame its label names: the glTF pages used to stand still once three.js had paused the action
        // at the clip's end (or at a negative first step), while the label went on.
        const QString dom = openPage(folder + "/page/index.html", QString("frame=6,12&until=0.4,1.3&tick=%1&size=%2x%3&matte&readback")
                                                                      .arg(1.0 / 60.0)
                                                                      .arg(kWidth)
                                                                      .arg(kHeight));
        QVERIFY2(dom.contains("<title>ready</title>"), qPrintable(dom.left(2000)));
        // One line a stop: the label it was shown under, a tab, the picture.
        QRegularExpressionMatchIterator stops =
            QRegularExpression("frame (\\d+) of 24[^\\t\\n<]*\\tdata:image/png;base64,([A-Za-z0-9+/=]+)").globalMatch(dom);
        const QStringList names{"still 6", "still 12", "played to 0.4 s", "played to 1.3 s"};
        std::vector<int> played;
        for (const QString& name : names) {
            QVERIFY2(stops.hasNext(), qPrintable(QString("the page wrote no picture for %1").arg(name)));
            const QRegularExpressionMatch stop = stops.next();
            const int frame = stop.captured(1).toInt();
            QVERIFY2(frame >= 1 && frame < kRenderedFrames, qPrintable(name + ": " + stop.captured(0).left(40)));
            const QImage picture = QImage::fromData(QByteArray::fromBase64(stop.captured(2).toLatin1()), "PNG");
            QCOMPARE(picture.size(), QSize(kWidth, kHeight));
            const Mask page = matteMask(picture);
            std::vector<double> overlap;
            for (const Mask& rendered : m_rendered)
                overlap.push_back(intersectionOverUnion(page, rendered));
            const int best = int(std::max_element(overlap.begin(), overlap.end()) - overlap.begin());
            qInfo("%s %s: label frame %d, overlap with its render %.4f, of frame 0 %.4f; best match frame %d", qPrintable(format),
                  qPrintable(name), frame, overlap[std::size_t(frame)], overlap[0], best);
            QVERIFY2(overlap[std::size_t(frame)] >= minimumOverlap, qPrintable(QString::number(overlap[std::size_t(frame)])));
            // It is that frame: no other matches better than a neighbour at the swim's turning points,
            // and the rest pose is far off.
            QVERIFY2(std::abs(best - frame) <= 1, qPrintable(QString("best match %1").arg(best)));
            QVERIFY(overlap[0] < overlap[std::size_t(frame)] - 0.1);
            if (name.startsWith("still"))
                QCOMPARE(frame, name.section(' ', 1).toInt());
            else
                played.push_back(frame);
        }
        QVERIFY2(!stops.hasNext(), "the page wrote more pictures than it was asked for");
        QVERIFY2(played[0] != played[1], qPrintable(QString("frames %1 and %2").arg(played[0]).arg(played[1])));
    }

    // Every module the page imports is in its import map, under the name it is imported by: a relative
    // import left in a data: URL module cannot resolve and the page stays blank.
    void everyImportResolvesInsideThePage() {
        const auto inlined = softtouch::io::inlineThreeModules(
            "import * as THREE from 'three';\nimport { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';\n"
            "import { EXRLoader } from 'three/addons/loaders/EXRLoader.js';\n",
            SOFTTOUCH_SOURCE_DIR "/web/node_modules/three");
        QVERIFY2(inlined.ok(), inlined.message().c_str());
        QVERIFY(inlined.value().script.find("from 'three/build/three.module.js'") != std::string::npos);
        const QJsonObject imports =
            QJsonDocument::fromJson(QByteArray::fromStdString(inlined.value().importMapJson)).object()["imports"].toObject();
        // three.module.js, three.core.js, the two loaders, BufferGeometryUtils, SkeletonUtils, fflate.
        QCOMPARE(imports.size(), 7);
        QCOMPARE(inlined.value().moduleCount, 7);
        const QRegularExpression specifier(R"((?:^|[\s}])from\s*'([^']+)')");
        for (auto it = imports.begin(); it != imports.end(); ++it) {
            const QString url = it.value().toString();
            QVERIFY(url.startsWith("data:text/javascript;base64,"));
            const QString source = QString::fromUtf8(QByteArray::fromBase64(url.mid(28).toLatin1()));
            for (const QString& line : source.split('\n')) {
                const QString trimmed = line.trimmed();
                if (trimmed.startsWith('*') || trimmed.startsWith("//") || trimmed.startsWith("/*"))
                    continue;
                for (auto m = specifier.globalMatch(line); m.hasNext();) {
                    const QString name = m.next().captured(1);
                    QVERIFY2(imports.contains(name), qPrintable(it.key() + " imports " + name));
                }
            }
        }
    }

    // The page of every kind is built from a real bake (the part of the test above that is SoftTouch's own
    // code, so the sanitizer run, which leaves the browser comparison to release, still runs it).
    void everyKindBuildsItsPage_data() {
        QTest::addColumn<QString>("format");
        QTest::addColumn<QString>("out");
        QTest::addColumn<QString>("clip");
        QTest::addColumn<QString>("kind");
        QTest::addColumn<bool>("compress");
        QTest::newRow("skinned") << "skin" << "s.glb" << "s.glb" << "skinned" << false;
        QTest::newRow("skinned, compressed") << "skin" << "c.glb" << "c.glb" << "skinned" << true;
        QTest::newRow("morph") << "pca" << "m.glb" << "m.glb" << "morph" << false;
        QTest::newRow("morph, compressed") << "pca" << "p.glb" << "p.glb" << "morph" << true;
        QTest::newRow("vat") << "vat" << "v" << "v.vat.json" << "vat" << false;
        QTest::newRow("lattice") << "lattice" << "l" << "l.lattice.bin" << "lattice" << false;
    }

    void everyKindBuildsItsPage() {
        QFETCH(QString, format);
        QFETCH(QString, out);
        QFETCH(QString, clip);
        QFETCH(QString, kind);
        QFETCH(bool, compress);
        const QString folder = m_dir.filePath("pages/" + format + (compress ? "-packed" : ""));
        QVERIFY(QDir().mkpath(folder));
        QStringList bakeArgs{"bake", kScene, "--clip", "swim", "--frames", "3", "--format", format, "--out", folder + "/" + out, "--quiet"};
        if (compress)
            bakeArgs << "--compress";
        const auto bake = runCli(bakeArgs);
        QVERIFY2(bake.exitCode == 0, qPrintable(bake.err));
        const auto preview = runCli({"preview", folder + "/" + clip, "--out", folder + "/page"});
        QVERIFY2(preview.exitCode == 0, qPrintable(preview.err));
        QVERIFY2(preview.out.contains(kind + " clip") && preview.out.contains("3 frames at 24 fps"), qPrintable(preview.out));
        QFile page(folder + "/page/index.html");
        QVERIFY(page.open(QIODevice::ReadOnly));
        const QByteArray html = page.readAll();
        QVERIFY2(html.size() > 100000 && html.contains("<script type=\"importmap\">"), qPrintable(QString::number(html.size())));
    }

    void clipsItCannotPlayAreRefusedByName() {
        const QString folder = m_dir.filePath("bad");
        QVERIFY(QDir().mkpath(folder));
        // A rest OBJ is no clip; a GLB with nothing that moves (a VAT's mesh alone, renamed).
        QFile obj(folder + "/rest.obj");
        QVERIFY(obj.open(QIODevice::WriteOnly));
        obj.write("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        obj.close();
        auto run = runCli({"preview", folder + "/rest.obj", "--out", folder + "/page"});
        QCOMPARE(run.exitCode, 1);
        QVERIFY2(run.err.contains("rest.obj is not a clip the preview plays"), qPrintable(run.err));
        QVERIFY(!QFile::exists(folder + "/page/index.html"));

        const auto bake = runCli({"bake", kScene, "--clip", "swim", "--frames", "2", "--format", "vat", "--out", folder + "/v", "--quiet"});
        QVERIFY2(bake.exitCode == 0, qPrintable(bake.err));
        QVERIFY(QFile::copy(folder + "/v.vat-mesh.glb", folder + "/still.glb"));
        run = runCli({"preview", folder + "/still.glb", "--out", folder + "/page"});
        QCOMPARE(run.exitCode, 1);
        QVERIFY2(run.err.contains("still.glb has neither a skin nor morph targets"), qPrintable(run.err));

        // A VAT whose texture is gone names the texture.
        QVERIFY(QFile::remove(folder + "/v.vat-normal.exr"));
        run = runCli({"preview", folder + "/v.vat.json", "--out", folder + "/page"});
        QCOMPARE(run.exitCode, 1);
        QVERIFY2(run.err.contains("v.vat-normal.exr"), qPrintable(run.err));

        run = runCli({"preview", folder + "/v.vat.json"});
        QCOMPARE(run.exitCode, 2);
        QVERIFY2(run.err.contains("Usage: softtouch-cli preview CLIP --out DIR"), qPrintable(run.err));
    }

    // Every file a glTF names (a buffer's or an image's URI) is read only when it is a regular file in the
    // glTF's folder or below: a page made of a shared clip used to carry ../../etc/hostname's bytes, and a
    // buffer that was a FIFO blocked the preview forever. Percent-encoding ("%2e%2e/") is decoded as tinygltf
    // decodes it before the check, and a link is followed before it.
    void gltfSideFilesStayInItsFolder_data() {
        QTest::addColumn<QString>("pointer");
        QTest::addColumn<QString>("value");
        QTest::addColumn<QString>("expected");
        const QString secret = hostileFolder() + "/secret.bin";
        QTest::newRow("parent folder") << "/buffers/0/uri" << R"("../secret.bin")"
                                       << R"(/buffers/0/uri: "../secret.bin" leads outside the clip's folder)";
        QTest::newRow("absolute") << "/buffers/0/uri" << "\"" + secret + "\""
                                  << "/buffers/0/uri: \"" + secret + "\" is an absolute path";
        QTest::newRow("percent-encoded") << "/buffers/0/uri" << R"("%2e%2e/secret.bin")"
                                         << R"(/buffers/0/uri: "%2e%2e/secret.bin" (decoded "../secret.bin") leads outside)";
        QTest::newRow("link out of the folder") << "/buffers/0/uri" << R"("link.bin")"
                                                << R"(/buffers/0/uri: "link.bin" leads outside the clip's folder)";
        QTest::newRow("device") << "/buffers/0/uri" << R"("../../../../../../../../../../dev/zero")"
                                << R"(/buffers/0/uri: "../../../../../../../../../../dev/zero" leads outside)";
        QTest::newRow("FIFO") << "/buffers/0/uri" << R"("pipe.bin")"
                              << R"(/buffers/0/uri: "pipe.bin" is not a regular file (a FIFO))";
        QTest::newRow("image outside") << "/images" << R"([{"uri": "../secret.bin"}])"
                                       << R"(/images/0/uri: "../secret.bin" leads outside the clip's folder)";
        QTest::newRow("image FIFO") << "/images" << R"([{"uri": "pipe.bin"}])" << R"(/images/0/uri: "pipe.bin" is not a regular file (a FIFO))";
    }

    void gltfSideFilesStayInItsFolder() {
        QFETCH(QString, pointer);
        QFETCH(QString, value);
        QFETCH(QString, expected);
        checkRefused(false, pointer, value, expected);
    }

    // A glTF three.js cannot play (it would leave an empty page, or make the browser allocate what the file
    // claims) is refused before a page is written, with the place in it and why.
    void gltfThreeJsCannotPlayIsRefused_data() {
        QTest::addColumn<bool>("binary");
        QTest::addColumn<QString>("pointer");
        QTest::addColumn<QString>("value");
        QTest::addColumn<QString>("expected");
        QTest::newRow("accessor past its view")
            << false << "/accessors/0/count" << "1000000" << "/accessors/0: 1000000 VEC3 elements of 12 bytes";
        QTest::newRow("accessor offset past its view")
            << false << "/accessors/1/byteOffset" << "40" << "/accessors/1: 3 VEC3 elements of 12 bytes from byte 40";
        QTest::newRow("GLB, accessor past its view")
            << true << "/accessors/2/count" << "3000000000" << "/accessors/2: 3000000000 SCALAR elements of 4 bytes";
        QTest::newRow("accessor of no view") << false << "/accessors/0/bufferView" << "9" << "/accessors/0/bufferView: there is no bufferView 9";
        QTest::newRow("huge accessor without a view")
            << false << "/accessors/3" << R"({"componentType": 5126, "count": 4000000000, "type": "MAT4"})"
            << "/accessors/3: 4000000000 MAT4 elements of 64 bytes";
        QTest::newRow("view past its buffer") << false << "/bufferViews/3/byteLength" << "4000"
                                              << "/bufferViews/3: its 4000 bytes from byte 80 lie outside buffer 0 (88 bytes)";
        QTest::newRow("view of no buffer") << false << "/bufferViews/0/buffer" << "3" << "/bufferViews/0/buffer: there is no buffer 3";
        QTest::newRow("node cycle") << false << "/nodes" << R"([{"mesh": 0, "children": [1]}, {"children": [0]}])"
                                    << "/nodes/0: node 0 is its own ancestor";
        QTest::newRow("node its own child") << false << "/nodes/0/children" << "[0]" << "/nodes/0: node 0 is its own ancestor";
        QTest::newRow("node with two parents") << false << "/nodes" << R"([{"mesh": 0, "children": [1, 2]}, {"children": [2]}, {}])"
                                               << "/nodes/1/children/0: node 2 is already a child of node 0";
        QTest::newRow("child that is no node") << false << "/nodes/0/children" << "[9]" << "/nodes/0/children/0: there is no node 9";
        QTest::newRow("scene root that is no node") << false << "/scenes/0/nodes" << "[5]" << "/scenes/0/nodes/0: there is no node 5";
        QTest::newRow("morph target of no accessor")
            << false << "/meshes/0/primitives/0/targets/0/POSITION" << "7" << "/meshes/0/primitives/0/targets/0/POSITION: there is no accessor 7";
        QTest::newRow("animation of no node")
            << false << "/animations/0/channels/0/target/node" << "4" << "/animations/0/channels/0/target/node: there is no node 4";
        QTest::newRow("bogus required extension") << false << "/extensionsRequired" << R"(["KHR_bogus"])"
                                                  << R"(/extensionsRequired/0: "KHR_bogus" is not an extension three.js's GLTFLoader plays)";
        QTest::newRow("Draco required") << false << "/extensionsRequired" << R"(["KHR_draco_mesh_compression"])"
                                        << R"(/extensionsRequired/0: "KHR_draco_mesh_compression" is not an extension)";
        QTest::newRow("GLB, bogus required extension") << true << "/extensionsRequired" << R"(["EXT_bogus"])"
                                                       << R"(/extensionsRequired/0: "EXT_bogus" is not an extension)";
    }

    void gltfThreeJsCannotPlayIsRefused() {
        QFETCH(bool, binary);
        QFETCH(QString, pointer);
        QFETCH(QString, value);
        QFETCH(QString, expected);
        checkRefused(binary, pointer, value, expected);
    }

    // A VAT's textures and mesh and a lattice cache's mesh are held to the same folder: a link beside the
    // clip that leads out of its folder used to put the file it points to in the page.
    void vatAndLatticeFilesStayInTheirFolder() {
        const QString folder = m_dir.filePath("linked");
        QVERIFY(QDir().mkpath(folder + "/clip"));
        QVERIFY(writeBytes(folder + "/secret.exr", "not for the page"));
        for (const QString format : {"vat", "lattice"}) {
            const auto bake = runCli({"bake", kScene, "--clip", "swim", "--frames", "2", "--format", format, "--out",
                                      folder + "/clip/" + format, "--quiet"});
            QVERIFY2(bake.exitCode == 0, qPrintable(bake.err));
        }
        QVERIFY(QFile::remove(folder + "/clip/vat.vat-normal.exr"));
        QVERIFY(QFile::link("../secret.exr", folder + "/clip/vat.vat-normal.exr"));
        auto run = runCliWithin({"preview", folder + "/clip/vat.vat.json", "--out", folder + "/vat-page"}, 60);
        QCOMPARE(run.exitCode, 1);
        QVERIFY2(run.err.contains(R"(vat.vat.json: /normalTexture: "vat.vat-normal.exr" leads outside the clip's folder)"),
                 qPrintable(run.err));
        QVERIFY(!QFile::exists(folder + "/vat-page/index.html"));

        QVERIFY(QFile::rename(folder + "/clip/lattice.lattice.glb", folder + "/lattice.lattice.glb"));
        QVERIFY(QFile::link("../lattice.lattice.glb", folder + "/clip/lattice.lattice.glb"));
        run = runCliWithin({"preview", folder + "/clip/lattice.lattice.bin", "--out", folder + "/lattice-page"}, 60);
        QCOMPARE(run.exitCode, 1);
        QVERIFY2(run.err.contains(R"(lattice.lattice.bin: /mesh: "lattice.lattice.glb" leads outside the clip's folder)"),
                 qPrintable(run.err));
        QVERIFY(!QFile::exists(folder + "/lattice-page/index.html"));
    }

    // What the checks above leave alone still plays: data beside the glTF, in a folder below it, in a data:
    // URI or a GLB's own chunk, and the extensions SoftTouch's packed exports require.
    void gltfInItsOwnFolderPlays_data() {
        QTest::addColumn<bool>("binary");
        QTest::addColumn<QString>("pointer");
        QTest::addColumn<QString>("value");
        QTest::newRow("beside it") << false << "/buffers/0/uri" << R"("data.bin")";
        QTest::newRow("in a folder below") << false << "/buffers/0/uri" << R"("sub/data.bin")";
        QTest::newRow("through its folder") << false << "/buffers/0/uri" << R"("sub/../data.bin")";
        QTest::newRow("data URI") << false << "/buffers/0/uri"
                                  << "\"data:application/octet-stream;base64," + QString::fromLatin1(morphClipData().toBase64()) + "\"";
        QTest::newRow("GLB") << true << "/buffers/0/byteLength" << "88";
        QTest::newRow("packed extensions required") << false << "/extensionsRequired"
                                                    << R"(["KHR_mesh_quantization", "EXT_meshopt_compression"])";
    }

    void gltfInItsOwnFolderPlays() {
        QFETCH(bool, binary);
        QFETCH(QString, pointer);
        QFETCH(QString, value);
        const QString folder = hostileFolder() + "/clip";
        nlohmann::json gltf = morphClipGltf();
        gltf[nlohmann::json::json_pointer(pointer.toStdString())] = nlohmann::json::parse(value.toStdString());
        const QString name = binary ? "good.glb" : "good.gltf";
        QVERIFY(writeBytes(folder + "/" + name, binary ? glbOf(gltf, morphClipData()) : QByteArray::fromStdString(gltf.dump())));
        const QString page = folder + "/good-" + QTest::currentDataTag();
        const auto run = runCliWithin({"preview", folder + "/" + name, "--out", page}, 60);
        QVERIFY2(run.exitCode == 0, qPrintable(run.err));
        QVERIFY2(run.out.contains("morph clip " + name + ": 2 frames at 24 fps, 1 morph targets"), qPrintable(run.out));
        QFile html(page + "/index.html");
        QVERIFY(html.open(QIODevice::ReadOnly));
        // The data is in the page (its file's, embedded; or inside the glTF itself).
        const QByteArray text = html.readAll();
        QVERIFY(binary || pointer != "/buffers/0/uri" || value.startsWith("\"data:") ||
                text.contains("\"data.bin\":\"" + morphClipData().toBase64() + "\""));
    }
};

QTEST_GUILESS_MAIN(TestPreview)
#include "test_preview.moc"

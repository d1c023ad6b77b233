// The clip preview page (softtouch-cli preview) played in headless Chromium (SwiftShader's WebGL 2):
// every export kind a game plays (skinned, morph, VAT, lattice cache) is baked from the angelfish's swim
// clip, opened as a page at a frame, read back from the page's canvas, and compared with the project's
// own render of that frame (softtouch-cli render, the same camera).

#include "../cli/cli_run.h"
#include "io/clip_preview.h"

#include <QDir>
#include <QImage>
#include <QJsonDocument>
#include <QJsonObject>
#include <QProcess>
#include <QRegularExpression>
#include <QStandardPaths>
#include <QTemporaryDir>
#include <QtTest>

#include <algorithm>
#include <vector>

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
        for (const int frame : {6, 12}) {
            const QString dom = openPage(folder + "/page/index.html",
                                         QString("frame=%1&size=%2x%3&matte&readback").arg(frame).arg(kWidth).arg(kHeight));
            QVERIFY2(dom.contains("<title>ready</title>"), qPrintable(dom.left(2000)));
            const auto data = QRegularExpression("data:image/png;base64,([A-Za-z0-9+/=]+)").match(dom);
            QVERIFY2(data.hasMatch(), "the page wrote no picture");
            const QImage picture = QImage::fromData(QByteArray::fromBase64(data.captured(1).toLatin1()), "PNG");
            QCOMPARE(picture.size(), QSize(kWidth, kHeight));
            const Mask page = matteMask(picture);
            std::vector<double> overlap;
            for (const Mask& rendered : m_rendered)
                overlap.push_back(intersectionOverUnion(page, rendered));
            const int best = int(std::max_element(overlap.begin(), overlap.end()) - overlap.begin());
            qInfo("%s frame %d: overlap with the render of the same frame %.4f, of frame 0 %.4f; best match frame %d",
                  qPrintable(format), frame, overlap[std::size_t(frame)], overlap[0], best);
            QVERIFY2(overlap[std::size_t(frame)] >= minimumOverlap, qPrintable(QString::number(overlap[std::size_t(frame)])));
            // It is that frame: no other matches better than a neighbour at the swim's turning points,
            // and the rest pose is far off.
            QVERIFY2(std::abs(best - frame) <= 1, qPrintable(QString("best match %1").arg(best)));
            QVERIFY(overlap[0] < overlap[std::size_t(frame)] - 0.1);
        }
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
};

QTEST_GUILESS_MAIN(TestPreview)
#include "test_preview.moc"

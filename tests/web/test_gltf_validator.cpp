// Every GLB kind the exporter writes, judged by the Khronos glTF validator (npm gltf-validator, run in Node
// by validate_gltf.mjs): no errors, and every warning explained in docs/formats.md. A pipeline that gates on
// the validator must accept what SoftTouch ships. Compressed files are judged after expandGlb(): the
// validator cannot decode EXT_meshopt_compression, so it would check nothing inside them.

#include "helpers/cli_run.h"
#include "helpers/gltf_read.h"
#include "io/import/gltf_meshopt.h"

#include <QDir>
#include <QFile>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QProcess>
#include <QStandardPaths>
#include <QTemporaryDir>
#include <QtTest>

#include <algorithm>
#include <fstream>
#include <iterator>

using softtouch::test::accessorFloats;
using softtouch::test::loadGlb;
using softtouch::test::runCli;

namespace {

const QString kSource = QStringLiteral(SOFTTOUCH_SOURCE_DIR);
const QString kNodeModules = kSource + "/web/node_modules";

std::string readBytes(const QString& path) {
    std::ifstream in(path.toStdString(), std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

}  // namespace

class TestGltfValidator : public QObject {
    Q_OBJECT
private slots:
    void everyGlbKindPassesTheValidator_data();
    void everyGlbKindPassesTheValidator();
    void loopClipsCloseOnTheirFirstFrame_data();
    void loopClipsCloseOnTheirFirstFrame();
    void threeJsLoopsThemByLengthWithoutAJump_data();
    void threeJsLoopsThemByLengthWithoutAJump();
};

void TestGltfValidator::everyGlbKindPassesTheValidator_data() {
    QTest::addColumn<QString>("scene");
    QTest::addColumn<QStringList>("bake");      // after "bake SCENE", before "--out"
    QTest::addColumn<QString>("out");           // the --out name
    QTest::addColumn<QString>("glb");           // the GLB to judge
    QTest::addColumn<bool>("compressed");       // judge expandGlb() of it
    const QString fish = "angelfish-swim.softtouch";
    const QStringList swim{"--clip", "swim"};
    QTest::newRow("morph") << fish << (swim + QStringList{"--format", "glb"}) << "swim.glb" << "swim.glb" << false;
    QTest::newRow("pca") << fish << (swim + QStringList{"--format", "pca"}) << "swim.glb" << "swim.glb" << false;
    QTest::newRow("pca, compressed") << fish << (swim + QStringList{"--format", "pca", "--compress"}) << "swim.glb"
                                     << "swim.glb" << true;
    QTest::newRow("skin") << fish << (swim + QStringList{"--format", "skin"}) << "swim.glb" << "swim.glb" << false;
    QTest::newRow("skin, compressed") << fish << (swim + QStringList{"--format", "skin", "--compress"}) << "swim.glb"
                                      << "swim.glb" << true;
    QTest::newRow("skin of the rigged guppy") << "guppy-rigged.softtouch" << QStringList{"--format", "skin"} << "swim.glb"
                                              << "swim.glb" << false;
    QTest::newRow("skin on the rigged guppy's own rig") << "guppy-rigged.softtouch" << (swim + QStringList{"--format", "skin"})
                                                        << "swim.glb" << "swim.glb" << false;
    QTest::newRow("skin on the rigged guppy's own rig, compressed")
        << "guppy-rigged.softtouch" << (swim + QStringList{"--format", "skin", "--compress"}) << "swim.glb" << "swim.glb" << true;
    QTest::newRow("skin of the rigged guppy, fitted bones")
        << "guppy-rigged.softtouch" << (swim + QStringList{"--format", "skin", "--rig", "fitted"}) << "swim.glb" << "swim.glb"
        << false;
    QTest::newRow("vat mesh") << fish << (swim + QStringList{"--format", "vat"}) << "swim" << "swim.vat-mesh.glb" << false;
    QTest::newRow("lattice cache mesh") << fish << (swim + QStringList{"--format", "lattice"}) << "swim"
                                        << "swim.lattice.glb" << false;
}

void TestGltfValidator::everyGlbKindPassesTheValidator() {
    QFETCH(QString, scene);
    QFETCH(QStringList, bake);
    QFETCH(QString, out);
    QFETCH(QString, glb);
    QFETCH(bool, compressed);
    const QString node = QStandardPaths::findExecutable("node");
    if (node.isEmpty() || !QFile::exists(kNodeModules + "/gltf-validator/package.json"))
        QSKIP("glTF validator test skipped: node or web/node_modules/gltf-validator is missing "
              "(scripts/install-deps.sh installs both)");
    QTemporaryDir dir;
    const auto baked = runCli(QStringList{"bake", kSource + "/presets/scenes/" + scene} + bake +
                              QStringList{"--out", dir.filePath(out), "--quiet"});
    QVERIFY2(baked.exitCode == 0, qPrintable(baked.err));
    QString judged = dir.filePath(glb);
    if (compressed) {
        auto expanded = softtouch::io::expandGlb(readBytes(judged), judged.toStdString());
        QVERIFY2(expanded, expanded.message().c_str());
        judged = dir.filePath("expanded.glb");
        std::ofstream(judged.toStdString(), std::ios::binary) << expanded.value();
    }
    QProcess validator;
    validator.start(node, {kSource + "/tests/web/validate_gltf.mjs", kNodeModules, judged});
    QVERIFY(validator.waitForFinished(120000));
    const QByteArray printed = validator.readAllStandardOutput();
    QVERIFY2(validator.exitCode() == 0, validator.readAllStandardError().constData());
    const QJsonObject report = QJsonDocument::fromJson(printed).object();
    QVERIFY2(report.contains("errors"), printed.constData());
    QFile formats(kSource + "/docs/formats.md");
    QVERIFY(formats.open(QIODevice::ReadOnly));
    const QString explained = QString::fromUtf8(formats.readAll());
    for (const QJsonValue& m : report["messages"].toArray()) {
        const QJsonObject message = m.toObject();
        const QString code = message["code"].toString();
        qInfo("%s: %s %s", qPrintable(message["severity"].toString()), qPrintable(code),
              qPrintable(message["pointer"].toString() + " " + message["message"].toString()));
        if (message["severity"].toString() == "warning")
            QVERIFY2(explained.contains("`" + code + "`"), qPrintable(code + " is not explained in docs/formats.md"));
    }
    QCOMPARE(report["errors"].toInt(), 0);
}

void TestGltfValidator::loopClipsCloseOnTheirFirstFrame_data() {
    QTest::addColumn<QString>("format");
    QTest::addColumn<QString>("frames");  // --frames: one cycle, two cycles, or part of one (no closing key)
    QTest::addColumn<int>("keys");
    QTest::newRow("morph, one cycle") << "glb" << "24" << 25;
    QTest::newRow("pca, two cycles") << "pca" << "48" << 49;
    QTest::newRow("skin, one cycle") << "skin" << "24" << 25;
    QTest::newRow("skin, part of a cycle") << "skin" << "12" << 12;
}

// The swim is a 24-frame loop at 24 fps. A player that loops a glTF animation by its length used to go from
// frame 23 (at 23/24 s, the last key) to frame 0 in no time; the export now closes a whole cycle with a key at
// 24/24 s equal to frame 0, and says so in the animation's extras. Part of a cycle gets no such key.
void TestGltfValidator::loopClipsCloseOnTheirFirstFrame() {
    QFETCH(QString, format);
    QFETCH(QString, frames);
    QFETCH(int, keys);
    QTemporaryDir dir;
    const QString out = dir.filePath("swim.glb");
    const auto baked = runCli({"bake", kSource + "/presets/scenes/angelfish-swim.softtouch", "--clip", "swim", "--format",
                               format, "--frames", frames, "--out", out, "--quiet"});
    QVERIFY2(baked.exitCode == 0, qPrintable(baked.err));
    const tinygltf::Model model = loadGlb(out.toStdString());
    QCOMPARE(model.animations.size(), std::size_t(1));
    const tinygltf::Animation& animation = model.animations[0];
    const bool closes = keys > frames.toInt();
    QCOMPARE(animation.extras.Has("loopClosingKey"), closes);
    for (const tinygltf::AnimationSampler& sampler : animation.samplers) {
        const std::vector<float> times = accessorFloats(model, sampler.input);
        QCOMPARE(int(times.size()), keys);
        QVERIFY2(std::abs(double(times.back()) - double(keys - 1) / 24.0) < 1e-6, qPrintable(QString::number(times.back())));
        const std::vector<float> values = accessorFloats(model, sampler.output);
        const std::size_t row = values.size() / times.size();
        if (closes)  // the closing key is frame 0 exactly
            QVERIFY(std::equal(values.end() - std::ptrdiff_t(row), values.end(), values.begin()) ||
                    format == "skin");  // a bone's quaternion may be the other hemisphere's: checked below
    }
    if (closes && format == "skin")  // every bone's closing rotation is frame 0's, up to sign
        for (const tinygltf::AnimationChannel& channel : animation.channels) {
            const std::vector<float> values = accessorFloats(model, animation.samplers[std::size_t(channel.sampler)].output);
            const std::size_t row = channel.target_path == "rotation" ? 4 : 3;
            double dot = 0.0, first = 0.0;
            for (std::size_t c = 0; c < row; ++c) {
                dot += double(values[values.size() - row + c]) * double(values[c]);
                first += double(values[c]) * double(values[c]);
            }
            QVERIFY2(std::abs(std::abs(dot) - first) < 1e-6, qPrintable(QString::fromStdString(channel.target_path)));
        }
}

void TestGltfValidator::threeJsLoopsThemByLengthWithoutAJump_data() {
    QTest::addColumn<QStringList>("bake");
    QTest::newRow("morph") << QStringList{"--format", "glb"};
    QTest::newRow("pca") << QStringList{"--format", "pca"};
    QTest::newRow("skin") << QStringList{"--format", "skin"};
    QTest::newRow("skin, compressed") << QStringList{"--format", "skin", "--compress"};
}

// The swim played by three.js as a game plays it (loop_by_length.mjs: a mixer looping by the clip's length,
// vertices skinned and morphed on the CPU): one cycle is 24 distinct frames and one second, the frame one
// cycle on is the first, and the step across the seam is like the others (the clip's own seam is 0.3x the
// median on its lattice nodes). Before the closing key the length was 23/24 s: 23 frames a cycle, frame 23
// never shown, and the step from frame 22 to frame 0 at the seam.
void TestGltfValidator::threeJsLoopsThemByLengthWithoutAJump() {
    QFETCH(QStringList, bake);
    const QString node = QStandardPaths::findExecutable("node");
    if (node.isEmpty() || !QFile::exists(kNodeModules + "/three/package.json"))
        QSKIP("glTF validator test skipped: node or web/node_modules/three is missing (scripts/install-deps.sh installs both)");
    QTemporaryDir dir;
    const QString out = dir.filePath("swim.glb");
    const auto baked = runCli(QStringList{"bake", kSource + "/presets/scenes/angelfish-swim.softtouch", "--clip", "swim"} + bake +
                              QStringList{"--out", out, "--quiet"});
    QVERIFY2(baked.exitCode == 0, qPrintable(baked.err));
    QProcess player;
    player.start(node, {kSource + "/tests/web/loop_by_length.mjs", kNodeModules, out, "24"});
    QVERIFY(player.waitForFinished(120000));
    const QByteArray printed = player.readAllStandardOutput();
    QVERIFY2(player.exitCode() == 0, player.readAllStandardError().constData());
    const QJsonObject played = QJsonDocument::fromJson(printed).object();
    std::vector<double> steps;
    for (const QJsonValue& v : played["steps"].toArray())
        steps.push_back(v.toDouble());
    QCOMPARE(played["frames"].toInt(), 24);
    QVERIFY2(std::abs(played["duration"].toDouble() - 1.0) < 1e-6, printed.constData());
    QCOMPARE(int(steps.size()), 48);
    std::vector<double> sorted = steps;
    std::sort(sorted.begin(), sorted.end());
    const double median = sorted[sorted.size() / 2];
    const double seam = steps[23];  // frame 23 to frame 24, which is frame 0 again
    qInfo("one cycle: %d frames in %.4f s; step across the seam %.3g m, median step %.3g m, smallest %.3g m; frame 24 is "
          "frame 0 within %.3g m",
          played["frames"].toInt(), played["duration"].toDouble(), seam, median, sorted.front(), played["cycle"].toDouble());
    QVERIFY2(sorted.front() > 0.0, "two frames in a row are the same frame");
    QVERIFY2(seam <= 1.5 * median, qPrintable(QString("seam %1 against median %2").arg(seam).arg(median)));
    QVERIFY2(played["cycle"].toDouble() < 1e-5, printed.constData());
}

QTEST_GUILESS_MAIN(TestGltfValidator)
#include "test_gltf_validator.moc"

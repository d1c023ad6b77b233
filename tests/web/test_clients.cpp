// Every animated GLB kind played by the clients a game team uses, against the PC2 of the same bake: Blender
// 3.4's own glTF importer (play_in_blender.py, headless) and three.js as a game plays it (play_in_threejs.mjs,
// in Node). Each plays the clip the bake wrote, frame by frame, and its error over every vertex and frame must
// be the error the bake printed: the exporter's claim is checked against what a user's player shows. Packed
// files (EXT_meshopt_compression) play in three.js; Blender 3.4 refuses them, saying so (docs/formats.md).

#include "helpers/cli_run.h"

#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QProcess>
#include <QRegularExpression>
#include <QStandardPaths>
#include <QTemporaryDir>
#include <QtTest>

using softtouch::test::runCli;

namespace {

const QString kSource = QStringLiteral(SOFTTOUCH_SOURCE_DIR);
const QString kNodeModules = kSource + "/web/node_modules";

/// The error a bake printed for its export: "RMS error X, worst vertex error Y" (skin) or "worst frame RMS error
/// X, worst vertex error Y" (pca), fractions of the diagonal; none (0, 0) for a format that stores every frame.
std::pair<double, double> printedError(const QString& out) {
    const QRegularExpression claim("RMS error ([0-9.e+-]+), worst vertex error ([0-9.e+-]+) of the diagonal");
    const QRegularExpressionMatch m = claim.match(out);
    return m.hasMatch() ? std::pair{m.captured(1).toDouble(), m.captured(2).toDouble()} : std::pair{0.0, 0.0};
}

QJsonObject play(const QString& program, const QStringList& args) {
    QProcess player;
    player.start(program, args);
    if (!player.waitForFinished(300000))
        return {{"error", program + " did not finish"}};
    const QByteArray printed = player.readAllStandardOutput();
    for (const QByteArray& line : printed.split('\n'))
        if (line.startsWith('{'))
            return QJsonDocument::fromJson(line).object();
    return {{"error", QString::fromUtf8(printed.right(400) + player.readAllStandardError().right(400))}};
}

}  // namespace

class TestClients : public QObject {
    Q_OBJECT
private slots:
    void everyGlbKindPlaysAsTheBakeSays_data();
    void everyGlbKindPlaysAsTheBakeSays();
    void theRiggedGuppyKeepsItsSkeletonInBlender();
};

void TestClients::everyGlbKindPlaysAsTheBakeSays_data() {
    QTest::addColumn<QString>("scene");
    QTest::addColumn<QStringList>("bake");  // after "bake SCENE", before "--out"
    const QStringList swim{"--clip", "swim"};
    QTest::newRow("morph") << "angelfish-swim" << (swim + QStringList{"--format", "glb"});
    QTest::newRow("pca") << "angelfish-swim" << (swim + QStringList{"--format", "pca"});
    QTest::newRow("pca, compressed") << "angelfish-swim" << (swim + QStringList{"--format", "pca", "--compress"});
    QTest::newRow("skin") << "angelfish-swim" << (swim + QStringList{"--format", "skin"});
    QTest::newRow("skin, compressed") << "angelfish-swim" << (swim + QStringList{"--format", "skin", "--compress"});
    QTest::newRow("skin of the rigged guppy") << "guppy-rigged" << QStringList{"--format", "skin"};
    QTest::newRow("skin on the rigged guppy's own rig") << "guppy-rigged" << (swim + QStringList{"--format", "skin"});
    QTest::newRow("skin of the rigged guppy, fitted bones")
        << "guppy-rigged" << (swim + QStringList{"--format", "skin", "--rig", "fitted"});
}

void TestClients::everyGlbKindPlaysAsTheBakeSays() {
    QFETCH(QString, scene);
    QFETCH(QStringList, bake);
    const QString node = QStandardPaths::findExecutable("node");
    const QString blender = QStandardPaths::findExecutable("blender");
    if (node.isEmpty() || !QFile::exists(kNodeModules + "/three/package.json") || blender.isEmpty())
        QSKIP("client test skipped: node, web/node_modules/three or blender is missing (scripts/install-deps.sh "
              "installs them)");
    QTemporaryDir dir;
    const QString project = kSource + "/presets/scenes/" + scene + ".softtouch";
    const QStringList common = bake.mid(0, bake.indexOf("--format"));
    const auto cache = runCli(QStringList{"bake", project} + common + QStringList{"--out", dir.filePath("c.pc2"), "--quiet"});
    QVERIFY2(cache.exitCode == 0, qPrintable(cache.err));
    const auto baked = runCli(QStringList{"bake", project} + bake + QStringList{"--out", dir.filePath("c.glb")});
    QVERIFY2(baked.exitCode == 0, qPrintable(baked.err));
    const auto [rms, worst] = printedError(baked.out);
    const bool exact = bake.contains("glb");
    QVERIFY2(exact || rms > 0.0, qPrintable(baked.out));  // a fitted format says what it lost
    const QString fps = "24";
    const QStringList files{dir.filePath("c.glb"), dir.filePath("c.pc2"), dir.filePath("c.obj"), fps};

    const QJsonObject three = play(node, QStringList{kSource + "/tests/web/play_in_threejs.mjs", kNodeModules} + files);
    const QJsonObject inBlender = play(blender, QStringList{"-b", "--factory-startup", "--python",
                                                            kSource + "/tests/web/play_in_blender.py", "--"} + files);
    qInfo("printed by the bake: RMS %.3g, worst %.3g; three.js: RMS %.3g, worst %.3g; Blender: %s", rms, worst,
          three["rms"].toDouble(), three["worst"].toDouble(),
          inBlender["imported"].toBool() ? qPrintable(QString("RMS %1, worst %2").arg(inBlender["rms"].toDouble(), 0, 'g', 3)
                                                          .arg(inBlender["worst"].toDouble(), 0, 'g', 3))
                                         : qPrintable("not imported: " + inBlender["error"].toString()));
    auto check = [&, printedRms = rms, printedWorst = worst](const QJsonObject& played, bool byBlender) {
        if (byBlender && bake.contains("--compress")) {
            // Blender 3.4's importer has no EXT_meshopt_compression: it says so, which docs/formats.md tells users.
            QVERIFY2(!played["imported"].toBool() && played["error"].toString().contains("EXT_meshopt_compression"),
                     qPrintable(QJsonDocument(played).toJson()));
            return;
        }
        QVERIFY2(!played.contains("error") && played["frames"].toInt() > 1, qPrintable(QJsonDocument(played).toJson()));
        const double playedRms = played["rms"].toDouble(), playedWorst = played["worst"].toDouble();
        if (exact) {  // one morph target a frame, float32
            QVERIFY2(playedRms < 1e-7 && playedWorst < 1e-6, qPrintable(QJsonDocument(played).toJson()));
            return;
        }
        // skin: the RMS over every frame, as printed; pca: the worst frame's RMS bounds the whole clip's. The worst
        // vertex, as printed (float32 in the file and in the player: 1e-6 of the diagonal).
        if (bake.contains("skin"))
            QVERIFY2(std::abs(playedRms - printedRms) <= 0.01 * printedRms + 1e-6,
                     qPrintable(QString("RMS %1 played, %2 printed").arg(playedRms).arg(printedRms)));
        else
            QVERIFY2(playedRms <= printedRms + 1e-6, qPrintable(QString("RMS %1 played, worst frame %2 printed").arg(playedRms).arg(printedRms)));
        // The bake prints three significant digits: the played worst may be above the printed one by its rounding.
        QVERIFY2(playedWorst <= 1.005 * printedWorst + 1e-6, qPrintable(QString("worst %1 played, %2 printed").arg(playedWorst).arg(printedWorst)));
    };
    check(three, false);
    if (QTest::currentTestFailed())
        return;
    check(inBlender, true);
    if (QTest::currentTestFailed())
        return;
    if (inBlender["imported"].toBool())  // the two players agree
        QVERIFY2(std::abs(inBlender["rms"].toDouble() - three["rms"].toDouble()) < 1e-6, "Blender and three.js differ");
}

// The rigged guppy's swim exported onto its own rig, as Blender 3.4 imports it (rig_in_blender.py): every source
// joint is there under its own name and parent, its rest matrix is the source file's, and at every frame its world
// matrix is the source's at the take time the bake played, within 1e-6 (translations over the diagonal); the
// helper bones hang under source joints. The clip's own error against the PC2 is checked by the rows above.
void TestClients::theRiggedGuppyKeepsItsSkeletonInBlender() {
    const QString blender = QStandardPaths::findExecutable("blender");
    if (blender.isEmpty())
        QSKIP("client test skipped: blender is missing (scripts/install-deps.sh installs it)");
    QTemporaryDir dir;
    const QString project = kSource + "/presets/scenes/guppy-rigged.softtouch";
    const auto cache = runCli({"bake", project, "--clip", "swim", "--out", dir.filePath("c.pc2"), "--quiet"});
    QVERIFY2(cache.exitCode == 0, qPrintable(cache.err));
    const auto baked = runCli({"bake", project, "--clip", "swim", "--format", "skin", "--out", dir.filePath("c.glb")});
    QVERIFY2(baked.exitCode == 0, qPrintable(baked.err));
    // Where the clip sits in the take: the clip's start and rate from the project, the take's span from the import.
    QFile file(project);
    QVERIFY(file.open(QIODevice::ReadOnly));
    const QJsonObject clip = QJsonDocument::fromJson(file.readAll()).object()["clips"].toObject()["library"].toArray()[0].toObject();
    const QRegularExpressionMatch take = QRegularExpression("from ([0-9.]+) s for ([0-9.]+) s").match(baked.out);
    QVERIFY2(take.hasMatch(), qPrintable(baked.out));
    const QStringList args{"-b", "--factory-startup", "--python", kSource + "/tests/web/rig_in_blender.py", "--",
                           kSource + "/presets/meshes/guppy-rigged.glb", dir.filePath("c.glb"), dir.filePath("c.obj"),
                           QString::number(clip["fps"].toDouble()), QString::number(clip["frames"].toInt()),
                           QString::number(clip["start"].toDouble(), 'g', 17), take.captured(1), take.captured(2)};
    const QJsonObject seen = play(blender, args);
    qInfo("%s", QJsonDocument(seen).toJson(QJsonDocument::Compact).constData());
    QVERIFY2(!seen.contains("error"), qPrintable(seen["error"].toString()));
    QCOMPARE(seen["joints"].toInt(), 6);
    QVERIFY2(seen["missing"].toArray().isEmpty() && seen["reparented"].toArray().isEmpty(),
             QJsonDocument(seen).toJson().constData());
    QVERIFY2(seen["rest"].toDouble() < 1e-6, "a joint's rest (bind) matrix differs from the source file's");
    QVERIFY2(seen["animation"].toDouble() < 1e-6, "a joint's world matrix differs from the source file's");
    const QJsonObject helpers = seen["helpers"].toObject();
    QVERIFY(helpers.size() <= 16);
    for (const QString& helper : helpers.keys())
        QVERIFY2(helper.startsWith(helpers[helper].toString() + "_wobble_"), qPrintable(helper));
}

QTEST_GUILESS_MAIN(TestClients)
#include "test_clients.moc"

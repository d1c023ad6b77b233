// Every GLB kind the exporter writes, judged by the Khronos glTF validator (npm gltf-validator, run in Node
// by validate_gltf.mjs): no errors, and every warning explained in docs/formats.md. A pipeline that gates on
// the validator must accept what SoftTouch ships. Compressed files are judged after expandGlb(): the
// validator cannot decode EXT_meshopt_compression, so it would check nothing inside them.

#include "../cli/cli_run.h"
#include "io/gltf_meshopt.h"

#include <QDir>
#include <QFile>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QProcess>
#include <QStandardPaths>
#include <QTemporaryDir>
#include <QtTest>

#include <fstream>
#include <iterator>

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
};

void TestGltfValidator::everyGlbKindPassesTheValidator_data() {
    QTest::addColumn<QString>("scene");
    QTest::addColumn<QStringList>("bake");      // after "bake SCENE", before "--out"
    QTest::addColumn<QString>("out");           // the --out name
    QTest::addColumn<QString>("glb");           // the GLB to judge
    QTest::addColumn<bool>("compressed");       // judge expandGlb() of it
    const QString fish = "angelfish-swim.softtouch";
    const QStringList swim{"--clip", "swim"};
    QTest::newRow("morph") << fish << (swim + QStringList{"--format", "gltf"}) << "swim.glb" << "swim.glb" << false;
    QTest::newRow("pca") << fish << (swim + QStringList{"--format", "pca"}) << "swim.glb" << "swim.glb" << false;
    QTest::newRow("pca, compressed") << fish << (swim + QStringList{"--format", "pca", "--compress"}) << "swim.glb"
                                     << "swim.glb" << true;
    QTest::newRow("skin") << fish << (swim + QStringList{"--format", "skin"}) << "swim.glb" << "swim.glb" << false;
    QTest::newRow("skin, compressed") << fish << (swim + QStringList{"--format", "skin", "--compress"}) << "swim.glb"
                                      << "swim.glb" << true;
    QTest::newRow("skin of the rigged guppy") << "guppy-rigged.softtouch" << QStringList{"--format", "skin"} << "swim.glb"
                                              << "swim.glb" << false;
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

QTEST_GUILESS_MAIN(TestGltfValidator)
#include "test_gltf_validator.moc"

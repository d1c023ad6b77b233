// The Blender add-on (blender/addons/softtouch_wobble) driven headless in Debian's Blender 3.4 as a user drives it, on the
// rigged guppy imported from presets/meshes/guppy-rigged.glb (addon_checks.py): it registers and its settings
// live in the .blend; Bake wobble plays, through a Mesh Cache modifier after the armature, exactly what
// softtouch-cli bakes of the project it wrote, on a rig turned, scaled and moving through the scene; a goal of 1 is the
// rig's own motion; the action's keys are never touched; a bad preset is one error line and leaves the previous
// bake as it was; a cancelled bake leaves no modifier and no files.

#include <QDir>
#include <QFile>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QProcess>
#include <QStandardPaths>
#include <QTemporaryDir>
#include <QtTest>

namespace {

const QString kSource = QStringLiteral(SOFTTOUCH_SOURCE_DIR);

/// One check of addon_checks.py in a fresh Blender, with the source tree's blender/ as its scripts folder (its
/// addons/softtouch_wobble, as a user of a checkout sets it up) and the build's softtouch-cli; what it found, or
/// {"error": ...}.
QJsonObject runCheck(const QString& check, const QTemporaryDir& work, const QString& cli = SOFTTOUCH_BIN_DIR "/softtouch-cli") {
    const QString blender = QStandardPaths::findExecutable("blender");
    QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
    env.insert("BLENDER_USER_SCRIPTS", kSource + "/blender");  // as docs/blender.md has a source checkout do it
    env.insert("SOFTTOUCH_CLI", cli);
    env.insert("XDG_DATA_HOME", work.filePath("data"));  // the user's presets, empty but for what a check writes
    env.insert("HOME", work.path());
    QProcess process;
    process.setProcessEnvironment(env);
    process.start(blender, {"-b", "--factory-startup", "--python", kSource + "/tests/blender/addon_checks.py", "--", check,
                            work.path()});
    if (!process.waitForFinished(300000))
        return {{"error", "blender did not finish"}};
    const QByteArray printed = process.readAllStandardOutput();
    for (const QByteArray& line : printed.split('\n'))
        if (line.startsWith('{'))
            return QJsonDocument::fromJson(line).object();
    return {{"error", QString::fromUtf8(printed.right(1500) + process.readAllStandardError().right(1500))}};
}

QStringList strings(const QJsonValue& v) {
    QStringList out;
    for (const QJsonValue& x : v.toArray())
        out << (x.isArray() ? x.toArray()[0].toString() + "/" + x.toArray()[1].toString() : x.toString());
    return out;
}

}  // namespace

class TestBlenderAddon : public QObject {
    Q_OBJECT
private slots:
    void init() {
        if (QStandardPaths::findExecutable("blender").isEmpty())
            QSKIP("Blender add-on test skipped: blender is missing (scripts/install-deps.sh installs it)");
    }
    void registersAndKeepsItsSettingsInTheBlend();
    void bakeIsTheCliBakeOfTheWrittenProject();
    void goalOfOneIsTheRigsOwnMotion();
    void reloadBakesTheProjectAsTheEditorSavedIt();
    void loopPlaysAsACycleOnEveryFrame();
    void shapeKeysAloneAreTheMotionItWobblesOn();
    void openInSoftTouchStartsTheEditorOnTheProject();
    void badPresetIsOneErrorAndChangesNothing();
    void cancelLeavesNothing();
};

void TestBlenderAddon::registersAndKeepsItsSettingsInTheBlend() {
    QTemporaryDir work;
    const QJsonObject found = runCheck("register", work);
    QVERIFY2(!found.contains("error"), qPrintable(found["error"].toString()));
    QCOMPARE(found["module"].toString(), QString("softtouch_wobble"));
    QVERIFY(found["panel"].toBool());
    QCOMPARE(strings(found["operators"]), (QStringList{"bake_wobble", "reload", "open_in_softtouch"}));
    QCOMPARE(found["blender"].toArray()[0].toInt(), 3);  // says which Blender it supports
    // Set, saved, changed, reopened: the reopened file has what was saved.
    const QJsonArray reopened = found["reopened"].toArray();
    QCOMPARE(reopened[0].toString(), QString("jelly"));
    QCOMPARE(reopened[1].toArray(), (QJsonArray{6, 4, 3}));
    QCOMPARE(reopened[2].toString(), QString("implicit-euler"));
    QCOMPARE(reopened[3].toInt(), 480);
    QCOMPARE(reopened[4].toString(), QString("tail"));
    QVERIFY(reopened[5].toBool());
}

void TestBlenderAddon::bakeIsTheCliBakeOfTheWrittenProject() {
    QTemporaryDir work;
    const QJsonObject found = runCheck("bake", work);
    QVERIFY2(!found.contains("error") && !found.contains("errors"), qPrintable(QJsonDocument(found).toJson()));
    qInfo("guppy, goal ramp from tail (0) to head (1), rig turned, scaled and moving: %d frames baked; at frames "
          "0, 5, 11, 17, 23 the modifier's mesh is %.3g of the diagonal from softtouch-cli's bake of the written project; "
          "the wobble moves it up to %.3g of the diagonal from the armature's",
          found["cacheFrames"].toInt(), found["worst"].toDouble(), found["wobble"].toDouble());
    QCOMPARE(strings(found["modifiers"]), (QStringList{"Armature/ARMATURE", "SoftTouch wobble/MESH_CACHE"}));
    QCOMPARE(found["cacheFrames"].toInt(), 24);
    QVERIFY(found["matchedBy"].toDouble() <= 1e-6);  // the test's own vertex matching found every vertex
    QVERIFY(found["worst"].toDouble() <= 1e-6);
    QVERIFY(found["wobble"].toDouble() >= 0.005);  // there is a wobble to see
    QVERIFY(found["keysUnchanged"].toBool());
}

void TestBlenderAddon::goalOfOneIsTheRigsOwnMotion() {
    QTemporaryDir work;
    const QJsonObject found = runCheck("pinned", work);
    QVERIFY2(!found.contains("error") && !found.contains("errors"), qPrintable(QJsonDocument(found).toJson()));
    qInfo("goal group at 1 everywhere: the modifier's mesh is %.3g of the diagonal from the armature's own at 5 frames",
          found["worst"].toDouble());
    QCOMPARE(strings(found["modifiers"]), (QStringList{"Armature/ARMATURE", "SoftTouch wobble/MESH_CACHE"}));
    QVERIFY(found["worst"].toDouble() <= 1e-6);
    QVERIFY(found["keysUnchanged"].toBool());
}

void TestBlenderAddon::reloadBakesTheProjectAsTheEditorSavedIt() {
    QTemporaryDir work;
    const QJsonObject found = runCheck("reload", work);
    QVERIFY2(!found.contains("error") && !found.contains("errors"), qPrintable(QJsonDocument(found).toJson()));
    qInfo("project edited as the editor saves it (node goal weights, jelly, a 5x4x4 lattice), reloaded: the modifier's "
          "mesh is %.3g of the diagonal from softtouch-cli's bake of it", found["worst"].toDouble());
    QVERIFY(found["projectKept"].toBool());  // Reload bakes the saved project; it does not write its own over it
    QCOMPARE(strings(found["modifiers"]), (QStringList{"Armature/ARMATURE", "SoftTouch wobble/MESH_CACHE"}));
    QVERIFY(found["matchedBy"].toDouble() <= 1e-6);
    QVERIFY(found["worst"].toDouble() <= 1e-6);
    QVERIFY(found["keysUnchanged"].toBool());
}

void TestBlenderAddon::loopPlaysAsACycleOnEveryFrame() {
    // The guppy's one-second swim baked as a loop over frames 0-23: a frame a cycle before, after or two after
    // is the same pose, the wobble included; the driver that cycles it is a simple expression, which Blender runs
    // with scripts untrusted (as here). A one-shot bake after it takes the cycle away.
    QTemporaryDir work;
    const QJsonObject found = runCheck("cycle", work);
    QVERIFY2(!found.contains("error") && !found.contains("errors"), qPrintable(QJsonDocument(found).toJson()));
    QVERIFY(!found["autoExec"].toBool());
    const QJsonArray drivers = found["drivers"].toArray();
    QCOMPARE(drivers.size(), 1);
    QCOMPARE(drivers[0].toArray()[0].toString(), QString("modifiers[\"SoftTouch wobble\"].eval_frame"));
    QVERIFY(drivers[0].toArray()[1].toBool());  // simple expression
    QVERIFY(drivers[0].toArray()[2].toBool());  // valid
    QVERIFY2(found["worst"].toDouble() <= 1e-6, qPrintable(QString::number(found["worst"].toDouble())));
    QVERIFY(found["wobbleAfter"].toDouble() >= 0.005);  // past the range the wobble still plays
    QCOMPARE(found["driversAfterOneShot"].toInt(), 0);
    QCOMPARE(found["playModeAfterOneShot"].toString(), QString("SCENE"));
}

void TestBlenderAddon::shapeKeysAloneAreTheMotionItWobblesOn() {
    // A body with no armature, bent by one animated shape key: the bake follows the bend (its wobble is a small
    // part of it, not the whole bend missing) and is the CLI's bake of the written project.
    QTemporaryDir work;
    const QJsonObject found = runCheck("shapekeys", work);
    QVERIFY2(!found.contains("error") && !found.contains("errors"), qPrintable(QJsonDocument(found).toJson()));
    QCOMPARE(strings(found["modifiers"]), QStringList{"SoftTouch wobble/MESH_CACHE"});
    QCOMPARE(found["cacheFrames"].toInt(), 24);
    QVERIFY(found["matchedBy"].toDouble() <= 1e-6);
    QVERIFY(found["worst"].toDouble() <= 1e-6);
    const double bend = found["bend"].toDouble(), wobble = found["wobble"].toDouble();
    QVERIFY2(bend >= 0.1, qPrintable(QString::number(bend)));  // the key moves the body
    QVERIFY2(wobble >= 0.005 && wobble <= 0.25 * bend, qPrintable(QString("wobble %1, bend %2").arg(wobble).arg(bend)));
    QVERIFY(found["keysUnchanged"].toBool());
}

void TestBlenderAddon::openInSoftTouchStartsTheEditorOnTheProject() {
    QTemporaryDir work;
    // The editor beside softtouch-cli is a stand-in that writes down its arguments; the program is the real one.
    const QString bin = work.filePath("bin");
    QDir().mkpath(bin);
    QVERIFY(QFile::link(QStringLiteral(SOFTTOUCH_BIN_DIR "/softtouch-cli"), bin + "/softtouch-cli"));
    QFile editor(bin + "/softtouch");
    QVERIFY(editor.open(QIODevice::WriteOnly));
    editor.write(QString("#!/bin/sh\necho \"$@\" > '%1'\n").arg(work.filePath("editor-started-with")).toUtf8());
    editor.close();
    QVERIFY(editor.setPermissions(editor.permissions() | QFileDevice::ExeOwner));
    const QJsonObject found = runCheck("open", work, bin + "/softtouch-cli");
    QVERIFY2(!found.contains("error"), qPrintable(found["error"].toString()));
    QCOMPARE(found["startedWith"].toString(), found["project"].toString());
    QCOMPARE(strings(found["files"]), (QStringList{"guppy.glb", "guppy.softtouch"}));
    QVERIFY2(found["validated"].toBool(), qPrintable(found["validation"].toString()));
    QCOMPARE(strings(found["modifiers"]), QStringList{"Armature"});  // nothing baked yet
}

void TestBlenderAddon::badPresetIsOneErrorAndChangesNothing() {
    QTemporaryDir work;
    const QJsonObject found = runCheck("bad-preset", work);
    QVERIFY2(!found.contains("error"), qPrintable(found["error"].toString()));
    QVERIFY2(found["firstErrors"].toArray().isEmpty(), qPrintable(QJsonDocument(found).toJson()));
    const QStringList errors = strings(found["errors"]);
    QCOMPARE(errors.size(), 1);
    QVERIFY2(errors[0].contains("broken.stpreset") && errors[0].contains("/objects/0/material/preset"), qPrintable(errors[0]));
    QVERIFY(!errors[0].contains(".softtouch-bake-"));  // no staging path: the message starts at the field
    QVERIFY(found["unchanged"].toBool());
    QCOMPARE(strings(found["files"]), (QStringList{"guppy.glb", "guppy.pc2", "guppy.softtouch"}));
}

void TestBlenderAddon::cancelLeavesNothing() {
    QTemporaryDir work;
    const QJsonObject found = runCheck("cancel", work);
    QVERIFY2(!found.contains("error"), qPrintable(found["error"].toString()));
    QCOMPARE(found["state"].toString(), QString("running"));  // cancelled halfway, not after the end
    QCOMPARE(strings(found["staged"]), (QStringList{"guppy.glb", "guppy.softtouch"}));
    QVERIFY(found["exited"].toBool());
    QCOMPARE(strings(found["modifiers"]), QStringList{"Armature"});
    QVERIFY(!found["folderLeft"].toBool());
}

QTEST_GUILESS_MAIN(TestBlenderAddon)
#include "test_blender_addon.moc"

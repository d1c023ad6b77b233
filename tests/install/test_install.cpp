// The installed build works on its own, installed both ways a studio would: `cmake --install` into a fresh
// folder, and the Debian package (cpack) unpacked into a clean one. Then the CLI validates and bakes the
// installed presets, finds the installed device plugins, builds the installed batch manifest's library,
// starts softtouch-bench for a measurement, and the editor opens its installed default scene (a
// screenshot) — nothing read from the source or build tree.
#include <QDir>
#include <QDirIterator>
#include <QFileInfo>
#include <QFile>
#include <QImage>
#include <QProcess>
#include <QStandardPaths>
#include <QTemporaryDir>
#include <QtTest>

namespace {

struct Output {
    int exitCode = -1;
    QString text;
};

/// Runs a program with the environment cleared of SoftTouch's own variables; stdout and stderr together.
Output run(const QString& program, const QStringList& args, const QString& workingDirectory, int timeoutMs = 300000) {
    QProcess p;
    QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
    env.remove("SOFTTOUCH_PLUGIN_PATH");
    p.setProcessEnvironment(env);
    p.setWorkingDirectory(workingDirectory);
    p.setProcessChannelMode(QProcess::MergedChannels);
    p.start(program, args);
    if (!p.waitForFinished(timeoutMs)) {
        p.kill();
        p.waitForFinished();
        return {-1, program + " did not finish"};
    }
    return {p.exitStatus() == QProcess::NormalExit ? p.exitCode() : -1, QString::fromUtf8(p.readAll())};
}

}  // namespace

class TestInstall : public QObject {
    Q_OBJECT
private slots:
    void installedBuildRunsOnItsOwn_data();
    void installedBuildRunsOnItsOwn();
};

void TestInstall::installedBuildRunsOnItsOwn_data() {
    QTest::addColumn<bool>("package");
    QTest::newRow("cmake --install") << false;
    QTest::newRow("Debian package") << true;
}

void TestInstall::installedBuildRunsOnItsOwn() {
    QFETCH(bool, package);
    QTemporaryDir dir;
    QString prefix = dir.filePath("softtouch");
    if (!package) {
        const Output installed = run(QStringLiteral(SOFTTOUCH_CMAKE), {"--install", QStringLiteral(SOFTTOUCH_BUILD_DIR), "--prefix", prefix},
                                     dir.path());
        QVERIFY2(installed.exitCode == 0, qPrintable(installed.text));
    } else {
        // The .deb as CPack makes it (cmake/SoftTouchPackage.cmake), unpacked into a clean folder: its /usr is the prefix.
        const Output packed = run(QStringLiteral(SOFTTOUCH_CPACK), {"--config", QStringLiteral(SOFTTOUCH_BUILD_DIR "/CPackConfig.cmake"), "-B",
                                                                    dir.filePath("package")},
                                  dir.path());
        QVERIFY2(packed.exitCode == 0, qPrintable(packed.text));
        const QStringList debs = QDir(dir.filePath("package")).entryList({"softtouch_*.deb"}, QDir::Files);
        QVERIFY2(debs.size() == 1, qPrintable(packed.text));
        const QString deb = dir.filePath("package/" + debs.front());
        const Output unpacked = run("dpkg-deb", {"-x", deb, dir.filePath("root")}, dir.path());
        QVERIFY2(unpacked.exitCode == 0, qPrintable(unpacked.text));
        prefix = dir.filePath("root/usr");
        // Its Depends come from the binaries (dpkg-shlibdeps) and name packages that exist: every one is
        // installed on this machine, which built and runs it.
        const Output depends = run("dpkg-deb", {"--field", deb, "Depends"}, dir.path());
        QVERIFY2(depends.exitCode == 0 && depends.text.contains("libqt6gui6") && depends.text.contains("libassimp5"),
                 qPrintable(depends.text));
        for (const QString& clause : depends.text.trimmed().split(',')) {
            const QString name = clause.trimmed().section(' ', 0, 0).section('|', 0, 0).trimmed();
            const Output known = run("dpkg-query", {"-W", "-f=${Status}", name}, dir.path());
            QVERIFY2(known.text.contains("install ok installed"), qPrintable(name + ": " + known.text));
        }
    }
    const QString cli = prefix + "/bin/softtouch-cli", share = prefix + "/share/softtouch";
    QVERIFY(QFile::exists(cli) && QFile::exists(prefix + "/bin/softtouch") && QFile::exists(prefix + "/bin/softtouch-bench"));
    QVERIFY(QFile::exists(share + "/shaders/lattice_deform.glsl"));
    // The user's docs, and only those: the design and the measurements stay in the source tree.
    const QString docs = prefix + "/share/doc/softtouch/docs";
    for (const char* page : {"user-guide.md", "formats.md", "project-format.md", "farm.md"})
        QVERIFY2(QFile::exists(docs + "/" + page), page);
    QVERIFY(!QFileInfo::exists(docs + "/design") && !QFileInfo::exists(docs + "/measurements"));
    // A working folder outside both trees.
    QDir(dir.path()).mkdir("work");
    const QString work = dir.filePath("work");

    const QStringList scenes = QDir(share + "/presets/scenes").entryList({"*.softtouch"}, QDir::Files);
    QVERIFY(scenes.size() >= 5);
    for (const QString& scene : scenes) {
        const Output validated = run(cli, {"validate", share + "/presets/scenes/" + scene}, work);
        QVERIFY2(validated.exitCode == 0, qPrintable(scene + ": " + validated.text));
    }
    const Output baked = run(cli, {"bake", share + "/presets/scenes/guppy-swim.softtouch", "--out", "guppy.pc2", "--frames", "4", "--quiet"}, work);
    QVERIFY2(baked.exitCode == 0 && QFile::exists(work + "/guppy.pc2"), qPrintable(baked.text));
    const Output haptic = run(cli, {"haptic", share + "/presets/scenes/star-drag.softtouch", "--device", "scripted", "--device-arg",
                                    share + "/presets/devices/figure-eight.sttraj", "--manual", "--seconds", "0.05"},
                              work);
    QVERIFY2(haptic.exitCode == 0 && haptic.text.contains("plugin scripted"), qPrintable(haptic.text));
    const Output batch = run(cli, {"batch", "run", share + "/presets/batch/fish-library.stbatch", "--library", "library", "--jobs", "2"}, work);
    QVERIFY2(batch.exitCode == 0 && batch.text.contains("8 jobs: 8 ran"), qPrintable(batch.text));
    // A measurement: softtouch-cli starts the installed softtouch-bench beside it.
    const Output modes = run(cli, {"modes", share + "/presets/scenes/guppy-swim.softtouch", "--count", "1"}, work);
    QVERIFY2(modes.exitCode == 0 && modes.text.contains("Hz"), qPrintable(modes.text));
    // The preview page from the installed player, three.js modules and shaders.
    QVERIFY(QFile::exists(share + "/web/preview.js") && QFile::exists(share + "/web/node_modules/three/build/three.module.js"));
    // Only the modules the page embeds (the whole three.js package was 572 files, 10 MB), and Debian's copyright
    // file with three.js's licence beside SoftTouch's terms.
    int threeFiles = 0;
    for (QDirIterator it(share + "/web/node_modules/three", QDir::Files, QDirIterator::Subdirectories); it.hasNext(); it.next())
        ++threeFiles;
    QVERIFY2(threeFiles <= 12, qPrintable(QString::number(threeFiles)));
    QFile copyright(prefix + "/share/doc/softtouch/copyright");
    QVERIFY(copyright.open(QIODevice::ReadOnly));
    const QString terms = QString::fromUtf8(copyright.readAll());
    QVERIFY2(terms.contains("Files: usr/share/softtouch/web/node_modules/three/*") && terms.contains("License: MIT") &&
                 terms.contains(" Permission is hereby granted"),
             qPrintable(terms));
    const Output lattice = run(cli, {"bake", share + "/presets/scenes/guppy-swim.softtouch", "--out", "guppy", "--format", "lattice",
                                     "--frames", "4", "--quiet"},
                               work);
    QVERIFY2(lattice.exitCode == 0, qPrintable(lattice.text));
    const Output preview = run(cli, {"preview", "guppy.lattice.bin", "--out", "page"}, work);
    QVERIFY2(preview.exitCode == 0 && preview.text.contains("lattice clip guppy.lattice.bin: 4 frames") &&
                 QFile::exists(work + "/page/index.html"),
             qPrintable(preview.text));

    // The Blender add-on where Blender finds it, running the programs of its own install (blender, when present).
    const QString addon = prefix + "/share/blender/scripts/addons/softtouch_wobble";
    QVERIFY(QFile::exists(addon + "/__init__.py") && QFile::exists(addon + "/bake.py"));
    if (const QString blender = QStandardPaths::findExecutable("blender"); !blender.isEmpty()) {
        QProcess process;
        QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
        env.insert("BLENDER_USER_SCRIPTS", prefix + "/share/blender/scripts");
        env.remove("SOFTTOUCH_CLI");
        process.setProcessEnvironment(env);
        process.start(blender, {"-b", "--factory-startup", "--python-expr",
                                "import addon_utils; m = addon_utils.enable('softtouch_wobble', default_set=True); "
                                "from softtouch_wobble import programs; print('runs', programs.find_cli())"});
        QVERIFY(process.waitForFinished(120000));
        const QString out = QString::fromUtf8(process.readAllStandardOutput());
        QVERIFY2(out.contains("runs " + QFileInfo(cli).absoluteFilePath() + "\n"), qPrintable(out.right(800)));
    }

    // The editor on its installed default scene (this suite runs under Xvfb).
    const Output editor = run(prefix + "/bin/softtouch", {"--screenshot", work + "/editor.png"}, work);
    QVERIFY2(editor.exitCode == 0, qPrintable(editor.text));
    const QImage shot(work + "/editor.png");
    QVERIFY(!shot.isNull() && shot.width() > 400);
}

QTEST_GUILESS_MAIN(TestInstall)
#include "test_install.moc"

// The installed build works on its own: `cmake --install` into a fresh folder, then the CLI validates and
// bakes the installed presets, finds the installed device plugins, builds the installed batch manifest's
// library, and the editor opens its installed default scene (a screenshot) — nothing read from the
// source or build tree.
#include <QDir>
#include <QFile>
#include <QImage>
#include <QProcess>
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
    void installedBuildRunsOnItsOwn();
};

void TestInstall::installedBuildRunsOnItsOwn() {
    QTemporaryDir dir;
    const QString prefix = dir.filePath("softtouch");
    const Output installed = run(QStringLiteral(SOFTTOUCH_CMAKE), {"--install", QStringLiteral(SOFTTOUCH_BUILD_DIR), "--prefix", prefix},
                                 dir.path());
    QVERIFY2(installed.exitCode == 0, qPrintable(installed.text));
    const QString cli = prefix + "/bin/softtouch-cli", share = prefix + "/share/softtouch";
    QVERIFY(QFile::exists(cli) && QFile::exists(prefix + "/bin/softtouch"));
    QVERIFY(QFile::exists(share + "/shaders/lattice_deform.glsl"));
    QVERIFY(QFile::exists(prefix + "/share/doc/softtouch/docs/farm.md"));
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
    // The preview page from the installed player, three.js modules and shaders.
    QVERIFY(QFile::exists(share + "/web/preview.js") && QFile::exists(share + "/web/node_modules/three/build/three.module.js"));
    const Output lattice = run(cli, {"bake", share + "/presets/scenes/guppy-swim.softtouch", "--out", "guppy", "--format", "lattice",
                                     "--frames", "4", "--quiet"},
                               work);
    QVERIFY2(lattice.exitCode == 0, qPrintable(lattice.text));
    const Output preview = run(cli, {"preview", "guppy.lattice.bin", "--out", "page"}, work);
    QVERIFY2(preview.exitCode == 0 && preview.text.contains("lattice clip guppy.lattice.bin: 4 frames") &&
                 QFile::exists(work + "/page/index.html"),
             qPrintable(preview.text));

    // The editor on its installed default scene (this suite runs under Xvfb).
    const Output editor = run(prefix + "/bin/softtouch", {"--screenshot", work + "/editor.png"}, work);
    QVERIFY2(editor.exitCode == 0, qPrintable(editor.text));
    const QImage shot(work + "/editor.png");
    QVERIFY(!shot.isNull() && shot.width() > 400);
}

QTEST_GUILESS_MAIN(TestInstall)
#include "test_install.moc"

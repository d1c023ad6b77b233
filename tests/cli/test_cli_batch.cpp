// softtouch-cli batch end to end: a library of 2 fish x 2 material presets x 2 formats planned, built,
// skipped when up to date, partly rebuilt when one preset changes, reproduced byte for byte, finished
// after a kill, and failing one job without touching its final name.
#include "helpers/cli_run.h"
#include "helpers/tree_contents.h"

#include <QCryptographicHash>
#include <QDir>
#include <QDirIterator>
#include <QElapsedTimer>
#include <QFile>
#include <QFileInfo>
#include <QMap>
#include <QProcess>
#include <QTemporaryDir>
#include <QThread>
#include <QtTest>

#include <csignal>

using namespace softtouch::test;

namespace {

const QString kPresets = QStringLiteral(SOFTTOUCH_SOURCE_DIR "/presets/");

/// A manifest in `dir` over the shipped angelfish and guppy, the two presets copied into `dir` (so a
/// test can edit one), the swim clip and `formats`.
QString writeManifest(const QTemporaryDir& dir, const QString& formats = R"("pc2", "glb")", const QString& extra = {}) {
    for (const QString name : {"jelly", "rubber"})
        if (!QFile::exists(dir.filePath(name + ".stpreset")))
            QFile::copy(kPresets + "materials/" + name + ".stpreset", dir.filePath(name + ".stpreset"));
    const QString text = QString(R"({"format": "softtouch-batch", "version": 1,
        "scenes": ["%1scenes/angelfish-swim.softtouch", "%1scenes/guppy-swim.softtouch"],
        "presets": ["jelly.stpreset", "rubber.stpreset"], "clips": ["swim"], "formats": [%2]%3})")
                             .arg(kPresets, formats, extra);
    const QString path = dir.filePath("fish.stbatch");
    QFile f(path);
    f.open(QIODevice::WriteOnly | QIODevice::Truncate);
    f.write(text.toUtf8());
    return path;
}

}  // namespace

class TestCliBatch : public QObject {
    Q_OBJECT
private slots:
    void planRunSkipAndRebuildWhatChanged();
    void libraryIsReproducibleByteForByte();
    void killedHalfwayFinishesOnRerun();
    void failedJobLeavesNothingUnderItsName();
    void badManifestsFailCleanly_data();
    void badManifestsFailCleanly();
    void slurmScriptRunsEveryJobOfTheArray();
    void videoPreviewsAreRenderedHeadless();
    void gameReadyExportsInALibrary();
};

void TestCliBatch::planRunSkipAndRebuildWhatChanged() {
    QTemporaryDir dir;
    const QString manifest = writeManifest(dir);
    const Run plan = runCli({"batch", "plan", manifest});
    QVERIFY2(plan.exitCode == 0, qPrintable(plan.err));
    QCOMPARE(plan.out.count(" to-run "), 8);
    QVERIFY2(plan.out.contains("angelfish-swim.jelly.swim.pc2") && plan.out.contains("guppy-swim.rubber.swim.glb"),
             qPrintable(plan.out));

    const Run first = runCli({"batch", "run", manifest, "--jobs", "2"});
    QVERIFY2(first.exitCode == 0, qPrintable(first.err));
    QVERIFY2(first.out.contains("8 jobs: 8 ran, 0 up to date, 0 failed"), qPrintable(first.out));
    const QString library = dir.filePath("library");
    QVERIFY(QFile::exists(library + "/angelfish-swim/jelly/swim-pc2.pc2"));
    QVERIFY(QFile::exists(library + "/guppy-swim/rubber/swim-glb.glb"));
    const Run checked = runCli({"batch", "check", manifest});
    QVERIFY2(checked.exitCode == 0 && checked.out.contains("8 of 8 jobs done and readable"), qPrintable(checked.out + checked.err));

    const Run second = runCli({"batch", "run", manifest, "--jobs", "2"});
    QVERIFY2(second.out.contains("8 jobs: 0 ran, 8 up to date, 0 failed"), qPrintable(second.out));

    // Stiffer rubber: its four jobs run again and change; jelly's four are left as they are.
    const auto before = treeContents(library);
    QFile rubber(dir.filePath("rubber.stpreset"));
    QVERIFY(rubber.open(QIODevice::ReadOnly));
    QByteArray text = rubber.readAll();
    rubber.close();
    QVERIFY(text.contains("\"modulus\": 4334"));
    const QByteArray stiffer = text.replace("\"modulus\": 4334", "\"modulus\": 6000");
    QVERIFY(rubber.open(QIODevice::WriteOnly | QIODevice::Truncate));
    rubber.write(stiffer);
    rubber.close();
    const Run replan = runCli({"batch", "plan", manifest});
    QCOMPARE(replan.out.count(" to-run "), 4);
    const Run third = runCli({"batch", "run", manifest, "--jobs", "2"});
    QVERIFY2(third.exitCode == 0 && third.out.contains("8 jobs: 4 ran, 4 up to date, 0 failed"), qPrintable(third.out + third.err));
    const auto after = treeContents(library);
    for (auto it = before.begin(); it != before.end(); ++it) {
        const bool rubberFile = it.key().contains("/rubber/") || it.key().contains(".rubber.");
        if (rubberFile && it.key().endsWith(".pc2"))
            QVERIFY2(after.value(it.key()) != it.value(), qPrintable(it.key() + " did not change"));
        if (!rubberFile)
            QVERIFY2(after.value(it.key()) == it.value(), qPrintable(it.key() + " changed"));
    }
}

void TestCliBatch::libraryIsReproducibleByteForByte() {
    QTemporaryDir dir;
    const QString manifest = writeManifest(dir);
    QVERIFY(runCli({"batch", "run", manifest, "--library", dir.filePath("a"), "--jobs", "2"}).exitCode == 0);
    QVERIFY(runCli({"batch", "run", manifest, "--library", dir.filePath("b"), "--jobs", "1"}).exitCode == 0);
    const auto a = treeContents(dir.filePath("a")), b = treeContents(dir.filePath("b"));
    QCOMPARE(a.size(), 8 * 2 + 8);  // each job: its cache and rest OBJ; and a stamp per job
    QVERIFY(a == b);
}

void TestCliBatch::killedHalfwayFinishesOnRerun() {
    QTemporaryDir dir;
    const QString manifest = writeManifest(dir, R"("pc2", "glb", "objseq")");
    QVERIFY(runCli({"batch", "run", manifest, "--library", dir.filePath("clean")}).exitCode == 0);

    // The batch and its job processes in a session of their own, killed together (kill -9) once the first
    // job has finished and others are under way.
    QProcess batch;
    batch.start("setsid", {kCli, "batch", "run", manifest, "--library", dir.filePath("killed"), "--jobs", "2", "--quiet"});
    QVERIFY(batch.waitForStarted());
    QElapsedTimer clock;
    clock.start();
    const QString stamps = dir.filePath("killed/.softtouch-batch");
    while (QDir(stamps).entryList({"*.json"}, QDir::Files).isEmpty() && clock.elapsed() < 60000)
        QThread::msleep(5);
    QVERIFY(::kill(-pid_t(batch.processId()), SIGKILL) == 0);
    batch.waitForFinished();
    const int finished = QDir(stamps).entryList({"*.json"}, QDir::Files).size();  // not a stamp's temporary
    QVERIFY2(finished >= 1 && finished < 12, qPrintable(QString::number(finished)));

    const Run rerun = runCli({"batch", "run", manifest, "--library", dir.filePath("killed"), "--jobs", "2"});
    QVERIFY2(rerun.exitCode == 0, qPrintable(rerun.err));
    QVERIFY2(rerun.out.contains(QString("%1 up to date").arg(finished)), qPrintable(rerun.out));
    QVERIFY(runCli({"batch", "check", manifest, "--library", dir.filePath("killed")}).exitCode == 0);
    // Nothing corrupt and nothing left over: the same files, byte for byte, as the uninterrupted library.
    const auto clean = treeContents(dir.filePath("clean")), killed = treeContents(dir.filePath("killed"));
    QStringList extra = killed.keys(), missing = clean.keys();
    for (const QString& k : clean.keys())
        extra.removeAll(k);
    for (const QString& k : killed.keys())
        missing.removeAll(k);
    QVERIFY2(extra.isEmpty() && missing.isEmpty(), qPrintable("left over: " + extra.join(", ") + "; missing: " + missing.join(", ")));
    QVERIFY(killed == clean);
}

void TestCliBatch::failedJobLeavesNothingUnderItsName() {
    QTemporaryDir dir;
    const QString manifest = writeManifest(dir);
    // A folder where one job's cache should go: that bake is refused before it writes anything.
    QVERIFY(QDir().mkpath(dir.filePath("library/guppy-swim/jelly/swim-pc2.pc2")));
    const Run run = runCli({"batch", "run", manifest, "--jobs", "2"});
    QCOMPARE(run.exitCode, 1);
    QVERIFY2(run.out.contains("8 jobs: 7 ran, 0 up to date, 1 failed"), qPrintable(run.out));
    QVERIFY2(run.err.contains("job guppy-swim.jelly.swim.pc2 failed:") && run.err.contains("swim-pc2.pc2"), qPrintable(run.err));
    QVERIFY(!QFile::exists(dir.filePath("library/guppy-swim/jelly/swim-pc2.obj")));
    QVERIFY(!QFile::exists(dir.filePath("library/.softtouch-batch/guppy-swim.jelly.swim.pc2.json")));
    const Run check = runCli({"batch", "check", manifest});
    QCOMPARE(check.exitCode, 1);
    QVERIFY2(check.err.contains("guppy-swim.jelly.swim.pc2: not done") && check.out.contains("7 of 8"), qPrintable(check.out + check.err));
}

void TestCliBatch::badManifestsFailCleanly_data() {
    QTest::addColumn<QString>("formats");
    QTest::addColumn<QString>("extra");
    QTest::addColumn<QString>("expected");
    QTest::newRow("unknown format") << R"("pc2", "fbx")" << "" << "/formats/1: unknown format \"fbx\"";
    QTest::newRow("no formats") << "" << "" << "/formats: expected a non-empty array";
    QTest::newRow("clip a scene lacks") << R"("pc2")" << R"(, "clips": ["swim", "backflip"])" << "has no clip \"backflip\"";
    QTest::newRow("outputs collide") << R"("pc2")" << R"(, "output": "{scene}/{clip}")" << "would both write";
    QTest::newRow("typo") << R"("pc2")" << R"(, "fromats": ["pc2"])" << "/fromats";
    QTest::newRow("odd video size") << R"("mp4")" << R"(, "video": {"size": [641, 360]})" << "/video/size: expected even";
    QTest::newRow("nothing to pack") << R"("pc2")" << R"(, "compress": true)" << "/compress: packs glb, pca and skin outputs";
    QTest::newRow("output outside the library") << R"("pc2")" << R"(, "output": "../{scene}-{preset}-{format}")"
                                                << "/output: expected a relative path pattern";
}

void TestCliBatch::badManifestsFailCleanly() {
    QFETCH(QString, formats);
    QFETCH(QString, extra);
    QFETCH(QString, expected);
    QTemporaryDir dir;
    QString manifest = writeManifest(dir, formats);
    if (!extra.isEmpty()) {
        QFile f(manifest);
        QVERIFY(f.open(QIODevice::ReadWrite));
        QByteArray text = f.readAll();
        if (extra.contains("\"clips\""))
            text.replace(R"("clips": ["swim"], )", "");
        text.insert(text.lastIndexOf('}'), extra.toUtf8());
        f.resize(0);
        f.write(text);
    }
    for (const QString action : {"plan", "run"}) {
        const Run r = runCli({"batch", action, manifest});
        QCOMPARE(r.exitCode, 1);
        QVERIFY2(r.err.contains("fish.stbatch") && r.err.contains(expected), qPrintable(r.err));
    }
    QVERIFY(!QFile::exists(dir.filePath("library")));
}

void TestCliBatch::slurmScriptRunsEveryJobOfTheArray() {
    // Without a cluster: the generated script is run once per array index, as sbatch would, and the
    // collector then finds the library complete and equal to a local run.
    QTemporaryDir dir;
    const QString manifest = writeManifest(dir);
    const QString farm = dir.filePath("farm");
    const Run written = runCli({"batch", "slurm", manifest, "--out", farm, "--library", dir.filePath("farmed")});
    QVERIFY2(written.exitCode == 0 && written.out.contains("8 of 8 jobs to run"), qPrintable(written.out + written.err));
    QFile script(farm + "/softtouch-batch.sbatch");
    QVERIFY(script.open(QIODevice::ReadOnly));
    const QString text = QString::fromUtf8(script.readAll());
    QVERIFY2(text.contains("#SBATCH --array=0-7") && text.contains("#SBATCH --mem=") && text.contains("--job \"$id\""),
             qPrintable(text));
    for (int task = 0; task < 8; ++task) {
        QProcess p;
        QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
        env.insert("SLURM_ARRAY_TASK_ID", QString::number(task));
        p.setProcessEnvironment(env);
        p.start("bash", {farm + "/softtouch-batch.sbatch"});
        QVERIFY(p.waitForFinished(120000));
        QVERIFY2(p.exitCode() == 0, p.readAllStandardError().constData());
    }
    QProcess collect;
    collect.start("bash", {farm + "/collect.sh"});
    QVERIFY(collect.waitForFinished(120000));
    QVERIFY2(collect.exitCode() == 0, collect.readAllStandardError().constData());
    QVERIFY(runCli({"batch", "run", manifest, "--library", dir.filePath("local")}).exitCode == 0);
    QVERIFY(treeContents(dir.filePath("farmed")) == treeContents(dir.filePath("local")));
    // Once done, a new script has nothing to run.
    const Run again = runCli({"batch", "slurm", manifest, "--out", farm, "--library", dir.filePath("farmed")});
    QVERIFY2(again.out.contains("every one of the 8 jobs is up to date"), qPrintable(again.out));
    // Submitted anyway (a nightly `batch slurm && sbatch`), it runs as sbatch would run it, with no array
    // task id, and succeeds having run nothing.
    QProcess nothing;
    QProcessEnvironment noArray = QProcessEnvironment::systemEnvironment();
    noArray.remove("SLURM_ARRAY_TASK_ID");
    nothing.setProcessEnvironment(noArray);
    nothing.start("bash", {farm + "/softtouch-batch.sbatch"});
    QVERIFY(nothing.waitForFinished(60000));
    QVERIFY2(nothing.exitCode() == 0, nothing.readAllStandardError().constData());
    QVERIFY(nothing.readAllStandardOutput().contains("nothing to run"));
}

void TestCliBatch::videoPreviewsAreRenderedHeadless() {
    // Previews beside the caches, drawn without a window system (EGL), checked by reading them back.
    QTemporaryDir dir;
    const QString manifest = writeManifest(dir, R"("mp4", "gif")", R"(, "frames": 4, "video": {"size": [96, 64]})");
    const Run run = runCli({"batch", "run", manifest, "--jobs", "2"}, /*headless=*/true);
    QVERIFY2(run.exitCode == 0 && run.out.contains("8 jobs: 8 ran"), qPrintable(run.out + run.err));
    QVERIFY(QFileInfo(dir.filePath("library/guppy-swim/rubber/swim-mp4.mp4")).size() > 0);
    QVERIFY(QFileInfo(dir.filePath("library/angelfish-swim/jelly/swim-gif.gif")).size() > 0);
    const Run check = runCli({"batch", "check", manifest}, true);
    QVERIFY2(check.exitCode == 0 && check.out.contains("8 of 8 jobs done and readable"), qPrintable(check.out + check.err));
}

void TestCliBatch::gameReadyExportsInALibrary() {
    // Skinned and compressed-morph GLBs beside the caches, read back by batch check (assimp); then packed.
    QTemporaryDir dir;
    const QString manifest = writeManifest(dir, R"("skin", "pca")", R"(, "frames": 8)");
    const Run run = runCli({"batch", "run", manifest, "--jobs", "2"});
    QVERIFY2(run.exitCode == 0 && run.out.contains("8 jobs: 8 ran"), qPrintable(run.out + run.err));
    QVERIFY(QFileInfo(dir.filePath("library/guppy-swim/rubber/swim-skin.glb")).size() > 0);
    QVERIFY(QFileInfo(dir.filePath("library/angelfish-swim/jelly/swim-pca.glb")).size() > 0);
    const Run check = runCli({"batch", "check", manifest});
    QVERIFY2(check.exitCode == 0 && check.out.contains("8 of 8 jobs done and readable"), qPrintable(check.out + check.err));

    // Packed for shipping: the skinned outputs are smaller, and batch check still reads them (expanded for
    // assimp). The setting is part of a packed job's hash: turned off, the skins are made again, the caches
    // beside them are up to date.
    QTemporaryDir packed;
    const QString packedManifest = writeManifest(packed, R"("skin", "pc2")", R"(, "frames": 8, "compress": true)");
    const Run packedRun = runCli({"batch", "run", packedManifest, "--jobs", "2"});
    QVERIFY2(packedRun.exitCode == 0 && packedRun.out.contains("8 jobs: 8 ran"), qPrintable(packedRun.out + packedRun.err));
    const QString skin = "library/guppy-swim/rubber/swim-skin.glb";
    QFile packedSkin(packed.filePath(skin));
    QVERIFY(packedSkin.open(QIODevice::ReadOnly));
    QVERIFY(packedSkin.readAll().contains("EXT_meshopt_compression"));
    QVERIFY2(QFileInfo(packed.filePath(skin)).size() * 2 < QFileInfo(dir.filePath(skin)).size(),
             qPrintable(QString("%1 against %2").arg(QFileInfo(packed.filePath(skin)).size()).arg(QFileInfo(dir.filePath(skin)).size())));
    const Run packedCheck = runCli({"batch", "check", packedManifest});
    QVERIFY2(packedCheck.exitCode == 0 && packedCheck.out.contains("8 of 8 jobs done and readable"),
             qPrintable(packedCheck.out + packedCheck.err));
    writeManifest(packed, R"("skin", "pc2")", R"(, "frames": 8)");
    const Run unpacked = runCli({"batch", "run", packedManifest, "--jobs", "2"});
    QVERIFY2(unpacked.exitCode == 0 && unpacked.out.contains("8 jobs: 4 ran, 4 up to date"), qPrintable(unpacked.out + unpacked.err));
    QFile unpackedSkin(packed.filePath(skin));
    QVERIFY(unpackedSkin.open(QIODevice::ReadOnly));
    QVERIFY(!unpackedSkin.readAll().contains("EXT_meshopt_compression"));
}

QTEST_GUILESS_MAIN(TestCliBatch)
#include "test_cli_batch.moc"

// Hostile and careless inputs to the pipeline (docs/design/reliability.md, "Confinement"): batch names that
// would write outside the library, a manifest name that would inject a command into the Slurm script,
// jobs that outlive their batch, temporaries of a killed bake, a video too large for the memory at
// hand, JSON that asks for gigabytes, inputs validate passed and bake refused, and the editor's usage
// errors. The last test runs each hostile input under strace in a sandbox and lists every path touched.
#include "helpers/cli_run.h"

#include <QDir>
#include <QDirIterator>
#include <QElapsedTimer>
#include <QFile>
#include <QFileInfo>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QProcess>
#include <QRegularExpression>
#include <QHash>
#include <QSet>
#include <QTemporaryDir>
#include <QThread>
#include <QtTest>

#include <csignal>

using namespace softtouch::test;

namespace {

const QString kPresets = QStringLiteral(SOFTTOUCH_SOURCE_DIR "/presets/");
const QString kEditor = QStringLiteral(SOFTTOUCH_BIN_DIR "/softtouch");

bool writeFile(const QString& path, const QByteArray& bytes) {
    QDir().mkpath(QFileInfo(path).absolutePath());
    QFile f(path);
    if (!f.open(QIODevice::WriteOnly | QIODevice::Truncate))
        return false;
    return f.write(bytes) == bytes.size();
}

QByteArray readFile(const QString& path) {
    QFile f(path);
    return f.open(QIODevice::ReadOnly) ? f.readAll() : QByteArray();
}

/// A folder laid out as presets/ is: scenes/guppy-swim.softtouch, meshes/guppy.obj and
/// materials/fish-body.stpreset, so the guppy scene loads from inside it; and a folder beside it,
/// outside/, holding files no input may reach.
struct Sandbox {
    QTemporaryDir root;
    QString path(const QString& relative) const { return root.filePath("sandbox/" + relative); }
    QString outside(const QString& relative = {}) const { return root.filePath("outside/" + relative); }
    QString scene() const { return path("scenes/guppy-swim.softtouch"); }

    Sandbox() {
        QDir().mkpath(path("scenes"));
        QDir().mkpath(outside());
        QFile::copy(kPresets + "scenes/guppy-swim.softtouch", scene());
        QDir().mkpath(path("meshes"));
        QFile::copy(kPresets + "meshes/guppy.obj", path("meshes/guppy.obj"));
        QDir().mkpath(path("materials"));
        QFile::copy(kPresets + "materials/fish-body.stpreset", path("materials/fish-body.stpreset"));
        writeFile(outside("secret.bin"), QByteArray(64, 's'));
        writeFile(outside("secret.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    }

    /// A manifest in the sandbox over the guppy scene: pc2, four frames, plus `extra` keys.
    QString manifest(const QString& name, const QString& extra = {}) const {
        const QString text = QString(R"({"format": "softtouch-batch", "version": 1, "scenes": ["scenes/guppy-swim.softtouch"],
            "formats": ["pc2"], "frames": 4%1})")
                                 .arg(extra);
        writeFile(path(name), text.toUtf8());
        return path(name);
    }

    /// Every file under the sandbox and outside/, by path relative to the root.
    QStringList files() const {
        QStringList list;
        QDirIterator it(root.path(), QDir::Files | QDir::Hidden | QDir::System, QDirIterator::Subdirectories);
        while (it.hasNext())
            list << QDir(root.path()).relativeFilePath(it.next());
        list.sort();
        return list;
    }
};

/// For a render: no window system (EGL alone), and no shader cache written into the user's home.
QProcessEnvironment headlessRenderEnvironment() {
    QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
    env.remove("DISPLAY");
    env.insert("MESA_SHADER_CACHE_DISABLE", "true");
    return env;
}

/// The guppy scene with `before` replaced by `after` in its text.
bool editScene(const Sandbox& box, const QByteArray& before, const QByteArray& after) {
    QByteArray text = readFile(box.scene());
    if (!text.contains(before))
        return false;
    return writeFile(box.scene(), text.replace(before, after));
}

/// Live processes whose environment holds `entry` (a batch's jobs carry SOFTTOUCH_BATCH_PARENT=PID).
QList<int> processesWithEnvironment(const QByteArray& entry) {
    QList<int> pids;
    for (const QString& name : QDir("/proc").entryList(QDir::Dirs)) {
        bool number = false;
        const int pid = name.toInt(&number);
        if (!number)
            continue;
        const QByteArray environ = readFile("/proc/" + name + "/environ");
        const QByteArray stat = readFile("/proc/" + name + "/stat");
        const bool zombie = stat.mid(stat.lastIndexOf(')') + 2, 1) == "Z";
        if (!zombie && environ.split('\0').contains(entry))
            pids << pid;
    }
    return pids;
}

/// The files named by the file system calls of a command run under strace, split into opened for
/// reading, written (created, opened for writing, renamed onto, made, removed) and only looked at
/// (stat, access, readlink).
struct Touched {
    int exitCode = -1;
    QString err;
    QSet<QString> read, written, looked;
    QHash<QString, int> opens;  ///< How often each path was opened.
};

Touched traced(const QStringList& command, const QString& workingDirectory) {
    Touched t;
    QTemporaryDir logDir;
    const QString log = logDir.filePath("trace");
    QProcess p;
    p.setWorkingDirectory(workingDirectory);
    // LeakSanitizer cannot run under ptrace (the sanitizer build's leak check is the other tests' job).
    QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
    env.insert("ASAN_OPTIONS", "detect_leaks=0");
    p.setProcessEnvironment(env);
    p.start("strace", QStringList{"-f", "-qq", "-s", "4096", "-e", "trace=%file", "-o", log} + command);
    if (!p.waitForFinished(120000)) {
        p.kill();
        p.waitForFinished();
        t.err = "timed out";
        return t;
    }
    t.exitCode = p.exitStatus() == QProcess::NormalExit ? p.exitCode() : -1;
    t.err = QString::fromUtf8(p.readAllStandardError());
    // pid syscall(args) = result: every quoted argument that is a path, made absolute.
    static const QRegularExpression call(R"(^\d+\s+(\w+)\((.*)\)\s+=\s+(-?\d+))");
    static const QRegularExpression quoted("\"((?:[^\"\\\\]|\\\\.)*)\"");
    for (const QString& line : QString::fromUtf8(readFile(log)).split('\n')) {
        const auto m = call.match(line);
        if (!m.hasMatch())
            continue;
        const QString name = m.captured(1), args = m.captured(2);
        QStringList paths;
        for (auto it = quoted.globalMatch(args); it.hasNext();) {
            paths << QDir::cleanPath(QDir(workingDirectory).absoluteFilePath(it.next().captured(1)));
            if (name.startsWith("exec"))
                break;  // the program; the rest are its arguments
        }
        if (paths.isEmpty())
            continue;
        const bool writes = name.startsWith("rename") || name.startsWith("unlink") || name.startsWith("mkdir") ||
                            name.startsWith("rmdir") || name.startsWith("link") || name.startsWith("symlink") ||
                            name == "creat" || name.startsWith("truncate") || name.startsWith("chmod") ||
                            ((name == "open" || name == "openat") && (args.contains("O_WRONLY") || args.contains("O_RDWR") ||
                                                                     args.contains("O_CREAT")));
        const bool opens = name == "open" || name == "openat" || name == "openat2" || name.startsWith("exec");
        for (const QString& path : paths) {
            (writes ? t.written : opens ? t.read : t.looked).insert(path);
            if (name == "open" || name == "openat")
                ++t.opens[path];
        }
    }
    return t;
}

}  // namespace

class TestCliHostile : public QObject {
    Q_OBJECT
private slots:
    void batchNamesCannotLeaveTheLibrary_data();
    void batchNamesCannotLeaveTheLibrary();
    void slurmScriptCannotBeMadeToRunACommand();
    void killedObjSequenceIsSweptByAShorterRerun();
    void killedRenderIsSweptByTheRerun();
    void stoppedBatchLeavesNoJobRunning_data();
    void stoppedBatchLeavesNoJobRunning();
    void hugeVideoIsRefusedForTheMemoryAtHand();
    void jsonOfMillionsOfKeysIsRefusedBeforeParsing();
    void validateRefusesWhatBakeWouldRefuse_data();
    void validateRefusesWhatBakeWouldRefuse();
    void validateReadsBatchManifests();
    void planReadsEachInputOnce();
    void oddMp4SizeIsAUsageError();
    void editorUsageErrorsExitTwo_data();
    void editorUsageErrorsExitTwo();
    void hostileInputsTouchNothingOutsideTheirFolder_data();
    void hostileInputsTouchNothingOutsideTheirFolder();
};

void TestCliHostile::batchNamesCannotLeaveTheLibrary_data() {
    QTest::addColumn<QString>("extra");    // manifest keys
    QTest::addColumn<QString>("rename");   // the scene file's new name ("" keeps it)
    QTest::addColumn<QString>("defaultClip"); // the scene's own clip renamed to this ("" keeps it)
    QTest::addColumn<QString>("expected"); // in the message
    QTest::newRow("relative clip name") << R"(, "clips": ["../../../escaped-rel"])" << "" << ""
                                        << "/clips/0: expected a clip name, not a path";
    QTest::newRow("absolute clip name") << R"(, "clips": ["/tmp/escaped-abs"])" << "" << ""
                                        << "/clips/0: expected a clip name, not a path";
    QTest::newRow("scene whose stem is ..") << "" << "...softtouch" << ""
                                            << "/scenes/0: the file name \"...softtouch\" gives no name";
    QTest::newRow("scene's own clip named ..") << "" << "" << ".." << "its clip \"..\" gives no name";
    QTest::newRow("library outside the manifest's folder") << R"(, "outputRoot": "../outside")" << "" << ""
                                                           << "/outputRoot: expected a folder inside the manifest's folder";
    QTest::newRow("absolute library") << R"(, "outputRoot": "/tmp/library")" << "" << ""
                                      << "/outputRoot: expected a folder inside the manifest's folder";
    QTest::newRow("empty scene path") << "" << "EMPTY" << "" << "/scenes/0: expected a file path, got an empty string";
    QTest::newRow("NUL in the output pattern") << R"(, "output": "{scene}\u0000/x")" << "" << ""
                                               << "/output: expected a relative path pattern";
}

void TestCliHostile::batchNamesCannotLeaveTheLibrary() {
    QFETCH(QString, extra);
    QFETCH(QString, rename);
    QFETCH(QString, defaultClip);
    QFETCH(QString, expected);
    Sandbox box;
    if (!defaultClip.isEmpty()) {
        QVERIFY(editScene(box, R"("name": "swim")", QString(R"("name": "%1")").arg(defaultClip).toUtf8()));
        QVERIFY(editScene(box, R"("library": [)", QString(R"("default": "%1", "library": [)").arg(defaultClip).toUtf8()));
    }
    QString manifest = box.manifest("lib.stbatch", extra);
    if (rename == "EMPTY") {
        writeFile(manifest, readFile(manifest).replace("\"scenes/guppy-swim.softtouch\"", "\"\""));
    } else if (!rename.isEmpty()) {
        QVERIFY(QFile::rename(box.scene(), box.path("scenes/" + rename)));
        writeFile(manifest, readFile(manifest).replace("guppy-swim.softtouch", rename.toUtf8()));
    }
    const QStringList before = box.files();
    for (const char* action : {"plan", "run"}) {
        const Run r = runCli({"batch", action, manifest});
        QVERIFY2(r.exitCode == 1, qPrintable(QString(action) + ": " + r.out + r.err));
        QVERIFY2(r.err.contains(expected), qPrintable(r.err));
        QVERIFY2(r.err.contains("lib.stbatch"), qPrintable(r.err));  // the file is named
    }
    // validate says the same, and nothing was written anywhere.
    const Run v = runCli({"validate", manifest});
    QVERIFY2(v.exitCode == 1 && v.err.contains(expected), qPrintable(v.out + v.err));
    QCOMPARE(box.files(), before);
    QVERIFY(!QFileInfo::exists("/tmp/escaped-abs.pc2") && !QFileInfo::exists("/tmp/library"));
}

void TestCliHostile::slurmScriptCannotBeMadeToRunACommand() {
    Sandbox box;
    // A newline in the manifest's name would start a command of its own in the script: refused.
    const QString newline = box.manifest("x\ntouch PWNED\n.stbatch");
    const Run refused = runCli({"batch", "slurm", newline, "--out", box.path("farm")});
    QVERIFY2(refused.exitCode == 1 && refused.err.contains("control character"), qPrintable(refused.out + refused.err));
    QVERIFY(!QFileInfo::exists(box.path("farm/softtouch-batch.sbatch")));

    // Shell syntax in a name is only text: the script parses, runs the job, and runs nothing else.
    const QString shelly = box.manifest("fish $(touch PWNED1) `touch PWNED2` 'q' ;touch PWNED3.stbatch");
    const QString farm = box.path("farm $(touch PWNED4)");
    const Run written = runCli({"batch", "slurm", shelly, "--out", farm});
    QVERIFY2(written.exitCode == 0, qPrintable(written.out + written.err));
    const QString script = farm + "/softtouch-batch.sbatch";
    QProcess parse;
    parse.start("bash", {"-n", script});
    QVERIFY(parse.waitForFinished(10000));
    QVERIFY2(parse.exitCode() == 0, parse.readAllStandardError().constData());
    QProcess task;
    QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
    env.insert("SLURM_ARRAY_TASK_ID", "0");
    task.setProcessEnvironment(env);
    task.setWorkingDirectory(box.path(""));
    task.start("bash", {script});
    QVERIFY(task.waitForFinished(120000));
    QVERIFY2(task.exitCode() == 0, task.readAllStandardError().constData());
    QVERIFY(QFileInfo::exists(box.path("library/guppy-swim/as-authored/drivers-pc2.pc2")));
    for (const QString& file : box.files())
        QVERIFY2(!QFileInfo(file).fileName().startsWith("PWNED"), qPrintable(file));
    QVERIFY(!QFileInfo::exists("PWNED1") && !QFileInfo::exists(QDir::homePath() + "/PWNED1"));
}

void TestCliHostile::killedObjSequenceIsSweptByAShorterRerun() {
    // An OBJ sequence stages every frame before it publishes any: a kill -9 leaves them all. A re-run
    // with fewer frames must sweep the frames beyond its own too.
    Sandbox box;
    const QString out = box.path("seq/guppy.obj");
    QDir().mkpath(box.path("seq"));
    QProcess bake;
    bake.start(kCli, {"bake", box.scene(), "--format", "objseq", "--frames", "2000", "--out", out});
    QVERIFY(bake.waitForStarted());
    QElapsedTimer waited;
    waited.start();
    auto temporaries = [&] { return QDir(box.path("seq")).entryList({"*.tmp-*"}, QDir::Files).size(); };
    while (temporaries() < 100 && waited.elapsed() < 120000 && bake.state() == QProcess::Running)
        QThread::msleep(20);
    QVERIFY2(bake.state() == QProcess::Running, "the bake finished before it could be killed");
    ::kill(pid_t(bake.processId()), SIGKILL);
    QVERIFY(bake.waitForFinished(10000));
    const int left = temporaries();
    QVERIFY(left >= 100);
    const Run rerun = runCli({"bake", box.scene(), "--format", "objseq", "--frames", "10", "--out", out});
    QVERIFY2(rerun.exitCode == 0, qPrintable(rerun.err));
    QCOMPARE(temporaries(), 0);
    QCOMPARE(QDir(box.path("seq")).entryList({"guppy_*.obj"}, QDir::Files).size(), 10);
}

void TestCliHostile::killedRenderIsSweptByTheRerun() {
    // A render killed with kill -9 leaves its temporary (video.mp4.tmp-PID-N); the next render of the
    // same file removes it.
    Sandbox box;
    const QString out = box.path("video.mp4");
    QProcess render;
    const QProcessEnvironment env = headlessRenderEnvironment();
    render.setProcessEnvironment(env);
    render.start(kCli, {"render", box.scene(), "--size", "640x360", "--frames", "2000", "--out", out, "--quiet"});
    QVERIFY(render.waitForStarted());
    QElapsedTimer waited;
    waited.start();
    auto temporaries = [&] { return QDir(box.path("")).entryList({"video.mp4.tmp-*"}, QDir::Files).size(); };
    while (temporaries() == 0 && waited.elapsed() < 60000 && render.state() == QProcess::Running)
        QThread::msleep(20);
    QThread::msleep(200);
    QVERIFY2(render.state() == QProcess::Running, "the render finished before it could be killed");
    ::kill(pid_t(render.processId()), SIGKILL);
    QVERIFY(render.waitForFinished(10000));
    QCOMPARE(temporaries(), 1);
    QProcess again;
    again.setProcessEnvironment(env);
    again.start(kCli, {"render", box.scene(), "--size", "64x36", "--frames", "2", "--out", out, "--quiet"});
    QVERIFY(again.waitForFinished(120000));
    QVERIFY2(again.exitCode() == 0, again.readAllStandardError().constData());
    QCOMPARE(temporaries(), 0);
    QVERIFY(QFileInfo(out).size() > 0);
}

void TestCliHostile::stoppedBatchLeavesNoJobRunning_data() {
    QTest::addColumn<int>("signal");
    QTest::newRow("SIGTERM") << int(SIGTERM);
    QTest::newRow("SIGHUP") << int(SIGHUP);
    QTest::newRow("SIGKILL") << int(SIGKILL);
}

void TestCliHostile::stoppedBatchLeavesNoJobRunning() {
    QFETCH(int, signal);
    Sandbox box;
    // One long job: 3,000 frames of OBJ sequence.
    const QString manifest = box.manifest("long.stbatch");
    writeFile(manifest, readFile(manifest).replace(R"("pc2")", R"("objseq")").replace(R"("frames": 4)", R"("frames": 3000)"));
    QProcess batch;
    batch.start(kCli, {"batch", "run", manifest, "--quiet"});
    QVERIFY(batch.waitForStarted());
    const QByteArray entry = "SOFTTOUCH_BATCH_PARENT=" + QByteArray::number(batch.processId());
    QElapsedTimer waited;
    waited.start();
    while (processesWithEnvironment(entry).isEmpty() && waited.elapsed() < 30000)
        QThread::msleep(20);
    QVERIFY2(!processesWithEnvironment(entry).isEmpty(), "the job's process never started");
    QThread::msleep(300);  // the job is under way
    ::kill(pid_t(batch.processId()), signal);
    QVERIFY(batch.waitForFinished(20000));
    // The batch has returned; its job is gone with it (a kill -9 of the batch: within moments), and
    // nothing is published after that.
    waited.restart();
    while (!processesWithEnvironment(entry).isEmpty() && waited.elapsed() < 5000)
        QThread::msleep(20);
    if (signal != SIGKILL)
        QVERIFY(waited.elapsed() < 1000);  // already gone when the batch returned (a scan of /proc or two)
    QVERIFY2(processesWithEnvironment(entry).isEmpty(), "the job outlived its batch");
    const QStringList after = box.files();
    QThread::msleep(1500);
    QCOMPARE(box.files(), after);
    for (const QString& file : after)
        QVERIFY2(!file.contains(".softtouch-batch/") && !file.contains("guppy-swim/as-authored/drivers-objseq_"),
                 qPrintable("published after the stop: " + file));
}

void TestCliHostile::hugeVideoIsRefusedForTheMemoryAtHand() {
    // 8192x8192, the largest size a video accepts, under a 3 GB address-space limit: refused before
    // anything is allocated, saying how much it needs, with no temporary left; alone and as a batch job.
    Sandbox box;
    const QString out = box.path("big.mp4");
    QProcess p;
    const QProcessEnvironment env = headlessRenderEnvironment();
    p.setProcessEnvironment(env);
    p.start("prlimit", {"--as=3000000000", "--", kCli, "render", box.scene(), "--size", "8192x8192", "--frames", "2",
                        "--out", out});
    QVERIFY(p.waitForFinished(120000));
    const QString err = QString::fromUtf8(p.readAllStandardError());
    QVERIFY2(p.exitStatus() == QProcess::NormalExit && p.exitCode() == 1, qPrintable(err));
    QVERIFY2(err.contains("8192x8192") && err.contains("GB"), qPrintable(err));
    QVERIFY(box.files().filter(".tmp-").isEmpty());
    QVERIFY(!QFileInfo::exists(out));

    const QString manifest = box.manifest("video.stbatch", R"(, "video": {"size": [8192, 8192]})");
    writeFile(manifest, readFile(manifest).replace(R"("pc2")", R"("mp4")").replace(R"("frames": 4)", R"("frames": 2)"));
    QProcess job;
    job.setProcessEnvironment(env);
    job.start("prlimit", {"--as=3000000000", "--", kCli, "batch", "run", manifest, "--quiet"});
    QVERIFY(job.waitForFinished(120000));
    const QString jobErr = QString::fromUtf8(job.readAllStandardError());
    QVERIFY2(job.exitStatus() == QProcess::NormalExit && job.exitCode() == 1, qPrintable(jobErr));
    QVERIFY2(jobErr.contains("8192x8192") && !jobErr.contains("signal"), qPrintable(jobErr));
    QVERIFY2(box.files().filter(".tmp-").isEmpty(), qPrintable(box.files().join('\n')));
}

void TestCliHostile::jsonOfMillionsOfKeysIsRefusedBeforeParsing() {
    // 1.1 million unknown keys (16 MB, under the 256 MiB file limit) used to be parsed into a tree of
    // gigabytes (5 million took 2.7 GB and aborted); refused from a scan of the text instead.
    Sandbox box;
    QByteArray text = R"({"format": "softtouch-project", "version": 2, "objects": [], "junk": {)";
    text.reserve(18 << 20);
    for (int i = 0; i < 1'100'000; ++i)
        text += (i ? ",\"k" : "\"k") + QByteArray::number(i) + "\":0";
    text += "}}";
    QVERIFY(writeFile(box.path("keys.softtouch"), text));
    for (const char* command : {"validate", "bake"}) {
        const QStringList args = QString(command) == "validate" ? QStringList{"validate", box.path("keys.softtouch")}
                                                               : QStringList{"bake", box.path("keys.softtouch"), "--out",
                                                                             box.path("keys.pc2")};
        QProcess p;
        p.start("prlimit", QStringList{"--as=1500000000", "--", kCli} + args);
        QVERIFY(p.waitForFinished(120000));
        const QString err = QString::fromUtf8(p.readAllStandardError());
        QVERIFY2(p.exitStatus() == QProcess::NormalExit && p.exitCode() == 1, qPrintable(err));
        QVERIFY2(err.contains("keys.softtouch: holds 1100004 keys, more than the 1000000"), qPrintable(err.left(500)));
    }
}

void TestCliHostile::validateRefusesWhatBakeWouldRefuse_data() {
    QTest::addColumn<QByteArray>("before");
    QTest::addColumn<QByteArray>("after");
    QTest::addColumn<QString>("expected");
    // One key moving node 0 by 1e300 m.
    QTest::newRow("key displacement 1e300")
        << QByteArray(R"("clips": {)")
        << QByteArray(R"("keyframes": [{"name": "k", "objects": [{"keys": [{"time": 0, "nodes": [0], "displacement": [[1e300, 0, 0]]}]}]}],
                         "clips": {)")
        << "/keyframes/0/objects/0/keys/0/displacement/0: a key moves a node at most 10000 m";
    // A take recorded at 1/120 s in a scene stepping 1/240 s (64 nodes at rest).
    QByteArray zeros;
    for (int i = 0; i < 192; ++i)
        zeros += i ? ",0" : "0";
    QTest::newRow("take step unlike the scene's")
        << QByteArray(R"("clips": {)")
        << QByteArray(R"("sessions": [{"name": "t", "dt": 0.008333333333333333, "start": {"step": 0, "bodies": [{"position": [)" +
                      zeros + "], \"velocity\": [" + zeros + R"(]}]}, "end": 10}], "clips": {)")
        << "/sessions/0/dt: the take was recorded with a step of 0.00833333 s and the scene steps 0.00416667 s";
}

void TestCliHostile::validateRefusesWhatBakeWouldRefuse() {
    QFETCH(QByteArray, before);
    QFETCH(QByteArray, after);
    QFETCH(QString, expected);
    Sandbox box;
    QVERIFY(editScene(box, before, after));
    const Run v = runCli({"validate", box.scene()});
    QVERIFY2(v.exitCode == 1 && v.err.contains(expected), qPrintable(v.out + v.err));
    const Run b = runCli({"bake", box.scene(), "--frames", "2", "--out", box.path("x.pc2")});
    QVERIFY2(b.exitCode == 1 && b.err.contains(expected), qPrintable(b.err));
}

void TestCliHostile::validateReadsBatchManifests() {
    // batch's errors end with "'softtouch-cli validate' lists them all": validate reads a manifest as
    // one, every problem listed, and plans it (it used to read a .stbatch as a mesh).
    Sandbox box;
    const QString good = box.manifest("good.stbatch");
    const Run ok = runCli({"validate", good});
    QVERIFY2(ok.exitCode == 0 && ok.out.contains("good.stbatch: ok, 1 jobs"), qPrintable(ok.out + ok.err));
    const QString bad = box.manifest("bad.stbatch", R"(, "fromats": [], "video": {"size": [641, 360]})");
    const Run b = runCli({"validate", bad});
    QVERIFY2(b.exitCode == 1 && b.err.contains("bad.stbatch: /fromats") && b.err.contains("bad.stbatch: /video/size"),
             qPrintable(b.err));
    QVERIFY(!b.err.contains("mesh"));
    // A device trajectory whose workspace is ±1e300 m: the coupling divides by its size.
    QByteArray trajectory = readFile(kPresets + "devices/figure-eight.sttraj");
    QVERIFY(trajectory.contains(R"("samples")"));
    trajectory.replace(R"("samples")", R"("device": {"workspace": {"min": [-1e300, -1e300, -1e300], "max": [1e300, 1e300, 1e300]}}, "samples")");
    QVERIFY(writeFile(box.path("wide.sttraj"), trajectory));
    const Run t = runCli({"validate", box.path("wide.sttraj")});
    QVERIFY2(t.exitCode == 1 && t.err.contains("/device/workspace: expected a workspace within 1000 m"), qPrintable(t.out + t.err));
}

void TestCliHostile::planReadsEachInputOnce() {
    // A product of 1 scene x 40 presets x 3 formats is 120 jobs that all read the scene and its mesh: the
    // plan hashed every input of every job (a 90,000-job product took over 30 s); it now reads each once
    // for its hash, besides loading it.
    Sandbox box;
    QString presets;
    for (int i = 0; i < 40; ++i) {
        QFile::copy(kPresets + "materials/jelly.stpreset", box.path(QString("materials/p%1.stpreset").arg(i)));
        presets += QString(i ? ", \"materials/p%1.stpreset\"" : "\"materials/p%1.stpreset\"").arg(i);
    }
    const QString manifest = box.manifest("wide.stbatch", ", \"presets\": [" + presets + "]");
    writeFile(manifest, readFile(manifest).replace(R"(["pc2"])", R"(["pc2", "mdd", "glb"])"));
    const Touched t = traced({kCli, "batch", "plan", manifest}, box.path(""));
    QVERIFY2(t.exitCode == 0, qPrintable(t.err));
    const int sceneOpens = t.opens.value(QDir::cleanPath(box.scene()));
    const int meshOpens = t.opens.value(QDir::cleanPath(box.path("meshes/guppy.obj")));
    const int presetOpens = t.opens.value(QDir::cleanPath(box.path("materials/p7.stpreset")));
    QVERIFY2(sceneOpens >= 1 && sceneOpens <= 3, qPrintable(QString::number(sceneOpens)));
    // The import opens it several times (the header check, assimp's format probe and read), the hash once;
    // a hash per job would be 120 more.
    QVERIFY2(meshOpens >= 1 && meshOpens <= 10, qPrintable(QString::number(meshOpens)));
    QVERIFY2(presetOpens >= 1 && presetOpens <= 3, qPrintable(QString::number(presetOpens)));
}

void TestCliHostile::oddMp4SizeIsAUsageError() {
    // Like --size 0x0: the options cannot work together, so it is a usage error (exit 2), found before
    // the scene is even loaded.
    Sandbox box;
    const Run r = runCli({"render", box.scene(), "--size", "161x96", "--out", box.path("odd.mp4")}, true);
    QVERIFY2(r.exitCode == 2 && r.err.contains("even width and height") && r.err.contains("Usage:"), qPrintable(r.err));
    const Run gif = runCli({"render", box.scene(), "--size", "161x96", "--frames", "1", "--out", box.path("odd.gif")}, true);
    QVERIFY2(gif.exitCode == 0, qPrintable(gif.err));
}

void TestCliHostile::editorUsageErrorsExitTwo_data() {
    QTest::addColumn<QStringList>("args");
    QTest::addColumn<QString>("expected");
    QTest::newRow("unknown option") << QStringList{"--bogus"} << "Unknown option 'bogus'";
    QTest::newRow("seconds abc") << QStringList{"--seconds", "abc", "--screenshot", "x.png"} << "--seconds must be";
    QTest::newRow("seconds nan") << QStringList{"--seconds", "nan", "--screenshot", "x.png"} << "--seconds must be";
    QTest::newRow("seconds -5") << QStringList{"--seconds", "-5", "--screenshot", "x.png"} << "--seconds must be";
    QTest::newRow("seconds 1e9") << QStringList{"--seconds", "1e9", "--screenshot", "x.png"} << "--seconds must be";
    QTest::newRow("missing value") << QStringList{"--screenshot"} << "Missing value after '--screenshot'";
}

void TestCliHostile::editorUsageErrorsExitTwo() {
    QFETCH(QStringList, args);
    QFETCH(QString, expected);
    QTemporaryDir dir;
    QProcess p;
    QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
    env.insert("QT_QPA_PLATFORM", "offscreen");  // no X server needed: each case ends before a window opens
    // Under the sanitizer build, Qt's own allocations left at an early exit are not this test's concern (the
    // editor's suites run with leak detection off for the same reason: tests/CMakeLists.txt, XVFB).
    env.insert("ASAN_OPTIONS", "detect_leaks=0");
    p.setProcessEnvironment(env);
    p.setWorkingDirectory(dir.path());
    p.start(kEditor, QStringList{"--no-recovery", "--autosave-folder", dir.path()} + args);
    const bool finished = p.waitForFinished(20000);
    if (!finished) {
        p.kill();
        p.waitForFinished();
    }
    QVERIFY2(finished, "the editor did not exit");
    const QString err = QString::fromUtf8(p.readAllStandardError());
    QVERIFY2(p.exitStatus() == QProcess::NormalExit && p.exitCode() == 2, qPrintable(QString::number(p.exitCode()) + " " + err));
    QVERIFY2(err.contains(expected), qPrintable(err));
}

void TestCliHostile::hostileInputsTouchNothingOutsideTheirFolder_data() {
    QTest::addColumn<QString>("kind");
    for (const char* kind : {"relative clip", "absolute clip", "library outside", "forged stamp", "gltf buffer outside",
                             "gltf buffer absolute", "gltf buffer percent-encoded", "slurm names", "mesh buffer outside",
                             "obj material outside"})
        QTest::newRow(kind) << QString(kind);
}

void TestCliHostile::hostileInputsTouchNothingOutsideTheirFolder() {
    // Each hostile input runs in a sandbox beside a folder outside/ that holds files worth stealing.
    // strace lists every path the command's file system calls name: none under outside/ is opened or
    // written, nothing outside the sandbox is written, and everything else read is the system's or
    // SoftTouch's own (its libraries, three.js, shaders).
    QFETCH(QString, kind);
    QProcess version;
    version.start("strace", {"-V"});
    if (!version.waitForFinished(10000) || version.exitCode() != 0)
        QFAIL("strace is not installed (scripts/install-deps.sh installs it)");
    Sandbox box;
    QStringList command;
    const QString outside = QDir::cleanPath(box.outside());
    const QString sandbox = QDir::cleanPath(box.path(""));
    if (kind == "relative clip" || kind == "absolute clip") {
        // The scene has a clip of that name, so only the name's refusal keeps the output in the library.
        const QString clip = kind == "relative clip" ? QString("../../../outside/escaped") : outside + "/escaped";
        QVERIFY(editScene(box, R"("name": "swim")", QString(R"("name": "%1")").arg(clip).toUtf8()));
        command = {kCli, "batch", "run", box.manifest("m.stbatch", QString(R"(, "clips": ["%1"])").arg(clip))};
    } else if (kind == "library outside") {
        command = {kCli, "batch", "run", box.manifest("m.stbatch", R"(, "outputRoot": "../outside/lib")")};
    } else if (kind == "forged stamp") {
        // A finished library whose stamp is edited to name a file outside it: check reads only the library.
        const QString manifest = box.manifest("m.stbatch");
        const Run run = runCli({"batch", "run", manifest, "--quiet"});
        QVERIFY2(run.exitCode == 0, qPrintable(run.err));
        const QString stamp = box.path("library/.softtouch-batch/guppy-swim.as-authored.drivers.pc2.json");
        QVERIFY2(readFile(stamp).contains("guppy-swim/as-authored/drivers-pc2.obj"), readFile(stamp).constData());
        const qint64 size = QFileInfo(box.outside("secret.obj")).size();
        const QJsonDocument doc = QJsonDocument::fromJson(readFile(stamp));
        QJsonObject object = doc.object();
        QJsonArray files = object["files"].toArray();
        for (int i = 0; i < files.size(); ++i) {
            QJsonObject f = files[i].toObject();
            if (f["path"].toString().endsWith(".obj")) {
                f["path"] = "../../outside/secret.obj";
                f["bytes"] = size;
            }
            files[i] = f;
        }
        object["files"] = files;
        QVERIFY(writeFile(stamp, QJsonDocument(object).toJson()));
        command = {kCli, "batch", "check", manifest};
    } else if (kind.startsWith("gltf buffer")) {
        const QString uri = kind == "gltf buffer outside"    ? QString("../../outside/secret.bin")
                            : kind == "gltf buffer absolute" ? box.outside("secret.bin")
                                                             : QString("%2e%2e/%2e%2e/outside/secret.bin");
        QDir().mkpath(box.path("clips/fish"));
        writeFile(box.path("clips/fish/fish.gltf"),
                  QString(R"({"asset": {"version": "2.0"}, "buffers": [{"uri": "%1", "byteLength": 64}]})").arg(uri).toUtf8());
        command = {kCli, "preview", box.path("clips/fish/fish.gltf"), "--out", box.path("page")};
    } else if (kind == "mesh buffer outside") {
        // A mesh a project could name, whose one triangle's positions are a file outside its folder: the
        // importer (assimp) reads side files from the mesh's folder only.
        writeFile(box.path("meshes/evil.gltf"), R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
            "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}],
            "bufferViews": [{"buffer": 0, "byteLength": 36}],
            "buffers": [{"uri": "../../outside/secret.bin", "byteLength": 64}]})");
        command = {kCli, "validate", box.path("meshes/evil.gltf")};
    } else if (kind == "obj material outside") {
        writeFile(box.path("meshes/evil.obj"), "mtllib ../../outside/secret.obj\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        command = {kCli, "validate", box.path("meshes/evil.obj")};
    } else {
        const QString manifest = box.manifest("fish $(cat ..\\outside\\secret.bin).stbatch");
        command = {kCli, "batch", "slurm", manifest, "--out", box.path("farm")};
    }
    const Touched t = traced(command, sandbox);
    QVERIFY2(t.err != "timed out", "the command did not finish");
    const QStringList systemPrefixes = {"/usr/", "/lib/", "/lib64/", "/etc/ld.so.", "/etc/localtime", "/proc/", "/sys/",
                                        "/dev/null", "/dev/urandom", "/etc/nsswitch.conf", "/etc/passwd", "/etc/group", "/etc/gcrypt/",
                                        QStringLiteral(SOFTTOUCH_SOURCE_DIR "/"), QStringLiteral(SOFTTOUCH_BIN_DIR "/../")};
    auto underSandbox = [&](const QString& path) { return path == sandbox || path.startsWith(sandbox + "/"); };
    auto isSystem = [&](const QString& path) {
        for (const QString& prefix : systemPrefixes)
            if (path.startsWith(QDir::cleanPath(prefix) + (prefix.endsWith('/') ? "/" : "")) || path == QDir::cleanPath(prefix))
                return true;
        return false;
    };
    for (const QString& path : t.read + t.written)
        QVERIFY2(!path.startsWith(outside), qPrintable(kind + " touched " + path + "\n" + t.err));
    for (const QString& path : t.written)
        QVERIFY2(underSandbox(path), qPrintable(kind + " wrote outside its sandbox: " + path));
    for (const QString& path : t.read)
        QVERIFY2(underSandbox(path) || isSystem(path), qPrintable(kind + " read " + path));
    QCOMPARE(QDir(outside).entryList(QDir::Files | QDir::Dirs | QDir::NoDotAndDotDot).size(), 2);  // secret.bin, .obj
    // Each of them is a refusal, never a success that read the secret; the slurm names write a script, and
    // the OBJ imports without the material library it may not read.
    const bool succeeds = kind == "slurm names" || kind == "obj material outside";
    QVERIFY2(succeeds ? t.exitCode == 0 : t.exitCode == 1, qPrintable(QString::number(t.exitCode) + t.err));
    if (kind == "slurm names")
        QVERIFY(!readFile(box.path("farm/softtouch-batch.sbatch")).contains("ssssssss"));
}

QTEST_GUILESS_MAIN(TestCliHostile)
#include "test_cli_hostile.moc"

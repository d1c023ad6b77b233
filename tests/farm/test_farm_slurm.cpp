// A real Slurm: a one-node cluster (munged, slurmctld, slurmd from Debian's packages) configured in a
// temporary folder, the job array `softtouch-cli batch slurm` writes for 2 fish x 2 presets x 2 formats
// submitted with sbatch, and its library compared byte for byte with a local `batch run`. Where the
// daemons cannot start (not root, packages missing) the test says why and skips; on this project's
// machines it runs (scripts/install-deps.sh installs slurm-wlm and munge).
#include "helpers/cli_run.h"
#include "helpers/tree_contents.h"

#include <QCryptographicHash>
#include <QDir>
#include <QDirIterator>
#include <QElapsedTimer>
#include <QFile>
#include <QProcess>
#include <QRegularExpression>
#include <QStandardPaths>
#include <QTemporaryDir>
#include <QThread>
#include <QtTest>

#include <csignal>
#include <unistd.h>

using namespace softtouch::test;

namespace {

const QString kPresets = QStringLiteral(SOFTTOUCH_SOURCE_DIR "/presets/");

struct Output {
    int exitCode = -1;
    QString text;
};

/// Runs a program with SLURM_CONF set, stdout and stderr together.
Output run(const QString& program, const QStringList& args, const QString& slurmConf, int timeoutMs = 60000) {
    QProcess p;
    QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
    env.insert("SLURM_CONF", slurmConf);
    p.setProcessEnvironment(env);
    p.setProcessChannelMode(QProcess::MergedChannels);
    p.start(program, args);
    if (!p.waitForFinished(timeoutMs)) {
        p.kill();
        p.waitForFinished();
        return {-1, program + " did not finish"};
    }
    return {p.exitStatus() == QProcess::NormalExit ? p.exitCode() : -1, QString::fromUtf8(p.readAll())};
}

/// The cluster's daemons, stopped when it goes out of scope (whatever the test's outcome).
class OneNodeSlurm {
public:
    explicit OneNodeSlurm(const QString& dir) : m_dir(dir) {}
    ~OneNodeSlurm() {
        for (const QString pidFile : {"slurmd.pid", "slurmctld.pid", "munged.pid"}) {
            QFile f(m_dir + "/" + pidFile);
            if (!f.open(QIODevice::ReadOnly))
                continue;
            const pid_t pid = f.readAll().trimmed().toInt();
            if (pid <= 0 || ::kill(pid, SIGTERM) != 0)
                continue;
            for (int i = 0; i < 100 && ::kill(pid, 0) == 0; ++i)  // gone before its folder is removed
                QThread::msleep(50);
        }
        QFile::setPermissions(m_dir + "/munge.key", QFileDevice::ReadOwner | QFileDevice::WriteOwner);
    }
    QString conf() const { return m_dir + "/slurm.conf"; }

    /// Starts munged, slurmctld and slurmd; empty on success, else why not.
    QString start() {
        char name[256] = {};
        ::gethostname(name, sizeof name - 1);
        const QString host = QString::fromLocal8Bit(name).section('.', 0, 0);
        QDir(m_dir).mkpath("state");
        QDir(m_dir).mkpath("spool");
        QFile key(m_dir + "/munge.key");
        if (!key.open(QIODevice::WriteOnly))
            return "cannot write the munge key";
        QFile random("/dev/urandom");
        random.open(QIODevice::ReadOnly);
        key.write(random.read(1024));
        key.close();
        key.setPermissions(QFileDevice::ReadOwner);
        const QString socket = m_dir + "/munge.socket";
        const Output munged = run("munged", {"--key-file=" + m_dir + "/munge.key", "--socket=" + socket,
                                             "--pid-file=" + m_dir + "/munged.pid", "--log-file=" + m_dir + "/munged.log",
                                             "--seed-file=" + m_dir + "/munge.seed", "--force"},
                                  conf());
        if (munged.exitCode != 0)
            return "munged did not start: " + munged.text;
        // Ports off the defaults and apart per process, so a second run or a real cluster does not clash.
        const int port = 20000 + int(::getpid() % 5000) * 2;
        QFile f(conf());
        if (!f.open(QIODevice::WriteOnly))
            return "cannot write slurm.conf";
        f.write(QString("ClusterName=softtouch\nSlurmctldHost=%1\nSlurmctldPort=%2\nSlurmdPort=%3\n"
                        "AuthType=auth/munge\nAuthInfo=socket=%4\nCredType=cred/munge\n"
                        "ProctrackType=proctrack/linuxproc\nTaskPlugin=task/none\nSelectType=select/cons_tres\n"
                        "SlurmUser=root\nSlurmdUser=root\nStateSaveLocation=%5/state\nSlurmdSpoolDir=%5/spool\n"
                        "SlurmctldPidFile=%5/slurmctld.pid\nSlurmdPidFile=%5/slurmd.pid\n"
                        "SlurmctldLogFile=%5/slurmctld.log\nSlurmdLogFile=%5/slurmd.log\nReturnToService=2\n"
                        "MpiDefault=none\nJobCompType=jobcomp/none\nAccountingStorageType=accounting_storage/none\n"
                        "NodeName=%1 CPUs=2 RealMemory=%6 State=UNKNOWN\nPartitionName=main Nodes=%1 Default=YES MaxTime=INFINITE State=UP\n")
                    .arg(host)
                    .arg(port)
                    .arg(port + 1)
                    .arg(socket, m_dir)
                    .arg(::sysconf(_SC_PHYS_PAGES) / (1048576 / ::sysconf(_SC_PAGESIZE)))
                    .toUtf8());
        f.close();
        if (const Output ctld = run("slurmctld", {"-c"}, conf()); ctld.exitCode != 0)
            return "slurmctld did not start: " + ctld.text;
        if (const Output d = run("slurmd", {}, conf()); d.exitCode != 0)
            return "slurmd did not start: " + d.text;
        QElapsedTimer clock;
        clock.start();
        while (clock.elapsed() < 60000) {
            const Output info = run("sinfo", {"-h", "-o", "%t"}, conf());
            if (info.exitCode == 0 && info.text.trimmed() == "idle")
                return {};
            QThread::msleep(250);
        }
        return "the node did not become idle within 60 s (see " + m_dir + "/slurmd.log)";
    }

private:
    QString m_dir;
};

}  // namespace

class TestFarmSlurm : public QObject {
    Q_OBJECT
private slots:
    void jobArrayBuildsTheLibraryALocalRunBuilds();
};

void TestFarmSlurm::jobArrayBuildsTheLibraryALocalRunBuilds() {
    for (const QString program : {"munged", "slurmctld", "slurmd", "sbatch", "squeue", "sinfo"})
        if (QStandardPaths::findExecutable(program).isEmpty())
            QSKIP(qPrintable("farm test skipped: " + program + " is not installed (packages slurm-wlm and munge)"));
    if (::geteuid() != 0)
        QSKIP("farm test skipped: starting slurmctld, slurmd and munged on this machine needs root");

    QTemporaryDir dir;
    OneNodeSlurm slurm(dir.filePath("cluster"));
    QDir().mkpath(dir.filePath("cluster"));
    QElapsedTimer clock;
    clock.start();
    const QString why = slurm.start();
    if (!why.isEmpty())
        QSKIP(qPrintable("farm test skipped: the cluster did not start: " + why));
    const qint64 startMs = clock.restart();

    const QString manifest = dir.filePath("fish.stbatch");
    QFile m(manifest);
    QVERIFY(m.open(QIODevice::WriteOnly));
    m.write(QString(R"({"format": "softtouch-batch", "version": 1,
        "scenes": ["%1scenes/angelfish-swim.softtouch", "%1scenes/guppy-swim.softtouch"],
        "presets": ["%1materials/jelly.stpreset", "%1materials/rubber.stpreset"], "clips": ["swim"],
        "formats": ["pc2", "glb"], "resources": {"cpusPerTask": 1, "memoryMB": 256, "minutes": 5}})")
                .arg(kPresets)
                .toUtf8());
    m.close();
    const QString farm = dir.filePath("farm");
    const Run written = runCli({"batch", "slurm", manifest, "--out", farm, "--library", dir.filePath("farmed")});
    QVERIFY2(written.exitCode == 0, qPrintable(written.err));

    const Output submitted = run("sbatch", {farm + "/softtouch-batch.sbatch"}, slurm.conf());
    const QRegularExpressionMatch id = QRegularExpression("Submitted batch job (\\d+)").match(submitted.text);
    QVERIFY2(submitted.exitCode == 0 && id.hasMatch(), qPrintable(submitted.text));
    while (clock.elapsed() < 300000) {
        const Output queue = run("squeue", {"-h", "-j", id.captured(1)}, slurm.conf());
        if (queue.exitCode == 0 && queue.text.trimmed().isEmpty())
            break;
        QThread::msleep(250);
    }
    const qint64 arrayMs = clock.restart();
    const QStringList logs = QDir(farm + "/logs").entryList(QDir::Files);
    QVERIFY2(logs.size() == 8, qPrintable(logs.join(", ")));

    const Output collected = run("bash", {farm + "/collect.sh"}, slurm.conf());
    QVERIFY2(collected.exitCode == 0 && collected.text.contains("8 of 8 jobs done and readable"), qPrintable(collected.text));

    clock.restart();
    QVERIFY(runCli({"batch", "run", manifest, "--library", dir.filePath("local"), "--jobs", "2"}).exitCode == 0);
    const qint64 localMs = clock.elapsed();
    const auto farmed = treeContents(dir.filePath("farmed")), local = treeContents(dir.filePath("local"));
    QCOMPARE(farmed.size(), 24);
    QVERIFY(farmed == local);
    qInfo("cluster up in %.1f s; 8-task array done in %.1f s; the same library locally (--jobs 2) in %.1f s",
          startMs / 1000.0, arrayMs / 1000.0, localMs / 1000.0);
}

QTEST_GUILESS_MAIN(TestFarmSlurm)
#include "test_farm_slurm.moc"

#pragma once
// Runs softtouch-cli from the end-to-end suites and collects what it printed.

#include <QProcess>
#include <QString>
#include <QStringList>
#include <QtGlobal>

namespace softtouch::test {

/// The built CLI.
inline const QString kCli = QStringLiteral(SOFTTOUCH_BIN_DIR "/softtouch-cli");

/// Exit code (-1 when it crashed) and the two output streams of one run.
struct Run {
    int exitCode = -1;
    QString out;
    QString err;
};

/// Runs the CLI to completion (5 minutes at most). `headless` removes DISPLAY and WAYLAND_DISPLAY, so
/// anything that renders must do so without a window system.
inline Run runCli(const QStringList& args, bool headless = false) {
    QProcess p;
    if (headless) {
        QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
        env.remove("DISPLAY");
        env.remove("WAYLAND_DISPLAY");
        p.setProcessEnvironment(env);
    }
    p.start(kCli, args);
    if (!p.waitForFinished(300000))
        qFatal("softtouch-cli did not finish");
    return {p.exitStatus() == QProcess::NormalExit ? p.exitCode() : -1, QString::fromUtf8(p.readAllStandardOutput()),
            QString::fromUtf8(p.readAllStandardError())};
}

}  // namespace softtouch::test

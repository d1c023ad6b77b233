// softtouch: the editor. Parses the command line and opens the main window on a project (the bundled
// default scene when none is given). `--screenshot FILE.png` renders one frame of the window, writes
// it and exits (docs and tests).
#include "app/editor_paths.h"
#include "ui/main_window.h"

#include <QApplication>
#include <QCommandLineParser>
#include <QDir>
#include <QSurfaceFormat>
#include <QTimer>

#include <cstdio>

int main(int argc, char** argv) {
    // The viewport needs OpenGL 3.3 core; ask for it before any context exists.
    QSurfaceFormat format;
    format.setVersion(3, 3);
    format.setProfile(QSurfaceFormat::CoreProfile);
    format.setDepthBufferSize(24);
    format.setSamples(4);
    QSurfaceFormat::setDefaultFormat(format);
    QApplication app(argc, argv);
    QApplication::setOrganizationName("SoftTouch");
    QApplication::setApplicationName("SoftTouch");
    QApplication::setApplicationVersion("0.1.0");

    QCommandLineParser parser;
    parser.setApplicationDescription("SoftTouch — cartoon soft-body animation on a mass-spring Bezier lattice");
    parser.addHelpOption();
    parser.addVersionOption();
    parser.addPositionalArgument("project", "Project to open (*.softtouch); the default scene when omitted.", "[PROJECT]");
    const QCommandLineOption screenshot("screenshot", "Render one frame of the window to FILE.png and exit.", "FILE.png");
    const QCommandLineOption mode("mode", "Viewport shading: shaded, wireframe or xray.", "MODE", "shaded");
    const QCommandLineOption seconds("seconds", "With --screenshot: simulate this long before the picture.", "S", "0");
    const QCommandLineOption noRecovery("no-recovery", "Do not offer an autosave left by a previous run.");
    parser.addOptions({screenshot, mode, seconds, noRecovery});
    parser.process(app);

    const QString project = parser.positionalArguments().value(0, softtouch::app::defaultScenePath());
    softtouch::ui::MainWindowOptions options;
    options.presetFolder = softtouch::app::presetFolder();
    softtouch::ui::MainWindow window(options);
    const QString shading = parser.value(mode);
    if (shading == "wireframe")
        window.viewport()->setShadeMode(softtouch::render::ShadeMode::Wireframe);
    else if (shading == "xray")
        window.viewport()->setShadeMode(softtouch::render::ShadeMode::XRay);
    else if (shading != "shaded") {
        std::fprintf(stderr, "softtouch: error: --mode must be shaded, wireframe or xray, got '%s'\n", qPrintable(shading));
        return 2;
    }
    window.show();

    if (parser.isSet(screenshot)) {
        // No dialogs in batch use: a bad project is a message and exit status 1.
        if (softtouch::Status s = window.document()->open(project); !s) {
            std::fprintf(stderr, "softtouch: error: %s\n", s.message().c_str());
            return 1;
        }
        window.simulation()->pause();
        window.simulation()->advance(parser.value(seconds).toDouble());
        QApplication::processEvents();
        window.refreshStatus();
        const QImage image = window.grab().toImage();
        if (!window.viewport()->renderProblem().isEmpty())
            std::fprintf(stderr, "softtouch: warning: %s\n", qPrintable(window.viewport()->renderProblem()));
        if (image.isNull() || !image.save(parser.value(screenshot))) {
            std::fprintf(stderr, "softtouch: error: cannot write %s\n", qPrintable(parser.value(screenshot)));
            return 1;
        }
        window.document()->undoStack()->setClean();
        return 0;
    }

    // A crashed or killed run leaves an autosave: offer it before opening anything else.
    if (parser.isSet(noRecovery) || !window.offerRecovery())
        window.openFile(project);
    return QApplication::exec();
}

// softtouch: the editor. Parses the command line and opens the main window on a project (the bundled
// default scene when none is given). `--screenshot FILE.png` and what goes with it are the editor's scripting
// for pictures, docs and tests (app/editor_script.h).
#include "app/editor_paths.h"
#include "app/editor_script.h"
#include "ui/main_window.h"

#include <QAction>
#include <QApplication>
#include <QCommandLineParser>
#include <QDockWidget>
#include <QSurfaceFormat>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <set>
#include <string>

namespace {

/// The names --tool takes: the tool actions' labels, lower case.
constexpr const char* kToolNames = "drag, paint, anchor, void, select, pose, lattice or collider";

/// Whether the command line asks only for text (help or version), which needs no window system.
bool asksForTextOnly(int argc, char** argv) {
    const std::set<std::string> text{"-h", "--help", "-?", "--help-all", "-v", "--version"};
    for (int i = 1; i < argc; ++i) {
        if (text.count(argv[i]))
            return true;
    }
    return false;
}

/// Whether Qt has a window system to open: a display named in the environment, or a platform chosen
/// explicitly (QT_QPA_PLATFORM, e.g. offscreen for tests, eglfs on a kiosk), which Qt then reports on itself.
bool hasWindowSystem() {
    for (const char* name : {"DISPLAY", "WAYLAND_DISPLAY", "QT_QPA_PLATFORM"}) {
        const char* value = std::getenv(name);
        if (value && *value)
            return true;
    }
    return false;
}

}  // namespace

int main(int argc, char** argv) {
    // The viewport needs OpenGL 3.3 core; ask for it before any context exists.
    QSurfaceFormat format;
    format.setVersion(3, 3);
    format.setProfile(QSurfaceFormat::CoreProfile);
    format.setDepthBufferSize(24);
    format.setSamples(4);
    QSurfaceFormat::setDefaultFormat(format);
    // --help and --version print text only, so they open no window system (they work over ssh). Anything else
    // needs a display; without one Qt would abort with a message about its xcb plugin, so say what to do.
    const bool textOnly = asksForTextOnly(argc, argv);
    if (!textOnly && !hasWindowSystem()) {
        std::fprintf(stderr, "softtouch: error: no display to open the editor on (DISPLAY and WAYLAND_DISPLAY are "
                             "unset). Run it in a desktop session, under 'xvfb-run -a softtouch --screenshot FILE.png "
                             "...' for a picture, or use softtouch-cli for headless work.\n");
        return 2;
    }
    const std::unique_ptr<QCoreApplication> app =
        textOnly ? std::make_unique<QCoreApplication>(argc, argv) : std::make_unique<QApplication>(argc, argv);
    QCoreApplication::setOrganizationName("SoftTouch");
    QCoreApplication::setApplicationName("SoftTouch");
    QCoreApplication::setApplicationVersion("0.1.0");

    QCommandLineParser parser;
    parser.setApplicationDescription("SoftTouch — cartoon soft-body animation on a mass-spring Bezier lattice");
    const QCommandLineOption helpOption = parser.addHelpOption();
    const QCommandLineOption versionOption = parser.addVersionOption();
    parser.addPositionalArgument("project", "Project to open (*.softtouch); the default scene when omitted.", "[PROJECT]");
    const QCommandLineOption mode("mode", "Viewport shading: shaded, wireframe or xray.", "MODE", "shaded");
    const QCommandLineOption dock("dock", "Bring a dock to the front: properties, presets, study.", "NAME");
    const QCommandLineOption autosaveFolder("autosave-folder", "Where autosaves go (default: the user's data folder).", "DIR");
    const QCommandLineOption autosaveSeconds("autosave-seconds", "Seconds between autosaves (default 60).", "S", "60");
    const QCommandLineOption noRecovery("no-recovery", "Do not offer an autosave left by a previous run.");
    const QCommandLineOption toolOption("tool", QString("The active tool: %1 (with --screenshot: its settings show in the "
                                                        "tool options bar).").arg(kToolNames), "NAME");
    const QCommandLineOption windowSize("window", "With --screenshot: the window's size, e.g. 1280x800.", "WxH");
    parser.addOptions({mode, dock, autosaveFolder, autosaveSeconds, noRecovery, toolOption, windowSize});
    const softtouch::app::EditorScript script;
    script.addOptions(parser);
    // parse(), not process(): process() exits with status 1 on an unknown option or a missing value, where
    // every SoftTouch program exits 2 on bad usage (docs/design/reliability.md).
    if (!parser.parse(QCoreApplication::arguments())) {
        std::fprintf(stderr, "softtouch: error: %s\nTry 'softtouch --help'.\n", qPrintable(parser.errorText()));
        return 2;
    }
    if (parser.isSet(helpOption))
        parser.showHelp(0);  // exits
    if (parser.isSet(versionOption))
        parser.showVersion();  // exits
    if (const QString problem = script.problem(parser); !problem.isEmpty()) {
        std::fprintf(stderr, "softtouch: error: %s\n", qPrintable(problem));
        return 2;
    }

    const QString project = parser.positionalArguments().value(0, softtouch::app::defaultScenePath());
    softtouch::ui::MainWindowOptions options;
    options.presetFolder = softtouch::app::presetFolder();
    options.webFolder = QString::fromStdString(softtouch::app::bundledFolder("web", "web").string());
    options.shaderFolder = QString::fromStdString(softtouch::app::bundledFolder("shaders", "io/shaders").string());
    options.autosaveFolder = parser.value(autosaveFolder);
    const double autosaveS = parser.value(autosaveSeconds).toDouble();
    if (!(autosaveS >= 0.05 && autosaveS <= 86400)) {
        std::fprintf(stderr, "softtouch: error: --autosave-seconds must be in [0.05, 86400], got '%s'\n",
                     qPrintable(parser.value(autosaveSeconds)));
        return 2;
    }
    options.autosaveMilliseconds = int(autosaveS * 1000.0);
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
    if (parser.isSet(windowSize)) {
        const QStringList wh = parser.value(windowSize).split('x');
        const int w = wh.value(0).toInt(), h = wh.value(1).toInt();
        if (wh.size() != 2 || w < 640 || h < 400 || w > 8192 || h > 8192) {
            std::fprintf(stderr, "softtouch: error: --window expects WIDTHxHEIGHT from 640x400 to 8192x8192, got '%s'\n",
                         qPrintable(parser.value(windowSize)));
            return 2;
        }
        window.resize(w, h);
    }
    window.show();
    if (parser.isSet(toolOption)) {
        // The tool actions are named "tool" + their label ("toolPaint"); triggering one is what a click does.
        const QString name = parser.value(toolOption);
        auto* action = window.findChild<QAction*>("tool" + name.left(1).toUpper() + name.mid(1).toLower());
        if (!action) {
            std::fprintf(stderr, "softtouch: error: --tool must be %s, got '%s'\n", kToolNames, qPrintable(name));
            return 2;
        }
        action->trigger();
    }
    if (parser.isSet(dock)) {
        auto* d = window.findChild<QDockWidget*>(parser.value(dock) + "Dock");
        if (!d) {
            std::fprintf(stderr, "softtouch: error: no dock named '%s'\n", qPrintable(parser.value(dock)));
            return 2;
        }
        d->raise();
    }

    if (script.wanted(parser))
        return script.run(window, parser, project);

    // A crashed or killed run leaves an autosave: offer it before opening anything else.
    if (parser.isSet(noRecovery) || !window.offerRecovery()) {
        const std::optional<QPointF> drag = script.drag(parser);
        if (window.openFile(project) && drag) {
            window.simulation()->pause();
            softtouch::app::dragTail(window, *drag, script.seconds(parser));
            window.simulation()->play();
        }
        if (const int n = script.shownMode(parser))
            softtouch::app::showMode(window, n, false);  // pauses the simulation
    }
    return QApplication::exec();
}

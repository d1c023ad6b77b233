// softtouch: the editor. Parses the command line and opens the main window on a project (the bundled
// default scene when none is given). `--screenshot FILE.png` renders one frame of the window, writes
// it and exits (docs and tests); `--show-mode N` presses the Properties' "Show" of mode N first;
// `--measure-study` presses the Speed vs accuracy dock's "Measure this scene" and waits for it.
#include "app/editor_paths.h"
#include "ui/main_window.h"
#include "ui/frame_ruler.h"
#include "ui/study_panel.h"
#include "ui/timeline_panel.h"

#include <QAction>
#include <QAbstractButton>
#include <QApplication>
#include <QCommandLineParser>
#include <QDir>
#include <QDockWidget>
#include <QEventLoop>
#include <QKeyEvent>
#include <QListWidget>
#include <QMouseEvent>
#include <QPushButton>
#include <QSurfaceFormat>
#include <QTimer>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <numbers>
#include <set>
#include <string>

namespace {

/// Types `keys` into the viewport, one key press and release each (letters, digits, '.' and '-'), as
/// the user would with the viewport focused; false, typing nothing, for any other character.
bool typeKeys(QWidget* viewport, const QString& keys) {
    std::vector<std::pair<int, QString>> events;
    for (const QChar c : keys) {
        const QChar upper = c.toUpper();
        if (upper >= 'A' && upper <= 'Z')
            events.emplace_back(Qt::Key_A + (upper.unicode() - 'A'), QString(c));
        else if (c >= '0' && c <= '9')
            events.emplace_back(Qt::Key_0 + (c.unicode() - '0'), QString(c));
        else if (c == '.')
            events.emplace_back(Qt::Key_Period, QString(c));
        else if (c == '-')
            events.emplace_back(Qt::Key_Minus, QString(c));
        else
            return false;
    }
    for (const auto& [key, text] : events) {
        QKeyEvent press(QEvent::KeyPress, key, Qt::NoModifier, text);
        QKeyEvent release(QEvent::KeyRelease, key, Qt::NoModifier, text);
        QApplication::sendEvent(viewport, &press);
        QApplication::sendEvent(viewport, &release);
    }
    return true;
}

/// The names --tool takes: the tool actions' labels, lower case.
constexpr const char* kToolNames = "drag, paint, anchor, void, select, pose, lattice or collider";

/// A scripted mouse gesture for pictures of the drag tool: press on the tail, move, hold while the
/// body follows, all recorded as a take (the same events a person's mouse sends).
void dragTail(softtouch::ui::MainWindow& window, const QPointF& offset, double seconds) {
    softtouch::ui::Viewport* view = window.viewport();
    const auto* sim = window.simulation()->simulation();
    if (!sim)
        return;
    // The mesh vertex nearest the tail's mid-line (u = 0.15, v = 0.5): a point on the surface.
    const softtouch::Lattice& lattice = sim->object(0).lattice;
    softtouch::Vec3 best(0.5, 0.5, 0.5);
    double bestDistance = 1e300;
    for (const softtouch::Vec3f& p : sim->object(0).mesh->positions) {
        const softtouch::Vec3 uvw = lattice.box().toParameters(p.cast<double>());
        const double d = std::hypot(uvw.x() - 0.15, uvw.y() - 0.5);
        if (d < bestDistance) {
            bestDistance = d;
            best = uvw;
        }
    }
    const QPointF from = view->toWidget(lattice.evaluate(best, sim->simulator(0).state().position));
    auto send = [view](QEvent::Type type, const QPointF& at, Qt::MouseButtons buttons) {
        QMouseEvent event(type, at, view->mapToGlobal(at), type == QEvent::MouseMove ? Qt::NoButton : Qt::LeftButton,
                          buttons, Qt::NoModifier);
        QApplication::sendEvent(view, &event);
    };
    window.simulation()->startRecording();
    send(QEvent::MouseButtonPress, from, Qt::LeftButton);
    window.simulation()->pause();
    for (int i = 1; i <= 10; ++i) {
        send(QEvent::MouseMove, from + offset * (i / 10.0), Qt::LeftButton);
        window.simulation()->advance(seconds / 10.0);
    }
    window.simulation()->stopRecording();
}

/// Presses the Properties' "Show" toggle of mode `n` (1-3), as a person would; false when the body has
/// no such mode. With `hold`, the view is frozen at the mode's largest displacement (a quarter cycle).
bool showMode(softtouch::ui::MainWindow& window, int n, bool hold) {
    auto* button = window.findChild<QPushButton*>(QStringLiteral("showMode%1").arg(n));
    if (!button || button->isHidden())
        return false;
    if (!button->isChecked())
        button->click();
    if (hold)
        window.viewport()->holdModeView(0.25 / softtouch::kModeDisplayHz);
    return window.viewport()->shownMode() == n;
}

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
    const QCommandLineOption screenshot("screenshot", "Render one frame of the window to FILE.png and exit.", "FILE.png");
    const QCommandLineOption mode("mode", "Viewport shading: shaded, wireframe or xray.", "MODE", "shaded");
    const QCommandLineOption seconds("seconds", "With --screenshot: simulate this long before the picture.", "S", "0");
    const QCommandLineOption drag("drag", "Record a take in which the mouse pulls the object's tail "
                                          "(lattice point u=0.15) by DX,DY pixels, held for --seconds.", "DX,DY");
    const QCommandLineOption dock("dock", "Bring a dock to the front: properties, presets, study.", "NAME");
    const QCommandLineOption cameraOption("camera", "With --screenshot: look from YAW,PITCH degrees (yaw about +y, 0 "
                                                    "looks along -z; negative pitch looks down), framing everything.",
                                          "YAW,PITCH");
    const QCommandLineOption showModeOption("show-mode", "Animate vibration mode N (1-3) of the object in the viewport "
                                                         "(with --screenshot: at its largest displacement).", "N");
    const QCommandLineOption measureStudy("measure-study", "With --screenshot: measure the scene in the Speed vs accuracy "
                                                           "dock first (add --dock study to see it).");
    const QCommandLineOption autosaveFolder("autosave-folder", "Where autosaves go (default: the user's data folder).", "DIR");
    const QCommandLineOption autosaveSeconds("autosave-seconds", "Seconds between autosaves (default 60).", "S", "60");
    const QCommandLineOption noRecovery("no-recovery", "Do not offer an autosave left by a previous run.");
    const QCommandLineOption toolOption("tool", QString("The active tool: %1 (with --screenshot: its settings show in the "
                                                        "tool options bar).").arg(kToolNames), "NAME");
    const QCommandLineOption selectOption("select", "With --screenshot: select these lattice nodes of the first object "
                                                    "(indices, comma-separated).", "NODES");
    const QCommandLineOption keysOption("keys", "With --screenshot: type these keys into the viewport last, e.g. 'rz30' "
                                                "(the pose tool's rotate about Z, 30°, shown under way).", "KEYS");
    const QCommandLineOption clipOption("clip", "With --screenshot: select this clip in the timeline and show FRAME of it "
                                                "(NAME or NAME@FRAME).", "NAME[@FRAME]");
    const QCommandLineOption windowSize("window", "With --screenshot: the window's size, e.g. 1280x800.", "WxH");
    const QCommandLineOption clickOption("click", "With --screenshot: press the button of this object name first, e.g. "
                                                  "compareSolid (Properties' Compare with the solid).", "NAME");
    parser.addOptions({screenshot, mode, seconds, drag, dock, cameraOption, showModeOption, measureStudy, autosaveFolder,
                       autosaveSeconds, noRecovery, toolOption, windowSize, selectOption, keysOption, clipOption,
                       clickOption});
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
    // Simulated before a screenshot, in the editor's own loop: beyond ten minutes it is a typo.
    constexpr double kMaxScreenshotSeconds = 600.0;
    bool secondsRead = false;
    const double simulatedSeconds = parser.value(seconds).toDouble(&secondsRead);
    if (!secondsRead || !(simulatedSeconds >= 0.0 && simulatedSeconds <= kMaxScreenshotSeconds)) {
        std::fprintf(stderr, "softtouch: error: --seconds must be a number of seconds in [0, %g], got '%s'\n",
                     kMaxScreenshotSeconds, qPrintable(parser.value(seconds)));
        return 2;
    }

    const QString project = parser.positionalArguments().value(0, softtouch::app::defaultScenePath());
    softtouch::ui::MainWindowOptions options;
    options.presetFolder = softtouch::app::presetFolder();
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

    if (parser.isSet(screenshot)) {
        // No dialogs in batch use: a bad project is a message and exit status 1.
        if (softtouch::Status s = window.document()->open(project); !s) {
            std::fprintf(stderr, "softtouch: error: %s\n", s.message().c_str());
            return 1;
        }
        window.simulation()->pause();
        if (parser.isSet(cameraOption)) {
            const QStringList c = parser.value(cameraOption).split(',');
            bool yawOk = false, pitchOk = false;
            const double yaw = c.value(0).toDouble(&yawOk), pitch = c.value(1).toDouble(&pitchOk);
            if (c.size() != 2 || !yawOk || !pitchOk || std::abs(pitch) >= 89.0) {
                std::fprintf(stderr, "softtouch: error: --camera expects YAW,PITCH in degrees (|pitch| < 89), got '%s'\n",
                             qPrintable(parser.value(cameraOption)));
                return 2;
            }
            window.viewport()->camera().yaw = yaw * std::numbers::pi / 180.0;
            window.viewport()->camera().pitch = pitch * std::numbers::pi / 180.0;
            window.viewport()->frameAll();
        }
        if (parser.isSet(drag)) {
            const QStringList d = parser.value(drag).split(',');
            bool xRead = false, yRead = false;
            if (d.size() == 2) {
                const double dx = d[0].toDouble(&xRead), dy = d[1].toDouble(&yRead);
                xRead = xRead && std::abs(dx) <= 1e5;
                yRead = yRead && std::abs(dy) <= 1e5;
            }
            if (!xRead || !yRead) {
                std::fprintf(stderr, "softtouch: error: --drag expects DX,DY in pixels (each within 1e5), got '%s'\n", qPrintable(parser.value(drag)));
                return 2;
            }
            QApplication::processEvents();
            dragTail(window, QPointF(d[0].toDouble(), d[1].toDouble()), simulatedSeconds);
        } else {
            window.simulation()->advance(simulatedSeconds);
        }
        QApplication::processEvents();
        if (parser.isSet(showModeOption) && !showMode(window, parser.value(showModeOption).toInt(), true)) {
            std::fprintf(stderr, "softtouch: error: the object has no mode '%s' to show (1-3)\n",
                         qPrintable(parser.value(showModeOption)));
            return 2;
        }
        if (parser.isSet(measureStudy)) {
            QEventLoop loop;
            QObject::connect(window.study(), &softtouch::ui::StudyPanel::finished, &loop, &QEventLoop::quit);
            window.study()->measure();
            if (window.study()->isMeasuring())
                loop.exec();
        }
        if (parser.isSet(clickOption)) {
            auto* button = window.findChild<QAbstractButton*>(parser.value(clickOption));
            if (!button || !button->isEnabled()) {
                std::fprintf(stderr, "softtouch: error: --click: no enabled button named '%s'\n",
                             qPrintable(parser.value(clickOption)));
                return 2;
            }
            button->click();
            QApplication::processEvents();
        }
        if (parser.isSet(clipOption)) {
            const QStringList parts = parser.value(clipOption).split('@');
            const auto& clips = window.document()->project().clips.clips;
            int index = -1;
            for (std::size_t c = 0; c < clips.size(); ++c)
                if (QString::fromStdString(clips[c].name) == parts.value(0))
                    index = int(c);
            bool frameOk = parts.size() == 1;
            const int frame = parts.size() > 1 ? parts[1].toInt(&frameOk) : 0;
            if (index < 0 || !frameOk || parts.size() > 2) {
                std::fprintf(stderr, "softtouch: error: --clip expects the name of a clip of the project, optionally "
                                     "@FRAME, got '%s'\n", qPrintable(parser.value(clipOption)));
                return 2;
            }
            window.timeline()->findChild<QListWidget*>("clips")->setCurrentRow(index);
            QApplication::processEvents();
            window.timeline()->showClipFrame(index, frame);
            window.timeline()->ruler()->setFrame(frame);
        }
        if (parser.isSet(selectOption)) {
            std::set<int> nodes;
            const auto* sim = window.simulation()->simulation();
            const int count = sim ? int(sim->simulator(0).state().position.size()) : 0;
            for (const QString& item : parser.value(selectOption).split(',')) {
                bool ok = false;
                const int n = item.trimmed().toInt(&ok);
                if (!ok || n < 0 || n >= count) {
                    std::fprintf(stderr, "softtouch: error: --select expects node indices from 0 to %d, got '%s'\n",
                                 count - 1, qPrintable(item));
                    return 2;
                }
                nodes.insert(n);
            }
            window.viewport()->setSelection(nodes);
        }
        if (parser.isSet(keysOption) && !typeKeys(window.viewport(), parser.value(keysOption))) {
            std::fprintf(stderr, "softtouch: error: --keys takes letters, digits, '.' and '-', got '%s'\n",
                         qPrintable(parser.value(keysOption)));
            return 2;
        }
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
    if (parser.isSet(noRecovery) || !window.offerRecovery()) {
        if (window.openFile(project) && parser.isSet(drag)) {
            const QStringList d = parser.value(drag).split(',');
            if (d.size() == 2) {
                window.simulation()->pause();
                dragTail(window, QPointF(d[0].toDouble(), d[1].toDouble()), simulatedSeconds);
                window.simulation()->play();
            }
        }
        if (parser.isSet(showModeOption))
            showMode(window, parser.value(showModeOption).toInt(), false);  // pauses the simulation
    }
    return QApplication::exec();
}

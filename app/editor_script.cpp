#include "app/editor_script.h"

#include "core/geometry/lattice.h"
#include "ui/frame_ruler.h"
#include "ui/properties_panel.h"
#include "ui/study_panel.h"
#include "ui/timeline_panel.h"

#include <QAbstractButton>
#include <QApplication>
#include <QEventLoop>
#include <QKeyEvent>
#include <QLabel>
#include <QListWidget>
#include <QMouseEvent>
#include <QPushButton>
#include <QTimer>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <set>
#include <utility>
#include <vector>

namespace softtouch::app {

namespace {

/// Simulated before a screenshot, in the editor's own loop: beyond ten minutes it is a typo.
constexpr double kMaxScreenshotSeconds = 600.0;

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

}  // namespace

EditorScript::EditorScript()
    : m_screenshot("screenshot", "Render one frame of the window to FILE.png and exit.", "FILE.png"),
      m_seconds("seconds", "With --screenshot: simulate this long before the picture.", "S", "0"),
      m_drag("drag", "Record a take in which the mouse pulls the object's tail (lattice point u=0.15) by DX,DY pixels, "
                     "held for --seconds.", "DX,DY"),
      m_camera("camera", "With --screenshot: look from YAW,PITCH degrees (yaw about +y, 0 looks along -z; negative "
                         "pitch looks down), framing everything.", "YAW,PITCH"),
      m_showMode("show-mode", "Animate vibration mode N (1-3) of the object in the viewport (with --screenshot: at its "
                              "largest displacement).", "N"),
      m_measureStudy("measure-study", "With --screenshot: measure the scene in the Speed vs accuracy dock first (add "
                                      "--dock study to see it)."),
      m_select("select", "With --screenshot: select these lattice nodes of the first object (indices, "
                         "comma-separated).", "NODES"),
      m_keys("keys", "With --screenshot: type these keys into the viewport last, e.g. 'rz30' (the pose tool's rotate "
                     "about Z, 30°, shown under way).", "KEYS"),
      m_clip("clip", "With --screenshot: select this clip in the timeline and show FRAME of it (NAME or NAME@FRAME).",
             "NAME[@FRAME]"),
      m_click("click", "With --screenshot: press the button of this object name first, e.g. compareSolid (Properties' "
                       "Compare with the solid).", "NAME") {}

void EditorScript::addOptions(QCommandLineParser& parser) const {
    parser.addOptions({m_screenshot, m_seconds, m_drag, m_camera, m_showMode, m_measureStudy, m_select, m_keys, m_clip,
                       m_click});
}

QString EditorScript::problem(const QCommandLineParser& parser) const {
    bool read = false;
    const double s = parser.value(m_seconds).toDouble(&read);
    if (!read || !(s >= 0.0 && s <= kMaxScreenshotSeconds))
        return QString("--seconds must be a number of seconds in [0, %1], got '%2'")
            .arg(kMaxScreenshotSeconds)
            .arg(parser.value(m_seconds));
    return {};
}

double EditorScript::seconds(const QCommandLineParser& parser) const { return parser.value(m_seconds).toDouble(); }

std::optional<QPointF> EditorScript::drag(const QCommandLineParser& parser) const {
    if (!parser.isSet(m_drag))
        return std::nullopt;
    const QStringList d = parser.value(m_drag).split(',');
    if (d.size() != 2)
        return std::nullopt;
    bool xRead = false, yRead = false;
    const double dx = d[0].toDouble(&xRead), dy = d[1].toDouble(&yRead);
    if (!xRead || !yRead || std::abs(dx) > 1e5 || std::abs(dy) > 1e5)
        return std::nullopt;
    return QPointF(dx, dy);
}

int EditorScript::shownMode(const QCommandLineParser& parser) const {
    return parser.isSet(m_showMode) ? parser.value(m_showMode).toInt() : 0;
}

int EditorScript::run(ui::MainWindow& window, const QCommandLineParser& parser, const QString& project) const {
    // No dialogs in batch use: a bad project is a message and exit status 1.
    if (Status s = window.document()->open(project); !s) {
        std::fprintf(stderr, "softtouch: error: %s\n", s.message().c_str());
        return 1;
    }
    window.simulation()->pause();
    if (parser.isSet(m_camera)) {
        const QStringList c = parser.value(m_camera).split(',');
        bool yawOk = false, pitchOk = false;
        const double yaw = c.value(0).toDouble(&yawOk), pitch = c.value(1).toDouble(&pitchOk);
        if (c.size() != 2 || !yawOk || !pitchOk || std::abs(pitch) >= 89.0) {
            std::fprintf(stderr, "softtouch: error: --camera expects YAW,PITCH in degrees (|pitch| < 89), got '%s'\n",
                         qPrintable(parser.value(m_camera)));
            return 2;
        }
        window.viewport()->camera().yaw = yaw * std::numbers::pi / 180.0;
        window.viewport()->camera().pitch = pitch * std::numbers::pi / 180.0;
        window.viewport()->frameAll();
    }
    if (parser.isSet(m_drag)) {
        const std::optional<QPointF> offset = drag(parser);
        if (!offset) {
            std::fprintf(stderr, "softtouch: error: --drag expects DX,DY in pixels (each within 1e5), got '%s'\n",
                         qPrintable(parser.value(m_drag)));
            return 2;
        }
        QApplication::processEvents();
        dragTail(window, *offset, seconds(parser));
    } else {
        window.simulation()->advance(seconds(parser));
    }
    QApplication::processEvents();
    if (parser.isSet(m_showMode) && !showMode(window, parser.value(m_showMode).toInt(), true)) {
        std::fprintf(stderr, "softtouch: error: the object has no mode '%s' to show (1-3)\n",
                     qPrintable(parser.value(m_showMode)));
        return 2;
    }
    if (parser.isSet(m_measureStudy)) {
        QEventLoop loop;
        QObject::connect(window.study(), &ui::StudyPanel::finished, &loop, &QEventLoop::quit);
        window.study()->measure();
        if (window.study()->isMeasuring())
            loop.exec();
    }
    if (parser.isSet(m_click)) {
        auto* button = window.findChild<QAbstractButton*>(parser.value(m_click));
        if (!button || !button->isEnabled()) {
            std::fprintf(stderr, "softtouch: error: --click: no enabled button named '%s'\n",
                         qPrintable(parser.value(m_click)));
            return 2;
        }
        button->click();
        QApplication::processEvents();
    }
    if (parser.isSet(m_clip)) {
        const QStringList parts = parser.value(m_clip).split('@');
        const auto& clips = window.document()->project().clips.clips;
        int index = -1;
        for (std::size_t c = 0; c < clips.size(); ++c)
            if (QString::fromStdString(clips[c].name) == parts.value(0))
                index = int(c);
        bool frameOk = parts.size() == 1;
        const int frame = parts.size() > 1 ? parts[1].toInt(&frameOk) : 0;
        if (index < 0 || !frameOk || parts.size() > 2) {
            std::fprintf(stderr, "softtouch: error: --clip expects the name of a clip of the project, optionally "
                                 "@FRAME, got '%s'\n", qPrintable(parser.value(m_clip)));
            return 2;
        }
        window.timeline()->findChild<QListWidget*>("clips")->setCurrentRow(index);
        QApplication::processEvents();
        window.timeline()->showClipFrame(index, frame);
        window.timeline()->ruler()->setFrame(frame);
    }
    if (parser.isSet(m_select)) {
        std::set<int> nodes;
        const auto* sim = window.simulation()->simulation();
        const int count = sim ? int(sim->simulator(0).state().position.size()) : 0;
        for (const QString& item : parser.value(m_select).split(',')) {
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
    if (parser.isSet(m_keys) && !typeKeys(window.viewport(), parser.value(m_keys))) {
        std::fprintf(stderr, "softtouch: error: --keys takes letters, digits, '.' and '-', got '%s'\n",
                     qPrintable(parser.value(m_keys)));
        return 2;
    }
    QApplication::processEvents();
    window.refreshStatus();
    const QImage image = window.grab().toImage();
    if (!window.viewport()->renderProblem().isEmpty())
        std::fprintf(stderr, "softtouch: warning: %s\n", qPrintable(window.viewport()->renderProblem()));
    if (image.isNull() || !image.save(parser.value(m_screenshot))) {
        std::fprintf(stderr, "softtouch: error: cannot write %s\n", qPrintable(parser.value(m_screenshot)));
        return 1;
    }
    window.document()->undoStack()->setClean();
    return 0;
}

void dragTail(ui::MainWindow& window, const QPointF& offset, double seconds) {
    ui::Viewport* view = window.viewport();
    const auto* sim = window.simulation()->simulation();
    if (!sim)
        return;
    // The mesh vertex nearest the tail's mid-line (u = 0.15, v = 0.5): a point on the surface.
    const Lattice& lattice = sim->object(0).lattice;
    Vec3 best(0.5, 0.5, 0.5);
    double bestDistance = 1e300;
    for (const Vec3f& p : sim->object(0).mesh->positions) {
        const Vec3 uvw = lattice.box().toParameters(p.cast<double>());
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

bool showMode(ui::MainWindow& window, int n, bool hold) {
    // The modes are analysed on a worker thread once the scene opens: their buttons appear when that is done.
    if (auto* modes = window.findChild<QLabel*>(QStringLiteral("modes")); modes && modes->property("analysing").toBool()) {
        QEventLoop loop;
        QObject::connect(window.properties(), &ui::PropertiesPanel::modesShown, &loop, &QEventLoop::quit);
        QTimer::singleShot(60000, &loop, &QEventLoop::quit);  // a bound, not a wait on a hung analysis
        loop.exec();
    }
    auto* button = window.findChild<QPushButton*>(QStringLiteral("showMode%1").arg(n));
    if (!button || button->isHidden())
        return false;
    if (!button->isChecked())
        button->click();
    if (hold)
        window.viewport()->holdModeView(0.25 / kModeDisplayHz);
    return window.viewport()->shownMode() == n;
}

}  // namespace softtouch::app

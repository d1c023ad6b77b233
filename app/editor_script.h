#pragma once
// The editor's scripting for pictures, docs and tests: `softtouch --screenshot FILE.png`, with what may go before
// the picture (simulated seconds, a recorded drag on the tail, a camera, a vibration mode shown, the study
// measured, a button pressed, a clip's frame, selected nodes, keys typed into the viewport). main() adds these
// options to its parser and, when --screenshot is given, runs the script on the window instead of the event
// loop. --drag and --show-mode also apply to an interactive start (dragTail(), showMode()).

#include "ui/main_window.h"

#include <QCommandLineOption>
#include <QCommandLineParser>
#include <QPointF>
#include <QString>

#include <optional>

namespace softtouch::app {

class EditorScript {
public:
    EditorScript();

    /// Adds the script's options to `parser`.
    void addOptions(QCommandLineParser& parser) const;

    /// What is wrong with the parsed options that can be told before a window opens (--seconds out of range);
    /// empty when nothing is.
    QString problem(const QCommandLineParser& parser) const;

    /// --screenshot was given.
    bool wanted(const QCommandLineParser& parser) const { return parser.isSet(m_screenshot); }

    /// Opens `project` in `window`, runs the script and writes the picture: the exit status (0; 1 when the project
    /// or the picture fails; 2 on a bad option, with the message on stderr).
    int run(ui::MainWindow& window, const QCommandLineParser& parser, const QString& project) const;

    /// Seconds simulated before the picture or during the drag (--seconds; 0 when not given).
    double seconds(const QCommandLineParser& parser) const;
    /// The --drag offset in pixels, when given and well formed.
    std::optional<QPointF> drag(const QCommandLineParser& parser) const;
    /// The --show-mode number, 0 when not given.
    int shownMode(const QCommandLineParser& parser) const;

private:
    QCommandLineOption m_screenshot, m_seconds, m_drag, m_camera, m_showMode, m_measureStudy, m_select, m_keys, m_clip,
        m_click;
};

/// A scripted mouse gesture for pictures of the drag tool: press on the tail, move by `offset` pixels, hold for
/// `seconds` while the body follows, all recorded as a take (the same events a person's mouse sends).
void dragTail(ui::MainWindow& window, const QPointF& offset, double seconds);

/// Presses the Properties' "Show" toggle of mode `n` (1-3), as a person would; false when the body has no such
/// mode. With `hold`, the view is frozen at the mode's largest displacement (a quarter cycle).
bool showMode(ui::MainWindow& window, int n, bool hold);

}  // namespace softtouch::app

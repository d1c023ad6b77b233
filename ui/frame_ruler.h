#pragma once
/// The timeline's frame ruler: frame numbers and ticks over the shown take or clip, the playhead at the
/// current frame, the in/out range a clip is cut from, and the keys of the pose keyframes as ticks that
/// can be selected, dragged to retime (Ctrl+drag copies) and deleted. Click or drag on the ruler to scrub.
/// It draws and reports; the timeline panel and the keys panel make the edits (one undo step each).

#include "core/authoring/keyframes.h"

#include <QWidget>

class QPainter;

#include <optional>
#include <utility>
#include <vector>

namespace softtouch::ui {

/// A key interpolation as the editor's menus name it ("Smooth", "Linear", "Constant (hold)").
QString keyInterpolationLabel(KeyInterpolation interpolation);

/// Draws a key as the ruler and the dope sheet show it, its shape saying how it moves on to the next: smooth a
/// diamond, linear a circle, constant a square. Selected keys are filled orange, keys not editable there grey.
void drawKeyGlyph(QPainter& painter, QPointF at, KeyInterpolation how, bool selected, bool editable = true);

class FrameRuler : public QWidget {
    Q_OBJECT
public:
    explicit FrameRuler(QWidget* parent = nullptr);

    /// Shows frames 0..lastFrame at `fps`, frame 0 being `originSeconds` of key time (a clip's start); the
    /// playhead goes back to frame 0 and the in/out range is cleared.
    void setSpan(int lastFrame, double fps, double originSeconds = 0.0);
    int lastFrame() const { return m_lastFrame; }
    double fps() const { return m_fps; }
    /// Key time of frame 0, seconds.
    double originSeconds() const { return m_origin; }
    /// The playhead's frame.
    int frame() const { return m_frame; }
    /// Scene (or key) time of `frame`, seconds: frames count from the shown clip's or take's start.
    double secondsOfFrame(int frame) const { return m_origin + frame / m_fps; }
    /// Moves the playhead (clamped to the span) without emitting frameChanged.
    void setFrame(int frame);

    /// The in/out range ([in, out), frames) a clip is cut from; std::nullopt hides it.
    void setInOut(std::optional<std::pair<int, int>> range);
    std::optional<std::pair<int, int>> inOut() const { return m_inOut; }

    /// A named stretch of time drawn on the span: a clip cut from the take on show, a base animation.
    struct Range {
        QString label;        ///< "swim", "base: Swim".
        double fromSeconds;   ///< Key time, like the keys.
        double toSeconds;
    };
    /// The stretches to draw (replacing those before).
    void setRanges(std::vector<Range> ranges);
    const std::vector<Range>& ranges() const { return m_ranges; }

    /// The keys to show, seconds of key time (in order), and how each moves on to the next (drawn as its shape:
    /// smooth a diamond, linear a circle, constant a square with a bar held to the next key; all smooth when
    /// not given).
    void setKeys(std::vector<double> seconds, std::vector<KeyInterpolation> interpolation = {});
    const std::vector<double>& keys() const { return m_keys; }
    /// What the row of key ticks is called in the gutter: the key set they belong to ("keys" until set).
    void setKeysLabel(const QString& label);
    const QString& keysLabel() const { return m_keysLabel; }
    /// The selected key (-1: none).
    int selectedKey() const { return m_selectedKey; }

    /// Room left of the frames, pixels, where the dope sheet under the ruler names its rows (0: none).
    void setGutter(double pixels);
    double gutter() const { return m_gutter; }
    /// Where frame f is drawn, pixels from the left; and the frame nearest to x.
    double xOfFrame(double f) const;
    int frameAt(double x) const;
    /// Where key k is drawn (its tick's centre).
    QPointF keyPoint(int k) const;
    /// The frame (fractional) at which `seconds` of key time is drawn.
    double frameOfSeconds(double seconds) const { return (seconds - m_origin) * m_fps; }

    QSize sizeHint() const override;
    QSize minimumSizeHint() const override;

signals:
    /// Another span is shown (setSpan): whatever is drawn on the ruler's frames is to be drawn again.
    void spanChanged();
    /// The playhead is at `frame`: scrubbed, played, stepped, or back at 0 on another span.
    void playheadMoved(int frame);
    /// The user scrubbed to `frame`.
    void frameChanged(int frame);
    /// A key tick was dropped at `seconds` (snapped to a frame): moved, or copied with Ctrl.
    void keyMoved(int index, double seconds, bool copy);
    /// The selected key is to be deleted (Delete or Backspace, or its right-click menu).
    void keyDeleted(int index);
    /// A key's right-click menu chose how it moves on to the next.
    void keyInterpolationChosen(int index, softtouch::KeyInterpolation interpolation);
    /// A key tick was clicked: show its pose.
    void keySelected(int index);
    /// An in or out handle was dragged.
    void inOutChanged(int in, int out);

protected:
    void paintEvent(QPaintEvent* event) override;
    void mousePressEvent(QMouseEvent* event) override;
    void mouseMoveEvent(QMouseEvent* event) override;
    void mouseReleaseEvent(QMouseEvent* event) override;
    void keyPressEvent(QKeyEvent* event) override;
    void contextMenuEvent(QContextMenuEvent* event) override;

private:
    enum class Drag { None, Scrub, Key, In, Out };
    /// The key tick under `pos`, -1 when none.
    int keyAt(const QPointF& pos) const;

    double m_gutter = 0.0;
    int m_lastFrame = 0;
    double m_fps = 24.0;
    double m_origin = 0.0;
    int m_frame = 0;
    std::optional<std::pair<int, int>> m_inOut;
    std::vector<double> m_keys;
    QString m_keysLabel = QStringLiteral("keys");
    std::vector<KeyInterpolation> m_interpolation;  ///< Per key.
    std::vector<Range> m_ranges;
    int m_selectedKey = -1;
    Drag m_drag = Drag::None;
    int m_dragFrame = 0;   ///< Where a dragged key or handle is now, frames.
    bool m_copy = false;   ///< The key drag started with Ctrl: a copy.
};

}  // namespace softtouch::ui

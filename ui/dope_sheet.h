#pragma once
/// The timeline's dope sheet, under its frame ruler and on the ruler's frame grid: a row per scene object with
/// its pose keys, and a row per keyed clip as the stretch of key time it plays (a loop marked so).
///
/// On the current object's row keys are selected (click, Shift+click, or a box dragged across them), moved
/// together (drag; Ctrl+drag copies), deleted (Delete) and given an interpolation (right-click). Another
/// object's row makes that object current; a clip's bar shows the clip, and its right-click menu makes it a
/// loop or a one-shot. In a dock too short for every row the wheel scrolls them, and a note says how many are
/// out of sight. It draws and reports; the keys panel and the timeline make each edit (one undo step).

#include "core/authoring/keyframes.h"

#include <QList>
#include <QWidget>

#include <optional>
#include <vector>

namespace softtouch::ui {

class FrameRuler;

class DopeSheet : public QWidget {
    Q_OBJECT
public:
    /// One row: a scene object's keys, or a keyed clip.
    struct Row {
        QString label;                               ///< The object's or clip's name.
        int object = -1;                             ///< The scene object whose keys these are, or -1.
        int clip = -1;                               ///< The clip of the library, or -1.
        bool current = false;                        ///< The object the tools act on: its keys are edited here.
        std::vector<double> keys;                    ///< Key times, seconds of key time, in order.
        std::vector<KeyInterpolation> interpolation; ///< Per key.
        double fromSeconds = 0.0, toSeconds = 0.0;   ///< A clip's stretch of key time.
        bool loop = false;                           ///< A clip that cycles.
    };

    /// Rows on `ruler`'s frames: its span, fps and key time of frame 0 place every key and clip.
    explicit DopeSheet(const FrameRuler* ruler, QWidget* parent = nullptr);

    /// The rows to show (replacing those before). The selection keeps the current object's keys still there.
    void setRows(std::vector<Row> rows);
    const std::vector<Row>& rows() const { return m_rows; }
    /// Indices of the selected keys of the current object's row, in order.
    QList<int> selectedKeys() const;
    /// Where key `key` of row `row` is drawn, and row `row`'s band.
    QPointF keyPoint(int row, int key) const;
    QRectF rowRect(int row) const;
    /// Where a clip row's bar is drawn.
    QRectF clipBar(int row) const;

    QSize sizeHint() const override;
    QSize minimumSizeHint() const override;

signals:
    /// The selected keys are to move by `seconds` (whole frames), or be copied there with Ctrl.
    void keysMoved(QList<int> keys, double seconds, bool copy);
    void keysDeleted(QList<int> keys);
    void keysInterpolationChosen(QList<int> keys, softtouch::KeyInterpolation interpolation);
    /// A key was clicked: its pose is the one to show.
    void keySelected(int key);
    /// Another object's row was clicked: it is to become current.
    void objectChosen(int object);
    /// A clip's bar was clicked: the clip is to be shown.
    void clipChosen(int clip);
    /// A clip's menu asked it to cycle (or not).
    void clipLoopChosen(int clip, bool loop);

protected:
    void paintEvent(QPaintEvent* event) override;
    void mousePressEvent(QMouseEvent* event) override;
    void mouseMoveEvent(QMouseEvent* event) override;
    void mouseReleaseEvent(QMouseEvent* event) override;
    void keyPressEvent(QKeyEvent* event) override;
    void contextMenuEvent(QContextMenuEvent* event) override;
    void wheelEvent(QWheelEvent* event) override;
    void resizeEvent(QResizeEvent* event) override;

private:
    /// Rows that fit the widget's height (at least one).
    int visibleRows() const;
    /// Keeps the first row shown within what can scroll.
    void clampScroll();
    double xOfSeconds(double seconds) const;
    int rowAt(double y) const;
    int keyAt(int row, const QPointF& pos) const;
    /// The current object's row, or -1.
    int currentRow() const;
    bool isSelected(double seconds) const;
    void select(const QList<int>& keys);

    const FrameRuler* m_ruler;
    std::vector<Row> m_rows;
    std::vector<double> m_selected;       ///< Key times of the current object's selected keys.
    enum class Drag { None, Keys, Box } m_drag = Drag::None;
    bool m_copy = false;
    QPointF m_pressAt;                    ///< Where the drag began.
    int m_dragFrames = 0;                 ///< How far the dragged keys would move, frames.
    std::optional<QRectF> m_box;          ///< The selection box being dragged.
    int m_firstRow = 0;                   ///< The row shown at the top (the wheel scrolls rows that do not fit).
};

}  // namespace softtouch::ui

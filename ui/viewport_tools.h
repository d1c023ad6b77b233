#pragma once
/// The viewport's tools, a class each (as Tiled's tools are): what a press of the left button, a move with it
/// held and its release do, and what the tool draws over the view meanwhile. The viewport (ui/viewport.h)
/// keeps what the tools share: the camera and its navigation (which takes the mouse first), picking, the
/// current object, the selection, pen pressure, and the pose tool's transforms (G/R/S), which the keyboard
/// starts too. A new tool is a class here and a line in makeViewportTool().

#include <QPointF>
#include <Qt>

#include <memory>

class QPainter;

namespace softtouch::ui {

class Viewport;
enum class Tool;

class ViewportTool {
public:
    explicit ViewportTool(Viewport& view) : m_view(view) {}
    virtual ~ViewportTool() = default;
    ViewportTool(const ViewportTool&) = delete;
    ViewportTool& operator=(const ViewportTool&) = delete;

    /// The left button went down at `pos` with `modifiers` held (no navigation, no transform under way).
    /// True when that starts a gesture the following moves and the release belong to.
    virtual bool press(const QPointF& pos, Qt::KeyboardModifiers modifiers) = 0;
    /// The cursor moved from `from` to `to` with the button held, during a gesture this tool started.
    virtual void move(const QPointF& from, const QPointF& to) {
        (void)from;
        (void)to;
    }
    /// The button came up at `pos`: the gesture ends.
    virtual void release(const QPointF& pos) { (void)pos; }
    /// The gesture is abandoned (another tool was chosen while the button was held): undo nothing, apply nothing.
    virtual void cancel() {}
    /// The pen's pressure or tilt changed during the gesture (Viewport::tabletEvent()).
    virtual void pressureChanged() {}
    /// Draws over the view during the gesture (a selection box).
    virtual void draw(QPainter& painter) const { (void)painter; }

protected:
    Viewport& m_view;
};

/// The tool behind `tool` (the toolbar's choice) for `view`.
std::unique_ptr<ViewportTool> makeViewportTool(Tool tool, Viewport& view);

}  // namespace softtouch::ui

#pragma once
/// How the main window's panels take the mouse and the keyboard, the way Blender's and Maya's do:
/// - the wheel over a number field, a drop-down or a slider changes its value only once that field has the
///   keyboard focus (clicked or tabbed to); without focus the wheel scrolls the panel under it, so an animator
///   scrolling Properties no longer edits whatever value passes under the pointer;
/// - a button takes the keyboard focus from Tab only, not from a click: a clicked button kept it, so after
///   Export…, Esc to close its dialog and Space to play, Space pressed Export… again. Dialogs keep theirs.

#include <QObject>

namespace softtouch::ui {

/// Installed once on the application (QCoreApplication::installEventFilter); removes itself when destroyed.
class PanelInputGuard : public QObject {
public:
    using QObject::QObject;

protected:
    bool eventFilter(QObject* watched, QEvent* event) override;
};

}  // namespace softtouch::ui

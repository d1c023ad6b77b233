#pragma once
/// The mouse wheel over a number field, a drop-down or a slider changes its value only once that field has
/// the keyboard focus (clicked or tabbed to). Without focus the wheel goes on to the panel under it, which
/// scrolls: an animator scrolling Properties no longer edits whatever value passes under the pointer.

#include <QObject>

namespace softtouch::ui {

/// Installed once on the application (QCoreApplication::installEventFilter); removes itself when destroyed.
class WheelGuard : public QObject {
public:
    using QObject::QObject;

protected:
    bool eventFilter(QObject* watched, QEvent* event) override;
};

}  // namespace softtouch::ui

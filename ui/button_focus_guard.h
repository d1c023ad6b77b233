#pragma once
/// Buttons of the main window take no keyboard focus from a click, only from Tab, as Blender's and Maya's do.
/// A clicked button kept the focus, so after Export…, Esc to close its dialog and Space to play, Space pressed
/// Export… again; now the keys stay with the view or panel they were in.

#include <QObject>

namespace softtouch::ui {

/// Installed once on the application (QCoreApplication::installEventFilter); removes itself when destroyed.
class ButtonFocusGuard : public QObject {
public:
    using QObject::QObject;

protected:
    bool eventFilter(QObject* watched, QEvent* event) override;
};

}  // namespace softtouch::ui

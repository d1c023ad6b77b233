#include "ui/button_focus_guard.h"

#include <QAbstractButton>
#include <QDialog>
#include <QEvent>
#include <QMainWindow>

namespace softtouch::ui {

bool ButtonFocusGuard::eventFilter(QObject* watched, QEvent* event) {
    // At polish (before a button is first shown) it sits in its window: the main window's buttons, docks and
    // bars included, and not a dialog's, whose buttons a keyboard user presses with Space.
    if (event->type() == QEvent::Polish)
        if (auto* button = qobject_cast<QAbstractButton*>(watched))
            if (qobject_cast<QMainWindow*>(button->window()) && (button->focusPolicy() & Qt::ClickFocus))
                button->setFocusPolicy(Qt::TabFocus);
    return false;
}

}  // namespace softtouch::ui

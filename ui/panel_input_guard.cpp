#include "ui/panel_input_guard.h"

#include <QAbstractButton>
#include <QAbstractScrollArea>
#include <QAbstractSlider>
#include <QAbstractSpinBox>
#include <QComboBox>
#include <QCoreApplication>
#include <QEvent>
#include <QMainWindow>
#include <QWidget>

namespace softtouch::ui {

bool PanelInputGuard::eventFilter(QObject* watched, QEvent* event) {
    // At polish (before a button is first shown) it sits in its window: the main window's buttons, docks and
    // bars included, and not a dialog's, whose buttons a keyboard user presses with Space.
    if (event->type() == QEvent::Polish) {
        if (auto* button = qobject_cast<QAbstractButton*>(watched))
            if (qobject_cast<QMainWindow*>(button->window()) && (button->focusPolicy() & Qt::ClickFocus))
                button->setFocusPolicy(Qt::TabFocus);
        return false;
    }
    if (event->type() != QEvent::Wheel)
        return false;
    auto* widget = qobject_cast<QWidget*>(watched);
    if (!widget || widget->hasFocus())
        return false;
    // A spin box's wheel reaches its line edit first; a scroll bar is a slider whose wheel must scroll.
    QWidget* field = widget;
    if (qobject_cast<QAbstractSpinBox*>(widget->parentWidget()))
        field = widget->parentWidget();
    const bool valueField = qobject_cast<QAbstractSpinBox*>(field) || qobject_cast<QComboBox*>(field) ||
                            (qobject_cast<QAbstractSlider*>(field) && !field->inherits("QScrollBar"));
    if (!valueField || field->hasFocus())
        return false;
    // The panel it sits in scrolls instead. Sent to that panel's viewport, not left to QApplication's
    // propagation, which offers a wheel to the parents only when it came from the window system.
    for (QWidget* parent = field->parentWidget(); parent; parent = parent->parentWidget()) {
        if (auto* area = qobject_cast<QAbstractScrollArea*>(parent)) {
            QCoreApplication::sendEvent(area->viewport(), event);
            break;
        }
    }
    return true;
}

}  // namespace softtouch::ui

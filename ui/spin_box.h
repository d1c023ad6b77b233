#pragma once
/// The editor's number fields: one edit per committed value (not per keystroke), with range, decimals,
/// unit suffix and step.

#include <QDoubleSpinBox>
#include <QSignalBlocker>
#include <QString>

namespace softtouch::ui {

/// A spin box over [lo, hi]; `maxWidth` > 0 caps its width (its size hint is sized for the range's
/// largest value, which is too wide for a toolbar when that is 1e9).
inline QDoubleSpinBox* makeSpinBox(double lo, double hi, int decimals, const QString& suffix, double step = 1.0,
                                   int maxWidth = 0) {
    auto* s = new QDoubleSpinBox;
    s->setRange(lo, hi);
    s->setDecimals(decimals);
    s->setSuffix(suffix);
    s->setSingleStep(step);
    s->setKeyboardTracking(false);  // one edit per committed value, not per keystroke
    if (maxWidth > 0)
        s->setMaximumWidth(maxWidth);
    return s;
}

/// Shows `value` in `box` without emitting valueChanged: a field refreshed from the document, not an edit.
inline void setQuietly(QDoubleSpinBox* box, double value) {
    const QSignalBlocker block(box);
    box->setValue(value);
}

}  // namespace softtouch::ui

// The viewport's own keys: one table that both dispatches them and lists them for Help ▸ Keyboard
// Shortcuts. They are not window shortcuts because they act on the view (the cursor's place, the
// selection, a transform under way); the window's single-letter tool shortcuts step aside for them
// (event(): ShortcutOverride) only while they apply.

#include "ui/viewport.h"

#include <QAbstractSpinBox>
#include <QApplication>
#include <QKeyEvent>
#include <QLineEdit>
#include <QPlainTextEdit>
#include <QTextEdit>

#include <algorithm>

namespace softtouch::ui {

std::vector<Viewport::KeyBinding> Viewport::keyBindings() {
    const auto transformWith = [this](TransformKind kind) {
        return [this, kind](QKeyEvent*) {
            if (m_tool != Tool::Pose)
                return false;
            if (m_transform) {  // another transform instead, from the same start (as Blender switches G to R)
                const QPointF cursor = m_transformCursor;
                cancelTransform();
                beginTransform(kind, cursor);
                updateTransform(m_lastPos);
            } else if (!beginTransform(kind, m_lastPos)) {
                emit hint(tr("Select nodes first: click one, or drag a box; Shift adds."));
            }
            return true;
        };
    };
    const auto holdAxis = [this](TransformAxis axis) {
        return [this, axis](QKeyEvent*) {
            m_transform->toggleAxis(axis);
            updateTransform(m_lastPos);
            return true;
        };
    };
    std::vector<KeyBinding> keys = {
        {{Qt::Key_F}, "F", tr("View: frame the selected nodes (all objects when none)"), false,
         [this](QKeyEvent*) { frameSelection(); return true; }},
        {{Qt::Key_1}, "1", tr("View: front"), false, [this](QKeyEvent*) { viewFront(); return true; }},
        {{Qt::Key_3}, "3", tr("View: side"), false, [this](QKeyEvent*) { viewSide(); return true; }},
        {{Qt::Key_7}, "7", tr("View: top"), false, [this](QKeyEvent*) { viewTop(); return true; }},
        {{Qt::Key_Delete, Qt::Key_Backspace}, "Delete", tr("Collider tool: remove the picked collider"), false,
         [this](QKeyEvent*) {
             if (m_tool != Tool::Collider || m_collider < 0)
                 return false;
             deleteCollider();
             return true;
         }},
        {{Qt::Key_G}, "G", tr("Pose tool: move the selected nodes"), false, transformWith(TransformKind::Move)},
        {{Qt::Key_R}, "R", tr("Pose tool: rotate the selected nodes"), false, transformWith(TransformKind::Rotate)},
        {{Qt::Key_S}, "S", tr("Pose tool: scale the selected nodes"), false, transformWith(TransformKind::Scale)},
        {{Qt::Key_G}, "G, R, S", tr("Pose transform: switch to move, rotate or scale"), true, transformWith(TransformKind::Move)},
        {{Qt::Key_R}, "", "", true, transformWith(TransformKind::Rotate)},
        {{Qt::Key_S}, "", "", true, transformWith(TransformKind::Scale)},
        {{Qt::Key_X}, "X, Y, Z", tr("Pose transform: hold to that world axis (again: free)"), true, holdAxis(TransformAxis::X)},
        {{Qt::Key_Y}, "", "", true, holdAxis(TransformAxis::Y)},
        {{Qt::Key_Z}, "", "", true, holdAxis(TransformAxis::Z)},
        {{Qt::Key_0, Qt::Key_1, Qt::Key_2, Qt::Key_3, Qt::Key_4, Qt::Key_5, Qt::Key_6, Qt::Key_7, Qt::Key_8, Qt::Key_9,
          Qt::Key_Period, Qt::Key_Minus},
         "0-9 . -", tr("Pose transform: type the amount (metres, degrees or a factor; - flips the sign)"), true,
         [this](QKeyEvent* event) {
             const QString text = event->text();
             if (text.size() != 1 || !m_transform->type(text.at(0).toLatin1()))
                 return false;
             updateTransform(m_lastPos);
             return true;
         }},
        {{Qt::Key_Backspace}, "Backspace", tr("Pose transform: erase the last typed character"), true,
         [this](QKeyEvent*) {
             m_transform->backspace();
             updateTransform(m_lastPos);
             return true;
         }},
        {{Qt::Key_Return, Qt::Key_Enter}, "Enter", tr("Pose transform: apply (or click)"), true,
         [this](QKeyEvent*) { applyTransform(); return true; }},
        {{Qt::Key_Escape}, "Esc", tr("Pose transform: cancel (or right-click)"), true,
         [this](QKeyEvent*) { cancelTransform(); return true; }},
    };
    return keys;
}

QList<QPair<QString, QString>> Viewport::keyTable() const {
    QList<QPair<QString, QString>> rows;
    for (const KeyBinding& k : m_keys)
        if (!k.shown.isEmpty())
            rows.append({tr("Viewport ▸ ") + k.what, k.shown});
    return rows;
}

namespace {

bool plainKey(const QKeyEvent* event) {
    return !(event->modifiers() & (Qt::ControlModifier | Qt::AltModifier | Qt::MetaModifier));
}

}  // namespace

void Viewport::keyPressEvent(QKeyEvent* event) {
    if (plainKey(event))
        for (const KeyBinding& k : m_keys)
            if (k.duringTransform == m_transform.has_value() &&
                std::find(k.keys.begin(), k.keys.end(), event->key()) != k.keys.end() && k.run(event))
                return;
    QOpenGLWidget::keyPressEvent(event);
}

bool Viewport::event(QEvent* e) {
    // While a transform is under way every plain key is the viewport's (Space must not start the
    // simulation under the pose); in the pose tool, G, R and S are (S is also the select tool's shortcut).
    if (e->type() == QEvent::ShortcutOverride) {
        auto* key = static_cast<QKeyEvent*>(e);
        const bool transformKey = key->key() == Qt::Key_G || key->key() == Qt::Key_R || key->key() == Qt::Key_S;
        if (plainKey(key) && (m_transform || (m_tool == Tool::Pose && transformKey))) {
            e->accept();
            return true;
        }
    }
    return QOpenGLWidget::event(e);
}

void Viewport::enterEvent(QEnterEvent* event) {
    const QWidget* typing = QApplication::focusWidget();
    const bool editing = typing && (qobject_cast<const QLineEdit*>(typing) || qobject_cast<const QAbstractSpinBox*>(typing) ||
                                    qobject_cast<const QTextEdit*>(typing) || qobject_cast<const QPlainTextEdit*>(typing));
    if (!editing && isActiveWindow())
        setFocus(Qt::MouseFocusReason);
    QOpenGLWidget::enterEvent(event);
}

}  // namespace softtouch::ui

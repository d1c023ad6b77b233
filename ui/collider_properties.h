#pragma once
/// The collider the collider tool picked, in numbers: its shape, centre, size (radius, half length, half
/// extents or scale, as its shape has them), restitution and friction, each field one undo step. Shown in the
/// properties dock while the collider tool has a collider picked; hidden otherwise.

#include "core/body/colliders.h"

#include <QGroupBox>

#include <array>
#include <functional>

class QDoubleSpinBox;
class QLabel;

namespace softtouch::ui {

class Document;
class Viewport;

class ColliderProperties : public QGroupBox {
    Q_OBJECT
public:
    ColliderProperties(Document* document, Viewport* viewport, QWidget* parent = nullptr);

    /// The collider shown (index into the world's colliders), -1 when none (then the box is hidden).
    int collider() const { return m_collider; }

private:
    /// Shows the viewport's current collider, or hides the box outside the collider tool or with none picked.
    void refresh();
    /// One field's edit: `change` applied to a copy of the collider, validated, then one undo step named `text`
    /// (refused with the reason in the box's note when the collider would be invalid).
    void edit(const QString& text, const std::function<void(Collider&)>& change);

    Document* m_document;
    Viewport* m_viewport;
    int m_collider = -1;
    QLabel* m_shape = nullptr;
    std::array<QDoubleSpinBox*, 3> m_centre{};
    QDoubleSpinBox* m_radius = nullptr;
    QDoubleSpinBox* m_halfLength = nullptr;
    std::array<QDoubleSpinBox*, 3> m_halfExtents{};
    QDoubleSpinBox* m_scale = nullptr;
    QDoubleSpinBox* m_restitution = nullptr;
    QDoubleSpinBox* m_friction = nullptr;
    QLabel* m_note = nullptr;
};

}  // namespace softtouch::ui

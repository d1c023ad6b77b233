#include "ui/collider_properties.h"

#include "ui/document.h"
#include "ui/edit_commands.h"
#include "ui/spin_box.h"
#include "ui/viewport.h"

#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>

namespace softtouch::ui {

namespace {

/// Three spin boxes side by side (x, y, z) for one vector field.
QWidget* row(std::array<QDoubleSpinBox*, 3>& boxes, double lo, double hi, const QString& suffix, const QString& what) {
    auto* widget = new QWidget;
    auto* layout = new QHBoxLayout(widget);
    layout->setContentsMargins(0, 0, 0, 0);
    const char* axes[] = {"x", "y", "z"};
    for (int a = 0; a < 3; ++a) {
        boxes[std::size_t(a)] = makeSpinBox(lo, hi, 3, suffix, 0.01, 110);
        boxes[std::size_t(a)]->setToolTip(QString("%1, %2").arg(what, axes[a]));
        layout->addWidget(boxes[std::size_t(a)]);
    }
    return widget;
}

}  // namespace

ColliderProperties::ColliderProperties(Document* document, Viewport* viewport, QWidget* parent)
    : QGroupBox(parent), m_document(document), m_viewport(viewport) {
    setObjectName("colliderProperties");
    auto* form = new QFormLayout(this);
    m_shape = new QLabel;
    form->addRow(tr("Shape"), m_shape);
    form->addRow(tr("Centre"), row(m_centre, -1e4, 1e4, tr(" m"), tr("Centre")));
    m_radius = makeSpinBox(1e-4, 1e4, 4, tr(" m"), 0.01);
    m_radius->setObjectName("colliderRadius");
    form->addRow(tr("Radius"), m_radius);
    m_halfLength = makeSpinBox(0, 1e4, 4, tr(" m"), 0.01);
    m_halfLength->setObjectName("colliderHalfLength");
    m_halfLength->setToolTip(tr("Half the length of the capsule's segment (its end spheres' centres are this far from the centre)."));
    form->addRow(tr("Half length"), m_halfLength);
    form->addRow(tr("Half extents"), row(m_halfExtents, 1e-4, 1e4, tr(" m"), tr("Half the box's edge")));
    m_scale = makeSpinBox(1e-4, 1e6, 4, QString(), 0.1);
    m_scale->setToolTip(tr("Uniform scale of the collider mesh."));
    form->addRow(tr("Scale"), m_scale);
    m_restitution = makeSpinBox(0, 1, 3, QString(), 0.05);
    m_restitution->setObjectName("colliderRestitution");
    m_restitution->setToolTip(tr("How much of its speed into the collider a body keeps bouncing off: 0 sticks, 1 elastic."));
    form->addRow(tr("Restitution"), m_restitution);
    m_friction = makeSpinBox(0, 10, 3, QString(), 0.05);
    m_friction->setObjectName("colliderFriction");
    m_friction->setToolTip(tr("Coulomb friction coefficient: 0 slides freely."));
    form->addRow(tr("Friction"), m_friction);
    m_note = new QLabel;
    m_note->setWordWrap(true);
    form->addRow(m_note);

    for (int a = 0; a < 3; ++a) {
        connect(m_centre[std::size_t(a)], &QDoubleSpinBox::valueChanged, this,
                [this, a](double v) { edit(tr("Move collider"), [&](Collider& c) { c.centre[a] = v; }); });
        connect(m_halfExtents[std::size_t(a)], &QDoubleSpinBox::valueChanged, this,
                [this, a](double v) { edit(tr("Resize collider"), [&](Collider& c) { c.halfExtents[a] = v; }); });
    }
    connect(m_radius, &QDoubleSpinBox::valueChanged, this,
            [this](double v) { edit(tr("Resize collider"), [&](Collider& c) { c.radius = v; }); });
    connect(m_halfLength, &QDoubleSpinBox::valueChanged, this,
            [this](double v) { edit(tr("Resize collider"), [&](Collider& c) { c.halfLength = v; }); });
    connect(m_scale, &QDoubleSpinBox::valueChanged, this,
            [this](double v) { edit(tr("Resize collider"), [&](Collider& c) { c.scale = v; }); });
    connect(m_restitution, &QDoubleSpinBox::valueChanged, this,
            [this](double v) { edit(tr("Set collider restitution"), [&](Collider& c) { c.restitution = v; }); });
    connect(m_friction, &QDoubleSpinBox::valueChanged, this,
            [this](double v) { edit(tr("Set collider friction"), [&](Collider& c) { c.friction = v; }); });

    connect(viewport, &Viewport::currentColliderChanged, this, &ColliderProperties::refresh);
    connect(viewport, &Viewport::toolChanged, this, &ColliderProperties::refresh);
    connect(document, &Document::worldChanged, this, &ColliderProperties::refresh);
    connect(document, &Document::sceneReplaced, this, &ColliderProperties::refresh);
    refresh();
}

void ColliderProperties::refresh() {
    const auto& colliders = m_document->scene().world.colliders;
    const int index = m_viewport->currentCollider();
    const bool shown = m_viewport->tool() == Tool::Collider && index >= 0 && std::size_t(index) < colliders.size();
    m_collider = shown ? index : -1;
    setVisible(shown);
    if (!shown)
        return;
    const Collider& c = colliders[std::size_t(index)];
    setTitle(tr("Collider %1").arg(index + 1));
    m_shape->setText(QString::fromUtf8(colliderShapeName(c.shape)));
    for (int a = 0; a < 3; ++a) {
        setQuietly(m_centre[std::size_t(a)], c.centre[a]);
        setQuietly(m_halfExtents[std::size_t(a)], c.halfExtents[a]);
    }
    setQuietly(m_radius, c.radius);
    setQuietly(m_halfLength, c.halfLength);
    setQuietly(m_scale, c.scale);
    setQuietly(m_restitution, c.restitution);
    setQuietly(m_friction, c.friction);
    // Only the sizes this shape has.
    auto* form = static_cast<QFormLayout*>(layout());
    const bool round = c.shape == ColliderShape::Sphere || c.shape == ColliderShape::Capsule;
    form->setRowVisible(m_radius, round);
    form->setRowVisible(m_halfLength, c.shape == ColliderShape::Capsule);
    form->setRowVisible(m_halfExtents[0]->parentWidget(), c.shape == ColliderShape::Box);
    form->setRowVisible(m_scale, c.shape == ColliderShape::Mesh);
}

void ColliderProperties::edit(const QString& text, const std::function<void(Collider&)>& change) {
    if (m_collider < 0)
        return;
    const WorldSettings& before = m_document->scene().world;
    if (std::size_t(m_collider) >= before.colliders.size())
        return;
    WorldSettings after = before;
    change(after.colliders[std::size_t(m_collider)]);
    if (Status s = after.colliders[std::size_t(m_collider)].validate(); !s) {
        m_note->setText(tr("Not applied: %1").arg(QString::fromStdString(s.message())));
        refresh();
        return;
    }
    m_note->clear();
    m_document->undoStack()->push(new WorldEditCommand(m_document, before, std::move(after), text));
}

}  // namespace softtouch::ui

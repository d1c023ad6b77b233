#include "ui/tool_options_bar.h"

#include "ui/spin_box.h"

#include <QComboBox>
#include <QDoubleSpinBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QPushButton>
#include <QSignalBlocker>
#include <QStackedWidget>
#include <QStandardItemModel>

#include <algorithm>

namespace softtouch::ui {

namespace {

/// A page of label/field pairs in one row.
class Row {
public:
    Row() : m_page(new QWidget), m_layout(new QHBoxLayout(m_page)) { m_layout->setContentsMargins(4, 0, 4, 0); }
    /// Adds "label [field]"; returns the label (nullptr without one) so that both can be hidden together.
    QLabel* add(const QString& label, QWidget* field) {
        QLabel* shown = label.isEmpty() ? nullptr : new QLabel(label);
        if (shown)
            m_layout->addWidget(shown);
        m_layout->addWidget(field);
        m_layout->addSpacing(4);
        return shown;
    }
    QWidget* page() {
        m_layout->addStretch();
        return m_page;
    }

private:
    QWidget* m_page;
    QHBoxLayout* m_layout;
};

}  // namespace

ToolOptionsBar::ToolOptionsBar(Document* document, Viewport* viewport, QWidget* parent)
    : QToolBar(tr("Tool options"), parent), m_document(document), m_viewport(viewport) {
    setObjectName("toolOptionsBar");
    m_pages = new QStackedWidget;
    const auto page = [this](Tool tool, QWidget* w) { m_pageOf[tool] = m_pages->addWidget(w); };
    page(Tool::Drag, buildDragPage());
    page(Tool::Paint, buildPaintPage());
    page(Tool::Anchor, buildAnchorPage());
    page(Tool::Void, hintPage(tr("Void: click a node to remove it and its springs; drag a box for many, Ctrl+box clears.")));
    page(Tool::Select, hintPage(tr("Select: click or drag a box; Shift adds. Set values and smooth in Properties ▸ Selected nodes.")));
    page(Tool::Pose, buildPosePage());
    page(Tool::Lattice, hintPage(tr("Lattice: drag to move the box; Shift+drag scales it, Ctrl+drag turns it.")));
    page(Tool::Collider, hintPage(tr("Collider: drag to move; Shift+drag scales, Delete removes. Edit ▸ Add Collider adds one.")));
    addWidget(m_pages);
    connect(viewport, &Viewport::toolChanged, this, &ToolOptionsBar::showTool);
    connect(document, &Document::sceneReplaced, this, &ToolOptionsBar::refresh);
    connect(document, &Document::materialChanged, this, &ToolOptionsBar::refresh);
    connect(document, &Document::latticeChanged, this, &ToolOptionsBar::refresh);
    showTool(viewport->tool());
}

QWidget* ToolOptionsBar::buildDragPage() {
    m_dragStiffness = makeSpinBox(0.01, 1e6, 2, tr(" N/m"), 5, 130);
    m_dragStiffness->setObjectName("dragStiffness");
    m_dragStiffness->setValue(m_viewport->dragSettings().stiffness);
    m_dragStiffness->setToolTip(tr("Stiffness of the mouse's spring; pen pressure scales it."));
    m_dragDamping = makeSpinBox(0, 1e4, 3, tr(" N·s/m"), 0.1, 130);
    m_dragDamping->setObjectName("dragDamping");
    m_dragDamping->setValue(m_viewport->dragSettings().damping);
    connect(m_dragStiffness, &QDoubleSpinBox::valueChanged, this, [this](double v) { m_viewport->dragSettings().stiffness = v; });
    connect(m_dragDamping, &QDoubleSpinBox::valueChanged, this, [this](double v) { m_viewport->dragSettings().damping = v; });
    Row row;
    row.add(tr("Drag Ks"), m_dragStiffness);
    row.add(tr("Kd"), m_dragDamping);
    return row.page();
}

QWidget* ToolOptionsBar::buildPaintPage() {
    m_brushField = new QComboBox;
    m_brushField->setObjectName("brushField");
    for (const MaterialChannel& channel : materialChannels())  // named by the shown material in refresh()
        m_brushField->addItem(QString::fromUtf8(channel.rangeFor(MaterialModel::Continuum).label), int(channel.id));
    m_brushField->setSizeAdjustPolicy(QComboBox::AdjustToMinimumContentsLengthWithIcon);
    m_brushField->setMinimumContentsLength(12);
    // Field widths are capped so the whole row fits a 1280-pixel window (test_editor checks it).
    m_brushValue = makeSpinBox(1e-6, 1e9, 3, QString(), 1, 120);
    m_brushValue->setObjectName("brushValue");
    m_brushValue->setValue(m_viewport->brush().value);
    m_brushRadius = makeSpinBox(1, 2000, 0, tr(" px"), 5, 80);
    m_brushRadius->setObjectName("brushRadius");
    m_brushRadius->setValue(m_viewport->brush().radiusPixels);
    m_brushStrength = makeSpinBox(0, 1, 2, QString(), 0.05, 70);
    m_brushStrength->setObjectName("brushStrength");
    m_brushStrength->setValue(m_viewport->brush().strength);
    m_brushFalloff = new QComboBox;
    m_brushFalloff->setObjectName("brushFalloff");
    m_brushFalloff->addItem(tr("Smooth"), int(BrushFalloff::Smooth));
    m_brushFalloff->addItem(tr("Linear"), int(BrushFalloff::Linear));
    m_brushFalloff->addItem(tr("Constant"), int(BrushFalloff::Constant));
    // The overlay's colours: the painted values' min – max (re-ranged by every stroke), or a fixed range
    // in which one colour keeps one value.
    m_colourRange = new QComboBox;
    m_colourRange->setObjectName("colourRange");
    m_colourRange->addItem(tr("Auto"));
    m_colourRange->addItem(tr("Fixed"));
    m_colourRange->setToolTip(tr("Auto: blue to red spans the painted minimum to maximum, re-ranged after every "
                                 "stroke. Fixed: one colour keeps one value (values outside show the end colours)."));
    m_colourLow = makeSpinBox(-1e9, 1e9, 4, QString(), 1, 110);
    m_colourLow->setObjectName("colourLow");
    m_colourHigh = makeSpinBox(-1e9, 1e9, 4, QString(), 1, 110);
    m_colourHigh->setObjectName("colourHigh");

    connect(m_brushField, &QComboBox::currentIndexChanged, this, [this] {
        m_viewport->setBrushField(PaintField(m_brushField->currentData().toInt()));
        m_brushFieldShown.reset();  // offer a value in the new field's unit
        refresh();
    });
    connect(m_brushValue, &QDoubleSpinBox::valueChanged, this, [this](double v) {
        m_viewport->brush().value = v;
        if (!m_offering)
            m_brushValueOffered = false;  // the user's own value: kept whatever the material does
    });
    connect(m_brushRadius, &QDoubleSpinBox::valueChanged, this, [this](double v) { m_viewport->brush().radiusPixels = v; });
    connect(m_brushStrength, &QDoubleSpinBox::valueChanged, this, [this](double v) { m_viewport->brush().strength = v; });
    connect(m_brushFalloff, &QComboBox::currentIndexChanged, this,
            [this] { m_viewport->brush().falloff = BrushFalloff(m_brushFalloff->currentData().toInt()); });
    connect(m_colourRange, &QComboBox::currentIndexChanged, this, [this](int index) {
        const PaintField field = m_viewport->brush().field;
        if (index == 0) {
            m_viewport->setColourRange(field, std::nullopt);
        } else if (!m_viewport->fixedColourRange(field)) {
            // Start from the painted range; a uniform map gets 0 – 2× its value, so it shows mid-grey and
            // softer or stiffer strokes show blue or red.
            auto [lo, hi] = m_viewport->colourRange(m_viewport->currentObject());
            if (!(hi > lo)) {
                lo = hi > 0.0 ? 0.0 : hi - 1.0;
                hi = hi > 0.0 ? 2.0 * hi : hi + 1.0;
            }
            m_viewport->setColourRange(field, std::pair(lo, hi));
        }
        showColourRange();
    });
    const auto setFixed = [this] {
        if (m_colourRange->currentIndex() == 1 && m_colourHigh->value() > m_colourLow->value())
            m_viewport->setColourRange(m_viewport->brush().field, std::pair(m_colourLow->value(), m_colourHigh->value()));
    };
    connect(m_colourLow, &QDoubleSpinBox::valueChanged, this, setFixed);
    connect(m_colourHigh, &QDoubleSpinBox::valueChanged, this, setFixed);
    Row row;
    row.add(tr("Paint"), m_brushField);
    row.add(tr("Value"), m_brushValue);
    row.add(tr("Radius"), m_brushRadius);
    row.add(tr("Strength"), m_brushStrength);
    row.add(tr("Falloff"), m_brushFalloff);
    row.add(tr("Colours"), m_colourRange);
    m_colourLowLabel = row.add(tr("Blue at"), m_colourLow);  // shown with a fixed range only
    m_colourHighLabel = row.add(tr("Red at"), m_colourHigh);
    return row.page();
}

QWidget* ToolOptionsBar::buildAnchorPage() {
    m_anchorMode = new QComboBox;
    m_anchorMode->setObjectName("anchorMode");
    m_anchorMode->addItem(tr("Pinned (never moves)"), int(AnchorMode::Pinned));
    m_anchorMode->addItem(tr("Heavy (mass × ratio)"), int(AnchorMode::Heavy));
    m_anchorMode->setCurrentIndex(m_anchorMode->findData(int(m_viewport->anchorMode())));
    connect(m_anchorMode, &QComboBox::currentIndexChanged, this,
            [this] { m_viewport->setAnchorMode(AnchorMode(m_anchorMode->currentData().toInt())); });
    Row row;
    row.add(tr("Anchor"), m_anchorMode);
    row.add(QString(), new QLabel(tr("Click a node, or drag a box; Ctrl+box clears.")));
    return row.page();
}

QWidget* ToolOptionsBar::buildPosePage() {
    auto* rest = new QPushButton(tr("Selected to rest"));
    rest->setObjectName("poseToRest");
    rest->setToolTip(tr("Put the selected nodes (all when none is selected) back at their rest positions: one undo step."));
    connect(rest, &QPushButton::clicked, m_viewport, &Viewport::restSelection);
    auto* asRest = new QPushButton(tr("Pose as rest shape"));
    asRest->setObjectName("poseAsRest");
    asRest->setToolTip(tr("Make the mesh keep this pose as its rest shape; the lattice returns to rest around it "
                          "(one undo step; the project stores the edit, the mesh file is untouched)."));
    connect(asRest, &QPushButton::clicked, m_viewport, &Viewport::applyPoseAsRest);
    Row row;
    row.add(QString(), new QLabel(tr("Pose: select nodes; G move · R rotate · S scale (X/Y/Z axis, type an amount, Enter "
                                     "applies, Esc cancels) or drag the gizmo's arrows, squares, rings. I keys.")));
    row.add(QString(), rest);
    row.add(QString(), asRest);
    return row.page();
}

QWidget* ToolOptionsBar::hintPage(const QString& text) {
    Row row;
    row.add(QString(), new QLabel(text));
    return row.page();
}

void ToolOptionsBar::showTool(Tool tool) {
    m_shown = tool;
    // The bar takes the shown page's width, not the widest page's (a stacked widget asks for the
    // largest of its pages, which set the window's minimum width).
    for (int i = 0; i < m_pages->count(); ++i)
        m_pages->widget(i)->setSizePolicy(i == m_pageOf.at(tool) ? QSizePolicy::Preferred : QSizePolicy::Ignored,
                                          QSizePolicy::Preferred);
    m_pages->setCurrentIndex(m_pageOf.at(tool));
    m_pages->adjustSize();
    refresh();
}

void ToolOptionsBar::refresh() {
    showColourRange();
    const Scene& scene = m_document->scene();
    const int object = m_viewport->currentObject();
    if (object < 0 || std::size_t(object) >= scene.objects.size())
        return;
    const LatticeMaterial& material = scene.objects[std::size_t(object)].material;
    // Goal weight paints how closely a node follows a base animation: offered only where an object has one (a
    // scene opened after one that had keeps no goal-weight brush and legend).
    const bool animated = std::any_of(scene.objects.begin(), scene.objects.end(),
                                      [](const SceneObject& o) { return bool(o.baseAnimation); });
    if (!animated && materialChannel(m_viewport->brush().field).needsBaseAnimation) {
        m_viewport->setBrushField(PaintField::Stiffness);
        m_brushFieldShown.reset();
    }
    const PaintField field = m_viewport->brush().field;
    {
        const QSignalBlocker block(m_brushField);
        // The fields by the names the legend and Properties use for this material ("Young's modulus", "density").
        for (int i = 0; i < m_brushField->count(); ++i) {
            const MaterialChannel& channel = materialChannel(PaintField(m_brushField->itemData(i).toInt()));
            QString name = QString::fromUtf8(channel.rangeFor(material.model).label);
            name[0] = name[0].toUpper();
            if (channel.needsBaseAnimation)
                name += tr(" (base animation)");
            m_brushField->setItemText(i, name);
            if (auto* items = qobject_cast<QStandardItemModel*>(m_brushField->model()); items && channel.needsBaseAnimation)
                items->item(i)->setEnabled(animated);
        }
        m_brushField->setCurrentIndex(m_brushField->findData(int(field)));
    }
    const auto [low, high] = paintableRange(field, material.model);
    m_brushValue->setRange(low, high);
    m_brushValue->setSuffix(QString(" ") + fieldUnit(field, material.model));
    // A brush value in kg means nothing on a density map: when the field or what its values mean changes, start
    // the brush at twice the field's mean (paint "stiffer", "heavier"); an offered value also follows the mean when
    // something other than a stroke of this brush changed it (a stroke would otherwise raise its own target).
    const auto& values = fieldValues(material, field);
    double mean = 0.0;
    for (double x : values)
        mean += x / double(values.size());
    const std::pair shown{field, material.model};
    const bool fieldChanged = m_brushFieldShown != shown;
    const bool materialMoved = m_brushValueOffered && !m_viewport->isPainting() && mean != m_offeredFromMean;
    if (fieldChanged || materialMoved) {
        m_brushFieldShown = shown;
        m_offering = true;
        if (materialChannel(field).scaling == ChannelScaling::Fraction)
            m_brushValue->setValue(1.0);  // a fraction: paint "keep this part's volume", "follow exactly"
        else if (mean > 0.0)
            m_brushValue->setValue(2.0 * mean);  // valueChanged carries it to the brush
        m_offering = false;
        m_brushValueOffered = true;
        m_offeredFromMean = mean;
    }
}

void ToolOptionsBar::showColourRange() {
    const auto fixed = m_viewport->fixedColourRange(m_viewport->brush().field);
    const QSignalBlocker blockRange(m_colourRange), blockLow(m_colourLow), blockHigh(m_colourHigh);
    m_colourRange->setCurrentIndex(fixed ? 1 : 0);
    const auto [lo, hi] = fixed ? *fixed : m_viewport->colourRange(m_viewport->currentObject());
    m_colourLow->setValue(lo);
    m_colourHigh->setValue(hi);
    for (QWidget* w : {static_cast<QWidget*>(m_colourLow), static_cast<QWidget*>(m_colourHigh),
                       static_cast<QWidget*>(m_colourLowLabel), static_cast<QWidget*>(m_colourHighLabel)})
        w->setVisible(bool(fixed));
}

}  // namespace softtouch::ui

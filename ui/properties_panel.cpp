#include "ui/properties_panel.h"

#include "ui/collider_properties.h"
#include "ui/edit_commands.h"
#include "ui/material_tuning.h"
#include "ui/spin_box.h"

#include "core/body/network_elasticity.h"
#include "core/modes/mode_accuracy.h"
#include "core/modes/solid_modes.h"

#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QGridLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QPointer>
#include <QPushButton>
#include <QSpinBox>
#include <QThreadPool>
#include <QVBoxLayout>

#include <algorithm>
#include <cmath>

namespace softtouch::ui {

PropertiesPanel::PropertiesPanel(Document* document, SimulationController* simulation, Viewport* viewport, QWidget* parent)
    : QWidget(parent), m_document(document), m_simulation(simulation), m_viewport(viewport) {
    auto* layout = new QVBoxLayout(this);
    layout->addWidget(new ColliderProperties(document, viewport));  // shown while the collider tool has one picked
    layout->addWidget(buildSimulation());
    // The current object's sections: hidden in a scene with no objects, where a line says how to add one. They keep
    // their room when hidden: the window sizes this dock while its first scene may still be empty, and a dock sized
    // without them cut their fields off once they showed.
    m_noObject = new QLabel(tr("No object yet: File ▸ Add Mesh… or Import Animated Mesh… puts a body in the scene."));
    m_noObject->setObjectName("noObjectHint");
    m_noObject->setWordWrap(true);
    m_noObject->setSizePolicy(QSizePolicy::Ignored, QSizePolicy::Preferred);  // wrapped to the dock, not widening it
    m_noObject->hide();
    layout->addWidget(m_noObject);
    m_objectSections = {buildMaterial(), buildLattice(), buildSelection()};
    for (QWidget* section : m_objectSections) {
        QSizePolicy policy = section->sizePolicy();
        policy.setRetainSizeWhenHidden(true);
        section->setSizePolicy(policy);
        layout->addWidget(section);
    }
    layout->addStretch();
    connect(document, &Document::sceneReplaced, this, [this] { m_modesShownFor = -1; });  // before refresh()
    connect(document, &Document::sceneReplaced, this, &PropertiesPanel::refresh);
    connect(document, &Document::materialChanged, this, &PropertiesPanel::refresh);
    connect(document, &Document::latticeChanged, this, &PropertiesPanel::refresh);
    connect(document, &Document::worldChanged, this, &PropertiesPanel::refresh);
    connect(viewport, &Viewport::selectionChanged, this, &PropertiesPanel::refresh);
    connect(viewport, &Viewport::brushFieldChanged, this, &PropertiesPanel::refresh);  // the selection's unit
    refresh();
}

QWidget* PropertiesPanel::buildSimulation() {
    auto* box = new QGroupBox(tr("Simulation"));
    auto* form = new QFormLayout(box);
    m_integrator = new QComboBox;
    m_integrator->setObjectName("integrator");
    for (const IntegratorInfo& scheme : kIntegrators)
        m_integrator->addItem(QString::fromUtf8(scheme.label.data(), qsizetype(scheme.label.size())), int(scheme.kind));
    m_integrator->setToolTip(tr("Speed against accuracy: docs/measurements/study.md measures each scheme."));
    form->addRow(tr("Integrator"), m_integrator);
    m_stepsPerSecond = makeSpinBox(10, 100000, 0, tr(" steps/s"), 10);
    m_stepsPerSecond->setObjectName("stepsPerSecond");
    m_stepsPerSecond->setToolTip(tr("Fixed time step as steps per simulated second. Explicit schemes substep "
                                    "automatically below their stability bound."));
    form->addRow(tr("Time step"), m_stepsPerSecond);
    m_gravity = new QCheckBox(tr("Gravity (9.81 m/s² down)"));
    form->addRow(m_gravity);
    m_groundPlane = new QCheckBox(tr("Ground plane under the object"));
    m_groundPlane->setObjectName("groundPlane");
    form->addRow(m_groundPlane);
    connect(m_groundPlane, &QCheckBox::toggled, this, [this](bool on) {
        if (m_refreshing)
            return;
        const Scene& scene = m_document->scene();
        double lowest = 0.0;
        for (std::size_t i = 0; i < scene.objects.size(); ++i)
            lowest = i == 0 ? scene.objects[i].mesh->bounds().min.y() : std::min(lowest, scene.objects[i].mesh->bounds().min.y());
        editWorld(on ? tr("Add ground plane") : tr("Remove planes"), kNoMerge, [on, lowest](WorldSettings& w) {
            w.planes.clear();
            if (on) {
                CollisionPlane ground;
                ground.point = Vec3(0, lowest, 0);
                ground.restitution = 0.3;
                w.planes.push_back(ground);
            }
        });
    });
    m_bodiesCollide = new QCheckBox(tr("Objects collide with each other"));
    m_bodiesCollide->setObjectName("bodiesCollide");
    m_bodiesCollide->setToolTip(tr("Off, objects pass through each other (an eye sunk into a head stays put)."));
    form->addRow(m_bodiesCollide);
    connect(m_bodiesCollide, &QCheckBox::toggled, this, [this](bool on) {
        if (m_refreshing)
            return;
        editWorld(on ? tr("Objects collide") : tr("Objects pass through"), kNoMerge,
                  [on](WorldSettings& w) { w.bodyCollisions.enabled = on; });
    });
    m_drivers = new QCheckBox(tr("Drivers act (swim, scripted drags)"));
    m_drivers->setChecked(true);
    form->addRow(m_drivers);
    m_live = new QLabel;
    m_live->setObjectName("liveReadout");
    m_live->setWordWrap(true);
    form->addRow(m_live);

    connect(m_integrator, &QComboBox::currentIndexChanged, this, [this] {
        if (m_refreshing)
            return;
        const auto kind = IntegratorKind(m_integrator->currentData().toInt());
        editWorld(tr("Set integrator"), kNoMerge, [kind](WorldSettings& w) { w.simulation.integrator = kind; });
    });
    connect(m_stepsPerSecond, &QDoubleSpinBox::valueChanged, this, [this](double hz) {
        if (!m_refreshing)
            editWorld(tr("Set time step"), kMergeTimeStep, [hz](WorldSettings& w) { w.simulation.dt = 1.0 / hz; });
    });
    connect(m_gravity, &QCheckBox::toggled, this, [this](bool on) {
        if (!m_refreshing)
            editWorld(on ? tr("Gravity on") : tr("Gravity off"), kNoMerge,
                      [on](WorldSettings& w) { w.gravity = on ? Vec3(0, -9.81, 0) : Vec3::Zero(); });
    });
    connect(m_drivers, &QCheckBox::toggled, m_simulation, &SimulationController::setDriversEnabled);
    return box;
}

QWidget* PropertiesPanel::buildMaterial() {
    auto* box = new QGroupBox(tr("Material"));
    auto* form = new QFormLayout(box);
    m_element = new QComboBox;
    m_element->setObjectName("element");
    m_element->addItem(tr("Springs (the paper's, fastest)"), int(BodyElement::Springs));
    m_element->addItem(tr("Solid (same modes on every lattice)"), int(BodyElement::Solid));
    m_element->setToolTip(tr("What simulates the material. Springs join neighbouring nodes: fast, but a coarse "
                             "lattice's higher modes are off and a B-spline's end cells stiffen it. The solid element "
                             "runs the material as a solid on the lattice's own basis: its modes stay within 5% from "
                             "4x4x4 up, at about 20 to 45 times the cost of a step. Needs a continuum material and no "
                             "voids, strain limits or volume preservation; not with XPBD."));
    form->addRow(tr("Element"), m_element);
    connect(m_element, &QComboBox::currentIndexChanged, this, [this] {
        if (m_refreshing)
            return;
        const auto element = BodyElement(m_element->currentData().toInt());
        editMaterial(element == BodyElement::Solid ? tr("Simulate as a solid") : tr("Simulate with springs"), kNoMerge,
                     [element](LatticeMaterial& m) { m.element = element; });
    });
    m_frequency = makeSpinBox(0.001, 1000, 3, tr(" Hz"), 0.1);
    m_frequency->setObjectName("frequency");
    m_frequency->setToolTip(tr("How fast the whole body wobbles: the frequency of its lowest vibration mode, with "
                               "its anchors and voids. Typing a value scales all stiffness (and damping, so the "
                               "damping ratios stay), keeping what was painted."));
    form->addRow(tr("Wobble (lowest mode)"), m_frequency);
    m_dampingRatio = makeSpinBox(0, 100, 4, QString(), 0.01);
    m_dampingRatio->setObjectName("dampingRatio");
    m_dampingRatio->setToolTip(tr("How quickly the lowest mode settles: 0 rings forever, 1 settles without overshoot. "
                                  "Typing a value scales node and spring damping together."));
    form->addRow(tr("Damping ratio"), m_dampingRatio);
    // The three lowest modes, each with a toggle that animates its shape in the viewport.
    auto* modeGrid = new QGridLayout;
    modeGrid->setContentsMargins(0, 0, 0, 0);
    modeGrid->setColumnStretch(0, 1);
    for (int m = 0; m < 3; ++m) {
        auto* row = new QLabel;
        row->setObjectName(QStringLiteral("mode%1").arg(m + 1));
        row->setWordWrap(true);
        row->setTextInteractionFlags(Qt::TextSelectableByMouse);
        // A word-wrapped label in a layout gets one line's height unless told otherwise.
        row->setMinimumHeight(row->fontMetrics().lineSpacing() * 2);
        auto* show = new QPushButton(tr("Show"));
        show->setObjectName(QStringLiteral("showMode%1").arg(m + 1));
        show->setCheckable(true);
        show->setToolTip(tr("Animate this mode's shape on the body in the viewport (at 1 Hz, whatever its "
                            "frequency). Display only: nothing is changed; Play or choosing another object stops it."));
        modeGrid->addWidget(row, m, 0);
        modeGrid->addWidget(show, m, 1, Qt::AlignTop);
        m_modeRows[std::size_t(m)] = row;
        m_modeShow[std::size_t(m)] = show;
        connect(show, &QPushButton::toggled, this, [this, m](bool on) {
            if (m_refreshing)
                return;
            if (on && std::size_t(m) < m_analysedModes.size())
                m_viewport->showMode(object(), m + 1, m_analysedModes[std::size_t(m)]);
            else if (!on && m_viewport->shownMode() == m + 1)
                m_viewport->stopModeView();
            if (on && m_viewport->shownMode() != m + 1) {  // nothing to show (no simulation)
                const QSignalBlocker block(m_modeShow[std::size_t(m)]);
                m_modeShow[std::size_t(m)]->setChecked(false);
            }
        });
    }
    form->addRow(modeGrid);
    // The toggles follow the viewport: one mode at a time, off when the view stops.
    connect(m_viewport, &Viewport::modeViewChanged, this, [this](int, int index) {
        for (int m = 0; m < 3; ++m) {
            const QSignalBlocker block(m_modeShow[std::size_t(m)]);
            m_modeShow[std::size_t(m)]->setChecked(index == m + 1);
            m_modeShow[std::size_t(m)]->setText(index == m + 1 ? tr("Stop") : tr("Show"));
        }
    });
    m_modes = new QLabel;
    m_modes->setObjectName("modes");
    m_modes->setWordWrap(true);
    m_modes->setTextInteractionFlags(Qt::TextSelectableByMouse);
    // Room for a rigid-mode note and the integrator's effect, which wraps once or twice.
    m_modes->setMinimumHeight(m_modes->fontMetrics().lineSpacing() * 4);
    form->addRow(m_modes);
    // The lattice's own error: its modes against the solid the material describes, solved without it.
    m_compareSolid = new QPushButton(tr("Compare with the solid"));
    m_compareSolid->setObjectName("compareSolid");
    m_compareSolid->setToolTip(tr("Solve the painted material as a solid, without the lattice (a tenth of a second), "
                                  "and show how far each of the lattice's modes is from it: what a finer lattice "
                                  "would change. Display only; the next edit clears it."));
    connect(m_compareSolid, &QPushButton::clicked, this, &PropertiesPanel::compareWithSolid);
    m_solid = new QLabel;
    m_solid->setObjectName("solidModes");
    m_solid->setWordWrap(true);
    m_solid->setTextInteractionFlags(Qt::TextSelectableByMouse);
    // A word-wrapped label in a form gets one line's height unless told otherwise; the text wraps to three.
    m_solid->setMinimumHeight(m_solid->fontMetrics().lineSpacing() * 3);
    form->addRow(m_compareSolid);
    form->addRow(m_solid);
    m_totalMass = makeSpinBox(1e-6, 1e6, 4, tr(" kg"), 0.1);
    form->addRow(tr("Total mass"), m_totalMass);
    m_stiffness = makeSpinBox(1e-3, 1e12, 2, tr(" N/m"), 5);
    m_stiffness->setObjectName("stiffness");
    form->addRow(tr("Stiffness (mean)"), m_stiffness);
    m_damping = makeSpinBox(0, 1e9, 3, tr(" N·s/m"), 0.05);
    m_damping->setToolTip(tr("Spring damping: resists the relative velocity of a spring's two nodes, so it calms "
                             "wobble but never slows the body as a whole. Stronger on faster modes."));
    form->addRow(tr("Spring damping (mean)"), m_damping);
    m_nodeDamping = makeSpinBox(0, 1e6, 4, tr(" N·s/m"), 0.01);
    m_nodeDamping->setObjectName("nodeDamping");
    m_nodeDamping->setToolTip(tr("Node damping (the paper's D, its 'damper'): resists each node's absolute velocity, "
                                 "like moving through water, so a released body comes to rest. Stronger on slower modes."));
    form->addRow(tr("Node damping (mean)"), m_nodeDamping);
    auto* aniso = new QHBoxLayout;
    const char* axes[] = {"u", "v", "w"};
    for (int a = 0; a < 3; ++a) {
        m_anisotropy[std::size_t(a)] = makeSpinBox(1e-6, 1e6, 3, QString(), 0.1);
        m_anisotropy[std::size_t(a)]->setPrefix(QString(axes[a]) + " ");
        // Sized for the values shown, not for the range's widest (1e6 with three decimals): three of
        // those made the Material group wider than the dock and pushed its right column out of view.
        m_anisotropy[std::size_t(a)]->setMinimumWidth(80);
        aniso->addWidget(m_anisotropy[std::size_t(a)]);
        connect(m_anisotropy[std::size_t(a)], &QDoubleSpinBox::valueChanged, this, [this, a](double s) {
            if (!m_refreshing)
                editMaterial(tr("Set anisotropy"), kMergeAnisotropy, [a, s](LatticeMaterial& m) { m.anisotropy[a] = s; });
        });
    }
    form->addRow(tr("Anisotropy"), aniso);
    // Stretch and squash limits (core/body/strain_limits.h): each spin box's minimum, just below the limit's
    // range, reads "off".
    m_stretchLimit = makeSpinBox(1.0, kMaxStretchLimit, 2, tr(" × rest"), 0.05);
    m_stretchLimit->setObjectName("stretchLimit");
    m_stretchLimit->setSpecialValueText(tr("off"));
    m_stretchLimit->setToolTip(tr("No spring of the lattice gets longer than this many times its rest length, "
                                  "however hard it is pulled (a constraint after every step; it only ever takes energy out)."));
    form->addRow(tr("Stretch limit"), m_stretchLimit);
    m_squashLimit = makeSpinBox(0.0, kMaxSquashLimit, 2, tr(" × rest"), 0.05);
    m_squashLimit->setObjectName("squashLimit");
    m_squashLimit->setSpecialValueText(tr("off"));
    m_squashLimit->setToolTip(tr("No spring of the lattice gets shorter than this fraction of its rest length."));
    form->addRow(tr("Squash limit"), m_squashLimit);
    m_volumePreservation = makeSpinBox(0.0, 1.0, 2, QString(), 0.1);
    m_volumePreservation->setObjectName("volumePreservation");
    m_volumePreservation->setSpecialValueText(tr("off"));
    m_volumePreservation->setToolTip(tr("Keeps the mesh's volume: a squashed body bulges sideways. 0.5 resists a "
                                        "volume change as much as the springs resist a stretch, 0.9 nine times as "
                                        "much, 1 holds it exactly. Paint it (Paint tool, Volume preservation) to keep "
                                        "some parts and let others squash; this sets the largest painted value and "
                                        "scales the others with it."));
    form->addRow(tr("Volume preservation (largest)"), m_volumePreservation);
    connect(m_volumePreservation, &QDoubleSpinBox::valueChanged, this, [this](double p) {
        if (!m_refreshing)
            editMaterial(tr("Set volume preservation"), kMergeVolume, [p](LatticeMaterial& m) { setLargestVolumePreservation(m, p); });
    });
    connect(m_stretchLimit, &QDoubleSpinBox::valueChanged, this, [this](double x) {
        if (!m_refreshing)
            editMaterial(tr("Set stretch limit"), kMergeStrainLimits,
                         [x](LatticeMaterial& m) { m.strainLimits.stretch = x < kMinStretchLimit ? 0.0 : x; });
    });
    connect(m_squashLimit, &QDoubleSpinBox::valueChanged, this, [this](double x) {
        if (!m_refreshing)
            editMaterial(tr("Set squash limit"), kMergeStrainLimits,
                         [x](LatticeMaterial& m) { m.strainLimits.squash = x < kMinSquashLimit ? 0.0 : x; });
    });

    connect(m_frequency, &QDoubleSpinBox::valueChanged, this, [this](double hz) {
        if (!m_refreshing)
            editMaterial(tr("Set wobble frequency"), kMergeFrequency,
                         [hz, lattice = currentLattice(), follow = currentFollow()](LatticeMaterial& m) {
                             setFrequency(lattice, m, hz, follow ? &*follow : nullptr);
                         });
    });
    connect(m_dampingRatio, &QDoubleSpinBox::valueChanged, this, [this](double z) {
        if (!m_refreshing)
            editMaterial(tr("Set damping ratio"), kMergeDamping,
                         [z, lattice = currentLattice(), follow = currentFollow()](LatticeMaterial& m) {
                             setDampingRatio(lattice, m, z, follow ? &*follow : nullptr);
                         });
    });
    connect(m_totalMass, &QDoubleSpinBox::valueChanged, this, [this](double kg) {
        if (m_refreshing)
            return;
        editMaterial(tr("Set mass"), kMergeMass, [kg, lattice = currentLattice()](LatticeMaterial& m) {
            const double total = summarise(lattice, m).totalMass;
            if (total > 0.0)
                for (double& x : m.mass)
                    x *= kg / total;
        });
    });
    connect(m_stiffness, &QDoubleSpinBox::valueChanged, this, [this](double k) {
        if (!m_refreshing)
            editMaterial(tr("Set stiffness"), kMergeStiffness, [k](LatticeMaterial& m) { setMean(m.stiffness, m, k); });
    });
    connect(m_damping, &QDoubleSpinBox::valueChanged, this, [this](double c) {
        if (!m_refreshing)
            editMaterial(tr("Set spring damping"), kMergeDamping, [c](LatticeMaterial& m) { setMean(m.damping, m, c); });
    });
    connect(m_nodeDamping, &QDoubleSpinBox::valueChanged, this, [this](double d) {
        if (!m_refreshing)
            editMaterial(tr("Set node damping"), kMergeDamping,
                         [d](LatticeMaterial& m) { setMean(m.nodeDamping, m, d); });
    });
    return box;
}

QWidget* PropertiesPanel::buildLattice() {
    auto* box = new QGroupBox(tr("Lattice"));
    auto* form = new QFormLayout(box);
    m_latticeKind = new QComboBox;
    m_latticeKind->addItem(tr("Bezier (the paper's)"), int(LatticeKind::Bezier));
    m_latticeKind->addItem(tr("Cubic B-spline (local)"), int(LatticeKind::BSpline));
    form->addRow(tr("Kind"), m_latticeKind);
    auto* nodes = new QHBoxLayout;
    for (int a = 0; a < 3; ++a) {
        m_latticeNodes[std::size_t(a)] = new QSpinBox;
        m_latticeNodes[std::size_t(a)]->setRange(2, 64);
        nodes->addWidget(m_latticeNodes[std::size_t(a)]);
    }
    form->addRow(tr("Nodes u, v, w"), nodes);
    auto* apply = new QPushButton(tr("Apply resolution"));
    apply->setToolTip(tr("Rebuilds the lattice; painted values, anchors and voids are carried over."));
    form->addRow(apply);
    connect(apply, &QPushButton::clicked, this, &PropertiesPanel::applyLatticeShape);

    auto* move = new QHBoxLayout;
    const char* axes[] = {"x", "y", "z"};
    for (int a = 0; a < 3; ++a) {
        m_latticeMove[std::size_t(a)] = makeSpinBox(-1e4, 1e4, 3, QString(), 0.01);
        m_latticeMove[std::size_t(a)]->setPrefix(QString(axes[a]) + " ");
        move->addWidget(m_latticeMove[std::size_t(a)]);
    }
    form->addRow(tr("Move by (m)"), move);
    m_latticeScale = makeSpinBox(0.01, 100, 3, tr(" ×"), 0.05);
    m_latticeScale->setValue(1.0);
    form->addRow(tr("Scale by"), m_latticeScale);
    m_latticeTurn = makeSpinBox(-360, 360, 1, tr("°"), 5);
    form->addRow(tr("Turn about y"), m_latticeTurn);
    auto* placement = new QHBoxLayout;
    auto* transform = new QPushButton(tr("Transform"));
    transform->setToolTip(tr("Moves, scales and turns the lattice box about its centre; the mesh is rebound to it."));
    auto* fit = new QPushButton(tr("Fit to object"));
    fit->setToolTip(tr("Resets the box to the object's padded bounds."));
    auto* voids = new QPushButton(tr("Auto void"));
    voids->setObjectName("autoVoid");
    voids->setToolTip(tr("Marks nodes whose cells hold none of the mesh as void (removed with their springs)."));
    placement->addWidget(transform);
    placement->addWidget(fit);
    placement->addWidget(voids);
    form->addRow(placement);
    connect(transform, &QPushButton::clicked, this, &PropertiesPanel::transformLattice);
    connect(fit, &QPushButton::clicked, this, &PropertiesPanel::fitLattice);
    connect(voids, &QPushButton::clicked, this, &PropertiesPanel::autoVoid);
    return box;
}

QWidget* PropertiesPanel::buildSelection() {
    auto* box = new QGroupBox(tr("Selected nodes"));
    auto* form = new QFormLayout(box);
    m_selectionLabel = new QLabel;
    form->addRow(m_selectionLabel);
    m_selectionValue = makeSpinBox(1e-9, 1e9, 4, QString(), 1);
    form->addRow(tr("Value"), m_selectionValue);
    auto* buttons = new QHBoxLayout;
    auto* set = new QPushButton(tr("Set"));
    auto* smooth = new QPushButton(tr("Smooth"));
    buttons->addWidget(set);
    buttons->addWidget(smooth);
    form->addRow(buttons);
    auto nodes = [this] { return std::vector<int>(m_viewport->selection().begin(), m_viewport->selection().end()); };
    connect(set, &QPushButton::clicked, this, [this, nodes] {
        const PaintField field = m_viewport->brush().field;
        const double value = m_selectionValue->value();
        const std::vector<int> n = nodes();
        if (!n.empty())
            editMaterial(tr("Set %1 of %n node(s)", nullptr, int(n.size())).arg(fieldName(field, currentModel())), kNoMerge,
                         [&](LatticeMaterial& m) { fillNodes(m, field, n, value); });
    });
    connect(smooth, &QPushButton::clicked, this, [this, nodes] {
        const PaintField field = m_viewport->brush().field;
        const std::vector<int> n = nodes();
        const Lattice& lattice = m_document->scene().objects[std::size_t(object())].lattice;
        if (!n.empty())
            editMaterial(tr("Smooth %1").arg(fieldName(field, currentModel())), kNoMerge,
                         [&](LatticeMaterial& m) { smoothNodes(m, lattice, field, n); });
    });
    return box;
}

void PropertiesPanel::editMaterial(const QString& text, int mergeKey, const std::function<void(LatticeMaterial&)>& change) {
    const Scene& scene = m_document->scene();
    if (std::size_t(object()) >= scene.objects.size())
        return;
    LatticeMaterial before = scene.objects[std::size_t(object())].material;
    LatticeMaterial after = before;
    change(after);
    if (auto model = buildLatticeBody(scene.objects[std::size_t(object())].lattice, after); !model) {
        m_live->setText(tr("Not applied: %1").arg(QString::fromStdString(model.message())));
        refresh();
        return;
    }
    SceneObject edited = scene.objects[std::size_t(object())];
    edited.material = after;
    if (Status s = checkSolverLimits(edited, scene.world); !s) {
        m_live->setText(tr("Not applied: %1").arg(QString::fromStdString(s.message())));
        refresh();
        return;
    }
    m_document->undoStack()->push(new MaterialEditCommand(m_document, object(), std::move(before), std::move(after), text, mergeKey));
}

void PropertiesPanel::editWorld(const QString& text, int mergeKey, const std::function<void(WorldSettings&)>& change) {
    WorldSettings before = m_document->scene().world;
    WorldSettings after = before;
    change(after);
    Status s = after.validate();
    for (const SceneObject& o : m_document->scene().objects)
        if (s)
            s = checkSolverLimits(o, after);
    if (!s) {
        m_live->setText(tr("Not applied: %1").arg(QString::fromStdString(s.message())));
        refresh();
        return;
    }
    m_document->undoStack()->push(new WorldEditCommand(m_document, std::move(before), std::move(after), text, mergeKey));
}

void PropertiesPanel::applyLatticeShape() {
    const Scene& scene = m_document->scene();
    if (std::size_t(object()) >= scene.objects.size())
        return;
    const SceneObject& o = scene.objects[std::size_t(object())];
    LatticeShape shape;
    shape.kind = LatticeKind(m_latticeKind->currentData().toInt());
    for (int a = 0; a < 3; ++a)
        shape.nodes[std::size_t(a)] = m_latticeNodes[std::size_t(a)]->value();
    auto lattice = Lattice::create(shape, o.lattice.box());
    if (!lattice) {
        m_live->setText(tr("Not applied: %1").arg(QString::fromStdString(lattice.message())));
        return;
    }
    LatticeMaterial material = resampleMaterial(o.lattice, o.material, lattice.value(), true);
    m_document->undoStack()->push(new LatticeEditCommand(m_document, object(), o.lattice, o.material, lattice.value(),
                                                         std::move(material), tr("Change lattice resolution")));
}

void PropertiesPanel::applyLatticeBox(const OrientedBox& box, const QString& text) {
    const SceneObject& o = m_document->scene().objects[std::size_t(object())];
    auto lattice = Lattice::create(o.lattice.shape(), box);
    if (!lattice) {
        m_live->setText(tr("Not applied: %1").arg(QString::fromStdString(lattice.message())));
        return;
    }
    // Same shape, so node i keeps its painted values: the box moved, not the material.
    m_document->undoStack()->push(new LatticeEditCommand(m_document, object(), o.lattice, o.material, lattice.value(),
                                                         o.material, text));
}

void PropertiesPanel::transformLattice() {
    if (std::size_t(object()) >= m_document->scene().objects.size())
        return;
    const OrientedBox& box = m_document->scene().objects[std::size_t(object())].lattice.box();
    const Vec3 centre = box.toWorld(Vec3::Constant(0.5));
    const Vec3 move(m_latticeMove[0]->value(), m_latticeMove[1]->value(), m_latticeMove[2]->value());
    const double scale = m_latticeScale->value();
    const Mat3 turn = Eigen::AngleAxisd(m_latticeTurn->value() * 3.14159265358979323846 / 180.0, Vec3::UnitY()).toRotationMatrix();
    OrientedBox next = box;
    next.axes = turn * box.axes;
    next.size = box.size * scale;
    next.origin = centre + move - next.axes * (0.5 * next.size);
    applyLatticeBox(next, tr("Transform lattice"));
    for (QDoubleSpinBox* b : m_latticeMove)
        setQuietly(b, 0.0);
    setQuietly(m_latticeScale, 1.0);
    setQuietly(m_latticeTurn, 0.0);
}

void PropertiesPanel::fitLattice() {
    if (std::size_t(object()) >= m_document->scene().objects.size())
        return;
    auto box = fitBox(m_document->scene().objects[std::size_t(object())].mesh->positions);
    if (!box) {
        m_live->setText(tr("Not applied: %1").arg(QString::fromStdString(box.message())));
        return;
    }
    applyLatticeBox(box.value(), tr("Fit lattice to object"));
}

void PropertiesPanel::autoVoid() {
    if (std::size_t(object()) >= m_document->scene().objects.size())
        return;
    const SceneObject& o = m_document->scene().objects[std::size_t(object())];
    const std::vector<std::uint8_t> empty = findEmptyNodes(o.lattice, o.mesh);
    const auto count = std::count(empty.begin(), empty.end(), std::uint8_t(1));
    editMaterial(tr("Auto void (%n node(s))", nullptr, int(count)), kNoMerge, [&](LatticeMaterial& m) {
        for (std::size_t n = 0; n < empty.size(); ++n)
            m.isVoid[n] = m.isVoid[n] || empty[n];
    });
}

void PropertiesPanel::refresh() {
    const Scene& scene = m_document->scene();
    m_refreshing = true;
    const WorldSettings& w = scene.world;
    m_integrator->setCurrentIndex(m_integrator->findData(int(w.simulation.integrator)));
    setQuietly(m_stepsPerSecond, std::round(1.0 / w.simulation.dt));
    m_gravity->setChecked(w.gravity.squaredNorm() > 0.0);
    m_groundPlane->setChecked(!w.planes.empty());
    m_bodiesCollide->setChecked(w.bodyCollisions.enabled);
    m_bodiesCollide->setVisible(scene.objects.size() > 1);  // one object has nothing to collide with
    const bool hasObject = std::size_t(object()) < scene.objects.size();
    for (QWidget* section : m_objectSections)
        section->setVisible(hasObject);
    m_noObject->setVisible(!hasObject);
    if (hasObject) {
        const SceneObject& o = scene.objects[std::size_t(object())];
        const MaterialSummary s = summarise(o.lattice, o.material);
        m_element->setCurrentIndex(m_element->findData(int(o.material.element)));
        showMaterialUnits(o.material.model, o.material.element);
        if (m_modesShownFor != object()) {
            // Another scene or object: the wobble and damping shown were another body's, blank until measured.
            for (QDoubleSpinBox* box : {m_frequency, m_dampingRatio})
                if (auto* text = box->findChild<QLineEdit*>())
                    text->clear();
            m_modesShownFor = object();
        }
        refreshModes(o, w.simulation);
        setQuietly(m_totalMass, s.totalMass);
        setQuietly(m_stiffness, s.meanStiffness);
        setQuietly(m_damping, s.meanDamping);
        setQuietly(m_nodeDamping, s.meanNodeDamping);
        for (int a = 0; a < 3; ++a)
            setQuietly(m_anisotropy[std::size_t(a)], o.material.anisotropy[a]);
        setQuietly(m_stretchLimit, o.material.strainLimits.stretch > 0.0 ? o.material.strainLimits.stretch : 1.0);
        setQuietly(m_squashLimit, o.material.strainLimits.squash);
        setQuietly(m_volumePreservation, largestVolumePreservation(o.material));
        m_latticeKind->setCurrentIndex(m_latticeKind->findData(int(o.lattice.shape().kind)));
        for (int a = 0; a < 3; ++a)
            m_latticeNodes[std::size_t(a)]->setValue(o.lattice.count(a));
        const auto& sel = m_viewport->selection();
        const PaintField field = m_viewport->brush().field;
        m_selectionLabel->setText(sel.empty() ? tr("None: use the Select tool (click or drag a box).")
                                              : tr("%n node(s)", nullptr, int(sel.size())));
        if (!sel.empty())
            setQuietly(m_selectionValue, fieldValues(o.material, field)[std::size_t(*sel.begin())]);
        const auto [low, high] = paintableRange(field, o.material.model);
        m_selectionValue->setRange(low, high);
        m_selectionValue->setSuffix(QString(" ") + fieldUnit(field, o.material.model));
    }
    m_refreshing = false;
}

MaterialModel PropertiesPanel::currentModel() const {
    return m_document->scene().objects[std::size_t(object())].material.model;
}

void PropertiesPanel::showMaterialUnits(MaterialModel model, BodyElement element) {
    // The same fields, named and measured for what the values mean (lattice_body.h, MaterialModel).
    const bool continuum = model == MaterialModel::Continuum;
    const MaterialRanges& range = materialRanges(model);
    m_stiffness->setSuffix(QString(" ") + QString::fromUtf8(range.stiffness.unit));
    m_damping->setSuffix(QString(" ") + QString::fromUtf8(range.damping.unit));
    m_nodeDamping->setSuffix(QString(" ") + QString::fromUtf8(range.nodeDamping.unit));
    m_stiffness->setSingleStep(continuum ? 100.0 : 5.0);
    if (auto* form = qobject_cast<QFormLayout*>(m_stiffness->parentWidget()->layout())) {
        if (auto* label = qobject_cast<QLabel*>(form->labelForField(m_stiffness)))
            label->setText(continuum ? tr("Young's modulus (mean)") : tr("Stiffness (mean)"));
        if (auto* label = qobject_cast<QLabel*>(form->labelForField(m_damping)))
            label->setText(element == BodyElement::Solid ? tr("Viscosity (mean)")  // the solid's, not springs'
                           : continuum                   ? tr("Spring viscosity (mean)")
                                                         : tr("Spring damping (mean)"));
        if (auto* label = qobject_cast<QLabel*>(form->labelForField(m_nodeDamping)))
            label->setText(continuum ? tr("Node damping rate (mean)") : tr("Node damping (mean)"));
    }
}

std::optional<FollowSettings> PropertiesPanel::currentFollow() const {
    const SceneObject& o = m_document->scene().objects[std::size_t(object())];
    return o.baseAnimation ? std::optional<FollowSettings>(o.follow) : std::nullopt;
}

Lattice PropertiesPanel::currentLattice() const {
    return m_document->scene().objects[std::size_t(object())].lattice;
}

/// What the properties panel shows of an object's modes, worked out away from the UI thread.
struct ModesReport {
    std::vector<VibrationMode> modes;  ///< Empty: none to show, `lines` says why.
    std::vector<double> clipDamping;   ///< Per mode, the damping ratio the clip will have.
    QStringList lines;                 ///< The summary under the rows.
};

namespace {

/// The lowest modes of `o` under `settings` and what the scheme does to them: the eigensolve of up to
/// kLiveModalUnknowns unknowns and the scheme's figures (XPBD's measured by running it). Touches no widget.
ModesReport analyseModes(const SceneObject& o, const SimulationSettings& settings) {
    ModesReport r;
    auto body = buildLatticeBody(o.lattice, simulatedMaterial(o));
    if (!body) {
        r.lines << QObject::tr("No modes: %1").arg(QString::fromStdString(body.message()));
        return r;
    }
    int freeNodes = 0;
    for (double w : body.value()->inverseMass)
        freeNodes += w > 0.0;
    if (3 * freeNodes > kLiveModalUnknowns) {
        r.lines << QObject::tr("This lattice is too fine to analyse on every edit (%1 unknowns): run "
                               "'softtouch-cli modes' on the saved scene.").arg(3 * freeNodes);
        return r;
    }
    auto modes = objectModes(o, 3);  // with its goal springs when it follows a base animation
    if (!modes || modes->modes.empty()) {
        r.lines << (modes ? QObject::tr("No elastic mode: every node moves rigidly.")
                          : QObject::tr("No modes: %1").arg(QString::fromStdString(modes.message())));
        return r;
    }
    r.modes = modes->modes;
    const VibrationMode& lowest = modes->modes.front();
    // The damping each mode shows in the clip: implicit Euler adds its own to the material's. In closed form
    // per mode at the scheme's step (what schemeAccuracy() gives); XPBD's is measured by running it, so only
    // for the lowest mode.
    const bool measured = settings.integrator == IntegratorKind::Xpbd;
    const double h = measured ? 0.0 : integrationStep(Simulator(body.value(), settings));
    const ModeAccuracy lowestAccuracy =
        measured ? schemeAccuracy(body.value(), settings, lowest) : modeAccuracy(settings.integrator, lowest, h);
    r.clipDamping.push_back(lowestAccuracy.dampingRatio);
    for (std::size_t m = 1; !measured && m < modes->modes.size(); ++m)
        r.clipDamping.push_back(modeAccuracy(settings.integrator, modes->modes[m], h).dampingRatio);
    if (modes->rigidModes > 0)
        r.lines << QObject::tr("%n rigid mode(s): the body can drift or turn freely.", nullptr, modes->rigidModes);
    r.lines << QString::fromStdString(describeModeAccuracy(settings, lowest, lowestAccuracy));
    if (modes->rigidModes > 0)  // a free body: whether the scheme slows its spin
        if (const std::string spin = describeSpinKept(body.value(), settings); !spin.empty())
            r.lines << QString::fromStdString(spin);
    // The solid the springs make (it differs from the painted modulus on flat or long cells), or the one the solid
    // element runs (the painted material's), as `softtouch-cli modes` prints it.
    const bool element = o.material.element == BodyElement::Solid;
    const NetworkElasticity e = element ? materialElasticity(o.lattice, o.material) : networkElasticity(o.lattice, o.material);
    if (e.resistsEveryStrain) {
        auto g = [](double x) { return QString::number(x, 'g', 4); };
        QString springs = (element ? QObject::tr("The solid element acts as: E %1 / %2 / %3 Pa along u / v / w, shear %4 / %5 / %6 Pa")
                                   : QObject::tr("Springs act as: E %1 / %2 / %3 Pa along u / v / w, shear %4 / %5 / %6 Pa"))
                              .arg(g(e.youngsModulus.x()), g(e.youngsModulus.y()), g(e.youngsModulus.z()),
                                   g(e.shearModulus.x()), g(e.shearModulus.y()), g(e.shearModulus.z()));
        if (o.material.model == MaterialModel::Continuum)
            springs += QObject::tr(" (painted modulus: %1 Pa)").arg(g(solidMean(o.material.stiffness, o.material)));
        r.lines << springs;
    }
    if (const auto departure = element ? std::nullopt : springDeparture(o.lattice, o.material);
        departure && departure->largest() > kSpringDepartureTolerance)
        r.lines << QObject::tr("Springs on these cells are not the painted material (%1): the modes are the springs'. "
                               "Compare with the solid to see how far; the solid element runs the material.")
                       .arg(QString::fromStdString(departure->describe()));
    return r;
}

}  // namespace

void PropertiesPanel::refreshModes(const SceneObject& o, const SimulationSettings& settings) {
    m_solid->clear();  // a comparison describes the material it was made for
    m_solid->setVisible(false);
    m_compareSolid->setEnabled(false);  // until the lattice's own modes are shown below
    m_frequency->setEnabled(false);
    m_dampingRatio->setEnabled(false);
    // On a worker thread, one analysis at a time: an edit while one runs waits for it, and a stroke's dabs
    // meanwhile coalesce into the latest. Only the latest edit's result is shown.
    m_modesWanted = {o, settings};
    m_modes->setProperty("analysing", true);
    if (!m_modesRunning)
        startModesAnalysis();
}

void PropertiesPanel::startModesAnalysis() {
    auto [object, settings] = std::move(*m_modesWanted);
    m_modesWanted.reset();
    m_modesRunning = true;
    QPointer<PropertiesPanel> panel(this);
    QThreadPool::globalInstance()->start([panel, object = std::move(object), settings = settings] {
        auto report = std::make_shared<ModesReport>(analyseModes(object, settings));
        QMetaObject::invokeMethod(
            qApp, [panel, report] {
                if (panel)
                    panel->finishModesAnalysis(*report);
            },
            Qt::QueuedConnection);
    });
}

void PropertiesPanel::finishModesAnalysis(const ModesReport& report) {
    m_modesRunning = false;
    if (m_modesWanted) {  // edited meanwhile: this result is stale, analyse the latest
        startModesAnalysis();
        return;
    }
    m_modes->setProperty("analysing", false);
    const bool any = !report.modes.empty();
    m_frequency->setEnabled(any);
    m_dampingRatio->setEnabled(any);
    m_compareSolid->setEnabled(any);
    if (any) {
        setQuietly(m_frequency, report.modes.front().frequencyHz);
        setQuietly(m_dampingRatio, report.modes.front().dampingRatio);
    }
    showModeRows(report.modes, report.clipDamping);
    m_modes->setText(report.lines.join('\n'));
    emit modesShown();
}

void PropertiesPanel::compareWithSolid() {
    const SceneObject& o = m_document->scene().objects[std::size_t(object())];
    QApplication::setOverrideCursor(Qt::WaitCursor);
    auto compared = softtouch::compareWithSolid(o.lattice, o.material);
    QApplication::restoreOverrideCursor();
    QString text;
    if (!compared) {
        text = tr("No comparison: %1").arg(QString::fromStdString(compared.message()));
    } else if (!compared->solid.converged()) {
        text = tr("No converged solid: from degree %1 to %2 a mode moves by %3%. Anchors on single nodes or "
                  "lines hold nothing in a solid; anchor a face to compare.")
                   .arg(compared->solid.degree - 1)
                   .arg(compared->solid.degree)
                   .arg(100.0 * compared->solid.spread, 0, 'f', 1);
    } else {
        QStringList solid;
        for (double f : compared->solid.frequencyHz)
            solid << QString::number(f, 'f', 3);
        text = tr("The solid you painted: %1 Hz; this lattice's modes are %2 from it%3.")
                   .arg(solid.join(" / "), QString::fromStdString(describeModeErrors(compared->error)),
                        o.baseAnimation ? tr(" (both without the goal springs)") : QString());
    }
    m_solid->setText(text);
    m_solid->setVisible(true);
}

void PropertiesPanel::showModeRows(const std::vector<VibrationMode>& modes, const std::vector<double>& clipDamping) {
    m_analysedModes = modes;
    for (std::size_t m = 0; m < m_modeRows.size(); ++m) {
        const bool present = m < modes.size();
        m_modeRows[m]->setVisible(present);
        m_modeShow[m]->setVisible(present);
        if (!present)
            continue;
        const VibrationMode& mode = modes[m];
        // On the solid element the relative damping is its viscosity, not springs'.
        const bool element = std::size_t(object()) < m_document->scene().objects.size() &&
                             m_document->scene().objects[std::size_t(object())].material.element == BodyElement::Solid;
        QString row = (element ? tr("Mode %1: %2 Hz, ζ %3 (node %4, viscous %5)") : tr("Mode %1: %2 Hz, ζ %3 (node %4, spring %5)"))
                          .arg(m + 1)
                          .arg(mode.frequencyHz, 0, 'f', 3)
                          .arg(mode.dampingRatio, 0, 'f', 3)
                          .arg(mode.nodeDampingRatio, 0, 'f', 3)
                          .arg(mode.springDampingRatio, 0, 'f', 3);
        // What the integrator adds shows where it differs from the material's by a visible amount.
        if (m < clipDamping.size() && std::isfinite(clipDamping[m]) &&
            std::abs(clipDamping[m] - mode.dampingRatio) > std::max(0.0005, 0.02 * mode.dampingRatio))
            row += tr("; in the clip ζ %1").arg(clipDamping[m], 0, 'f', 3);
        m_modeRows[m]->setText(row);
    }
    // A mode being shown follows its new shape (a painted edit changes it), or stops when it is gone.
    const int shown = m_viewport->shownMode();
    if (shown > 0 && std::size_t(shown) <= modes.size())
        m_viewport->showMode(object(), shown, modes[std::size_t(shown - 1)]);
    else if (shown > 0)
        m_viewport->stopModeView();
}

void PropertiesPanel::refreshLive() {
    const SimulationStats& s = m_simulation->stats();
    // Before any step was timed (paused since opening) the cost is unknown, not 0 µs.
    QString text = s.stepMicros > 0.0 ? tr("%1 µs per step").arg(s.stepMicros, 0, 'f', 1) : tr("not run yet");
    if (s.stableStepSeconds > 0.0)  // explicit schemes only: what their substeps are cut to
        text += tr(" · stable explicit step %1 ms").arg(s.stableStepSeconds * 1e3, 0, 'g', 3);
    if (s.substeps > 1)
        text += tr(" · %1 substeps").arg(s.substeps);
    if (!m_simulation->problem().isEmpty())
        text = m_simulation->problem();
    m_live->setText(text);
}

}  // namespace softtouch::ui

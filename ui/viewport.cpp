#include "ui/viewport.h"

#include "ui/edit_commands.h"
#include "ui/surface_pick.h"
#include "ui/viewport_tools.h"

#include <QKeyEvent>
#include <QLabel>
#include <QMouseEvent>
#include <QLinearGradient>
#include <QPainter>
#include <QTabletEvent>
#include <QWheelEvent>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>

namespace softtouch::ui {

/// Objects the tools do not act on, when there are several: the default orange, greyed (linear RGB).
const Eigen::Vector3f kOtherObjectColour{0.42f, 0.38f, 0.36f};

/// The user's hands: for each grab, a line from the held point of the body to where the cursor pulls
/// it (the drag spring), so the pull is visible while the body lags behind.
class GrabIndicator : public QWidget {
public:
    GrabIndicator(QWidget* parent, std::function<std::vector<std::pair<QPointF, QPointF>>()> lines)
        : QWidget(parent), m_lines(std::move(lines)) {
        setAttribute(Qt::WA_TransparentForMouseEvents);
        setAttribute(Qt::WA_NoSystemBackground);
    }

protected:
    void paintEvent(QPaintEvent*) override {
        QPainter painter(this);
        painter.setRenderHint(QPainter::Antialiasing);
        for (const auto& [held, target] : m_lines()) {
            painter.setPen(QPen(QColor(255, 230, 90), 2, Qt::DashLine));
            painter.drawLine(held, target);
            painter.setPen(QPen(QColor(30, 30, 30), 1));
            painter.setBrush(QColor(255, 230, 90));
            painter.drawEllipse(held, 4.5, 4.5);
            painter.setBrush(Qt::NoBrush);
            painter.setPen(QPen(QColor(255, 230, 90), 2));
            painter.drawEllipse(target, 7.0, 7.0);
        }
    }

private:
    std::function<std::vector<std::pair<QPointF, QPointF>>()> m_lines;
};

/// The pose tool's gizmo and the caption of a transform under way (Viewport::drawGizmo), over the GL
/// picture as a child widget: painting over the GL frame itself would meet the renderer's GL state.
class PoseOverlay : public QWidget {
public:
    PoseOverlay(QWidget* parent, std::function<void(QPainter&)> draw) : QWidget(parent), m_draw(std::move(draw)) {
        setAttribute(Qt::WA_TransparentForMouseEvents);
        setAttribute(Qt::WA_NoSystemBackground);
    }

protected:
    void paintEvent(QPaintEvent*) override {
        QPainter painter(this);
        m_draw(painter);
    }

private:
    std::function<void(QPainter&)> m_draw;
};

/// While a take is recorded: a red frame around the view and "● REC" with the take's length, so
/// nobody records without knowing (or forgets to stop). A child widget over the GL picture.
class RecordingCue : public QWidget {
public:
    RecordingCue(QWidget* parent, std::function<double()> seconds) : QWidget(parent), m_seconds(std::move(seconds)) {
        setObjectName("recordingCue");
        setAttribute(Qt::WA_TransparentForMouseEvents);
        setAttribute(Qt::WA_NoSystemBackground);
        hide();
    }

protected:
    void paintEvent(QPaintEvent*) override {
        QPainter painter(this);
        painter.setRenderHint(QPainter::Antialiasing);
        painter.setPen(QPen(QColor(220, 30, 30), 4));
        painter.drawRect(QRectF(rect()).adjusted(2, 2, -2, -2));
        const QRectF label(12, 10, 150, 26);
        painter.fillRect(label, QColor(0, 0, 0, 120));
        painter.setPen(QColor(255, 80, 80));
        painter.drawText(label, Qt::AlignCenter, QStringLiteral("● REC  %1 s").arg(m_seconds(), 0, 'f', 1));
    }

private:
    std::function<double()> m_seconds;
};

/// The colour scale of the node overlay: the painted field from its lowest to its highest value, in
/// the node discs' blue-grey-red map. A child widget, so Qt composites it over the GL picture.
class ValueLegend : public QWidget {
public:
    explicit ValueLegend(QWidget* parent) : QWidget(parent) {
        setAttribute(Qt::WA_TransparentForMouseEvents);
        resize(260, 44);
    }
    void setRange(const QString& name, double lo, double hi, const QString& unit, bool fixed) {
        m_text = QStringLiteral("%1: %2 – %3 %4").arg(name).arg(lo, 0, 'g', 4).arg(hi, 0, 'g', 4).arg(unit).trimmed();
        if (fixed)
            m_text += tr(" (fixed)");
        update();
    }
    const QString& text() const { return m_text; }

protected:
    void paintEvent(QPaintEvent*) override {
        QPainter painter(this);
        painter.fillRect(rect(), QColor(0, 0, 0, 90));
        const QRectF bar(8, 26, width() - 16, 10);
        QLinearGradient gradient(bar.topLeft(), bar.topRight());
        gradient.setColorAt(0.0, QColor::fromRgbF(0.23f, 0.30f, 0.75f));  // render::coolWarm's stops
        gradient.setColorAt(0.5, QColor::fromRgbF(0.87f, 0.87f, 0.87f));
        gradient.setColorAt(1.0, QColor::fromRgbF(0.71f, 0.02f, 0.15f));
        painter.fillRect(bar, gradient);
        painter.setPen(Qt::white);
        painter.drawText(QRectF(8, 4, width() - 16, 18), Qt::AlignLeft | Qt::AlignVCenter, m_text);
    }

private:
    QString m_text;
};

Viewport::Viewport(Document* document, SimulationController* simulation, QWidget* parent)
    : QOpenGLWidget(parent), m_document(document), m_simulation(simulation), m_activeTool(makeViewportTool(m_tool, *this)) {
    setFocusPolicy(Qt::StrongFocus);
    setMouseTracking(true);
    setMinimumSize(320, 240);
    m_legend = new ValueLegend(this);
    m_recordingCue = new RecordingCue(this, [this] {
        const SceneSimulation* sim = m_simulation->simulation();
        return sim ? sim->time() - m_recordingStart : 0.0;
    });
    connect(simulation, &SimulationController::recordingChanged, this, [this](bool recording) {
        const SceneSimulation* sim = m_simulation->simulation();
        m_recordingStart = sim ? sim->time() : 0.0;
        m_recordingCue->setGeometry(rect());
        m_recordingCue->setVisible(recording);
        m_recordingCue->raise();
    });
    connect(simulation, &SimulationController::stepped, this, [this] {
        if (m_recordingCue->isVisible())
            m_recordingCue->update();
    });
    m_grabIndicator = new GrabIndicator(this, [this] {
        std::vector<std::pair<QPointF, QPointF>> lines;
        const SceneSimulation* sim = m_simulation->simulation();
        for (int slot = 0; sim && slot < SimulationController::kGrabSlots; ++slot) {
            const auto& g = m_simulation->grab(slot);
            if (!g || std::size_t(g->object) >= sim->objectCount())
                continue;
            Vec3 point, velocity;
            const BodyState& state = sim->simulator(std::size_t(g->object)).state();
            dragPointState(g->drag, state.position, state.velocity, point, velocity);
            lines.emplace_back(toWidget(point), toWidget(g->drag.target));
        }
        return lines;
    });
    connect(simulation, &SimulationController::stepped, m_grabIndicator, qOverload<>(&QWidget::update));
    m_poseOverlay = new PoseOverlay(this, [this](QPainter& painter) { drawGizmo(painter); });
    connect(simulation, &SimulationController::stepped, m_poseOverlay, qOverload<>(&QWidget::update));
    connect(document, &Document::materialChanged, this, &Viewport::updateLegend);
    connect(document, &Document::sceneReplaced, this, &Viewport::updateLegend);
    connect(simulation, &SimulationController::stepped, this, qOverload<>(&QWidget::update));
    connect(simulation, &SimulationController::rebuilt, this, [this] {
        m_transform.reset();  // its start belongs to the simulation that was replaced
        m_sceneDirty = true;
        update();
    });
    connect(document, &Document::sceneReplaced, this, [this] {
        m_object = 0;
        m_selection.clear();
        emit selectionChanged();
        frameAll();
    });
    connect(document, &Document::latticeChanged, this, [this] {
        m_selection.clear();
        emit selectionChanged();
    });

    // The mode view is display only: anything that moves the simulation or replaces the lattice ends it.
    m_modeCaption = new QLabel(this);
    m_modeCaption->setObjectName("modeCaption");
    m_modeCaption->setAttribute(Qt::WA_TransparentForMouseEvents);
    m_modeCaption->setStyleSheet("QLabel { background: rgba(0, 0, 0, 110); color: white; padding: 5px; }");
    m_modeCaption->hide();
    m_modeTimer.setInterval(16);
    connect(&m_modeTimer, &QTimer::timeout, this, qOverload<>(&QWidget::update));
    connect(simulation, &SimulationController::playingChanged, this, [this](bool playing) {
        if (playing)
            stopModeView();
    });
    connect(simulation, &SimulationController::stepped, this, [this] {
        const SceneSimulation* sim = m_simulation->simulation();
        if (m_modeView && (!sim || sim->stepCount() != m_modeView->step))
            stopModeView();
    });
    connect(document, &Document::sceneReplaced, this, &Viewport::stopModeView);
    connect(document, &Document::latticeChanged, this, &Viewport::stopModeView);
    m_keys = keyBindings();
    frameAll();
}

Viewport::~Viewport() {
    if (m_glReady) {
        makeCurrent();
        m_renderer.release();
        doneCurrent();
    }
}

void Viewport::initializeGL() {
    if (Status s = m_renderer.initialize(); !s) {
        m_renderProblem = tr("The viewport cannot draw: %1").arg(QString::fromStdString(s.message()));
        emit hint(m_renderProblem);
        return;
    }
    m_glReady = true;
    m_sceneDirty = true;
}

void Viewport::resizeGL(int, int) {
    m_recordingCue->setGeometry(rect());
    m_grabIndicator->resize(size());
    m_poseOverlay->resize(size());
    updateLegend();
}

void Viewport::uploadScene() {
    m_renderer.clearObjects();
    const SceneSimulation* sim = m_simulation->simulation();
    if (!sim)
        return;
    for (std::size_t i = 0; i < sim->objectCount(); ++i) {
        auto id = m_renderer.addObject(sim->object(i).mesh, sim->object(i).lattice);
        if (!id) {
            m_renderProblem = QString::fromStdString(id.message());
            emit hint(m_renderProblem);
        }
    }
    m_renderer.setPlanes(m_document->scene().world.planes,
                         float(std::max(1.0, 1.5 * sim->object(0).mesh->bounds().diagonal())));
    m_renderer.setColliders(m_document->scene().world.colliders);
    m_sceneDirty = false;
}

void Viewport::updateOverlay(int object, const std::vector<Vec3>& x) {
    const SceneSimulation* sim = m_simulation->simulation();
    const Simulator& simulator = sim->simulator(std::size_t(object));
    const BodyModel& model = simulator.model();
    const LatticeMaterial& material = m_document->scene().objects[std::size_t(object)].material;
    render::LatticeOverlay overlay;
    overlay.nodeValue = nodeColourParameters(object);
    for (std::size_t n = 0; n < overlay.nodeValue.size(); ++n) {
        overlay.anchor.push_back(std::uint8_t(material.anchor[n]));
        overlay.isVoid.push_back(material.isVoid[n]);
        overlay.selected.push_back(object == m_object && m_selection.count(int(n)) ? 1 : 0);
    }
    // Edge springs only: with the face and body diagonals (3x as many) the overlay hides the mesh.
    for (const Spring& s : model.springs) {
        if (s.kind != SpringKind::Edge)
            continue;
        overlay.springs.emplace_back(s.a, s.b);
        overlay.springStrain.push_back(float(((x[s.b] - x[s.a]).norm() - s.restLength) / s.restLength));
    }
    m_renderer.setOverlay(object, overlay);
    m_renderer.setOverlayVisible(object, m_overlayVisible);
}

void Viewport::paintGL() {
    QElapsedTimer timer;
    timer.start();
    const SceneSimulation* sim = m_simulation->simulation();
    if (m_glReady && sim) {
        if (m_sceneDirty)
            uploadScene();
        for (std::size_t i = 0; i < sim->objectCount() && int(i) < m_renderer.objectCount(); ++i) {
            const bool inMode = m_modeView && m_modeView->object == int(i);
            const std::vector<Vec3> pose = inMode ? displayedNodes(int(i)) : std::vector<Vec3>{};
            const std::vector<Vec3>& nodes = inMode ? pose : sim->simulator(i).state().position;
            render::showSceneObject(m_renderer, int(i), *sim, i, nodes, sim->time(), m_basePositions, m_baseNormals);
            render::MeshStyle style;
            style.mode = m_shadeMode;
            // The object the tools act on in full colour, the others greyed, so a click's target is never a guess.
            if (sim->objectCount() > 1 && int(i) != m_object)
                style.colour = kOtherObjectColour;
            m_renderer.setStyle(int(i), style);
            updateOverlay(int(i), nodes);
        }
        const qreal dpr = devicePixelRatioF();
        const int w = int(width() * dpr), h = int(height() * dpr);
        m_renderer.draw(m_camera.camera(w, h), w, h);
    }
    if (!m_renderProblem.isEmpty() || !sim) {
        QPainter painter(this);
        painter.fillRect(rect(), QColor(60, 60, 66));
        painter.setPen(Qt::white);
        painter.drawText(rect().adjusted(20, 20, -20, -20), Qt::AlignCenter | Qt::TextWordWrap,
                         !m_renderProblem.isEmpty() ? m_renderProblem : m_simulation->problem());
    }
    if (m_gesture == Gesture::Tool) {
        QPainter painter(this);
        m_activeTool->draw(painter);
    }
    m_poseOverlay->update();  // the gizmo follows the camera and the selection (it draws nothing outside the pose tool)
    const double ms = double(timer.nsecsElapsed()) * 1e-6;
    m_frameMs = m_frameMs == 0.0 ? ms : 0.9 * m_frameMs + 0.1 * ms;
}

void Viewport::updateLegend() {
    const Scene& scene = m_document->scene();
    const bool show = m_overlayVisible && std::size_t(m_object) < scene.objects.size();
    m_legend->setVisible(show);
    if (!show)
        return;
    const LatticeMaterial& material = scene.objects[std::size_t(m_object)].material;
    const auto [lo, hi] = colourRange(m_object);
    m_legend->setRange(QString::fromUtf8(fieldName(m_brush.field, material.model)), lo, hi,
                       QString::fromUtf8(fieldUnit(m_brush.field, material.model)),
                       m_fixedColourRanges.count(m_brush.field) > 0);
    m_legend->move(12, height() - m_legend->height() - 12);
}

void Viewport::setColourRange(PaintField field, std::optional<std::pair<double, double>> range) {
    if (range && range->second > range->first)
        m_fixedColourRanges[field] = *range;
    else
        m_fixedColourRanges.erase(field);
    updateLegend();
    update();  // paintGL recolours the overlay
}

std::optional<std::pair<double, double>> Viewport::fixedColourRange(PaintField field) const {
    const auto it = m_fixedColourRanges.find(field);
    return it == m_fixedColourRanges.end() ? std::nullopt : std::optional(it->second);
}

std::pair<double, double> Viewport::colourRange(int object) const {
    if (const auto fixed = fixedColourRange(m_brush.field))
        return *fixed;
    const Scene& scene = m_document->scene();
    if (object < 0 || std::size_t(object) >= scene.objects.size())
        return {0.0, 1.0};
    const std::vector<double>& values = fieldValues(scene.objects[std::size_t(object)].material, m_brush.field);
    if (values.empty())
        return {0.0, 1.0};
    const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
    return {*lo, *hi};
}

std::vector<float> Viewport::nodeColourParameters(int object) const {
    const Scene& scene = m_document->scene();
    if (object < 0 || std::size_t(object) >= scene.objects.size())
        return {};
    const std::vector<double>& values = fieldValues(scene.objects[std::size_t(object)].material, m_brush.field);
    const auto [lo, hi] = colourRange(object);
    std::vector<float> out;
    out.reserve(values.size());
    for (double v : values)
        out.push_back(hi > lo ? float(std::clamp((v - lo) / (hi - lo), 0.0, 1.0)) : 0.5f);
    return out;
}

QString Viewport::legendText() const { return m_legend->text(); }

QPointF Viewport::toWidget(const Vec3& world) const {
    const Eigen::Vector3d p = m_camera.project(world, width(), height());
    return {p.x(), p.y()};
}

std::vector<Vec3f> Viewport::deformedPositions(int object) const {
    const SceneSimulation* sim = m_simulation->simulation();
    if (!sim || object < 0 || std::size_t(object) >= sim->objectCount())
        return {};
    std::vector<Vec3f> positions(sim->object(std::size_t(object)).mesh->positions.size());
    sim->evaluate(std::size_t(object), positions, {});
    return positions;
}

std::vector<Vec3> Viewport::displayedNodes(int object) const {
    const SceneSimulation* sim = m_simulation->simulation();
    if (!sim || object < 0 || std::size_t(object) >= sim->objectCount())
        return {};
    if (m_modeView && m_modeView->object == object)
        return modePose(m_modeView->rest, m_modeView->mode, modeDisplacement());
    return sim->simulator(std::size_t(object)).state().position;
}

void Viewport::showMode(int object, int index, const VibrationMode& mode) {
    const SceneSimulation* sim = m_simulation->simulation();
    if (!sim || object < 0 || std::size_t(object) >= sim->objectCount())
        return;
    const Lattice& lattice = sim->object(std::size_t(object)).lattice;
    if (mode.shape.size() != std::size_t(lattice.nodeCount()))
        return;
    if (m_simulation->isPlaying())
        m_simulation->pause();  // the view shows the body at rest: the simulation waits meanwhile
    const bool same = m_modeView && m_modeView->object == object && m_modeView->index == index;
    ModeView view;
    view.object = object;
    view.index = index;
    view.mode = mode;
    view.rest = lattice.restNodes();
    view.amplitude = kModeDisplayFraction * lattice.box().size.maxCoeff();
    view.step = sim->stepCount();
    m_modeView = std::move(view);
    if (!same)
        m_modeClock.start();
    m_modeTimer.start();
    m_modeCaption->setText(tr("Mode %1 of %2: %3 Hz, ζ %4 — shown at %5 Hz, ±%6% of the box (display only)")
                               .arg(index)
                               .arg(QString::fromStdString(sim->object(std::size_t(object)).name))
                               .arg(mode.frequencyHz, 0, 'f', 3)
                               .arg(mode.dampingRatio, 0, 'f', 3)
                               .arg(kModeDisplayHz, 0, 'g', 3)
                               .arg(100.0 * kModeDisplayFraction, 0, 'g', 3));
    m_modeCaption->adjustSize();
    m_modeCaption->move(12, 12);
    m_modeCaption->show();
    if (!same)
        emit modeViewChanged(object, index);
    update();
}

void Viewport::stopModeView() {
    if (!m_modeView)
        return;
    const int object = m_modeView->object;
    m_modeView.reset();
    m_modeTimer.stop();
    m_modeCaption->hide();
    emit modeViewChanged(object, 0);
    update();
}

double Viewport::modeSeconds() const {
    return m_modeHeldSeconds >= 0.0 ? m_modeHeldSeconds : double(m_modeClock.elapsed()) * 1e-3;
}

double Viewport::modeDisplacement() const {
    if (!m_modeView)
        return 0.0;
    return m_modeView->amplitude * std::sin(2.0 * std::numbers::pi * kModeDisplayHz * modeSeconds());
}

void Viewport::holdModeView(double seconds) {
    m_modeHeldSeconds = seconds >= 0.0 ? seconds : -1.0;
    update();
}

std::vector<Eigen::Vector2d> Viewport::nodeScreenPositions(int object) const {
    std::vector<Eigen::Vector2d> out;
    const SceneSimulation* sim = m_simulation->simulation();
    if (!sim || std::size_t(object) >= sim->objectCount())
        return out;
    for (const Vec3& x : sim->simulator(std::size_t(object)).state().position) {
        const Eigen::Vector3d p = m_camera.project(x, width(), height());
        out.emplace_back(p.z() <= 1.0 ? Eigen::Vector2d(p.x(), p.y()) : Eigen::Vector2d::Constant(1e9));
    }
    return out;
}

int Viewport::nodeAt(const QPointF& pos, double radiusPixels) const {
    const auto screen = nodeScreenPositions(m_object);
    int best = -1;
    double bestDistance = radiusPixels;
    for (std::size_t n = 0; n < screen.size(); ++n) {
        const double d = (screen[n] - Eigen::Vector2d(pos.x(), pos.y())).norm();
        if (d < bestDistance) {
            bestDistance = d;
            best = int(n);
        }
    }
    return best;
}

std::vector<int> Viewport::nodesInRect(const QRectF& rect) const {
    std::vector<int> nodes;
    const auto screen = nodeScreenPositions(m_object);
    for (std::size_t n = 0; n < screen.size(); ++n) {
        if (rect.contains(QPointF(screen[n].x(), screen[n].y())))
            nodes.push_back(int(n));
    }
    return nodes;
}

Viewport::Gesture Viewport::navigationFor(const QMouseEvent* event) const {
    const Qt::MouseButton b = event->button();
    const Qt::KeyboardModifiers m = event->modifiers();
    if (m_navigation == NavigationStyle::Maya) {
        if (m & Qt::AltModifier) {
            if (b == Qt::LeftButton) return Gesture::Orbit;
            if (b == Qt::MiddleButton) return Gesture::Pan;
            if (b == Qt::RightButton) return Gesture::Dolly;
        }
        if (b == Qt::MiddleButton) return Gesture::Pan;
    } else if (b == Qt::MiddleButton) {
        if (m & Qt::ShiftModifier) return Gesture::Pan;
        if (m & Qt::ControlModifier) return Gesture::Dolly;
        return Gesture::Orbit;
    }
    return Gesture::None;
}

void Viewport::mousePressEvent(QMouseEvent* event) {
    m_lastPos = event->position();
    if (m_transform && m_gesture != Gesture::Tool) {  // G/R/S under way: a click applies, a right-click cancels
        if (event->button() == Qt::LeftButton)
            applyTransform();
        else if (event->button() == Qt::RightButton)
            cancelTransform();
        return;
    }
    m_gesture = navigationFor(event);
    if (m_gesture != Gesture::None || event->button() != Qt::LeftButton)
        return;
    m_gesture = Gesture::Tool;  // already while the press acts: a paint stroke's first dab is part of the stroke
    if (!m_activeTool->press(event->position(), event->modifiers()))
        m_gesture = Gesture::None;
    update();
}

void Viewport::mouseMoveEvent(QMouseEvent* event) {
    const QPointF pos = event->position();
    const QPointF from = m_lastPos;
    const QPointF delta = pos - from;
    m_lastPos = pos;
    if (m_transform && m_gesture == Gesture::None) {  // a transform the keyboard started follows the cursor
        updateTransform(pos);
        return;
    }
    switch (m_gesture) {
    case Gesture::Orbit: m_camera.orbit(delta.x(), delta.y()); break;
    case Gesture::Pan: m_camera.pan(delta.x(), delta.y(), height()); break;
    case Gesture::Dolly: m_camera.dolly(std::exp(0.005 * (delta.y() - delta.x()))); break;
    case Gesture::Tool: m_activeTool->move(from, pos); break;
    case Gesture::None: return;
    }
    update();
}

void Viewport::mouseReleaseEvent(QMouseEvent* event) {
    if (event->button() != Qt::LeftButton && m_gesture != Gesture::Orbit && m_gesture != Gesture::Pan &&
        m_gesture != Gesture::Dolly)
        return;
    const Gesture ended = m_gesture;
    m_gesture = Gesture::None;
    if (ended == Gesture::Tool)
        m_activeTool->release(event->position());
    m_pressure = 1.0;
    m_tiltDepth = 0.0;
    update();
}

void Viewport::wheelEvent(QWheelEvent* event) {
    m_camera.dolly(std::exp(-0.0015 * event->angleDelta().y()));
    update();
}

void Viewport::tabletEvent(QTabletEvent* event) {
    // Pen pressure scales the drag stiffness (a firmer press pulls harder); tilting the pen towards or
    // away from the screen moves the pulled point in depth, the third axis a 2D pen lacks (a stylus
    // device has it). The event is ignored so Qt delivers the matching mouse event, which drives the
    // tools as for a mouse.
    m_pressure = std::clamp(double(event->pressure()), 0.05, 1.0);
    m_tiltDepth = std::clamp(double(event->yTilt()) / 60.0, -1.0, 1.0);
    if (m_gesture == Gesture::Tool)
        m_activeTool->pressureChanged();
    event->ignore();
}

int Viewport::objectAt(const QPointF& pos, std::optional<SurfaceHit>* hit) const {
    const SceneSimulation* sim = m_simulation->simulation();
    if (!sim)
        return -1;
    const Ray ray = m_camera.rayThrough(pos.x(), pos.y(), width(), height());
    std::optional<SurfaceHit> best;
    int bestObject = -1;
    for (std::size_t i = 0; i < sim->objectCount(); ++i) {
        const std::vector<Vec3f> positions = deformedPositions(int(i));
        if (auto h = pickSurface(ray, positions, sim->object(i).mesh->triangles); h && (!best || h->distance < best->distance)) {
            best = h;
            bestObject = int(i);
        }
    }
    if (hit)
        *hit = best;
    return bestObject;
}

void Viewport::mouseDoubleClickEvent(QMouseEvent* event) {
    // A double-click on an object makes it the one the tools act on (the outliner follows).
    if (event->button() == Qt::LeftButton && !m_transform)
        if (const int object = objectAt(event->position()); object >= 0 && object != m_object)
            setCurrentObject(object);
    QOpenGLWidget::mouseDoubleClickEvent(event);
}

int Viewport::colliderAt(const QPointF& pos) const {
    const auto& colliders = m_document->scene().world.colliders;
    int best = -1;
    double bestDistance = 1e300;
    for (std::size_t k = 0; k < colliders.size(); ++k) {
        const Collider& c = colliders[k];
        const Vec3& centre = c.centre;
        // Its size on screen at its centre's depth: the view plane's metres per pixel there.
        const QPointF at = toWidget(centre);
        const Vec3 a = m_camera.pointOnViewPlane(at.x(), at.y(), width(), height(), centre);
        const Vec3 b = m_camera.pointOnViewPlane(at.x() + 1.0, at.y(), width(), height(), centre);
        const double pixels = colliderBoundingRadius(c) / std::max((b - a).norm(), 1e-12);
        const double distance = std::hypot(pos.x() - at.x(), pos.y() - at.y());
        if (distance <= std::max(30.0, pixels) && distance < bestDistance) {
            best = int(k);
            bestDistance = distance;
        }
    }
    return best;
}

void Viewport::setCurrentCollider(int index) {
    const bool changed = index != m_collider;
    m_collider = index;
    if (changed)
        emit currentColliderChanged(index);
    const auto& colliders = m_document->scene().world.colliders;
    if (index >= 0 && std::size_t(index) < colliders.size())
        emit hint(tr("%1 %2: drag to move, Shift+drag to scale, Delete to remove.")
                      .arg(QString::fromUtf8(colliderShapeName(colliders[std::size_t(index)].shape)))
                      .arg(index + 1));
}

void Viewport::deleteCollider() {
    const WorldSettings& before = m_document->scene().world;
    if (m_collider < 0 || std::size_t(m_collider) >= before.colliders.size())
        return;
    WorldSettings after = before;
    after.colliders.erase(after.colliders.begin() + m_collider);
    m_collider = -1;
    emit currentColliderChanged(-1);
    m_document->undoStack()->push(new WorldEditCommand(m_document, before, after, tr("Delete collider")));
}

void Viewport::setTool(Tool tool) {
    if (tool == m_tool)
        return;
    cancelTransform();
    if (m_gesture == Gesture::Tool)  // the old tool's gesture ends with it, unapplied
        m_activeTool->cancel();
    m_gesture = Gesture::None;
    m_tool = tool;
    m_activeTool = makeViewportTool(tool, *this);
    emit toolChanged(tool);
    update();
}

void Viewport::setShadeMode(render::ShadeMode mode) {
    m_shadeMode = mode;
    update();
}

void Viewport::setNavigationStyle(NavigationStyle style) { m_navigation = style; }

void Viewport::setOverlayVisible(bool visible) {
    m_overlayVisible = visible;
    updateLegend();
    update();
}

void Viewport::setAnchorMode(AnchorMode mode) { m_anchorMode = mode; }

void Viewport::setBrushField(PaintField field) {
    if (field == m_brush.field)
        return;
    m_brush.field = field;
    updateLegend();
    emit brushFieldChanged(field);
    update();
}

void Viewport::setCurrentObject(int object) {
    cancelTransform();
    const bool changed = object != m_object;
    if (m_modeView && m_modeView->object != object)
        stopModeView();
    m_object = object;
    updateLegend();
    m_selection.clear();
    emit selectionChanged();
    if (changed)
        emit currentObjectChanged(object);
    update();
}

void Viewport::setSelection(const std::set<int>& nodes) {
    m_selection = nodes;
    emit selectionChanged();
    update();
}

void Viewport::frameAll() {
    const Scene& scene = m_document->scene();
    if (scene.objects.empty())
        return;
    Bounds all = restBounds(scene);
    // Where the bodies are now, not where they rested: an unanchored body that fell or was thrown away is
    // found. The deformed mesh lies in the hull of its lattice's nodes (the basis weights are ≥ 0 and sum to
    // 1 inside the box), so the nodes' bounds enclose it.
    if (const SceneSimulation* sim = m_simulation->simulation(); sim && sim->objectCount() > 0) {
        all = boundsOf(sim->simulator(0).state().position);
        for (std::size_t i = 1; i < sim->objectCount(); ++i)
            all = all.united(boundsOf(sim->simulator(i).state().position));
    }
    m_camera.frame(all);
    update();
}

void Viewport::frameSelection() {
    const SceneSimulation* sim = m_simulation->simulation();
    if (m_selection.empty() || !sim || std::size_t(m_object) >= sim->objectCount()) {
        frameAll();
        return;
    }
    const std::vector<Vec3>& x = sim->simulator(std::size_t(m_object)).state().position;
    std::vector<Vec3> selected;
    for (int n : m_selection)
        selected.push_back(x[std::size_t(n)]);
    Bounds b = boundsOf(selected);
    // A single node still gets a view of its neighbourhood: a tenth of the object's size around it.
    const Vec3 room = Vec3::Constant(0.05 * sim->object(std::size_t(m_object)).mesh->bounds().diagonal());
    b.min -= room;
    b.max += room;
    m_camera.frame(b);
    update();
}

void Viewport::viewFront() { m_camera.viewFront(); update(); }
void Viewport::viewSide() { m_camera.viewSide(); update(); }
void Viewport::viewTop() { m_camera.viewTop(); update(); }

}  // namespace softtouch::ui

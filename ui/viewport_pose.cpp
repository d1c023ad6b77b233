// The viewport's pose tool: G/R/S transforms of the selected lattice nodes and the gizmo (arrows, squares, rings)
// (ui/node_transform.h holds the arithmetic; this file maps the mouse and keys onto it).

#include "ui/edit_commands.h"
#include "ui/viewport.h"

#include <QKeyEvent>
#include <QPainter>

#include <cmath>
#include <numbers>

namespace softtouch::ui {

namespace {

/// Length of a gizmo arrow on screen, pixels.
constexpr double kGizmoPixels = 70.0;
/// How near an arrow the cursor must be to grab it, pixels.
constexpr double kGizmoGrabPixels = 7.0;

double distanceToSegment(const QPointF& p, const QPointF& a, const QPointF& b) {
    const QPointF ab = b - a;
    const double length2 = QPointF::dotProduct(ab, ab);
    const double t = length2 > 0.0 ? std::clamp(QPointF::dotProduct(p - a, ab) / length2, 0.0, 1.0) : 0.0;
    const QPointF d = p - (a + t * ab);
    return std::hypot(d.x(), d.y());
}

/// "4 nodes", "1 node".
QString nodeCount(int count) {
    return count == 1 ? Viewport::tr("1 node") : Viewport::tr("%1 nodes").arg(count);
}

const char* kindName(TransformKind kind) {
    switch (kind) {
    case TransformKind::Move: return "Move";
    case TransformKind::Rotate: return "Rotate";
    case TransformKind::Scale: return "Scale";
    }
    return "";
}

}  // namespace

bool Viewport::beginTransform(TransformKind kind, const QPointF& cursor) {
    const SceneSimulation* sim = m_simulation->simulation();
    if (!sim || std::size_t(m_object) >= sim->objectCount() || m_selection.empty())
        return false;
    stopModeView();
    m_simulation->pause();
    m_transform.emplace(kind, sim->simulator(std::size_t(m_object)).state().position,
                        std::vector<int>(m_selection.begin(), m_selection.end()));
    m_transformCursor = cursor;
    m_transformTurn = 0.0;
    const QPointF centre = toWidget(m_transform->pivot());
    m_transformLastAngle = std::atan2(cursor.y() - centre.y(), cursor.x() - centre.x());
    updateTransform(cursor);
    return true;
}

void Viewport::updateTransform(const QPointF& pos) {
    if (!m_transform)
        return;
    const Vec3& pivot = m_transform->pivot();
    const QPointF centre = toWidget(pivot);
    switch (m_transform->kind()) {
    case TransformKind::Move:
        m_transform->setMouseMove(m_camera.pointOnViewPlane(pos.x(), pos.y(), width(), height(), pivot) -
                                  m_camera.pointOnViewPlane(m_transformCursor.x(), m_transformCursor.y(), width(), height(), pivot));
        break;
    case TransformKind::Rotate: {
        // Summed move by move, so a turn past half a circle keeps counting. Screen y points down: the
        // angle the viewer sees as counter-clockwise is the negative of atan2's.
        const double angle = std::atan2(pos.y() - centre.y(), pos.x() - centre.x());
        double step = angle - m_transformLastAngle;
        step = std::remainder(step, 2.0 * std::numbers::pi);
        m_transformLastAngle = angle;
        m_transformTurn -= step;
        m_transform->setMouseRotate(m_transformTurn, (m_camera.eye() - pivot).normalized());
        break;
    }
    case TransformKind::Scale: {
        const double from = std::hypot(m_transformCursor.x() - centre.x(), m_transformCursor.y() - centre.y());
        const double to = std::hypot(pos.x() - centre.x(), pos.y() - centre.y());
        m_transform->setMouseScale(to / std::max(from, 1.0));
        break;
    }
    }
    m_simulation->setObjectPose(m_object, m_transform->positions());
    emit hint(QString::fromStdString(m_transform->describe()) +
              tr(" — Enter applies, Esc cancels"));
    update();
}

void Viewport::applyTransform() {
    if (!m_transform)
        return;
    NodeTransform done = std::move(*m_transform);
    m_transform.reset();
    const std::vector<Vec3> after = done.positions();
    if (after == done.start()) {
        update();
        return;
    }
    const QString text = QString("%1 %2").arg(tr(kindName(done.kind())), nodeCount(int(done.nodes().size())));
    m_document->undoStack()->push(new PoseEditCommand(m_simulation, m_object, done.start(), after, text));
    emit hint(QString::fromStdString(done.describe()));
    update();
}

void Viewport::cancelTransform() {
    if (!m_transform)
        return;
    m_simulation->setObjectPose(m_object, m_transform->start());
    m_transform.reset();
    emit hint(tr("Transform cancelled."));
    update();
}

void Viewport::restSelection() {
    const SceneSimulation* sim = m_simulation->simulation();
    if (!sim || std::size_t(m_object) >= sim->objectCount())
        return;
    cancelTransform();
    const std::vector<Vec3>& before = sim->simulator(std::size_t(m_object)).state().position;
    const std::vector<Vec3> rest = sim->object(std::size_t(m_object)).lattice.restNodes();
    std::vector<Vec3> after = before;
    for (std::size_t n = 0; n < after.size(); ++n)
        if (m_selection.empty() || m_selection.count(int(n)))
            after[n] = rest[n];
    if (after == before)
        return;
    const int count = m_selection.empty() ? int(after.size()) : int(m_selection.size());
    m_document->undoStack()->push(new PoseEditCommand(m_simulation, m_object, before, after,
                                                      tr("Rest %1").arg(nodeCount(count))));
}

void Viewport::applyPoseAsRest() {
    const SceneSimulation* sim = m_simulation->simulation();
    if (!sim || std::size_t(m_object) >= sim->objectCount())
        return;
    applyTransform();
    const std::vector<Vec3> pose = sim->simulator(std::size_t(m_object)).state().position;
    if (Status s = m_document->applyRestShape(m_object, pose); !s)
        emit hint(tr("Not applied: %1").arg(QString::fromStdString(s.message())));
    else
        emit hint(tr("The pose is the rest shape now (Ctrl+Z takes it back)."));
}

std::optional<Viewport::Gizmo> Viewport::gizmo() const {
    const SceneSimulation* sim = m_simulation->simulation();
    if (m_tool != Tool::Pose || !sim || std::size_t(m_object) >= sim->objectCount() || m_selection.empty())
        return std::nullopt;
    const std::vector<Vec3>& x = sim->simulator(std::size_t(m_object)).state().position;
    Vec3 centre = Vec3::Zero();
    for (int n : m_selection)
        centre += x[std::size_t(n)];
    centre /= double(m_selection.size());
    // kGizmoPixels long on screen: the view plane's metres per pixel at the centre's depth.
    const QPointF c = toWidget(centre);
    const double metres = (m_camera.pointOnViewPlane(c.x() + kGizmoPixels, c.y(), width(), height(), centre) -
                           m_camera.pointOnViewPlane(c.x(), c.y(), width(), height(), centre)).norm();
    Gizmo g;
    g.centre = c;
    for (int a = 0; a < 3; ++a) {
        const Vec3 axis = Vec3::Unit(a);
        g.tips[std::size_t(a)] = toWidget(centre + metres * axis);
        g.scaleHandles[std::size_t(a)] = toWidget(centre + 0.6 * metres * axis);
        // The ring about this axis: a circle in the plane through the centre at right angles to it.
        const Vec3 u = Vec3::Unit((a + 1) % 3), v = Vec3::Unit((a + 2) % 3);
        for (int k = 0; k <= 48; ++k) {
            const double t = 2.0 * std::numbers::pi * k / 48.0;
            g.rings[std::size_t(a)].push_back(toWidget(centre + 0.85 * metres * (std::cos(t) * u + std::sin(t) * v)));
        }
    }
    return g;
}

std::optional<std::pair<TransformKind, TransformAxis>> Viewport::gizmoPartAt(const QPointF& pos) const {
    const std::optional<Gizmo> g = gizmo();
    if (!g)
        return std::nullopt;
    std::optional<std::pair<TransformKind, TransformAxis>> best;
    double bestDistance = kGizmoGrabPixels;
    const auto consider = [&](double d, TransformKind kind, int a) {
        if (d < bestDistance) {
            bestDistance = d;
            best = std::pair(kind, TransformAxis(a + 1));
        }
    };
    for (int a = 0; a < 3; ++a) {
        const QPointF arrow = g->tips[std::size_t(a)] - g->centre;
        if (std::hypot(arrow.x(), arrow.y()) >= 10.0) {  // seen end-on: no direction to drag along
            // Scale handles first (they sit on the arrows), then the arrows' outer part (near the centre all meet).
            const QPointF h = g->scaleHandles[std::size_t(a)];
            consider(std::max(std::abs(pos.x() - h.x()), std::abs(pos.y() - h.y())) - 1.0, TransformKind::Scale, a);
            consider(distanceToSegment(pos, g->centre + 0.75 * arrow, g->tips[std::size_t(a)]) + 0.5, TransformKind::Move, a);
        }
        const std::vector<QPointF>& ring = g->rings[std::size_t(a)];
        for (std::size_t k = 1; k < ring.size(); ++k)
            consider(distanceToSegment(pos, ring[k - 1], ring[k]) + 1.0, TransformKind::Rotate, a);
    }
    return best;
}

void Viewport::drawGizmo(QPainter& painter) const {
    if (const std::optional<Gizmo> g = gizmo()) {
        const QColor colours[3] = {QColor(230, 60, 60), QColor(90, 200, 70), QColor(70, 120, 240)};
        const char* names[3] = {"X", "Y", "Z"};
        painter.setRenderHint(QPainter::Antialiasing);
        for (std::size_t a = 0; a < 3; ++a) {
            const bool held = m_transform && m_transform->axis() == TransformAxis(a + 1);
            const auto width = [&](TransformKind kind) { return held && m_transform->kind() == kind ? 4.0 : 2.0; };
            painter.setBrush(Qt::NoBrush);
            painter.setPen(QPen(colours[a], width(TransformKind::Rotate)));
            painter.drawPolyline(g->rings[a].data(), int(g->rings[a].size()));
            painter.setPen(QPen(colours[a], width(TransformKind::Move)));
            painter.drawLine(g->centre, g->tips[a]);
            painter.setBrush(colours[a]);
            painter.drawEllipse(g->tips[a], 5.0, 5.0);
            painter.setPen(QPen(Qt::black, held && m_transform->kind() == TransformKind::Scale ? 2.0 : 1.0));
            painter.drawRect(QRectF(g->scaleHandles[a] - QPointF(4, 4), QSizeF(8, 8)));
            painter.setPen(colours[a]);
            painter.drawText(g->tips[a] + QPointF(7, -7), QString::fromLatin1(names[a]));
        }
        painter.setBrush(Qt::white);
        painter.setPen(QPen(Qt::black, 1));
        painter.drawEllipse(g->centre, 3.5, 3.5);
    }
    if (m_transform) {
        // What the transform does, at the foot of the view (the status bar says it too).
        const QString text = QString::fromStdString(m_transform->describe());
        const QRectF box(12, height() - 90, std::min(width() - 24, 520), 26);
        painter.fillRect(box, QColor(0, 0, 0, 140));
        painter.setPen(Qt::white);
        painter.drawText(box.adjusted(8, 0, -8, 0), Qt::AlignLeft | Qt::AlignVCenter, text);
    }
}

}  // namespace softtouch::ui

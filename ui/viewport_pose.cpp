// The viewport's pose tool: G/R/S transforms of the selected lattice nodes and the move gizmo
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

QPointF Viewport::gizmoCentre() const {
    const SceneSimulation* sim = m_simulation->simulation();
    if (!sim || std::size_t(m_object) >= sim->objectCount() || m_selection.empty())
        return {};
    const std::vector<Vec3>& x = sim->simulator(std::size_t(m_object)).state().position;
    Vec3 centre = Vec3::Zero();
    for (int n : m_selection)
        centre += x[std::size_t(n)];
    return toWidget(centre / double(m_selection.size()));
}

std::vector<QPointF> Viewport::gizmoTips() const {
    const SceneSimulation* sim = m_simulation->simulation();
    if (m_tool != Tool::Pose || !sim || std::size_t(m_object) >= sim->objectCount() || m_selection.empty())
        return {};
    const std::vector<Vec3>& x = sim->simulator(std::size_t(m_object)).state().position;
    Vec3 centre = Vec3::Zero();
    for (int n : m_selection)
        centre += x[std::size_t(n)];
    centre /= double(m_selection.size());
    // kGizmoPixels long on screen: the view plane's metres per pixel at the centre's depth.
    const QPointF c = toWidget(centre);
    const double metres = (m_camera.pointOnViewPlane(c.x() + kGizmoPixels, c.y(), width(), height(), centre) -
                           m_camera.pointOnViewPlane(c.x(), c.y(), width(), height(), centre)).norm();
    return {toWidget(centre + metres * Vec3::UnitX()), toWidget(centre + metres * Vec3::UnitY()),
            toWidget(centre + metres * Vec3::UnitZ())};
}

int Viewport::gizmoArrowAt(const QPointF& pos) const {
    const std::vector<QPointF> tips = gizmoTips();
    const QPointF centre = gizmoCentre();
    int best = -1;
    double bestDistance = kGizmoGrabPixels;
    for (std::size_t a = 0; a < tips.size(); ++a) {
        const QPointF arrow = tips[a] - centre;
        if (std::hypot(arrow.x(), arrow.y()) < 10.0)
            continue;  // seen end-on: no direction to drag along
        // The outer part of the arrow only: near the centre all three meet.
        const double d = distanceToSegment(pos, centre + 0.25 * arrow, tips[a]);
        if (d < bestDistance) {
            bestDistance = d;
            best = int(a);
        }
    }
    return best;
}

void Viewport::drawGizmo(QPainter& painter) const {
    const std::vector<QPointF> tips = gizmoTips();
    if (!tips.empty()) {
        const QPointF centre = gizmoCentre();
        const QColor colours[3] = {QColor(230, 60, 60), QColor(90, 200, 70), QColor(70, 120, 240)};
        const char* names[3] = {"X", "Y", "Z"};
        painter.setRenderHint(QPainter::Antialiasing);
        for (std::size_t a = 0; a < 3; ++a) {
            const bool held = m_transform && m_transform->axis() == TransformAxis(a + 1);
            painter.setPen(QPen(colours[a], held ? 4 : 2.5));
            painter.drawLine(centre, tips[a]);
            painter.setBrush(colours[a]);
            painter.drawEllipse(tips[a], 5.0, 5.0);
            painter.drawText(tips[a] + QPointF(7, -7), QString::fromLatin1(names[a]));
        }
        painter.setBrush(Qt::white);
        painter.setPen(QPen(Qt::black, 1));
        painter.drawEllipse(centre, 3.5, 3.5);
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

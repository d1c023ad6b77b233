#include "ui/viewport_tools.h"

#include "ui/edit_commands.h"
#include "ui/viewport.h"

#include <QPainter>
#include <QPen>

#include <algorithm>
#include <cmath>

namespace softtouch::ui {

/// Drag: pulls the material point under the cursor through a drag spring (Ctrl: a second hand that holds after
/// release). Pen pressure scales the spring; tilt pushes the point in depth.
class DragTool final : public ViewportTool {
public:
    using ViewportTool::ViewportTool;

    bool press(const QPointF& pos, Qt::KeyboardModifiers modifiers) override {
        Viewport& v = m_view;
        const SceneSimulation* sim = v.m_simulation->simulation();
        if (!sim)
            return false;
        const int slot = (modifiers & Qt::ControlModifier) ? 1 : 0;
        std::optional<SurfaceHit> best;
        const int bestObject = v.objectAt(pos, &best);
        if (!best) {
            if (slot == 1)
                v.m_simulation->setGrab(1, std::nullopt);  // Ctrl+click on empty space lets the held hand go
            emit v.hint(Viewport::tr("Nothing under the cursor to drag."));
            return false;
        }
        // The material point under the cursor: barycentric mix of the triangle's rest parameters.
        const SceneObject& object = sim->object(std::size_t(bestObject));
        const auto& tri = object.mesh->triangles[best->triangle];
        Vec3 uvw = Vec3::Zero();
        for (int k = 0; k < 3; ++k)
            uvw += best->barycentric[k] * object.lattice.box().toParameters(object.mesh->positions[tri[std::size_t(k)]].cast<double>());
        Grab grab;
        grab.object = bestObject;
        grab.drag.support = object.lattice.weights(uvw.cwiseMax(0.0).cwiseMin(1.0));
        grab.drag.target = best->point;
        grab.drag.stiffness = v.m_drag.stiffness * v.m_pressure;
        grab.drag.damping = v.m_drag.damping;
        // Pull from where the lattice point is now, so grabbing does not jolt the body.
        Vec3 point, velocity;
        dragPointState(grab.drag, sim->simulator(std::size_t(bestObject)).state().position,
                       sim->simulator(std::size_t(bestObject)).state().velocity, point, velocity);
        m_grabOffset = best->point - point;
        grab.drag.target = point;
        m_depthPoint = best->point;
        v.m_simulation->setGrab(slot, grab);
        m_slot = slot;
        if (!v.m_simulation->isPlaying())
            v.m_simulation->play();
        emit v.hint(slot == 1 ? Viewport::tr("Second hand: holds after release; Ctrl+click empty space to let go.")
                              : Viewport::tr("Dragging: release to let the body swing free."));
        return true;
    }

    void move(const QPointF&, const QPointF& to) override {
        Viewport& v = m_view;
        auto grab = v.m_simulation->grab(m_slot);
        if (!grab)
            return;
        const Vec3 cursor = v.m_camera.pointOnViewPlane(to.x(), to.y(), v.width(), v.height(), m_depthPoint);
        const double diagonal = v.m_simulation->simulation()->object(std::size_t(grab->object)).mesh->bounds().diagonal();
        grab->drag.target = cursor - m_grabOffset + v.m_camera.forward() * (v.m_tiltDepth * v.m_drag.tiltDepth * diagonal);
        grab->drag.stiffness = v.m_drag.stiffness * v.m_pressure;
        v.m_simulation->setGrab(m_slot, grab);
    }

    void release(const QPointF&) override {
        if (m_slot == 0)
            m_view.m_simulation->setGrab(0, std::nullopt);  // release: the body swings free
    }
    void cancel() override { release({}); }

    void pressureChanged() override {
        // A firmer press pulls harder at once, not only at the next move.
        if (auto g = m_view.m_simulation->grab(m_slot)) {
            g->drag.stiffness = m_view.m_drag.stiffness * m_view.m_pressure;
            m_view.m_simulation->setGrab(m_slot, g);
        }
    }

private:
    int m_slot = 0;                       ///< The grab slot pulled: 0 the mouse's hand, 1 the held one.
    Vec3 m_depthPoint = Vec3::Zero();     ///< The picked surface point: the view plane the cursor moves in.
    Vec3 m_grabOffset = Vec3::Zero();     ///< Picked point minus the lattice point it pulls.
};

/// Paint: brush dabs on the brush's field of the current object, one undo step a stroke.
class PaintTool final : public ViewportTool {
public:
    using ViewportTool::ViewportTool;

    bool press(const QPointF& pos, Qt::KeyboardModifiers) override {
        m_stroke = m_view.m_nextStrokeKey++;
        dab(pos);
        return true;
    }
    void move(const QPointF&, const QPointF& to) override { dab(to); }

private:
    void dab(const QPointF& pos) {
        Viewport& v = m_view;
        const Scene& scene = v.m_document->scene();
        if (std::size_t(v.m_object) >= scene.objects.size())
            return;
        LatticeMaterial before = scene.objects[std::size_t(v.m_object)].material;
        LatticeMaterial after = before;
        BrushSettings brush = v.m_brush;
        brush.strength = std::clamp(brush.strength * v.m_pressure, 0.0, 1.0);
        if (!applyDab(after, v.nodeScreenPositions(v.m_object), Eigen::Vector2d(pos.x(), pos.y()), brush))
            return;
        const QString name = Viewport::tr("Paint %1").arg(QString::fromUtf8(fieldName(v.m_brush.field, after.model)));
        v.m_document->undoStack()->push(
            new MaterialEditCommand(v.m_document, v.m_object, std::move(before), std::move(after), name, m_stroke));
    }
    int m_stroke = -1;  ///< The stroke's undo merge key.
};

/// Anchor, void and select: a click toggles the node under the cursor, a box sets every node in it (Ctrl+box
/// clears); select adds with Shift, and a click on another object's surface makes that object current.
class NodeTool : public ViewportTool {
public:
    NodeTool(Viewport& view, Tool kind) : ViewportTool(view), m_kind(kind) {}

    bool press(const QPointF& pos, Qt::KeyboardModifiers modifiers) override {
        m_from = m_to = pos;
        m_modifiers = modifiers;
        return true;
    }
    void move(const QPointF&, const QPointF& to) override { m_to = to; }
    void release(const QPointF& pos) override {
        Viewport& v = m_view;
        m_to = pos;
        const bool click = (pos - m_from).manhattanLength() < 4.0;
        std::vector<int> nodes;
        if (click) {
            if (int n = v.nodeAt(pos); n >= 0)
                nodes.push_back(n);
        } else {
            nodes = v.nodesInRect(QRectF(m_from, pos).normalized());
        }
        const bool selects = m_kind == Tool::Select || m_kind == Tool::Pose;
        // A click on no node of the current object, on another object's surface, picks that object instead.
        if (click && nodes.empty() && selects)
            if (const int object = v.objectAt(pos); object >= 0 && object != v.m_object) {
                v.setCurrentObject(object);
                return;
            }
        apply(nodes, click ? false : bool(m_modifiers & Qt::ControlModifier));
        if (click && nodes.empty() && selects)
            v.setSelection({});
    }
    void draw(QPainter& painter) const override {
        painter.setPen(QPen(QColor(255, 220, 80), 1, Qt::DashLine));
        painter.drawRect(QRectF(m_from, m_to).normalized());
    }

private:
    void apply(const std::vector<int>& nodes, bool clear) {
        Viewport& v = m_view;
        if (m_kind == Tool::Select || m_kind == Tool::Pose) {
            std::set<int> selection = (m_modifiers & Qt::ShiftModifier) ? v.m_selection : std::set<int>{};
            selection.insert(nodes.begin(), nodes.end());
            v.setSelection(selection);
            return;
        }
        if (nodes.empty() || std::size_t(v.m_object) >= v.m_document->scene().objects.size())
            return;
        LatticeMaterial before = v.m_document->scene().objects[std::size_t(v.m_object)].material;
        LatticeMaterial after = before;
        const bool toggle = nodes.size() == 1 && !clear;
        const AnchorMode mode = v.m_anchorMode;
        QString text;
        for (int n : nodes) {
            const auto i = std::size_t(n);
            if (m_kind == Tool::Anchor) {
                const bool set = toggle ? after.anchor[i] != mode : !clear;
                after.anchor[i] = set ? mode : AnchorMode::Free;
                text = set ? (mode == AnchorMode::Heavy ? Viewport::tr("Set heavy anchor") : Viewport::tr("Set pinned anchor"))
                           : Viewport::tr("Clear anchor");
            } else {
                const bool set = toggle ? !after.isVoid[i] : !clear;
                after.isVoid[i] = set ? 1 : 0;
                text = set ? Viewport::tr("Set void") : Viewport::tr("Clear void");
            }
        }
        if (nodes.size() > 1)
            text += Viewport::tr(" (%n nodes)", nullptr, int(nodes.size()));
        // A lattice with every node void or every node pinned cannot be built; refuse rather than break it.
        if (auto model = buildLatticeBody(v.m_document->scene().objects[std::size_t(v.m_object)].lattice, after); !model) {
            emit v.hint(Viewport::tr("Not applied: %1").arg(QString::fromStdString(model.message())));
            return;
        }
        v.m_document->undoStack()->push(new MaterialEditCommand(v.m_document, v.m_object, std::move(before), std::move(after), text));
    }

    Tool m_kind;
    QPointF m_from, m_to;
    Qt::KeyboardModifiers m_modifiers;
};

/// Pose: on the gizmo, moves, scales or turns the selected nodes along or about that axis while the button is
/// held (one undo step); elsewhere it selects as the select tool does.
class PoseTool final : public NodeTool {
public:
    explicit PoseTool(Viewport& view) : NodeTool(view, Tool::Pose) {}

    bool press(const QPointF& pos, Qt::KeyboardModifiers modifiers) override {
        Viewport& v = m_view;
        m_onGizmo = false;
        if (const auto part = v.gizmoPartAt(pos); part && v.beginTransform(part->first, pos)) {
            v.m_transform->toggleAxis(part->second);
            v.updateTransform(pos);
            m_onGizmo = true;
            return true;
        }
        return NodeTool::press(pos, modifiers);
    }
    void move(const QPointF& from, const QPointF& to) override {
        if (m_onGizmo)
            m_view.updateTransform(to);
        else
            NodeTool::move(from, to);
    }
    void release(const QPointF& pos) override {
        if (m_onGizmo)
            m_view.applyTransform();
        else
            NodeTool::release(pos);
    }
    void draw(QPainter& painter) const override {
        if (!m_onGizmo)
            NodeTool::draw(painter);
    }

private:
    bool m_onGizmo = false;  ///< The gesture drags the gizmo (else it selects).
};

/// Lattice: moves the current object's box in the view plane; Shift scales it about its centre, Ctrl turns it
/// about the vertical. One gesture is one undo step.
class LatticeTool final : public ViewportTool {
public:
    using ViewportTool::ViewportTool;

    bool press(const QPointF&, Qt::KeyboardModifiers modifiers) override {
        m_modifiers = modifiers;
        m_stroke = m_view.m_nextStrokeKey++;
        return true;
    }

    void move(const QPointF& from, const QPointF& to) override {
        Viewport& v = m_view;
        const Scene& scene = v.m_document->scene();
        if (std::size_t(v.m_object) >= scene.objects.size())
            return;
        const SceneObject& o = scene.objects[std::size_t(v.m_object)];
        const OrientedBox& box = o.lattice.box();
        const Vec3 centre = box.toWorld(Vec3::Constant(0.5));
        OrientedBox next = box;
        if (m_modifiers & Qt::ShiftModifier) {
            // Scale about the centre: up grows, down shrinks.
            const double factor = std::exp(-0.005 * (to.y() - from.y()));
            next.size = box.size * factor;
            next.origin = centre - next.axes * (0.5 * next.size);
        } else if (m_modifiers & Qt::ControlModifier) {
            // Turn about the vertical through the centre.
            const Mat3 turn = Eigen::AngleAxisd(0.01 * (to.x() - from.x()), Vec3::UnitY()).toRotationMatrix();
            next.axes = turn * box.axes;
            next.origin = centre - next.axes * (0.5 * box.size);
        } else {
            // Move in the view plane at the box centre's depth, so the box follows the cursor.
            const Vec3 a = v.m_camera.pointOnViewPlane(from.x(), from.y(), v.width(), v.height(), centre);
            const Vec3 b = v.m_camera.pointOnViewPlane(to.x(), to.y(), v.width(), v.height(), centre);
            next.origin = box.origin + (b - a);
        }
        auto lattice = Lattice::create(o.lattice.shape(), next);
        if (!lattice)
            return;
        v.m_document->undoStack()->push(new LatticeEditCommand(v.m_document, v.m_object, o.lattice, o.material, lattice.value(),
                                                               o.material, Viewport::tr("Place lattice"), m_stroke));
    }

private:
    Qt::KeyboardModifiers m_modifiers;
    int m_stroke = -1;
};

/// Collider: picks the collider under the cursor; dragging moves it in the view plane, Shift scales it. One
/// gesture is one undo step (Delete removes the picked one: a key of the viewport).
class ColliderTool final : public ViewportTool {
public:
    using ViewportTool::ViewportTool;

    bool press(const QPointF& pos, Qt::KeyboardModifiers modifiers) override {
        m_view.setCurrentCollider(m_view.colliderAt(pos));
        if (m_view.m_collider < 0)
            return false;
        m_modifiers = modifiers;
        m_stroke = m_view.m_nextStrokeKey++;
        return true;
    }

    void move(const QPointF& from, const QPointF& to) override {
        Viewport& v = m_view;
        const WorldSettings& before = v.m_document->scene().world;
        if (v.m_collider < 0 || std::size_t(v.m_collider) >= before.colliders.size())
            return;
        WorldSettings after = before;
        Collider& c = after.colliders[std::size_t(v.m_collider)];
        const bool scale = bool(m_modifiers & Qt::ShiftModifier);
        if (scale) {
            // Scale about its centre: up grows, down shrinks (each shape's own sizes, by the same factor).
            const double factor = std::exp(-0.005 * (to.y() - from.y()));
            c.radius *= factor;
            c.halfLength *= factor;
            c.halfExtents *= factor;
            c.scale *= factor;
        } else {
            // Move in the view plane at its centre's depth, so it follows the cursor.
            const Vec3 a = v.m_camera.pointOnViewPlane(from.x(), from.y(), v.width(), v.height(), c.centre);
            const Vec3 b = v.m_camera.pointOnViewPlane(to.x(), to.y(), v.width(), v.height(), c.centre);
            c.centre += b - a;
        }
        if (!c.validate().ok())
            return;  // scaled past a limit: keep the last good size
        v.m_document->undoStack()->push(new WorldEditCommand(
            v.m_document, before, after, scale ? Viewport::tr("Scale collider") : Viewport::tr("Move collider"), m_stroke));
    }

private:
    Qt::KeyboardModifiers m_modifiers;
    int m_stroke = -1;
};

std::unique_ptr<ViewportTool> makeViewportTool(Tool tool, Viewport& view) {
    switch (tool) {
    case Tool::Drag: return std::make_unique<DragTool>(view);
    case Tool::Paint: return std::make_unique<PaintTool>(view);
    case Tool::Anchor:
    case Tool::Void:
    case Tool::Select: return std::make_unique<NodeTool>(view, tool);
    case Tool::Pose: return std::make_unique<PoseTool>(view);
    case Tool::Lattice: return std::make_unique<LatticeTool>(view);
    case Tool::Collider: return std::make_unique<ColliderTool>(view);
    }
    return std::make_unique<DragTool>(view);
}

}  // namespace softtouch::ui

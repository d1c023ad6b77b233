#pragma once
/// The 3D viewport: draws every object deformed on the GPU (render::MeshRenderer uploads only the
/// lattice nodes each frame), the lattice overlay and the collision planes, and turns the mouse and
/// pen into camera moves and tool actions: drag (pick a surface point, pull it through a drag spring,
/// a second held grab with Ctrl), paint (brush strokes, one undo step each), anchor and void
/// (click or box), select (for numeric entry, fill and smooth), pose (select nodes, then G/R/S with
/// axis keys and typed amounts, or drag the gizmo: arrows move, squares scale, rings turn;
/// ui/node_transform.h; one transform is one undo step), lattice (move the box in the view plane; Shift
/// scales it, Ctrl turns it about the vertical; one gesture is one undo step), collider
/// (pick a collider, drag to move it in the view plane, Shift scales it, Delete removes it); each tool is a
/// class of ui/viewport_tools.h. The mode view animates one object's lattice in one of its vibration modes, for
/// display only.

#include "core/modes/modes.h"
#include "render/mesh_renderer.h"
#include "ui/node_brush.h"
#include "ui/node_transform.h"
#include "ui/orbit_camera.h"
#include "ui/simulation_controller.h"
#include "ui/surface_pick.h"

#include <QElapsedTimer>
#include <QOpenGLWidget>
#include <QTimer>

#include <array>

#include <functional>

#include <map>
#include <memory>
#include <optional>
#include <set>

class QLabel;

namespace softtouch::ui {
class ViewportTool;
}

namespace softtouch::ui {

/// What the left mouse button does.
enum class Tool { Drag, Paint, Anchor, Void, Select, Pose, Lattice, Collider };

/// Which camera conventions the mouse follows.
enum class NavigationStyle {
    Maya,    ///< Alt+left orbit, Alt+middle pan, Alt+right dolly.
    Blender, ///< Middle orbit, Shift+middle pan, Ctrl+middle dolly.
};

/// Settings of the drag tool.
struct DragToolSettings {
    double stiffness = 200.0; ///< Ks of the mouse's drag spring, N/m, (0, 1e9]. Pen pressure scales it.
    double damping = 0.5;     ///< Kd, N·s/m, [0, 1e6].
    double tiltDepth = 0.25;  ///< How far a fully tilted pen (60°) pushes the target into or out of the
                              ///< screen, as a fraction of the object's diagonal. [0, 10].
};

/// OpenGL viewport of one document.
class ValueLegend;
class GrabIndicator;
class PoseOverlay;

class Viewport : public QOpenGLWidget {
    Q_OBJECT
public:
    Viewport(Document* document, SimulationController* simulation, QWidget* parent = nullptr);
    ~Viewport() override;

    Tool tool() const { return m_tool; }
    render::ShadeMode shadeMode() const { return m_shadeMode; }
    OrbitCamera& camera() { return m_camera; }
    BrushSettings& brush() { return m_brush; }
    DragToolSettings& dragSettings() { return m_drag; }
    /// Anchor mode the anchor tool sets (Pinned or Heavy).
    AnchorMode anchorMode() const { return m_anchorMode; }
    /// Selected nodes of the current object.
    const std::set<int>& selection() const { return m_selection; }
    /// The object the tools act on.
    int currentObject() const { return m_object; }
    /// The collider the collider tool last picked (index into world.colliders), -1 when none.
    int currentCollider() const { return m_collider; }
    /// The transform under way (G, R or S pressed and neither applied nor cancelled yet), or nullptr.
    const NodeTransform* transform() const { return m_transform ? &*m_transform : nullptr; }
    /// Starts a transform of the selected nodes of the current object (the pose tool's G, R and S), with
    /// the cursor at `cursor`: the mouse drives it from there. False when nothing is selected.
    bool beginTransform(TransformKind kind, const QPointF& cursor);
    /// Applies the transform under way as one undo step ("Move 4 nodes").
    void applyTransform();
    /// Puts the nodes back where the transform found them.
    void cancelTransform();
    /// Puts the selected nodes of the current object (every node when none is selected) back at their rest
    /// positions, as one undo step (Blender's Alt+G, R and S at once).
    void restSelection();
    /// Makes the current object's pose its rest shape (Document::applyRestShape); the reason in the hint
    /// when it cannot.
    void applyPoseAsRest();
    /// The pose tool's gizmo as drawn now, in widget pixels, per world axis X, Y, Z: drag an arrow to move
    /// along it, its square to scale along it, the ring about it to turn about it.
    struct Gizmo {
        QPointF centre;                              ///< The selected nodes' centre.
        std::array<QPointF, 3> tips;                 ///< Move arrows' tips.
        std::array<QPointF, 3> scaleHandles;         ///< Scale squares, on the arrows.
        std::array<std::vector<QPointF>, 3> rings;   ///< Rotation rings (closed polylines).
    };
    /// std::nullopt outside the pose tool or with nothing selected.
    std::optional<Gizmo> gizmo() const;

    /// The keys the viewport handles itself (view, pose and transform keys: they act on the view, so they
    /// are not window shortcuts), as (what, keys) rows for Help ▸ Keyboard Shortcuts. The same table
    /// dispatches them (ui/viewport_keys.cpp), so the help cannot drift from what the keys do.
    QList<QPair<QString, QString>> keyTable() const;

    /// A paint stroke is under way (the paint tool's button is held).
    bool isPainting() const { return m_tool == Tool::Paint && m_gesture == Gesture::Tool; }
    /// Mean time to draw a frame, milliseconds (CPU side, including the node upload).
    double frameMilliseconds() const { return m_frameMs; }
    /// Why the viewport cannot draw (no OpenGL 3.3, shader error); empty when it can.
    const QString& renderProblem() const { return m_renderProblem; }

    /// Fixes the colour range of a painted field's node overlay and legend, so one colour keeps one value
    /// while painting (values outside clamp to the ends); std::nullopt returns to the field's min–max on the
    /// object, which each stroke re-ranges (a uniform map painted softer turns the unpainted nodes red).
    void setColourRange(PaintField field, std::optional<std::pair<double, double>> range);
    /// The fixed range of `field`, or std::nullopt when it follows the painted values.
    std::optional<std::pair<double, double>> fixedColourRange(PaintField field) const;
    /// The range the brush's field is coloured by on object i now (fixed, or its min–max).
    std::pair<double, double> colourRange(int object) const;
    /// Each node's place in colourRange() as the overlay colours it: 0 the low end, 1 the high end.
    std::vector<float> nodeColourParameters(int object) const;
    /// The legend's text ("stiffness: 0 – 100 N/m (fixed)").
    QString legendText() const;

    /// Pixel position of a world point in this widget (for tools and tests).
    QPointF toWidget(const Vec3& world) const;
    /// Deformed positions of object i's mesh right now (CPU evaluation: picking, tests).
    std::vector<Vec3f> deformedPositions(int object) const;
    /// Lattice node positions drawn for object i now: the simulation's, or the mode view's pose.
    std::vector<Vec3> displayedNodes(int object) const;

    /// The mode view: animates `object`'s lattice in `mode` about its rest pose, nodes at
    /// rest + a(t)·φ with a(t) = A·sin(2π·kModeDisplayHz·t) and A = kModeDisplayFraction of the box's
    /// largest side (core/modes/modes.h); the mesh follows through the usual lattice map. Display only: the
    /// document, its undo stack and the simulation's state are untouched (playback pauses while the
    /// view shows the body about rest). `index` (1-based) names the mode in
    /// the caption. Showing the same object and index again (the shape after a material edit) keeps
    /// the clock. Stops when playback starts, the simulation steps, the current object changes, or
    /// the scene or the lattice is replaced.
    void showMode(int object, int index, const VibrationMode& mode);
    /// Stops the mode view (the simulation's pose is drawn again).
    void stopModeView();
    /// Index (1-based) of the mode shown, 0 when the mode view is off.
    int shownMode() const { return m_modeView ? m_modeView->index : 0; }
    /// a(t) of the pose drawn now, metres (the nodes are rest + a·φ); 0 when the mode view is off.
    double modeDisplacement() const;
    /// Freezes the mode view `seconds` into its cycle (0.25 s at 1 Hz: the largest displacement), for
    /// screenshots and tests; a negative value lets it run on the clock again.
    void holdModeView(double seconds);

public slots:
    void setTool(softtouch::ui::Tool tool);
    void setShadeMode(softtouch::render::ShadeMode mode);
    void setNavigationStyle(softtouch::ui::NavigationStyle style);
    void setOverlayVisible(bool visible);
    /// Paints `field` from now on: the overlay and legend show it.
    void setBrushField(softtouch::ui::PaintField field);
    void setAnchorMode(softtouch::AnchorMode mode);
    void setCurrentObject(int object);
    /// Makes collider `index` the one the collider tool acts on (-1: none).
    void setCurrentCollider(int index);
    void setSelection(const std::set<int>& nodes);
    /// Frames every object.
    void frameAll();
    /// Frames the selected nodes (every object when nothing is selected).
    void frameSelection();
    void viewFront();
    void viewSide();
    void viewTop();

signals:
    void toolChanged(softtouch::ui::Tool tool);
    void brushFieldChanged(softtouch::ui::PaintField field);
    /// The mode view started, changed or stopped (index 0).
    void modeViewChanged(int object, int index);
    void selectionChanged();
    /// Another object became the one the tools act on (outliner, double-click, a click in select or pose).
    void currentObjectChanged(int object);
    /// The collider the collider tool acts on changed (-1: none).
    void currentColliderChanged(int index);
    /// A one-line hint for the status bar (what the tool would do, what was picked).
    void hint(const QString& text);

protected:
    void initializeGL() override;
    void resizeGL(int w, int h) override;
    void paintGL() override;
    void mousePressEvent(QMouseEvent* event) override;
    void mouseMoveEvent(QMouseEvent* event) override;
    void mouseReleaseEvent(QMouseEvent* event) override;
    void mouseDoubleClickEvent(QMouseEvent* event) override;
    void wheelEvent(QWheelEvent* event) override;
    void tabletEvent(QTabletEvent* event) override;
    void keyPressEvent(QKeyEvent* event) override;
    /// The pointer came over the view: its keys (G, R, S, typed amounts, frame and view keys) go where the
    /// pointer is, as in Blender, unless a text or number field is being typed into.
    void enterEvent(QEnterEvent* event) override;
    /// Claims the keys a transform or the pose tool uses (G, R, S, X, Y, Z, digits, Enter, Esc) before the
    /// window's shortcuts (S is the select tool's) take them.
    bool event(QEvent* event) override;

private:
    // The tools (ui/viewport_tools.h) act through the viewport's picking, camera and document.
    friend class DragTool;
    friend class PaintTool;
    friend class NodeTool;
    friend class PoseTool;
    friend class LatticeTool;
    friend class ColliderTool;
    /// What the mouse's held button does: a camera move, or the current tool's gesture.
    enum class Gesture { None, Orbit, Pan, Dolly, Tool };
    void uploadScene();
public slots:
    /// Shows the painted field's range (call after changing brush().field).
    void updateLegend();

private:
    void updateOverlay(int object, const std::vector<Vec3>& nodes);
    /// Seconds into the mode view's cycle.
    double modeSeconds() const;
    Gesture navigationFor(const QMouseEvent* event) const;
    std::vector<Eigen::Vector2d> nodeScreenPositions(int object) const;
    int nodeAt(const QPointF& pos, double radiusPixels = 14.0) const;
    /// The object whose deformed surface is nearest under `pos` (-1: none), and where (`hit`).
    int objectAt(const QPointF& pos, std::optional<SurfaceHit>* hit = nullptr) const;
    /// The collider under `pos` (within its drawn size, or 30 pixels of its centre), -1 when none.
    int colliderAt(const QPointF& pos) const;
    void deleteCollider();
    /// Feeds the cursor at `pos` to the transform under way and shows its pose.
    void updateTransform(const QPointF& pos);
    /// One key binding of the viewport (see keyTable()).
    struct KeyBinding {
        std::vector<int> keys;   ///< Qt::Key values that trigger it (without Ctrl, Alt or Meta).
        QString shown;           ///< The keys as the help shows them.
        QString what;            ///< What they do.
        bool duringTransform;    ///< Active while G/R/S is under way (and only then).
        std::function<bool(QKeyEvent*)> run;  ///< False: not applicable now; the key goes on to the window.
    };
    std::vector<KeyBinding> keyBindings();
    /// The gizmo part within a few pixels of `pos`: what it does and along or about which axis.
    std::optional<std::pair<TransformKind, TransformAxis>> gizmoPartAt(const QPointF& pos) const;
    void drawGizmo(QPainter& painter) const;
    std::vector<int> nodesInRect(const QRectF& rect) const;

    Document* m_document;
    SimulationController* m_simulation;
    QWidget* m_recordingCue = nullptr;  ///< Red frame and "● REC" while a take is recorded.
    double m_recordingStart = 0.0;      ///< Simulation time the take started at, s.
    render::MeshRenderer m_renderer;
    bool m_glReady = false;
    bool m_sceneDirty = true;
    QString m_renderProblem;
    OrbitCamera m_camera;
    Tool m_tool = Tool::Drag;
    std::unique_ptr<ViewportTool> m_activeTool;  ///< The tool behind m_tool.
    render::ShadeMode m_shadeMode = render::ShadeMode::Shaded;
    NavigationStyle m_navigation = NavigationStyle::Maya;
    bool m_overlayVisible = true;
    AnchorMode m_anchorMode = AnchorMode::Pinned;
    BrushSettings m_brush;
    DragToolSettings m_drag;
    std::set<int> m_selection;
    int m_collider = -1;
    int m_object = 0;

    Gesture m_gesture = Gesture::None;
    QPointF m_lastPos;
    double m_pressure = 1.0;
    double m_tiltDepth = 0.0;    ///< Pen tilt towards/away from the screen, in [-1, 1] (yTilt / 60°).
    int m_nextStrokeKey = 1000;  ///< A tool's next stroke's undo merge key (kFirstStrokeKey).
    double m_frameMs = 0.0;
    ValueLegend* m_legend = nullptr;
    std::map<PaintField, std::pair<double, double>> m_fixedColourRanges;  ///< See setColourRange().
    GrabIndicator* m_grabIndicator = nullptr;
    PoseOverlay* m_poseOverlay = nullptr;      ///< Draws the gizmo and the transform's caption.
    std::vector<KeyBinding> m_keys;            ///< keyBindings(), made once.
    std::optional<NodeTransform> m_transform;  ///< G/R/S under way (see beginTransform()).
    QPointF m_transformCursor;                 ///< Where the cursor was when it began.
    double m_transformTurn = 0.0;              ///< Rotate: the angle swept round the pivot so far, radians.
    double m_transformLastAngle = 0.0;         ///< Rotate: the cursor's screen angle at the last move.

    /// What the mode view shows (see showMode()).
    struct ModeView {
        int object = 0;             ///< Object index.
        int index = 1;              ///< 1-based mode number, for the caption.
        VibrationMode mode;         ///< Frequency, ζ and shape φ (max |φ_i| = 1).
        std::vector<Vec3> rest;     ///< The lattice's rest nodes, metres.
        double amplitude = 0.0;     ///< A, metres.
        long long step = 0;         ///< The simulation's step count when shown: a step ends the view.
    };
    std::optional<ModeView> m_modeView;
    QElapsedTimer m_modeClock;       ///< Time since the mode view started.
    double m_modeHeldSeconds = -1.0; ///< >= 0: frozen at this time into the cycle.
    QTimer m_modeTimer;              ///< Redraws the mode view at ~60 Hz.
    QLabel* m_modeCaption = nullptr; ///< Which mode is shown, its true frequency and ζ.
    std::vector<Vec3f> m_basePositions, m_baseNormals; ///< Bodies on a base animation, deformed on the CPU.
};

}  // namespace softtouch::ui

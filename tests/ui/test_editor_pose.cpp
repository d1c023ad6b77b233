// The editor driven through its real widgets (under Xvfb). Posing and pulling: the pose tool, the lattice
// tool, mouse, pen and device drags.
#include "editor_fixture.h"

void TestEditor::latticeToolMovesAndScalesTheBox() {
    MainWindow& w = *m_window;
    Viewport* view = w.viewport();
    w.findChild<QAction*>("toolLattice")->trigger();
    const OrientedBox before = w.document()->scene().objects[0].lattice.box();
    const Vec3 centre = before.toWorld(Vec3::Constant(0.5));
    const QPoint start = view->toWidget(centre).toPoint();
    const int undoBefore = w.document()->undoStack()->index();
    QTest::mousePress(view, Qt::LeftButton, {}, start);
    for (int i = 1; i <= 4; ++i)
        QTest::mouseMove(view, start + QPoint(15 * i, 0));
    QTest::mouseRelease(view, Qt::LeftButton, {}, start + QPoint(60, 0));
    const OrientedBox moved = w.document()->scene().objects[0].lattice.box();
    // The box centre now projects 60 pixels to the right, and the whole gesture is one undo step.
    const QPointF now = view->toWidget(moved.toWorld(Vec3::Constant(0.5)));
    QVERIFY2(std::abs(now.x() - (start.x() + 60)) < 2.0 && std::abs(now.y() - start.y()) < 2.0,
             qPrintable(QString("centre at %1,%2").arg(now.x()).arg(now.y())));
    QVERIFY(moved.size == before.size);
    QCOMPARE(w.document()->undoStack()->index(), undoBefore + 1);
    // The mesh did not move with it: at rest the map is still the identity.
    const std::vector<Vec3f> rest = w.document()->scene().objects[0].mesh->positions;
    QVERIFY(maxDistance(view->deformedPositions(0), rest) < 1e-5);
    // Shift+drag up grows the box about its centre.
    const QPoint c = now.toPoint();
    QTest::mousePress(view, Qt::LeftButton, Qt::ShiftModifier, c);
    QTest::mouseMove(view, c + QPoint(0, -40));
    QTest::mouseRelease(view, Qt::LeftButton, Qt::ShiftModifier, c + QPoint(0, -40));
    const OrientedBox grown = w.document()->scene().objects[0].lattice.box();
    QVERIFY(grown.size.x() > moved.size.x() * 1.1);
    QVERIFY((grown.toWorld(Vec3::Constant(0.5)) - moved.toWorld(Vec3::Constant(0.5))).norm() < 1e-9 * moved.diagonal() + 1e-12);
    w.document()->undoStack()->undo();
    w.document()->undoStack()->undo();
    QVERIFY(w.document()->scene().objects[0].lattice.box().origin == before.origin);
}

// The pose tool (#15 item 2), driven by the keys and the mouse: a click selects a node; G X 0.1 Enter moves
// it 0.1 m along X as one undo step; R Z 90 and S 2 turn and scale a selection about its centre (S scales
// rather than picking the select tool); G and the mouse move nodes with the cursor in the view plane, Esc
// puts them back, a click applies; dragging the gizmo's X arrow moves along X only; I keys the pose and the
// key holds it; Play lets physics take over; undo takes every pose back to rest.
void TestEditor::poseToolMovesRotatesScalesAndKeys() {
    MainWindow& w = *m_window;
    Viewport* view = startPosing(w);
    SimulationController* sim = w.simulation();
    QUndoStack* undo = w.document()->undoStack();
    QCOMPARE(view->tool(), Tool::Pose);
    QCOMPARE(w.findChild<ToolOptionsBar*>()->shownTool(), Tool::Pose);
    const auto nodes = [&] { return sim->simulation()->simulator(0).state().position; };
    const std::vector<Vec3> rest = nodes();
    const int undo0 = undo->index();
    const auto onlyMoved = [&](const std::vector<Vec3>& now, const std::vector<Vec3>& before, const std::set<int>& moved) {
        for (std::size_t m = 0; m < now.size(); ++m)
            if (!moved.count(int(m)) && now[m] != before[m])
                return false;
        return true;
    };

    // A click selects; G, X, 0.1, Enter.
    const int n = isolatedNode(w, 0);
    QVERIFY(n >= 0);
    QTest::mouseClick(view, Qt::LeftButton, {}, screenOfNode(w, n));
    QCOMPARE(view->selection(), std::set<int>{n});
    QTest::mouseMove(view, view->rect().center());
    QTest::keyClick(view, Qt::Key_G);
    QVERIFY(view->transform());
    QTest::keyClick(view, Qt::Key_X);
    QTest::keyClicks(view, "0.1");
    QTest::keyClick(view, Qt::Key_Return);
    QVERIFY(!view->transform());
    std::vector<Vec3> posed = nodes();
    QVERIFY2((posed[std::size_t(n)] - rest[std::size_t(n)] - Vec3(0.1, 0, 0)).norm() < 1e-12,
             qPrintable(QString("moved by %1").arg((posed[std::size_t(n)] - rest[std::size_t(n)]).norm())));
    QVERIFY(onlyMoved(posed, rest, {n}));
    QCOMPARE(undo->index(), undo0 + 1);
    QCOMPARE(undo->undoText(), QString("Move 1 node"));

    // R Z 90 and S 2 about the selection's centre.
    const std::set<int> four = {0, 1, 4, 5};
    view->setSelection(four);
    Vec3 pivot = Vec3::Zero();
    for (int m : four)
        pivot += posed[std::size_t(m)] / 4.0;
    QTest::keyClick(view, Qt::Key_R);
    QTest::keyClick(view, Qt::Key_Z);
    QTest::keyClicks(view, "90");
    QTest::keyClick(view, Qt::Key_Return);
    const Mat3 quarter = Eigen::AngleAxisd(std::numbers::pi / 2, Vec3::UnitZ()).toRotationMatrix();
    std::vector<Vec3> turned = nodes();
    for (int m : four)
        QVERIFY((turned[std::size_t(m)] - pivot - quarter * (posed[std::size_t(m)] - pivot)).norm() < 1e-12);
    QVERIFY(onlyMoved(turned, posed, four));
    QTest::keyClick(view, Qt::Key_S);
    QCOMPARE(view->tool(), Tool::Pose);  // S scaled; it did not pick the select tool
    QTest::keyClick(view, Qt::Key_2);
    QTest::keyClick(view, Qt::Key_Enter);
    std::vector<Vec3> scaled = nodes();
    for (int m : four)
        QVERIFY((scaled[std::size_t(m)] - pivot - 2.0 * (turned[std::size_t(m)] - pivot)).norm() < 1e-12);
    QCOMPARE(undo->index(), undo0 + 3);

    // The mouse: the node follows the cursor 40 px to the right in the view plane; Esc puts it back.
    view->setSelection({n});
    const QPoint from = view->rect().center();
    QTest::mouseMove(view, from);
    const QPointF shownBefore = view->toWidget(scaled[std::size_t(n)]);
    QTest::keyClick(view, Qt::Key_G);
    QTest::mouseMove(view, from + QPoint(20, 0));
    QTest::mouseMove(view, from + QPoint(40, 0));
    const QPointF shownDuring = view->toWidget(nodes()[std::size_t(n)]);
    QVERIFY2(std::abs(shownDuring.x() - shownBefore.x() - 40.0) < 1.0 && std::abs(shownDuring.y() - shownBefore.y()) < 1.0,
             qPrintable(QString("moved on screen by %1, %2").arg(shownDuring.x() - shownBefore.x()).arg(shownDuring.y() - shownBefore.y())));
    QTest::keyClick(view, Qt::Key_Escape);
    QVERIFY(!view->transform());
    QVERIFY(nodes() == scaled);
    QCOMPARE(undo->index(), undo0 + 3);
    QTest::mouseMove(view, from);
    QTest::keyClick(view, Qt::Key_G);
    QTest::mouseMove(view, from + QPoint(40, 0));
    QTest::mouseClick(view, Qt::LeftButton, {}, from + QPoint(40, 0));  // a click applies
    QVERIFY(!view->transform());
    QCOMPARE(undo->index(), undo0 + 4);
    const std::vector<Vec3> dragged = nodes();
    QVERIFY(std::abs(view->toWidget(dragged[std::size_t(n)]).x() - shownBefore.x() - 40.0) < 1.0);

    // The gizmo: dragging its X arrow moves the node along X only.
    const std::optional<Viewport::Gizmo> gizmo = view->gizmo();
    QVERIFY(gizmo);
    const QPointF centre = gizmo->centre;
    const QPointF along = gizmo->tips[0] - centre;
    QVERIFY(std::hypot(along.x(), along.y()) > 20.0);
    const QPoint grab = (centre + 0.8 * along).toPoint();
    const QPoint pulled = (centre + 1.6 * along).toPoint();
    QTest::mousePress(view, Qt::LeftButton, {}, grab);
    QVERIFY(view->transform() && view->transform()->axis() == TransformAxis::X);
    QTest::mouseMove(view, (grab + pulled) / 2);
    QTest::mouseMove(view, pulled);
    QTest::mouseRelease(view, Qt::LeftButton, {}, pulled);
    const std::vector<Vec3> gizmoed = nodes();
    const Vec3 step = gizmoed[std::size_t(n)] - dragged[std::size_t(n)];
    QVERIFY2(step.x() > 1e-3 && std::abs(step.y()) < 1e-12 && std::abs(step.z()) < 1e-12,
             qPrintable(QString("moved by %1, %2, %3").arg(step.x()).arg(step.y()).arg(step.z())));
    QCOMPARE(undo->index(), undo0 + 5);

    // I keys the pose of the selection at the Keys dock's time; the key holds it.
    QTest::keyClick(view, Qt::Key_I);
    const std::vector<LatticeKey> keyed = w.keyframes()->keys();
    QCOMPARE(keyed.size(), std::size_t(1));
    QCOMPARE(keyed[0].nodes.size(), std::size_t(1));
    const NamedKeyframes* set = w.document()->project().clips.findKeyframes(KeyframePanel::kDefaultSet);
    QVERIFY(set);
    const std::vector<Vec3> restNodes = w.document()->scene().objects[0].lattice.restNodes();
    QVERIFY((set->objects[0].pose(keyed[0].seconds, restNodes)[std::size_t(n)] - gizmoed[std::size_t(n)]).norm() < 1e-9);
    QCOMPARE(undo->index(), undo0 + 6);

    // The viewport's keys are in Help ▸ Keyboard Shortcuts, read from the table that dispatches them.
    bool listed = false;
    for (const auto& [what, keys] : view->keyTable())
        listed = listed || (what.contains("move the selected nodes") && keys == "G");
    QVERIFY(listed);

    // Physics takes over from the pose: the stretched node is pulled back.
    sim->advance(0.05);
    QVERIFY((nodes()[std::size_t(n)] - gizmoed[std::size_t(n)]).norm() > 1e-4);
    // Undo takes every step back: the key, then each pose, to rest.
    while (undo->index() > undo0)
        undo->undo();
    QVERIFY(w.keyframes()->keys().empty());
    QVERIFY(nodes() == rest);
}

// The pose tool's "Pose as rest shape": the tail turned with R Z 25 becomes the mesh's rest shape (what the
// viewport showed), the lattice is at rest around it, one undo step takes it back, and a saved project
// reopens with the same mesh.
// #42 item 4: the pose tool's keys go where the pointer is, as in Blender. With the keyboard focus elsewhere (the
// clips list, clicked last), moving the pointer over the view is enough for G to start a move there; the
// pointer crossing the view while a number is typed into a field leaves the typing alone.
void TestEditor::poseKeysGoWhereThePointerIs() {
    MainWindow& w = *m_window;
    Viewport* view = startPosing(w);
    const int n = isolatedNode(w, 0);
    QVERIFY(n >= 0);
    QTest::mouseClick(view, Qt::LeftButton, {}, screenOfNode(w, n));
    QCOMPARE(view->selection(), std::set<int>{n});
    // Focus elsewhere, as a click on the clips list leaves it, and the pointer over that list.
    auto* list = w.timeline()->findChild<QListWidget*>("clips");
    QVERIFY(list);
    QCursor::setPos(list->viewport()->mapToGlobal(list->viewport()->rect().center()));
    // The pointer has left the view before the view is entered again (a window opened under a pointer that an
    // earlier test left over the view starts with the view under it).
    QTRY_VERIFY(list->viewport()->underMouse() && !view->underMouse());
    QTest::mouseClick(list->viewport(), Qt::LeftButton, {}, list->viewport()->rect().center());
    QTRY_VERIFY(list->hasFocus());
    // The pointer moves over the view (a real pointer move: the X server sends the enter).
    QCursor::setPos(view->mapToGlobal(view->rect().center()));
    QTRY_VERIFY(view->hasFocus());
    QTest::keyClick(QApplication::focusWidget(), Qt::Key_G);  // where the keyboard's key goes
    QVERIFY(view->transform());
    QTest::keyClick(QApplication::focusWidget(), Qt::Key_Escape);
    QVERIFY(!view->transform());
    // A value being typed keeps the keyboard when the pointer passes over the view.
    auto* step = w.findChild<QDoubleSpinBox*>("stepsPerSecond");
    QVERIFY(step);
    QCursor::setPos(step->mapToGlobal(step->rect().center()));
    QTest::mouseClick(step, Qt::LeftButton, {}, step->rect().center());
    QTRY_VERIFY(step->hasFocus());
    QCursor::setPos(view->mapToGlobal(view->rect().center()));
    QTest::qWait(100);
    QVERIFY(step->hasFocus());
}

void TestEditor::poseAsRestShapeSavesAndUndoes() {
    MainWindow& w = *m_window;
    Viewport* view = startPosing(w);
    SimulationController* sim = w.simulation();
    const Lattice& lattice = w.document()->scene().objects[0].lattice;
    std::set<int> tail;
    for (int n = 0; n < lattice.nodeCount(); ++n)
        if (lattice.coords(n)[0] == 0)
            tail.insert(n);
    view->setSelection(tail);
    QTest::keyClick(view, Qt::Key_R);
    QTest::keyClick(view, Qt::Key_Z);
    QTest::keyClicks(view, "25");
    QTest::keyClick(view, Qt::Key_Return);
    const std::vector<Vec3f> shown = view->deformedPositions(0);
    const Mesh before = w.document()->scene().objects[0].mesh;
    QVERIFY(maxDistance(shown, before.positions) > 1e-3);
    const int undoBefore = w.document()->undoStack()->index();

    w.findChild<QPushButton*>("poseAsRest")->click();
    QCOMPARE(w.document()->undoStack()->index(), undoBefore + 1);
    const Mesh& after = w.document()->scene().objects[0].mesh;
    QVERIFY2(maxDistance(after.positions, shown) < 1e-6, qPrintable(QString::number(maxDistance(after.positions, shown))));
    // The simulation was rebuilt at rest: its nodes are the lattice's rest nodes and they draw the new shape.
    const std::vector<Vec3> restNodes = w.document()->scene().objects[0].lattice.restNodes();
    QVERIFY(sim->simulation()->simulator(0).state().position == restNodes);
    QVERIFY(maxDistance(view->deformedPositions(0), shown) < 1e-5);

    // Saved and reopened: the same mesh, bit for bit; the mesh file itself is untouched.
    const QString path = m_dir->filePath("bent.softtouch");
    QVERIFY(w.document()->saveAs(path).ok());
    Document reopened;
    QVERIFY(reopened.open(path).ok());
    QVERIFY(reopened.scene().objects[0].mesh->positions == after.positions);
    QCOMPARE(reopened.project().restShapeEdits[0].size(), std::size_t(1));

    // One undo step back to the fish as it was.
    w.document()->undoStack()->undo();
    QVERIFY(w.document()->scene().objects[0].mesh->positions == before.positions);
    QVERIFY(w.document()->project().restShapeEdits.empty() || w.document()->project().restShapeEdits[0].empty());
}

// The pose gizmo's other parts: dragging the Y scale square outward scales the selection along Y only, and
// dragging along the Z ring (seen face-on from the front) turns it about Z through its centre; each one undo
// step.
void TestEditor::poseGizmoScalesAndTurns() {
    MainWindow& w = *m_window;
    Viewport* view = startPosing(w);
    SimulationController* sim = w.simulation();
    QUndoStack* undo = w.document()->undoStack();
    view->viewFront();
    const auto nodes = [&] { return sim->simulation()->simulator(0).state().position; };
    const std::set<int> four = {21, 22, 25, 26};  // the middle of a 4x4x4 lattice, j = 1..2, k = 1
    view->setSelection(four);
    const std::vector<Vec3> start = nodes();
    Vec3 pivot = Vec3::Zero();
    for (int m : four)
        pivot += start[std::size_t(m)] / 4.0;
    const int undo0 = undo->index();
    // Scale along Y: the Y square dragged to twice its distance from the centre.
    std::optional<Viewport::Gizmo> g = view->gizmo();
    QVERIFY(g);
    const QPointF handle = g->scaleHandles[1];
    QTest::mousePress(view, Qt::LeftButton, {}, handle.toPoint());
    QVERIFY(view->transform() && view->transform()->kind() == TransformKind::Scale && view->transform()->axis() == TransformAxis::Y);
    QTest::mouseMove(view, (g->centre + 1.5 * (handle - g->centre)).toPoint());
    QTest::mouseMove(view, (g->centre + 2.0 * (handle - g->centre)).toPoint());
    QTest::mouseRelease(view, Qt::LeftButton, {}, (g->centre + 2.0 * (handle - g->centre)).toPoint());
    const std::vector<Vec3> scaled = nodes();
    QCOMPARE(undo->index(), undo0 + 1);
    double factor = 0.0;
    for (int m : four) {
        const Vec3 before = start[std::size_t(m)] - pivot, after = scaled[std::size_t(m)] - pivot;
            QVERIFY(std::abs(after.x() - before.x()) < 1e-12 && std::abs(after.z() - before.z()) < 1e-12);
        if (std::abs(before.y()) > 1e-6)
            factor = after.y() / before.y();
    }
    QVERIFY2(factor > 1.8 && factor < 2.2, qPrintable(QString::number(factor)));
    // Turn about Z: along the Z ring from its point at 22.5° to its point at 67.5° (where the X and Y arrows
    // cross the ring, the arrows are what a press takes).
    g = view->gizmo();
    QTest::mousePress(view, Qt::LeftButton, {}, g->rings[2][3].toPoint());
    QVERIFY(view->transform() && view->transform()->kind() == TransformKind::Rotate && view->transform()->axis() == TransformAxis::Z);
    QTest::mouseMove(view, g->rings[2][6].toPoint());
    QTest::mouseMove(view, g->rings[2][9].toPoint());
    QTest::mouseRelease(view, Qt::LeftButton, {}, g->rings[2][9].toPoint());
    const std::vector<Vec3> turned = nodes();
    QCOMPARE(undo->index(), undo0 + 2);
    double angle = 0.0;
    for (int m : four) {
        const Vec3 before = scaled[std::size_t(m)] - pivot, after = turned[std::size_t(m)] - pivot;
        QVERIFY(std::abs(after.z() - before.z()) < 1e-12);
        QVERIFY(std::abs(after.head<2>().norm() - before.head<2>().norm()) < 1e-9);
        angle = std::atan2(before.x() * after.y() - before.y() * after.x(), before.head<2>().dot(after.head<2>()));
    }
    QVERIFY2(std::abs(std::abs(angle) - std::numbers::pi / 4) < 0.05, qPrintable(QString::number(angle)));
    while (undo->index() > undo0)
        undo->undo();
    QVERIFY(nodes() == start);
}

void TestEditor::mouseDragPullsAndReleaseSwingsBack() {
    MainWindow& w = *m_window;
    w.simulation()->setDriversEnabled(false);  // only the mouse moves the fish
    Viewport* view = w.viewport();
    QCOMPARE(view->tool(), Tool::Drag);
    const std::vector<Vec3f> rest = view->deformedPositions(0);
    // Grab the tail half (the head is pinned): the centroid of the vertices at low u, on screen.
    const SceneObject& fish = w.document()->scene().objects[0];
    Vec3 tail = Vec3::Zero();
    int count = 0;
    for (const Vec3f& p : fish.mesh->positions) {
        if (fish.lattice.box().toParameters(p.cast<double>()).x() < 0.3) {
            tail += p.cast<double>();
            ++count;
        }
    }
    QVERIFY(count > 0);
    const QPoint grabAt = view->toWidget(tail / count).toPoint();
    QTest::mousePress(view, Qt::LeftButton, {}, grabAt);
    w.simulation()->pause();
    QVERIFY2(w.simulation()->grab(0).has_value(), "the press did not hit the fish");
    for (int i = 1; i <= 5; ++i)
        QTest::mouseMove(view, grabAt + QPoint(0, -24 * i));
    w.simulation()->advance(1.0);
    const double diagonal = fish.mesh->bounds().diagonal();
    const double pulled = maxDistance(view->deformedPositions(0), rest);
    QVERIFY2(pulled > 0.05 * diagonal, qPrintable(QString("moved %1 of the diagonal").arg(pulled / diagonal)));

    QTest::mouseRelease(view, Qt::LeftButton, {}, grabAt + QPoint(0, -120));
    w.simulation()->pause();
    QVERIFY(!w.simulation()->grab(0).has_value());
    w.simulation()->advance(0.15);
    const double swinging = maxDistance(view->deformedPositions(0), rest);
    w.simulation()->advance(6.0);
    const double settled = maxDistance(view->deformedPositions(0), rest);
    QVERIFY2(settled < 0.2 * pulled, qPrintable(QString("still %1 of the pull away after 6 s").arg(settled / pulled)));
    QVERIFY(swinging > settled);
}

void TestEditor::secondHandHoldsAndPenPressureScalesTheSpring() {
    MainWindow& w = *m_window;
    Viewport* view = w.viewport();
    const SceneObject& fish = w.document()->scene().objects[0];
    const QPoint body = view->toWidget(fish.lattice.box().toWorld(Vec3(0.5, 0.5, 0.5))).toPoint();
    // Ctrl+drag: the second hand, which keeps holding after the button is released.
    QTest::mousePress(view, Qt::LeftButton, Qt::ControlModifier, body);
    w.simulation()->pause();
    QVERIFY2(w.simulation()->grab(1).has_value(), "Ctrl+press did not grab the body");
    QTest::mouseMove(view, body + QPoint(40, 0));
    QTest::mouseRelease(view, Qt::LeftButton, Qt::ControlModifier, body + QPoint(40, 0));
    QVERIFY(w.simulation()->grab(1).has_value());
    // A pen at half pressure: the first hand's spring is half as stiff.
    QTabletEvent pen(QEvent::TabletPress, QPointingDevice::primaryPointingDevice(), body, view->mapToGlobal(body), 0.5,
                     0.0f, 0.0f, 0.0f, 0.0f, 0.0f, Qt::NoModifier, Qt::LeftButton, Qt::LeftButton);
    QApplication::sendEvent(view, &pen);
    QTest::mousePress(view, Qt::LeftButton, {}, body + QPoint(0, 10));
    w.simulation()->pause();
    QVERIFY(w.simulation()->grab(0).has_value());
    QCOMPARE(w.simulation()->grab(0)->drag.stiffness, 0.5 * view->dragSettings().stiffness);
    // Tilting the pen 30° pushes the target into the screen by half the tilt depth.
    const Vec3 flat = w.simulation()->grab(0)->drag.target;
    QTabletEvent tilt(QEvent::TabletMove, QPointingDevice::primaryPointingDevice(), body + QPoint(0, 10),
                      view->mapToGlobal(body + QPoint(0, 10)), 0.5, 0.0f, 30.0f, 0.0f, 0.0f, 0.0f, Qt::NoModifier,
                      Qt::LeftButton, Qt::LeftButton);
    QApplication::sendEvent(view, &tilt);
    QTest::mouseMove(view, body + QPoint(0, 10));
    const double depth = (w.simulation()->grab(0)->drag.target - flat).dot(view->camera().forward());
    const double expected = 0.5 * view->dragSettings().tiltDepth * fish.mesh->bounds().diagonal();
    QVERIFY2(std::abs(depth - expected) < 0.02 * expected, qPrintable(QString("depth %1, expected %2").arg(depth).arg(expected)));
    // Both hands act at once.
    w.simulation()->advance(0.05);
    QCOMPARE(w.simulation()->simulation()->interactiveDrags(0).size(), std::size_t(2));
    QTest::mouseRelease(view, Qt::LeftButton, {}, body + QPoint(0, 10));
    QVERIFY(!w.simulation()->grab(0).has_value());
    QVERIFY(w.simulation()->grab(1).has_value());
    // Ctrl+click on empty space lets the second hand go.
    QTest::mouseClick(view, Qt::LeftButton, Qt::ControlModifier, QPoint(5, 5));
    QVERIFY(!w.simulation()->grab(1).has_value());
}

void TestEditor::scriptedDeviceDrivesTheFishAtHapticRate() {
    MainWindow& w = *m_window;
    HapticController* haptics = w.haptics();
    QVERIFY2(haptics->deviceNames().contains("scripted"), qPrintable(haptics->deviceNames().join(", ")));
    QVERIFY(w.findChild<QAction*>("device_scripted") != nullptr);  // offered in Simulation > Input Device
    const std::vector<Vec3f> rest = w.viewport()->deformedPositions(0);
    haptics->setWorkspaceScale(2.0);
    const Status started = haptics->start("scripted", SOFTTOUCH_SOURCE_DIR "/presets/devices/figure-eight.sttraj", 0);
    QVERIFY2(started.ok(), started.message().c_str());
    QVERIFY(haptics->isRunning());
    QVERIFY(!w.simulation()->isPlaying());  // the loop owns the body now
    // Calibration: the workspace fitted onto the lattice box, scaled by the user's factor.
    {
        Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
        for (const Vec3& p : w.document()->scene().objects[0].lattice.restNodes()) {
            lo = lo.cwiseMin(p);
            hi = hi.cwiseMax(p);
        }
        auto trajectory = io::loadTrajectory(SOFTTOUCH_SOURCE_DIR "/presets/devices/figure-eight.sttraj");
        QVERIFY(trajectory.ok());
        const DeviceCalibration fit = DeviceCalibration::fit(trajectory->device, lo, hi);
        QCOMPARE(haptics->calibration().scale, 2.0 * fit.scale);
        QVERIFY((haptics->calibration().origin - fit.origin).norm() < 1e-12);
    }
    // The loop runs on its own thread at about 1 kHz; the viewport shows its snapshots.
    QTRY_VERIFY_WITH_TIMEOUT(haptics->snapshot().tick > 800, 10000);
    QTRY_VERIFY_WITH_TIMEOUT(maxDistance(w.viewport()->deformedPositions(0), rest) > 1e-3, 5000);
    QVERIFY(haptics->snapshot().grabbed);
    QVERIFY2(haptics->statusText().contains("Hz"), qPrintable(haptics->statusText()));
    QVERIFY(haptics->snapshot().stats.rateHz > 100.0);  // a loose floor: timing goals live in the bench
    haptics->stop();
    QVERIFY(!haptics->isRunning());
    // The editor's simulation takes the pose over and lets the fish swing back.
    w.simulation()->setDriversEnabled(false);
    w.simulation()->advance(5.0);
    QVERIFY(maxDistance(w.viewport()->deformedPositions(0), rest) < 0.05 * w.document()->scene().objects[0].mesh->bounds().diagonal());
}

// The Speed vs accuracy dock measures the scene that is open, not a stored study: a sphere imported as a
// user does, given the shipped fish-swim setup (pinned at one end, a tail beat) and the Jelly material so
// that it moves visibly (a few % of its diagonal; the default body barely bends). The
// measurement runs on a worker thread; the pick applies as one undo step and the scene as it then
// stands is re-measured within the target: what the person sees to trust the pick.

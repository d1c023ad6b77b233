// The dope sheet under the timeline's ruler (#42 item 5): every object's keys and the keyed clips on the ruler's
// frames; the current object's keys selected several at a time (Shift+click, a box), moved, copied, deleted and
// given an interpolation together, each one undo step; another object's row makes it current; a clip's bar
// shows the clip and its menu makes it a loop. Driven by mouse and key events on the widget.
#include "editor_fixture.h"

#include "ui/dope_sheet.h"

void TestEditor::dopeSheetShowsEveryObjectsKeysAndTheirClips() {
    MainWindow& w = *m_window;
    KeyframePanel* keys = w.keyframes();
    SimulationController* sim = w.simulation();
    DopeSheet* sheet = w.timeline()->dopeSheet();
    Viewport* view = w.viewport();
    QUndoStack* undo = w.document()->undoStack();
    QVERIFY(sheet->isVisible());
    sim->setDriversEnabled(false);
    w.findChild<QAction*>("actionDuplicateObject")->trigger();
    QCOMPARE(view->currentObject(), 1);
    // Two keys on the copy, and a clip of them.
    QVERIFY(keys->keyPose(0.0));
    std::vector<Vec3> pose = w.document()->scene().objects[1].lattice.restNodes();
    pose[0] += Vec3(0, 0.05, 0);
    QVERIFY(sim->setObjectPose(1, pose));
    QVERIFY(keys->keyPose(1.0));
    QVERIFY(keys->makeClip(false));
    const auto& rows = sheet->rows();
    QCOMPARE(int(rows.size()), 3);  // each object, then the keyed clip
    QCOMPARE(rows[0].object, 0);
    QVERIFY(rows[0].keys.empty() && !rows[0].current);
    QCOMPARE(rows[1].object, 1);
    QVERIFY(rows[1].current);
    QCOMPARE(rows[1].keys, (std::vector<double>{0.0, 1.0}));
    QCOMPARE(rows[2].clip, int(w.document()->project().clips.clips.size()) - 1);
    QCOMPARE(rows[2].fromSeconds, 0.0);
    QCOMPARE(rows[2].toSeconds, 1.0 + 1.0 / w.document()->scene().world.fps);  // the keys' frames, both ends in

    // The first object's row makes it current; its (empty) row is now the edited one.
    QTest::mouseClick(sheet, Qt::LeftButton, {}, sheet->rowRect(0).center().toPoint());
    QCOMPARE(view->currentObject(), 0);
    QVERIFY(sheet->rows()[0].current && !sheet->rows()[1].current);

    // The clip's bar shows the clip; its menu makes it a loop, one undo step.
    const int clip = rows[2].clip;
    auto* clipList = w.timeline()->findChild<QListWidget*>("clips");
    QTest::mouseClick(sheet, Qt::LeftButton, {}, sheet->clipBar(2).center().toPoint());
    QCOMPARE(clipList->currentRow(), clip);
    const int undo0 = undo->index();
    const QStringList offered = chooseFromMenu(sheet, sheet->clipBar(2).center().toPoint(), "clipRowMenu", "Loop");
    QVERIFY2(offered.contains("Loop"), qPrintable(offered.join(", ")));
    QVERIFY(w.document()->project().clips.clips[std::size_t(clip)].loop);
    QVERIFY(sheet->rows()[2].loop);
    QCOMPARE(undo->index(), undo0 + 1);
    QVERIFY(w.timeline()->findChild<QCheckBox*>("clipLoop")->isChecked());  // the timeline's Loop box agrees

    // In a dock one row high the wheel brings the others into sight, a row a notch.
    sheet->setFixedHeight(int(sheet->rowRect(0).height()) + 4);
    QVERIFY(sheet->rowRect(2).top() >= sheet->height());
    const QPointF middle = sheet->rect().center();
    for (int notch = 0; notch < 2; ++notch) {
        QWheelEvent down(middle, sheet->mapToGlobal(middle), QPoint(), QPoint(0, -120), Qt::NoButton, Qt::NoModifier,
                         Qt::NoScrollPhase, false);
        QApplication::sendEvent(sheet, &down);
    }
    QVERIFY(sheet->rowRect(2).top() >= 0.0 && sheet->rowRect(2).top() < sheet->height() / 2.0);
    clipList->setCurrentRow(-1);
    QTest::mouseClick(sheet, Qt::LeftButton, {}, sheet->clipBar(2).center().toPoint());  // what shows is what is hit
    QCOMPARE(clipList->currentRow(), clip);
}

void TestEditor::dopeSheetEditsSeveralKeysAsOne() {
    MainWindow& w = *m_window;
    KeyframePanel* keys = w.keyframes();
    SimulationController* sim = w.simulation();
    DopeSheet* sheet = w.timeline()->dopeSheet();
    FrameRuler* ruler = w.timeline()->ruler();
    QUndoStack* undo = w.document()->undoStack();
    sim->setDriversEnabled(false);
    const double fps = ruler->fps();
    constexpr int kApart = 8;  // frames between the keys
    QVERIFY(ruler->lastFrame() >= 4 * kApart);
    // Four keys, frames 0, 8, 16 and 24, each a different lift of node 0.
    const std::vector<Vec3> rest = w.document()->scene().objects[0].lattice.restNodes();
    for (int k = 0; k < 4; ++k) {
        std::vector<Vec3> pose = rest;
        pose[0] += Vec3(0, 0.01 * (k + 1), 0);
        QVERIFY(sim->setObjectPose(0, pose));
        QVERIFY(keys->keyPose(double(kApart * k) / fps));
    }
    const std::vector<LatticeKey> before = keys->keys();
    QCOMPARE(sheet->rows()[0].keys.size(), std::size_t(4));
    const auto point = [&](int key) { return sheet->keyPoint(0, key).toPoint(); };
    const auto at = [&](int key, int frames) { return QPoint(int(std::lround(ruler->xOfFrame(kApart * key + frames))), point(key).y()); };

    // Click the second key, Shift+click the third: both selected; drag them three frames on, one undo step.
    QTest::mouseClick(sheet, Qt::LeftButton, {}, point(1));
    QTest::mouseClick(sheet, Qt::LeftButton, Qt::ShiftModifier, point(2));
    QCOMPARE(sheet->selectedKeys(), (QList<int>{1, 2}));
    const int undo0 = undo->index();
    dragWith(sheet, point(1), at(1, 3));
    std::vector<LatticeKey> moved = keys->keys();
    QCOMPARE(moved.size(), std::size_t(4));
    QCOMPARE(undo->index(), undo0 + 1);
    for (int k = 0; k < 4; ++k) {
        const double expected = double(kApart * k + (k == 1 || k == 2 ? 3 : 0)) / fps;
        QVERIFY2(std::abs(moved[std::size_t(k)].seconds - expected) < 1e-9, qPrintable(QString("key %1 at %2 s").arg(k).arg(moved[std::size_t(k)].seconds)));
        QCOMPARE(moved[std::size_t(k)].displacement, before[std::size_t(k)].displacement);  // the poses went with them
    }
    QCOMPARE(sheet->selectedKeys(), (QList<int>{1, 2}));  // still selected where they landed

    // Ctrl+drag copies the two back to where they were: six keys, one undo step.
    dragWith(sheet, point(1), at(1, 0), Qt::ControlModifier);
    QCOMPARE(keys->keys().size(), std::size_t(6));
    QCOMPARE(undo->index(), undo0 + 2);

    // A box dragged across the first three keys (frames 0, 8 and 11) selects them; right-click, Linear: all three.
    const QPoint boxFrom(int(ruler->xOfFrame(0)) - 8, int(sheet->rowRect(0).top()) + 1);
    const QPoint boxTo(int(std::lround(ruler->xOfFrame(kApart + 4))), int(sheet->rowRect(0).bottom()) - 1);
    dragWith(sheet, boxFrom, boxTo);
    QCOMPARE(sheet->selectedKeys(), (QList<int>{0, 1, 2}));
    const QStringList offered = chooseFromMenu(sheet, point(1), "keysMenu", "Linear");
    QVERIFY2(offered.contains("Delete 3 keys"), qPrintable(offered.join(", ")));
    for (int k = 0; k < 6; ++k)
        QCOMPARE(keys->keys()[std::size_t(k)].interpolation, k < 3 ? KeyInterpolation::Linear : KeyInterpolation::Smooth);
    QCOMPARE(undo->index(), undo0 + 3);

    // Delete takes the three out at once.
    QTest::keyClick(sheet, Qt::Key_Delete);
    QCOMPARE(keys->keys().size(), std::size_t(3));
    QCOMPARE(undo->index(), undo0 + 4);
    QVERIFY(sheet->selectedKeys().isEmpty());
    // Ctrl+A selects every key of the row.
    QTest::keyClick(sheet, Qt::Key_A, Qt::ControlModifier);
    QCOMPARE(sheet->selectedKeys(), (QList<int>{0, 1, 2}));

    // Four undos: the four keys as they were.
    for (int i = 0; i < 4; ++i)
        undo->undo();
    QCOMPARE(keys->keys().size(), std::size_t(4));
    for (int k = 0; k < 4; ++k)
        QCOMPARE(keys->keys()[std::size_t(k)].seconds, before[std::size_t(k)].seconds);
}

void TestEditor::keySetsAreMadeAndChosenInTheKeysPanel() {
    // A second keyframe set beside "keys": made with New set (one undo step), keyed and clipped on its own, and
    // chosen in the Key set box; the dope sheet and the ruler show the chosen set's keys and clips only.
    MainWindow& w = *m_window;
    KeyframePanel* keys = w.keyframes();
    SimulationController* sim = w.simulation();
    DopeSheet* sheet = w.timeline()->dopeSheet();
    FrameRuler* ruler = w.timeline()->ruler();
    QUndoStack* undo = w.document()->undoStack();
    const ClipLibrary& library = w.document()->project().clips;
    sim->setDriversEnabled(false);
    auto* box = keys->findChild<QComboBox*>("keySet");
    QVERIFY(box);
    QCOMPARE(box->currentText(), QString("keys"));
    std::vector<Vec3> pose = w.document()->scene().objects[0].lattice.restNodes();
    QVERIFY(keys->keyPose(0.0));
    pose[0] += Vec3(0, 0.05, 0);
    QVERIFY(sim->setObjectPose(0, pose));
    QVERIFY(keys->keyPose(1.0));
    QVERIFY(keys->makeClip(false));

    const int before = undo->index();
    QTest::mouseClick(keys->findChild<QPushButton*>("newKeySet"), Qt::LeftButton);
    QCOMPARE(keys->keySet(), std::string("keys 2"));
    QCOMPARE(box->currentText(), QString("keys 2"));
    QCOMPARE(undo->index(), before + 1);
    QVERIFY(library.findKeyframes("keys 2") && keys->keys().empty());
    QVERIFY(sheet->rows()[0].keys.empty());
    QCOMPARE(int(sheet->rows().size()), 1);  // the "keys" clip is not this set's
    QVERIFY(ruler->keys().empty());
    QCOMPARE(ruler->keysLabel(), QString("keys 2"));  // the ruler's row of ticks says whose keys they are

    // Keys and a clip of the new set leave "keys" as it was.
    QVERIFY(keys->keyPose(0.5));
    pose[1] += Vec3(0.04, 0, 0);
    QVERIFY(sim->setObjectPose(0, pose));
    QVERIFY(keys->keyPose(1.5));
    QVERIFY(keys->makeClip(true));
    QCOMPARE(library.clips.back().sourceName, std::string("keys 2"));
    QCOMPARE(library.clips.back().name, std::string("keys 2 clip"));
    QCOMPARE(library.findKeyframes("keys")->objects[0].keys().size(), std::size_t(2));
    QCOMPARE(sheet->rows()[0].keys, (std::vector<double>{0.5, 1.5}));
    QCOMPARE(int(sheet->rows().size()), 2);
    QCOMPARE(sheet->rows()[1].clip, int(library.clips.size()) - 1);

    // The box, from the keyboard: back to "keys", its keys and clip on the dope sheet and the ruler.
    box->setFocus();
    QTest::keyClick(box, Qt::Key_Up);
    QCOMPARE(keys->keySet(), std::string("keys"));
    QCOMPARE(box->count(), 2);
    QCOMPARE(sheet->rows()[0].keys, (std::vector<double>{0.0, 1.0}));
    QCOMPARE(sheet->rows()[1].clip, int(library.clips.size()) - 2);
    QCOMPARE(ruler->keys(), (std::vector<double>{0.0, 1.0}));
    QCOMPARE(ruler->keysLabel(), QString("keys"));

    // Choosing a clip of the second set in the Clips list shows that set.
    auto* clipList = w.timeline()->findChild<QListWidget*>("clips");
    QListWidgetItem* second = clipList->item(int(library.clips.size()) - 1);
    QTest::mouseClick(clipList->viewport(), Qt::LeftButton, {}, clipList->visualItemRect(second).center());
    QCOMPARE(keys->keySet(), std::string("keys 2"));
    QCOMPARE(box->currentText(), QString("keys 2"));
    QCOMPARE(sheet->rows()[0].keys, (std::vector<double>{0.5, 1.5}));
    clipList->setCurrentRow(-1);

    // Undo takes the second set's edits back, then the set itself, shown to the end.
    for (int i = 0; i < 3; ++i)
        undo->undo();
    QCOMPARE(keys->keySet(), std::string("keys 2"));
    QVERIFY(keys->keys().empty());
    undo->undo();
    QCOMPARE(undo->index(), before);
    QVERIFY(!library.findKeyframes("keys 2"));
    QCOMPARE(keys->keySet(), std::string("keys"));  // the set gone, the panel is back on "keys"
    QCOMPARE(box->count(), 1);
    QCOMPARE(ruler->keys(), (std::vector<double>{0.0, 1.0}));
    QCOMPARE(library.findKeyframes("keys")->objects[0].keys().size(), std::size_t(2));
}

// The editor driven through its real widgets (under Xvfb). Painting the material: brush strokes, anchors,
// presets and undo.
#include "editor_fixture.h"
#include <QTextBrowser>
#include <numeric>
#include <QStandardItemModel>

// A paint stroke is not held up by the modes: the panel analyses them on a worker thread (the stroke's dabs
// return before the analysis is done, and coalesce into the latest), and what it shows once the stroke ends is
// the painted material's lowest mode, as core computes it.
void TestEditor::modesFollowAStrokeOffTheUiThread() {
    MainWindow& w = *m_window;
    Viewport* view = w.viewport();
    auto* modes = w.findChild<QLabel*>("modes");
    auto* frequency = w.findChild<QDoubleSpinBox*>("frequency");
    QVERIFY(modes && frequency);
    waitForModes(w);
    const double before = frequency->value();
    w.findChild<QAction*>("toolPaint")->trigger();
    view->brush().field = PaintField::Stiffness;
    const LatticeMaterial material = w.document()->scene().objects[0].material;
    view->brush().value = 4.0 * *std::max_element(material.stiffness.begin(), material.stiffness.end());
    int shown = 0;
    const QMetaObject::Connection counting =
        connect(w.properties(), &PropertiesPanel::modesShown, this, [&shown] { ++shown; });
    const auto stopCounting = qScopeGuard([&] { disconnect(counting); });
    paintStroke(view);
    QVERIFY2(modes->property("analysing").toBool(), "the stroke waited for the modes");
    waitForModes(w);
    QVERIFY2(shown >= 1 && shown < 6, qPrintable(QString("%1 analyses shown for a stroke of 7 dabs").arg(shown)));
    const auto expected = objectModes(w.document()->scene().objects[0], 1);
    QVERIFY2(expected && !expected->modes.empty(), expected.message().c_str());
    QVERIFY2(std::abs(frequency->value() - expected->modes[0].frequencyHz) < 1e-3 && frequency->value() > before,
             qPrintable(QString("shown %1 Hz, the material's %2 Hz, before %3 Hz")
                            .arg(frequency->value()).arg(expected->modes[0].frequencyHz).arg(before)));
    w.document()->undoStack()->undo();
}

void TestEditor::paintStrokeIsOneUndoStep() {
    MainWindow& w = *m_window;
    Viewport* view = w.viewport();
    w.findChild<QAction*>("toolPaint")->trigger();
    QCOMPARE(view->tool(), Tool::Paint);
    view->brush().field = PaintField::Stiffness;
    const LatticeMaterial before = w.document()->scene().objects[0].material;
    view->brush().value = 4.0 * *std::max_element(before.stiffness.begin(), before.stiffness.end());
    const int undoBefore = w.document()->undoStack()->index();
    paintStroke(view);

    const LatticeMaterial after = w.document()->scene().objects[0].material;
    int raised = 0;
    for (std::size_t n = 0; n < after.stiffness.size(); ++n) {
        QVERIFY(after.stiffness[n] >= before.stiffness[n]);
        raised += after.stiffness[n] > before.stiffness[n] ? 1 : 0;
    }
    QVERIFY2(raised > 0, "the stroke changed no node");
    QCOMPARE(w.document()->undoStack()->index(), undoBefore + 1);  // the whole stroke is one step
    QVERIFY(w.document()->isModified());

    w.document()->undoStack()->undo();
    QVERIFY(sameMaterial(w.document()->scene().objects[0].material, before));  // restored exactly
    QVERIFY(!w.document()->isModified());
    w.document()->undoStack()->redo();
    QVERIFY(sameMaterial(w.document()->scene().objects[0].material, after));
}

// #42 item 8: the paint brush does not carry state into what it no longer fits. Its fields are named as the
// legend names them; the value it offers (twice the field's mean) follows a material edit made elsewhere (a modulus
// quartered in Properties left it at 8x the new one); one the user typed is kept; and goal weight, offered only
// where an object follows a base animation, is not left selected in a scene without one.
void TestEditor::paintBrushFollowsTheSceneAndItsMaterial() {
    MainWindow& w = *m_window;
    Viewport* view = w.viewport();
    auto* field = w.toolOptions()->findChild<QComboBox*>("brushField");
    auto* value = w.toolOptions()->findChild<QDoubleSpinBox*>("brushValue");
    QVERIFY(field && value);
    w.findChild<QAction*>("toolPaint")->trigger();
    field->setCurrentIndex(field->findData(int(PaintField::Stiffness)));
    QCOMPARE(w.document()->scene().objects[0].material.model, MaterialModel::Continuum);
    QCOMPARE(field->currentText(), QString("Young's modulus"));
    QVERIFY2(view->legendText().startsWith("Young's modulus"), qPrintable(view->legendText()));
    const auto mean = [&] {
        const std::vector<double>& k = w.document()->scene().objects[0].material.stiffness;
        return std::accumulate(k.begin(), k.end(), 0.0) / double(k.size());
    };
    QVERIFY(std::abs(value->value() - 2.0 * mean()) < 1e-3 * mean());
    // Properties quarters the modulus (an edit that is not a stroke): the offered value follows.
    Document* doc = w.document();
    LatticeMaterial softer = doc->scene().objects[0].material;
    for (double& k : softer.stiffness)
        k *= 0.25;
    doc->undoStack()->push(new MaterialEditCommand(doc, 0, doc->scene().objects[0].material, softer, "Set modulus"));
    QVERIFY2(std::abs(value->value() - 2.0 * mean()) < 1e-3 * mean(), qPrintable(QString("brush %1, mean %2").arg(value->value()).arg(mean())));
    QCOMPARE(view->brush().value, value->value());
    // A stroke does not move it (each dab would raise its own target otherwise).
    const double before = value->value();
    paintStroke(view);
    QCOMPARE(value->value(), before);
    // A value the user typed stays, whatever the material does.
    value->setFocus();
    value->selectAll();
    QTest::keyClicks(value, "1234");
    QTest::keyClick(value, Qt::Key_Return);
    QCOMPARE(view->brush().value, 1234.0);
    doc->undoStack()->undo();  // the stroke
    QCOMPARE(value->value(), 1234.0);
    doc->undoStack()->undo();  // the quartering

    // Goal weight on the rigged guppy, then a scene with no base animation: the brush is back on the modulus.
    QVERIFY(w.openFile(QStringLiteral(SOFTTOUCH_SOURCE_DIR "/presets/scenes/guppy-rigged.softtouch")));
    field->setCurrentIndex(field->findData(int(PaintField::GoalWeight)));
    QCOMPARE(view->brush().field, PaintField::GoalWeight);
    QVERIFY(view->legendText().startsWith("goal weight", Qt::CaseInsensitive));
    QVERIFY(w.openFile(kDefaultScene));
    QCOMPARE(view->brush().field, PaintField::Stiffness);
    QCOMPARE(field->currentData().toInt(), int(PaintField::Stiffness));
    QVERIFY2(view->legendText().startsWith("Young's modulus"), qPrintable(view->legendText()));
    auto* items = qobject_cast<QStandardItemModel*>(field->model());
    QVERIFY(items && !items->item(field->findData(int(PaintField::GoalWeight)))->isEnabled());
}

void TestEditor::redoWithCtrlYAndCtrlShiftZ() {
    // A stroke undone with Ctrl+Z comes back with Ctrl+Y, and again with Ctrl+Shift+Z, typed at the window.
    MainWindow& w = *m_window;
    w.activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(&w));
    Viewport* view = w.viewport();
    w.findChild<QAction*>("toolPaint")->trigger();
    view->brush().field = PaintField::Stiffness;
    const LatticeMaterial before = w.document()->scene().objects[0].material;
    view->brush().value = 4.0 * *std::max_element(before.stiffness.begin(), before.stiffness.end());
    paintStroke(view);
    const LatticeMaterial after = w.document()->scene().objects[0].material;
    QVERIFY(!sameMaterial(after, before));
    for (const QKeyCombination redo : {QKeyCombination(Qt::ControlModifier, Qt::Key_Y),
                                       QKeyCombination(Qt::ControlModifier | Qt::ShiftModifier, Qt::Key_Z)}) {
        QTest::keyClick(&w, Qt::Key_Z, Qt::ControlModifier);
        QVERIFY(sameMaterial(w.document()->scene().objects[0].material, before));
        QTest::keyClick(&w, redo.key(), redo.keyboardModifiers());
        QVERIFY2(sameMaterial(w.document()->scene().objects[0].material, after),
                 qPrintable(QKeySequence(redo).toString() + " did not redo"));
    }
    // Help ▸ Keyboard Shortcuts lists them, read from the actions.
    const auto table = w.shortcutTable();
    bool listed = false;
    for (const auto& [what, keys] : table)
        listed = listed || (what == "Edit ▸ Redo" && keys.contains("Ctrl+Y") && keys.contains("Ctrl+Shift+Z"));
    QVERIFY2(listed, "Edit ▸ Redo with both shortcuts is not in the shortcut table");
    bool playListed = false;
    for (const auto& [what, keys] : table)
        playListed = playListed || (what == "Simulation ▸ Play" && keys == "Space");
    QVERIFY2(playListed, "Simulation ▸ Play (Space) is not in the shortcut table");
    QVERIFY(table.size() >= 10);
    // F1 shows them in a dialog that fits a 1280x800 window (the table is longer than that: it scrolls).
    const QSize size = w.size();
    w.resize(1280, 800);
    QTRY_COMPARE(w.height(), 800);
    QSize shown;
    QString text;
    QTimer::singleShot(100, this, [&] {
        if (auto* dialog = qobject_cast<QDialog*>(QApplication::activeModalWidget())) {
            shown = dialog->frameGeometry().size();
            if (auto* browser = dialog->findChild<QTextBrowser*>())
                text = browser->toPlainText();
            dialog->reject();
        }
    });
    w.activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(&w));
    QTest::keyClick(&w, Qt::Key_F1);
    QVERIFY2(shown.isValid() && shown.height() <= 800, qPrintable(QString("%1 x %2").arg(shown.width()).arg(shown.height())));
    QVERIFY2(text.contains("Simulation ▸ Next Frame") && text.contains("move the selected nodes"), qPrintable(text.left(300)));
    w.resize(size);
    // Play says what it does next and is never shown checked.
    QAction* play = w.findChild<QAction*>("actionPlay");
    QVERIFY(!play->isCheckable());
    w.simulation()->play();
    QCOMPARE(play->text(), QString("Pause"));
    w.simulation()->pause();
    QCOMPARE(play->text(), QString("Play"));
}

// The overlay's colours re-range to the painted min – max by default, so painting part of a uniform map
// softer turns the untouched nodes red ("stiff"); a fixed range keeps one colour per value.
void TestEditor::fixedColourRangeKeepsOneColourPerValue() {
    MainWindow& w = *m_window;
    Viewport* view = w.viewport();
    w.findChild<QAction*>("toolPaint")->trigger();
    auto* field = w.findChild<QComboBox*>("brushField");
    auto* colours = w.findChild<QComboBox*>("colourRange");
    auto* low = w.findChild<QDoubleSpinBox*>("colourLow");
    auto* high = w.findChild<QDoubleSpinBox*>("colourHigh");
    QVERIFY(field && colours && low && high);
    field->setCurrentIndex(field->findData(int(PaintField::Stiffness)));
    QCOMPARE(colours->currentIndex(), 0);
    QVERIFY(!low->isVisible());  // shown with a fixed range only
    const LatticeMaterial before = w.document()->scene().objects[0].material;
    const double top = *std::max_element(before.stiffness.begin(), before.stiffness.end());
    const double bottom = *std::min_element(before.stiffness.begin(), before.stiffness.end());
    view->brush().value = 0.25 * bottom;
    const int undoBefore = w.document()->undoStack()->index();
    paintStroke(view);
    const LatticeMaterial painted = w.document()->scene().objects[0].material;
    std::vector<std::size_t> untouched, softened;
    for (std::size_t n = 0; n < painted.stiffness.size(); ++n)
        (painted.stiffness[n] < before.stiffness[n] ? softened : untouched).push_back(n);
    QVERIFY(!softened.empty() && !untouched.empty());

    // Painted min – max: the stiffest untouched node is drawn at the red end, whatever its value was.
    std::vector<float> shown = view->nodeColourParameters(0);
    const auto stiffest = std::max_element(painted.stiffness.begin(), painted.stiffness.end()) - painted.stiffness.begin();
    QCOMPARE(shown[std::size_t(stiffest)], 1.0f);
    QVERIFY2(!view->legendText().contains("fixed"), qPrintable(view->legendText()));
    QCOMPARE(high->value(), view->colourRange(0).second);  // the fields show the painted range

    // Fixed at 0 – 2× the old stiffest value: a node of that value is mid-grey, the softened ones bluer.
    colours->setCurrentIndex(1);
    QVERIFY(low->isVisible() && high->isVisible());
    low->setValue(0.0);
    high->setValue(2.0 * top);
    QCOMPARE(view->colourRange(0), std::pair(0.0, 2.0 * top));
    shown = view->nodeColourParameters(0);
    for (std::size_t n : untouched)
        QVERIFY(std::abs(shown[n] - float(painted.stiffness[n] / (2.0 * top))) < 1e-6f);
    for (std::size_t n : softened)
        QVERIFY(shown[n] < float(before.stiffness[n] / (2.0 * top)));
    QVERIFY2(view->legendText().contains("(fixed)") && view->legendText().contains(QString::number(2.0 * top, 'g', 4)),
             qPrintable(view->legendText()));
    // A stroke beyond the range keeps the range; its nodes show the red end.
    view->brush().value = 8.0 * top;
    paintStroke(view);
    QCOMPARE(view->colourRange(0), std::pair(0.0, 2.0 * top));
    shown = view->nodeColourParameters(0);
    QVERIFY(*std::max_element(shown.begin(), shown.end()) == 1.0f);

    // The range belongs to the field: mass follows its own values, stiffness keeps its fixed range.
    field->setCurrentIndex(field->findData(int(PaintField::Mass)));
    QCOMPARE(colours->currentIndex(), 0);
    field->setCurrentIndex(field->findData(int(PaintField::Stiffness)));
    QCOMPARE(colours->currentIndex(), 1);
    QCOMPARE(high->value(), 2.0 * top);
    colours->setCurrentIndex(0);
    QVERIFY(!view->fixedColourRange(PaintField::Stiffness));
    QVERIFY(!view->legendText().contains("fixed"));

    while (w.document()->undoStack()->index() > undoBefore)
        w.document()->undoStack()->undo();
    QVERIFY(sameMaterial(w.document()->scene().objects[0].material, before));
}

// The active tool's settings sit in a bar under the tool buttons, not at the bottom of Properties.
void TestEditor::toolOptionsFollowTheActiveTool() {
    MainWindow& w = *m_window;
    Viewport* view = w.viewport();
    ToolOptionsBar* bar = w.toolOptions();
    QVERIFY(bar && bar->isVisible());
    QVERIFY(w.findChild<QToolBar*>("toolsToolBar")->geometry().bottom() <= bar->geometry().top());
    auto* field = bar->findChild<QComboBox*>("brushField");
    auto* ks = bar->findChild<QDoubleSpinBox*>("dragStiffness");
    auto* anchor = bar->findChild<QComboBox*>("anchorMode");
    QVERIFY(field && ks && anchor);
    QVERIFY(!w.findChild<PropertiesPanel*>()->findChild<QComboBox*>("brushField"));  // one place only

    w.findChild<QAction*>("toolPaint")->trigger();
    QCOMPARE(bar->shownTool(), Tool::Paint);
    QVERIFY(field->isVisible() && !ks->isVisible());
    // Every paint setting, a fixed colour range's ends included, fits the bar in a 1280-pixel-wide window,
    // and the bar does not make the window wider than that.
    auto* colours = bar->findChild<QComboBox*>("colourRange");
    colours->setCurrentIndex(1);
    const QSize size = w.size();
    w.resize(1280, 800);
    QTRY_COMPARE(w.width(), 1280);
    QVERIFY2(w.minimumSizeHint().width() <= 1280, qPrintable(QString::number(w.minimumSizeHint().width())));
    for (const char* name : {"brushField", "brushValue", "brushRadius", "brushStrength", "brushFalloff", "colourRange",
                             "colourLow", "colourHigh"}) {
        auto* wgt = bar->findChild<QWidget*>(name);
        QVERIFY2(wgt && wgt->isVisible(), name);
        const QRect inBar(wgt->mapTo(bar, QPoint(0, 0)), wgt->size());
        QVERIFY2(bar->rect().contains(inBar), qPrintable(QString("%1 at x %2 + %3 in a bar %4 wide").arg(name).arg(inBar.x()).arg(inBar.width()).arg(bar->width())));
    }
    colours->setCurrentIndex(0);
    w.resize(size);
    field->setCurrentIndex(field->findData(int(PaintField::Mass)));
    QCOMPARE(view->brush().field, PaintField::Mass);
    field->setCurrentIndex(field->findData(int(PaintField::Stiffness)));

    w.findChild<QAction*>("toolDrag")->trigger();
    QCOMPARE(bar->shownTool(), Tool::Drag);
    QVERIFY(ks->isVisible() && !field->isVisible());
    const double was = view->dragSettings().stiffness;
    ks->setValue(2.0 * was);
    QCOMPARE(view->dragSettings().stiffness, 2.0 * was);
    ks->setValue(was);

    w.findChild<QAction*>("toolAnchor")->trigger();
    QVERIFY(anchor->isVisible());
    anchor->setCurrentIndex(anchor->findData(int(AnchorMode::Heavy)));
    QCOMPARE(view->anchorMode(), AnchorMode::Heavy);
    anchor->setCurrentIndex(anchor->findData(int(AnchorMode::Pinned)));
    w.findChild<QAction*>("toolDrag")->trigger();
}

// Node damping is painted like the other fields: chosen in the Tools' "Paint" list, one stroke one undo
// step, the legend and the Properties' mean follow; typing the mean scales the painted map.
void TestEditor::paintsNodeDamping() {
    MainWindow& w = *m_window;
    Viewport* view = w.viewport();
    w.findChild<QAction*>("toolPaint")->trigger();
    auto* field = w.findChild<QComboBox*>("brushField");
    auto* mean = w.findChild<QDoubleSpinBox*>("nodeDamping");
    QVERIFY(field && mean);
    field->setCurrentIndex(field->findData(int(PaintField::NodeDamping)));
    QCOMPARE(view->brush().field, PaintField::NodeDamping);
    QCOMPARE(QString::fromUtf8(fieldName(PaintField::NodeDamping, MaterialModel::Continuum)), QString("node damping rate"));
    const LatticeMaterial before = w.document()->scene().objects[0].material;
    const double uniform = before.nodeDamping.front();  // the fish body's 1.28 1/s on every node
    QVERIFY(uniform > 0.0);
    QCOMPARE(before.nodeDamping, std::vector<double>(before.nodeDamping.size(), uniform));
    QVERIFY(std::abs(mean->value() - uniform) < 1e-3);
    view->brush().value = 4.0 * uniform;
    const int undoBefore = w.document()->undoStack()->index();
    paintStroke(view);

    const LatticeMaterial after = w.document()->scene().objects[0].material;
    int raised = 0;
    for (std::size_t n = 0; n < after.nodeDamping.size(); ++n) {
        QVERIFY(after.nodeDamping[n] >= before.nodeDamping[n]);
        raised += after.nodeDamping[n] > before.nodeDamping[n] ? 1 : 0;
    }
    QVERIFY2(raised > 0 && raised < int(after.nodeDamping.size()), qPrintable(QString("%1 nodes raised").arg(raised)));
    QVERIFY(after.stiffness == before.stiffness && after.damping == before.damping && after.mass == before.mass);
    QCOMPARE(w.document()->undoStack()->index(), undoBefore + 1);
    QCOMPARE(w.document()->undoStack()->undoText(), QString("Paint node damping rate"));
    double sum = 0.0;
    for (double d : after.nodeDamping)
        sum += d / double(after.nodeDamping.size());  // no void nodes on the angelfish
    QVERIFY2(std::abs(mean->value() - sum) < 1e-3, qPrintable(QString("mean shown %1, map's %2").arg(mean->value()).arg(sum)));
    // It reaches the body: the lowest mode's node damping ratio rose.
    auto zetaNode = [](const SceneObject& o) {
        return analyseModes(*buildLatticeBody(o.lattice, o.material).value(), 1)->modes.front().nodeDampingRatio;
    };
    SceneObject was = w.document()->scene().objects[0];
    was.material = before;
    QVERIFY(zetaNode(w.document()->scene().objects[0]) > zetaNode(was));

    // Typing the mean scales the painted map: its ratios stay, one undo step.
    mean->setValue(2.0 * sum);
    const LatticeMaterial scaled = w.document()->scene().objects[0].material;
    QCOMPARE(w.document()->undoStack()->index(), undoBefore + 2);
    const double factor = scaled.nodeDamping[0] / after.nodeDamping[0];  // 2, up to the box's 4 decimals
    QVERIFY(std::abs(factor - 2.0) < 1e-3);
    for (std::size_t n = 0; n < scaled.nodeDamping.size(); ++n)
        QVERIFY(std::abs(scaled.nodeDamping[n] / after.nodeDamping[n] / factor - 1.0) < 1e-12);

    w.document()->undoStack()->undo();
    w.document()->undoStack()->undo();
    QVERIFY(sameMaterial(w.document()->scene().objects[0].material, before));
    QVERIFY(!w.document()->isModified());
}

// Volume preservation is painted like the material: the brush starts at 1 (a fraction), a stroke paints
// some nodes and not others in one undo step, the running body keeps the painted region's volume as
// stiffly as the largest value, the Properties field shows that value and typing one scales the map.
void TestEditor::paintsVolumePreservation() {
    MainWindow& w = *m_window;
    Viewport* view = w.viewport();
    w.findChild<QAction*>("toolPaint")->trigger();
    auto* field = w.findChild<QComboBox*>("brushField");
    auto* largest = w.findChild<QDoubleSpinBox*>("volumePreservation");
    QVERIFY(field && largest);
    const LatticeMaterial before = w.document()->scene().objects[0].material;
    QCOMPARE(largestVolumePreservation(before), 0.0);
    QVERIFY(!w.simulation()->simulation()->simulator(0).model().volume.active());
    field->setCurrentIndex(field->findData(int(PaintField::VolumePreservation)));
    QCOMPARE(view->brush().field, PaintField::VolumePreservation);
    QCOMPARE(view->brush().value, 1.0);
    view->brush().strength = 1.0;
    view->brush().falloff = BrushFalloff::Constant;
    const int undoBefore = w.document()->undoStack()->index();
    paintStroke(view);

    const LatticeMaterial after = w.document()->scene().objects[0].material;
    int painted = 0;
    for (double p : after.volumePreservation) {
        QVERIFY(p >= 0.0 && p <= 1.0);
        painted += p > 0.0 ? 1 : 0;
    }
    QVERIFY2(painted > 0 && painted < int(after.volumePreservation.size()), qPrintable(QString("%1 nodes painted").arg(painted)));
    QCOMPARE(w.document()->undoStack()->index(), undoBefore + 1);
    QCOMPARE(w.document()->undoStack()->undoText(), QString("Paint volume preservation"));
    QVERIFY(after.stiffness == before.stiffness && after.mass == before.mass);
    QVERIFY(std::abs(largest->value() - largestVolumePreservation(after)) < 0.005);  // the field shows 2 decimals
    const VolumeConstraint& kept = w.simulation()->simulation()->simulator(0).model().volume;
    QVERIFY(kept.active());
    QCOMPARE(kept.preservation, largestVolumePreservation(after));

    // Typing the largest value scales the map, the painted ratios kept; one undo step.
    largest->setValue(0.4);
    const LatticeMaterial scaled = w.document()->scene().objects[0].material;
    QCOMPARE(w.document()->undoStack()->index(), undoBefore + 2);
    const double factor = 0.4 / largestVolumePreservation(after);
    for (std::size_t n = 0; n < scaled.volumePreservation.size(); ++n)
        QVERIFY(std::abs(scaled.volumePreservation[n] - factor * after.volumePreservation[n]) < 1e-12);
    QCOMPARE(w.simulation()->simulation()->simulator(0).model().volume.preservation, 0.4);

    w.document()->undoStack()->undo();
    w.document()->undoStack()->undo();
    QVERIFY(sameMaterial(w.document()->scene().objects[0].material, before));
    QVERIFY(!w.simulation()->simulation()->simulator(0).model().volume.active());
    field->setCurrentIndex(field->findData(int(PaintField::Stiffness)));
}

void TestEditor::anchorToolPinsAClickedNode() {
    MainWindow& w = *m_window;
    w.findChild<QAction*>("toolAnchor")->trigger();
    const int node = isolatedNode(w, 0);
    QVERIFY2(node >= 0, "no node stands apart on screen");
    QTest::mouseClick(w.viewport(), Qt::LeftButton, {}, screenOfNode(w, node));
    QCOMPARE(w.document()->scene().objects[0].material.anchor[std::size_t(node)], AnchorMode::Pinned);
    // The rebuilt body pins it: pulling the whole lattice leaves that node in place.
    const Vec3 rest = w.simulation()->simulation()->simulator(0).state().position[std::size_t(node)];
    w.simulation()->advance(0.5);
    QVERIFY(w.simulation()->simulation()->simulator(0).state().position[std::size_t(node)] == rest);
    // F frames the selection: select the node, frame it, and it lands in the middle of the view, closer.
    w.findChild<QAction*>("toolSelect")->trigger();
    QTest::mouseClick(w.viewport(), Qt::LeftButton, {}, screenOfNode(w, node));
    QCOMPARE(w.viewport()->selection().size(), std::size_t(1));
    const double distance = w.viewport()->camera().distance;
    QTest::keyClick(w.viewport(), Qt::Key_F);
    QVERIFY(w.viewport()->camera().distance < distance);
    QVERIFY(QLineF(QPointF(screenOfNode(w, node)), QPointF(w.viewport()->rect().center())).length() < 3.0);
    w.findChild<QAction*>("toolAnchor")->trigger();
    // Clicking again frees it; undo brings the anchor back.
    QTest::mouseClick(w.viewport(), Qt::LeftButton, {}, screenOfNode(w, node));
    QCOMPARE(w.document()->scene().objects[0].material.anchor[std::size_t(node)], AnchorMode::Free);
    w.document()->undoStack()->undo();
    QCOMPARE(w.document()->scene().objects[0].material.anchor[std::size_t(node)], AnchorMode::Pinned);
}

void TestEditor::presetAppliesAsOneUndoStep() {
    MainWindow& w = *m_window;
    PresetsPanel* presets = w.presets();
    QVERIFY(presets->count() >= 5);
    const LatticeMaterial before = w.document()->scene().objects[0].material;
    // "Jelly" is much softer than the fish body.
    int jelly = -1;
    for (int row = 0; row < presets->count(); ++row)
        if (presets->findChild<QListWidget*>("presetList")->item(row)->text() == "Jelly")
            jelly = row;
    QVERIFY(jelly >= 0);
    QStringList asked;
    presets->setConfirm([&](const QString& question) {
        asked << question;
        return false;
    });
    QVERIFY(presets->applyRow(jelly));
    QVERIFY2(asked.isEmpty(), "asked before replacing an unpainted material");
    const LatticeMaterial after = w.document()->scene().objects[0].material;
    QVERIFY(after.stiffness[0] != before.stiffness[0]);
    QVERIFY(after.anchor == before.anchor);  // anchors are the scene's, not the material's
    w.document()->undoStack()->undo();
    QVERIFY(sameMaterial(w.document()->scene().objects[0].material, before));
    // Thumbnails show behaviour: jelly sags further than stiff rubber (the lowest dark pixel is lower).
    auto lowestDark = [&](const QString& name) {
        auto* list = presets->findChild<QListWidget*>("presetList");
        for (int row = 0; row < list->count(); ++row) {
            if (list->item(row)->text() != name)
                continue;
            const QImage image = list->item(row)->icon().pixmap(72, 72).toImage();
            int lowest = -1;
            for (int y = 0; y < image.height(); ++y)
                for (int x = 0; x < image.width(); ++x)
                    if (QColor(image.pixel(x, y)).lightness() < 110)
                        lowest = y;
            return lowest;
        }
        return -2;
    };
    const int jellySag = lowestDark("Jelly"), stiffSag = lowestDark("Stiff rubber");
    QVERIFY2(jellySag > stiffSag && stiffSag > 0, qPrintable(QString("jelly %1, stiff %2").arg(jellySag).arg(stiffSag)));
    // A setup preset applies to the object as one undo step: painted maps, anchors, drivers and clips.
    int setup = -1;
    for (int row = 0; row < presets->count(); ++row)
        if (presets->findChild<QListWidget*>("presetList")->item(row)->text().startsWith("Setup: Fish swim"))
            setup = row;
    QVERIFY(setup >= 0);
    const io::Project projectBefore = w.document()->project();
    QVERIFY(presets->applyRow(setup));
    QVERIFY(w.document()->project().clips.findClip("swim") != nullptr);
    QVERIFY(w.simulation()->simulation() != nullptr);
    w.document()->undoStack()->undo();
    QVERIFY(sameMaterial(w.document()->scene().objects[0].material, projectBefore.scene.objects[0].material));
    // Over a painted map with nothing selected, it asks first: "no" keeps the paint, "yes" applies.
    w.findChild<QAction*>("toolPaint")->trigger();
    w.viewport()->brush().field = PaintField::Stiffness;
    const LatticeMaterial unpainted = w.document()->scene().objects[0].material;
    w.viewport()->brush().value = 4.0 * *std::max_element(unpainted.stiffness.begin(), unpainted.stiffness.end());
    paintStroke(w.viewport());
    const LatticeMaterial painted = w.document()->scene().objects[0].material;
    QVERIFY(!sameMaterial(painted, unpainted));
    QVERIFY(!presets->applyRow(jelly));
    QCOMPARE(asked.size(), 1);
    QVERIFY2(asked.front().contains("painted stiffness"), qPrintable(asked.front()));
    QVERIFY(sameMaterial(w.document()->scene().objects[0].material, painted));
    presets->setConfirm([](const QString&) { return true; });
    QVERIFY(presets->applyRow(jelly));
    QVERIFY(!sameMaterial(w.document()->scene().objects[0].material, painted));
    w.document()->undoStack()->undo();
    QVERIFY(sameMaterial(w.document()->scene().objects[0].material, painted));
    // Saving the current material as a preset lists it.
    QFile::remove(PresetsPanel::userFolder() + "/my-fish.stpreset");
    presets->reload();
    const int count = presets->count();
    QVERIFY(presets->saveCurrent("My fish").ok());
    QCOMPARE(presets->count(), count + 1);
    // The object's setup saves as a setup preset, which lists and applies like the shipped one.
    QFile::remove(PresetsPanel::userFolder() + "/my-swim.stpreset");
    presets->reload();
    const int withSetup = presets->count();
    const Status savedSetup = presets->saveSetup("My swim");
    QVERIFY2(savedSetup.ok(), savedSetup.message().c_str());
    QCOMPARE(presets->count(), withSetup + 1);
    // Importing a shared file validates it first: a broken one is refused naming the file and the field.
    const QString broken = m_dir->filePath("broken.stpreset");
    QFile bad(broken);
    QVERIFY(bad.open(QIODevice::WriteOnly));
    bad.write(R"({"format": "softtouch-preset", "version": 1, "kind": "material", "name": "Bad", "material": {"stiffness": -5}})");
    bad.close();
    const Status refused = presets->importFile(broken);
    QVERIFY(!refused.ok());
    QVERIFY2(QString::fromStdString(refused.message()).contains("broken.stpreset") &&
                 QString::fromStdString(refused.message()).contains("stiffness"),
             refused.message().c_str());
    QCOMPARE(presets->count(), withSetup + 1);
}

// A clip on show is the clip as it now bakes: after a material edit (and its undo) the timeline evaluates
// it again and the viewport shows the new frame, while the simulation kept its binding (rebuilt
// incrementally: the same object before and after).
void TestEditor::clipPreviewFollowsAMaterialEdit() {
    MainWindow& w = *m_window;
    SimulationController* sim = w.simulation();
    auto* clips = w.timeline()->findChild<QListWidget*>("clips");
    FrameRuler* ruler = w.timeline()->ruler();
    QVERIFY(clips && clips->count() > 0);
    clips->setCurrentRow(0);
    const int frame = std::min(12, ruler->lastFrame());
    QTest::mouseClick(ruler, Qt::LeftButton, {}, QPoint(int(std::lround(ruler->xOfFrame(frame))), 30));  // scrub there
    QCOMPARE(ruler->frame(), frame);
    const Clip clip = w.document()->project().clips.clips.front();
    const auto nodesOf = [&](const Scene& scene) {
        return evaluateClip(scene, w.document()->project().clips, clip).value().nodes[std::size_t(frame)].front();
    };
    const std::vector<Vec3> before = nodesOf(w.document()->scene());
    QVERIFY(sim->simulation()->simulator(0).state().position == before);
    const Binding* binding = &sim->simulation()->binding(0);

    LatticeMaterial stiffer = w.document()->scene().objects[0].material;
    for (double& e : stiffer.stiffness)
        e *= 4.0;
    w.document()->undoStack()->push(new MaterialEditCommand(w.document(), 0, w.document()->scene().objects[0].material, stiffer,
                                                            "stiffer"));
    const std::vector<Vec3> after = nodesOf(w.document()->scene());
    QVERIFY(after != before);  // the edit changes the clip's motion ...
    QVERIFY(sim->simulation()->simulator(0).state().position == after);  // ... and the viewport shows it
    QCOMPARE(&sim->simulation()->binding(0), binding);
    w.document()->undoStack()->undo();
    QVERIFY(sim->simulation()->simulator(0).state().position == before);
}

// The editor driven through its real widgets (under Xvfb). Properties and the study dock: modes, the solid,
// the element, strain limits, wheel, layout.
#include "editor_fixture.h"

// The Properties' stretch and squash limits: "off" at their minimum, a typed value reaches the material
// and the running body as one undo step, and undo turns it off again.
void TestEditor::strainLimitsFromTheProperties() {
    MainWindow& w = *m_window;
    auto* stretch = w.findChild<QDoubleSpinBox*>("stretchLimit");
    auto* squash = w.findChild<QDoubleSpinBox*>("squashLimit");
    QVERIFY(stretch && squash);
    QCOMPARE(stretch->text(), QString("off"));
    QCOMPARE(squash->text(), QString("off"));
    QVERIFY(!w.document()->scene().objects[0].material.strainLimits.any());
    const int undoBefore = w.document()->undoStack()->index();
    stretch->setValue(1.3);
    squash->setValue(0.6);
    QCOMPARE(w.document()->scene().objects[0].material.strainLimits, (StrainLimits{1.3, 0.6}));
    QCOMPARE(w.simulation()->simulation()->simulator(0).model().strainLimits, (StrainLimits{1.3, 0.6}));
    QCOMPARE(w.document()->undoStack()->index(), undoBefore + 1);  // both fields merge into one step
    w.document()->undoStack()->undo();
    QVERIFY(!w.document()->scene().objects[0].material.strainLimits.any());
    QCOMPARE(stretch->text(), QString("off"));
    QVERIFY(!w.simulation()->simulation()->simulator(0).model().strainLimits.any());

    // Volume preservation: the running body keeps the fish mesh's volume (sampled inside the mesh, so
    // less than the lattice box's).
    auto* volume = w.findChild<QDoubleSpinBox*>("volumePreservation");
    QVERIFY(volume);
    QCOMPARE(volume->text(), QString("off"));
    volume->setValue(0.9);
    QCOMPARE(largestVolumePreservation(w.document()->scene().objects[0].material), 0.9);
    const VolumeConstraint& kept = w.simulation()->simulation()->simulator(0).model().volume;
    QVERIFY(kept.active());
    const OrientedBox& box = w.document()->scene().objects[0].lattice.box();
    QVERIFY2(kept.restVolume > 0.05 * box.size.prod() && kept.restVolume < 0.8 * box.size.prod(),
             qPrintable(QString("%1 m³ of a %2 m³ box").arg(kept.restVolume).arg(box.size.prod())));
    w.document()->undoStack()->undo();
    QVERIFY(!w.simulation()->simulation()->simulator(0).model().volume.active());
}

void TestEditor::restingFishIsNotRedrawn() {
    // With its drivers off nothing acts on the fish: it falls asleep, and while it sleeps playing
    // costs nothing — no step moves a node, so no frame is announced for drawing — until a grab wakes it.
    MainWindow& w = *m_window;
    w.simulation()->setDriversEnabled(false);
    w.simulation()->advance(1.0);
    QVERIFY(w.simulation()->simulation()->simulator(0).isSleeping());
    QSignalSpy frames(w.simulation(), &SimulationController::stepped);
    const std::vector<Vec3> before = w.simulation()->simulation()->simulator(0).state().position;
    for (int i = 0; i < 10; ++i)
        w.simulation()->advance(0.1);
    QCOMPARE(frames.count(), 0);
    QVERIFY(w.simulation()->stats().asleep);
    QVERIFY(w.simulation()->simulation()->simulator(0).state().position == before);

    Viewport* view = w.viewport();
    const SceneObject& fish = w.document()->scene().objects[0];
    const Bounds bounds = fish.mesh->bounds();
    const QPoint grabAt = view->toWidget(0.5 * (bounds.min + bounds.max)).toPoint();
    QTest::mousePress(view, Qt::LeftButton, {}, grabAt);
    w.simulation()->pause();
    QVERIFY2(w.simulation()->grab(0).has_value(), "the press did not hit the fish");
    QTest::mouseMove(view, grabAt + QPoint(0, -40));
    w.simulation()->advance(0.1);
    QVERIFY(frames.count() > 0);
    QVERIFY(!w.simulation()->stats().asleep);
    QTest::mouseRelease(view, Qt::LeftButton, {}, grabAt + QPoint(0, -40));
}

void TestEditor::studyDockMeasuresTheOpenSceneAndAppliesAPick() {
    keepReferencesIn(*m_dir);
    MainWindow& w = *m_window;
    const QString sphere = m_dir->filePath("sphere.obj");
    QVERIFY(io::writeObj(sphere.toStdString(), makeUvEllipsoid(16, 32, Vec3::Constant(0.5))).ok());
    QVERIFY(w.document()->importMesh(sphere).ok());
    PresetsPanel* presets = w.presets();
    auto* list = presets->findChild<QListWidget*>("presetList");
    int setup = -1, jelly = -1;
    for (int row = 0; row < presets->count(); ++row) {
        if (list->item(row)->text().startsWith("Setup: Fish swim"))
            setup = row;
        if (list->item(row)->text() == "Jelly")
            jelly = row;
    }
    QVERIFY(setup >= 0 && jelly >= 0);
    QVERIFY(presets->applyRow(setup));
    QVERIFY(presets->applyRow(jelly));  // after the setup, whose painted maps would replace it
    const Scene& scene = w.document()->scene();
    QCOMPARE(QString::fromStdString(scene.objects[0].name), QString("sphere"));

    StudyPanel* study = w.study();
    auto* measure = study->findChild<QPushButton*>("studyMeasure");
    auto* apply = study->findChild<QPushButton*>("studyApply");
    auto* text = study->findChild<QLabel*>("studyText");
    auto* check = study->findChild<QLabel*>("studyCheck");
    // Before measuring, the pick cannot be used, and the dock says why and what to do.
    QVERIFY(!study->hasStudy());
    QVERIFY(!apply->isEnabled());
    QVERIFY2(check->text().contains("Measure this scene first"), qPrintable(check->text()));

    // The clip measured is the one Export… writes: the clip selected in the timeline (here the drivers' last 1.5 s,
    // which a game would ship without the start from rest).
    {
        ClipLibrary clips = w.document()->project().clips;
        Clip late;
        late.name = "after the start";
        late.startSeconds = 0.5;
        late.frames = 36;
        late.fps = 24.0;
        clips.clips.push_back(late);
        w.document()->setClips(clips);
        auto* clipList = w.timeline()->findChild<QListWidget*>("clips");
        QVERIFY(clipList && clipList->count() == int(clips.clips.size()));
        QListWidgetItem* item = clipList->item(clipList->count() - 1);
        QTest::mouseClick(clipList->viewport(), Qt::LeftButton, {}, clipList->visualItemRect(item).center());
        QCOMPARE(clipList->currentItem(), item);
    }

    QSignalSpy done(study, &StudyPanel::finished);
    QElapsedTimer clock;
    clock.start();
    measure->click();
    QVERIFY(study->isMeasuring());
    QVERIFY(!apply->isEnabled());
    QVERIFY(done.wait(kStudyWaitMs));
    qInfo("quick study of the imported sphere: %.1f s", double(clock.elapsed()) / 1000.0);
    QVERIFY(study->hasStudy());
    QVERIFY(!study->isMeasuring());
    QVERIFY(!study->study().cancelled);
    QCOMPARE(QString::fromStdString(study->study().clip.name), QString("after the start"));
    QCOMPARE(study->study().clip.startSeconds, 0.5);
    QCOMPARE(study->study().reference->frames.frames, 36);
    auto* chart = study->findChild<StudyChartView*>("studyPlot");
    QVERIFY(chart != nullptr && chart->studyChart()->hasPoints());
    QCOMPARE(static_cast<QStackedWidget*>(chart->parentWidget())->currentWidget(), chart);
    // The clip moves the mesh, so doing nothing has a price the settings are compared with.
    QVERIFY(study->study().motionAmplitude > 0.0 && study->study().restError > 0.0);

    // The reference is kept by content, as `softtouch-cli study` keeps it; a full study's reference of the same
    // scene and clip, when one is kept, is measured against instead (it certifies lower targets).
    {
        const auto clip = analysis::clipToPlay(scene, w.document()->project().clips, "after the start");
        QVERIFY(clip);
        const auto quickKey = io::referenceKey(w.document()->project(), clip.value(), analysis::quickReference());
        const auto fullKey = io::referenceKey(w.document()->project(), clip.value(), analysis::ReferenceOptions{});
        QVERIFY(quickKey && fullKey && quickKey.value() != fullKey.value());
        const auto kept = io::readCachedReference(io::referenceCacheFolder(), quickKey.value());
        QVERIFY2(kept, qPrintable(QString::fromStdString((io::referenceCacheFolder() / quickKey.value()).string())));
        QCOMPARE(kept->description, study->study().reference->description);
        analysis::ConvergedReference full = *kept;
        full.description = "a full study's reference";
        QVERIFY(io::writeCachedReference(io::referenceCacheFolder(), fullKey.value(), full).ok());
        measure->click();
        QVERIFY(done.wait(kStudyWaitMs));
        QCOMPARE(study->study().reference->description, std::string("a full study's reference"));
    }

    // The marked row is the scene's own setting.
    const analysis::StudyRow* current = study->currentRow();
    QVERIFY(current != nullptr);
    QCOMPARE(current->integrator, scene.world.simulation.integrator);
    QCOMPARE(current->dt, scene.world.simulation.dt);
    QVERIFY(current->lattice.kind == scene.objects[0].lattice.shape().kind);
    QVERIFY(current->lattice.nodes == scene.objects[0].lattice.shape().nodes);
    QVERIFY2(text->text().contains("Current"), qPrintable(text->text()));
    // Nothing is laid over the plot, in a short window too: the dock scrolls instead (its minimum height
    // once left the wrapped text out, and the text covered the plot's axis labels).
    QWidget* plot = chart->parentWidget();  // the chart's place in the dock (its note before a measurement)
    const auto textBelowPlot = [&] {
        QApplication::processEvents();
        return plot->geometry().bottom() < text->geometry().top();
    };
    const auto where = [&] {
        return QString("plot ends at %1, text starts at %2").arg(plot->geometry().bottom()).arg(text->geometry().top());
    };
    QVERIFY2(textBelowPlot(), qPrintable(where()));  // the text grew when the measurement ended
    const QSize size = w.size();
    for (const QSize small : {QSize(1280, 720), QSize(1280, 600)}) {
        w.resize(small);
        QTRY_COMPARE(w.size(), small);
        QVERIFY2(textBelowPlot(), qPrintable(where()));
    }
    w.resize(size);

    // The pick follows the chosen error: the cheapest row within the target in that error, or one whose cost
    // lies within the cheapest one's spread (a tie) and is more accurate.
    auto* kind = study->findChild<QComboBox*>("studyErrorKind");
    for (int k = kind->count() - 1; k >= 0; --k) {
        kind->setCurrentIndex(k);
        QCOMPARE(int(study->study().error), kind->currentData().toInt());
        if (const analysis::StudyRow* pick = study->suggestion()) {
            const analysis::StudyError error = study->study().error;
            const analysis::StudyRow* cheapest = nullptr;
            for (const analysis::StudyRow& r : study->study().rows)
                if (r.finite && r.error(error) <= study->target() && (!cheapest || r.costPerSecond < cheapest->costPerSecond))
                    cheapest = &r;
            QVERIFY(cheapest != nullptr);
            QVERIFY(pick->costPerSecond <= cheapest->costPerSecond * (1.0 + cheapest->costSpread));
            QVERIFY(pick->error(error) <= cheapest->error(error));
            QVERIFY(pick->error(error) <= study->target());
        }
    }
    QCOMPARE(study->study().error, analysis::StudyError::Total);
    // A target below every measured error says so and names the lowest.
    auto* target = study->findChild<QDoubleSpinBox*>("studyTarget");
    const double defaultTarget = target->value();
    double lowest = 1e300;
    for (const analysis::StudyRow& r : study->study().rows)
        lowest = std::min(lowest, r.finite ? r.rmsError : 1e300);
    target->setValue(target->minimum());
    if (lowest > study->target()) {
        QVERIFY(study->suggestion() == nullptr);
        QVERIFY(!apply->isEnabled());
        QVERIFY2(text->text().contains("No measured setting") && text->text().contains("the lowest is"), qPrintable(text->text()));
    }
    // Below ten times the reference's own uncertainty a target cannot be certified: nothing is offered.
    QVERIFY(study->target() < 10.0 * study->study().referenceUncertainty());
    QVERIFY(!apply->isEnabled());
    QVERIFY2(check->text().contains("cannot be certified"), qPrintable(check->text()));
    // At a target the reference certifies, doing nothing is not good enough (the jelly sphere moves more
    // than that), and the current setting (Verlet, 1/240 s) costs far more than the cheapest that is.
    // Ten times the uncertainty, in the spin box's % rounded up to its 0.01 steps.
    const double certified = std::ceil(1000.0 * 100.0 * study->study().referenceUncertainty()) / 100.0 + 0.01;
    target->setValue(std::max(defaultTarget, certified));
    QVERIFY2(study->study().restError > study->target(), qPrintable(QString("target %1 %, doing nothing %2")
                                                                         .arg(target->value()).arg(study->study().restError)));
    const analysis::StudyRow* suggested = study->suggestion();
    QVERIFY(suggested != nullptr);
    QVERIFY(suggested->rmsError <= study->target());
    QVERIFY(suggested != current);
    QVERIFY2(text->text().contains("Cheapest within"), qPrintable(text->text()));
    QVERIFY2(apply->isEnabled(), qPrintable(check->text()));
    const analysis::StudyRow pick = *suggested;

    // Applying it is one undo step that changes integrator, step and (when it differs) the lattice.
    const WorldSettings worldBefore = scene.world;
    const LatticeShape shapeBefore = scene.objects[0].lattice.shape();
    const LatticeMaterial materialBefore = scene.objects[0].material;
    QUndoStack* undo = w.document()->undoStack();
    const int steps = undo->count();
    apply->click();
    QCOMPARE(undo->count(), steps + 1);
    QCOMPARE(scene.world.simulation.integrator, pick.integrator);
    QCOMPARE(scene.world.simulation.dt, pick.dt);
    QVERIFY(scene.objects[0].lattice.shape().kind == pick.lattice.kind);
    QVERIFY(scene.objects[0].lattice.shape().nodes == pick.lattice.nodes);
    QCOMPARE(scene.objects[0].material.mass.size(), std::size_t(scene.objects[0].lattice.nodeCount()));
    QVERIFY(w.simulation()->simulation() != nullptr);
    QVERIFY(!study->isOutOfDate());  // the dock's own pick: the mark moves to it
    QVERIFY(study->currentRow() != nullptr && study->currentRow()->setting().dt == pick.dt);

    // The must-show: the scene as it now stands, re-measured, is within the target.
    QVERIFY(study->isMeasuring());
    QVERIFY(done.wait(kStudyWaitMs));
    QVERIFY(study->remeasured().has_value());
    QVERIFY2(study->remeasured()->total <= study->target(),
             qPrintable(QString("re-measured %1, target %2").arg(study->remeasured()->total).arg(study->target())));
    QVERIFY2(check->text().contains("Re-measured"), qPrintable(check->text()));

    // A dot on the chart names its setting under the pointer, and a click on it uses that setting: one
    // undo step, re-measured like the dock's own pick.
    auto* pointer = study->findChild<QLabel*>("studyPointer");
    w.findChild<QDockWidget*>("studyDock")->raise();
    QTRY_VERIFY(chart->isVisible());
    QApplication::processEvents();  // laid out at its shown size
    // A measured setting other than the current one, drawn clear of every other dot.
    const auto& rows = study->study().rows;
    const auto clear = [&](int r) {
        for (int o = 0; o < int(rows.size()); ++o)
            if (o != r && plottable(rows[std::size_t(o)], study->study().error) &&
                QLineF(chart->viewportPositionOf(o), chart->viewportPositionOf(r)).length() < 3 * StudyChartView::kPickRadius)
                return false;
        return true;
    };
    int other = -1;
    for (int r = 0; r < int(rows.size()) && other < 0; ++r)
        if (plottable(rows[std::size_t(r)], study->study().error) && !rows[std::size_t(r)].current && clear(r))
            other = r;
    QVERIFY(other >= 0);
    const analysis::StudyRow clicked = rows[std::size_t(other)];
    QTest::mouseMove(chart->viewport(), chart->viewportPositionOf(other));
    QTRY_COMPARE(chart->hoveredRow(), other);
    QVERIFY2(pointer->text().contains(QString("1/%1 s, %2").arg(std::lround(1.0 / clicked.dt)).arg(QString::fromStdString(clicked.resolution))) &&
                 pointer->text().contains("Click to use it"),
             qPrintable(pointer->text()));
    // The fish's head is pinned on a face, so each lattice has a converged solid to be measured against.
    QVERIFY2(clicked.solidModeError.size() == 3 &&
                 pointer->text().contains(QString::fromStdString(describeModeErrors(clicked.solidModeError)) +
                                          " from the solid"),
             qPrintable(pointer->text()));
    QTest::mouseClick(chart->viewport(), Qt::LeftButton, {}, chart->viewportPositionOf(other));
    QCOMPARE(undo->count(), steps + 2);
    QCOMPARE(scene.world.simulation.integrator, clicked.integrator);
    QCOMPARE(scene.world.simulation.dt, clicked.dt);
    QVERIFY(scene.objects[0].lattice.shape().nodes == clicked.lattice.nodes);
    QCOMPARE(scene.objects[0].material.element, clicked.element);  // springs or the solid element, as measured
    QVERIFY(study->isMeasuring());
    QVERIFY(done.wait(kStudyWaitMs));
    QVERIFY(study->remeasured().has_value());
    QVERIFY(!study->isOutOfDate());
    undo->undo();  // back to the dock's own pick
    QCOMPARE(scene.world.simulation.dt, pick.dt);
    QCOMPARE(scene.world.simulation.integrator, pick.integrator);

    // Undo restores the world and the lattice together; the measurement is then out of date and says so.
    undo->undo();
    QCOMPARE(scene.world.simulation.integrator, worldBefore.simulation.integrator);
    QCOMPARE(scene.world.simulation.dt, worldBefore.simulation.dt);
    QVERIFY(scene.objects[0].lattice.shape().kind == shapeBefore.kind);
    QVERIFY(scene.objects[0].lattice.shape().nodes == shapeBefore.nodes);
    QVERIFY(sameMaterial(scene.objects[0].material, materialBefore));
    QVERIFY(study->isOutOfDate());
    QVERIFY2(text->text().contains("Out of date"), qPrintable(text->text()));
    QVERIFY(study->currentRow() == current);  // the mark follows the scene back
    QVERIFY(!apply->isEnabled());
    QCOMPARE(measure->text(), QString("Measure again"));
    // Out of date, a dot still names its setting but says why it cannot be used, and a click does nothing.
    QTest::mouseMove(chart->viewport(), chart->viewportPositionOf(other) + QPoint(2, 1));
    QTRY_COMPARE(chart->hoveredRow(), other);
    QVERIFY2(pointer->text().contains("Measure again"), qPrintable(pointer->text()));
    const int stepsNow = undo->count();
    QTest::mouseClick(chart->viewport(), Qt::LeftButton, {}, chart->viewportPositionOf(other));
    QCOMPARE(undo->count(), stepsNow);
    QVERIFY(!study->isMeasuring());
}

// Cancel stops a measurement (the reference at its next frame, a grid run when it ends) and keeps nothing; closing the window while one runs
// stops it too, and destroying the window waits for the worker thread (no crash, no late delivery).
void TestEditor::studyDockCancelsAndStopsWithTheWindow() {
    keepReferencesIn(*m_dir);
    MainWindow& w = *m_window;
    StudyPanel* study = w.study();
    auto* measure = study->findChild<QPushButton*>("studyMeasure");
    QSignalSpy done(study, &StudyPanel::finished);
    measure->click();
    QVERIFY(study->isMeasuring());
    auto* cancel = study->findChild<QPushButton*>("studyCancel");
    QVERIFY(cancel->isVisible() && cancel->isEnabled());
    QElapsedTimer clock;
    clock.start();
    cancel->click();
    QVERIFY(done.wait(kStudyWaitMs));
    qInfo("cancelled after %.1f s (the reference stops at its next frame)", double(clock.elapsed()) / 1000.0);
    QVERIFY(!study->isMeasuring());
    QVERIFY(!study->hasStudy());
    QVERIFY2(study->findChild<QLabel*>("studyText")->text().contains("cancelled"),
             qPrintable(study->findChild<QLabel*>("studyText")->text()));
    QVERIFY(!study->findChild<QPushButton*>("studyApply")->isEnabled());
    QVERIFY(measure->isEnabled());

    measure->click();
    QVERIFY(study->isMeasuring());
    QTest::qWait(300);
    QVERIFY(w.close());
    m_window.reset();
}

// The wobble frequency and damping ratio in Properties are the body's lowest mode (as
// `softtouch-cli modes` prints it); typing a frequency lands the lowest mode on it in one undo step.
// The wobble and damping fields never show one body's numbers as another's: after opening another scene they are
// blank while its modes are measured (they showed the old fish's, or 0.001 Hz on a fresh start), then the new
// body's.
void TestEditor::wobbleIsBlankUntilTheNewSceneIsMeasured() {
    MainWindow& w = *m_window;
    auto* frequency = w.findChild<QDoubleSpinBox*>("frequency");
    auto* ratio = w.findChild<QDoubleSpinBox*>("dampingRatio");
    auto* modes = w.findChild<QLabel*>("modes");
    QVERIFY(frequency && ratio && modes);
    waitForModes(w);
    const QString angelfish = frequency->text();
    QVERIFY2(angelfish.endsWith(" Hz") && frequency->value() > 0.1, qPrintable(angelfish));
    QVERIFY(w.openFile(QStringLiteral(SOFTTOUCH_SOURCE_DIR "/presets/scenes/guppy-swim.softtouch")));
    if (modes->property("analysing").toBool())  // the usual case: the analysis runs on a worker thread
        QVERIFY2(!frequency->text().contains(QRegularExpression("[0-9]")) && !ratio->text().contains(QRegularExpression("[0-9]")) &&
                     !frequency->isEnabled(),
                 qPrintable(frequency->text() + " | " + ratio->text()));
    waitForModes(w);
    QVERIFY(frequency->isEnabled());
    QVERIFY2(frequency->text().endsWith(" Hz") && frequency->text() != angelfish, qPrintable(frequency->text()));
    QVERIFY(!ratio->text().isEmpty());
}

void TestEditor::propertiesShowTheBodysModes() {
    MainWindow& w = *m_window;
    auto* frequency = w.findChild<QDoubleSpinBox*>("frequency");
    auto* ratio = w.findChild<QDoubleSpinBox*>("dampingRatio");
    auto* modes = w.findChild<QLabel*>("modes");
    auto* mode3 = w.findChild<QLabel*>("mode3");
    QVERIFY(frequency && ratio && modes && mode3);
    waitForModes(w);
    QVERIFY(frequency->isEnabled());
    QVERIFY2(mode3->text().startsWith("Mode 3: "), qPrintable(mode3->text()));
    const Run cli = runCli({"modes", kDefaultScene});
    QCOMPARE(cli.exitCode, 0);
    const QRegularExpression row(R"(^\s+1\s+([0-9.]+)\s+([0-9.]+))", QRegularExpression::MultilineOption);
    const QRegularExpressionMatch match = row.match(cli.out);
    QVERIFY2(match.hasMatch(), qPrintable(cli.out));
    QVERIFY(std::abs(frequency->value() - match.captured(1).toDouble()) < 1e-3);
    QVERIFY(std::abs(ratio->value() - match.captured(2).toDouble()) < 1e-4);
    // The solid the springs make, as the CLI prints it.
    const QRegularExpressionMatch springs =
        QRegularExpression(R"(springs act as: E_u (\S+)  E_v (\S+)  E_w (\S+) Pa)").match(cli.out);
    QVERIFY2(springs.hasMatch(), qPrintable(cli.out));
    auto* summary = w.findChild<QLabel*>("modes");
    QVERIFY(summary);
    const QString shown = QString("E %1 / %2 / %3 Pa along u / v / w").arg(springs.captured(1), springs.captured(2), springs.captured(3));
    QVERIFY2(summary->text().contains(shown), qPrintable(summary->text() + " | " + shown));

    const LatticeMaterial before = w.document()->scene().objects[0].material;
    const int undoBefore = w.document()->undoStack()->count();
    frequency->setValue(2.0);
    QCOMPARE(w.document()->undoStack()->count(), undoBefore + 1);
    const SceneObject& fish = w.document()->scene().objects[0];
    auto body = buildLatticeBody(fish.lattice, fish.material);
    QVERIFY(body.ok());
    const auto after = analyseModes(*body.value(), 1);
    QVERIFY(after.ok());
    QVERIFY(std::abs(after->modes[0].frequencyHz - 2.0) < 1e-6);
    QVERIFY(std::abs(after->modes[0].dampingRatio - match.captured(2).toDouble()) < 1e-4);  // ratio kept
    w.document()->undoStack()->undo();
    QVERIFY(sameMaterial(w.document()->scene().objects[0].material, before));
}

// "Compare with the solid" shows the converged solid's modes and the lattice's error on each, as core
// computes them for the open scene; the next edit clears it, since it described the material before.
void TestEditor::propertiesCompareTheLatticeWithTheSolid() {
    MainWindow& w = *m_window;
    auto* compare = w.findChild<QPushButton*>("compareSolid");
    auto* solid = w.findChild<QLabel*>("solidModes");
    auto* frequency = w.findChild<QDoubleSpinBox*>("frequency");
    QVERIFY(compare && solid && frequency);
    waitForModes(w);
    QVERIFY(compare->isEnabled());
    QVERIFY(solid->text().isEmpty());
    compare->click();
    const SceneObject& fish = w.document()->scene().objects[0];
    auto expected = compareWithSolid(fish.lattice, fish.material);
    QVERIFY2(expected, expected.message().c_str());
    QVERIFY(expected->solid.converged());
    QStringList hz, off;
    for (double f : expected->solid.frequencyHz)
        hz << QString::number(f, 'f', 3);
    for (double e : expected->error)
        off << QString("%1%2%").arg(e >= 0.0 ? "+" : "").arg(100.0 * e, 0, 'f', 1);
    QVERIFY2(solid->isVisibleTo(&w) && solid->text().contains(hz.join(" / ") + " Hz") &&
                 solid->text().contains("are " + off.join(" / ") + " from it"),
             qPrintable(solid->text() + " | " + hz.join(" / ") + " | " + off.join(" / ")));
    // The bundled fish's springs: its lowest mode close, its second their flat cells' (they are not the painted
    // material, and the modes text says so beside the numbers).
    QVERIFY2(std::abs(expected->error[0]) < 0.05 && expected->error[1] < -0.1, qPrintable(off.join(" / ")));
    auto* modes = w.findChild<QLabel*>("modes");
    QVERIFY(modes);
    const auto departure = springDeparture(fish.lattice, fish.material);
    QVERIFY(departure && departure->largest() > 0.05);
    QVERIFY2(modes->text().contains("Springs on these cells are not the painted material (" +
                                    QString::fromStdString(departure->describe()) + ")"),
             qPrintable(modes->text()));

    const int undoBefore = w.document()->undoStack()->count();
    frequency->setValue(frequency->value() * 1.5);
    QCOMPARE(w.document()->undoStack()->count(), undoBefore + 1);
    QVERIFY2(solid->text().isEmpty() && !solid->isVisibleTo(&w), qPrintable(solid->text()));
    w.document()->undoStack()->undo();
}

// Properties ▸ Element: the solid element is an undoable material edit; the shown modes become the element's and
// "Compare with the solid" finds all three within 5% of the converged solid (the springs' second is 20% off); a
// world or material edit the element cannot run is not applied and says why; a save writes it.
void TestEditor::elementChoiceRunsTheSolidAndSaysWhatItCannot() {
    MainWindow& w = *m_window;
    auto* element = w.findChild<QComboBox*>("element");
    auto* integrator = w.findChild<QComboBox*>("integrator");
    auto* modes = w.findChild<QLabel*>("modes");
    auto* compare = w.findChild<QPushButton*>("compareSolid");
    auto* solid = w.findChild<QLabel*>("solidModes");
    auto* live = w.findChild<QLabel*>("liveReadout");
    QVERIFY(element && integrator && modes && compare && solid && live);
    QCOMPARE(BodyElement(element->currentData().toInt()), BodyElement::Springs);
    const int undoBefore = w.document()->undoStack()->count();
    element->setCurrentIndex(element->findData(int(BodyElement::Solid)));
    QCOMPARE(w.document()->undoStack()->count(), undoBefore + 1);
    const SceneObject& fish = w.document()->scene().objects[0];
    QCOMPARE(fish.material.element, BodyElement::Solid);
    auto body = buildLatticeBody(fish.lattice, fish.material);
    QVERIFY2(body, body.message().c_str());
    QVERIFY(body.value()->element != nullptr);
    const auto shown = analyseModes(*body.value(), 3);
    QVERIFY(shown.ok());
    waitForModes(w);
    QVERIFY2(modes->text().contains(QString::number(shown->modes[0].frequencyHz, 'f', 3)), qPrintable(modes->text()));
    QVERIFY2(modes->text().contains("The solid element acts as"), qPrintable(modes->text()));
    // The rows and fields name the element's damping for what it is: the solid's viscosity, not springs'.
    const auto labelled = [&w](const QString& text) {
        for (QLabel* label : w.findChildren<QLabel*>())
            if (label->isVisibleTo(&w) && label->text().contains(text))
                return true;
        return false;
    };
    QVERIFY(labelled("Viscosity (mean)") && !labelled("Spring viscosity") && labelled("viscous 0.0"));
    compare->click();
    auto expected = compareWithSolid(fish.lattice, fish.material);
    QVERIFY2(expected && expected->error.size() == 3, expected ? "no error" : expected.message().c_str());
    for (double e : expected->error)
        QVERIFY2(std::abs(e) < 0.05, qPrintable(solid->text()));
    QVERIFY(solid->isVisibleTo(&w));
    // The simulation runs it (the default scene's implicit Euler).
    w.simulation()->advance(0.5);
    QVERIFY(w.simulation()->simulation()->simulator(0).state().isFinite());

    // XPBD cannot run it: the integrator edit is not applied, and says why.
    const int undoSolid = w.document()->undoStack()->count();
    integrator->setCurrentIndex(integrator->findData(int(IntegratorKind::Xpbd)));
    QCOMPARE(w.document()->undoStack()->count(), undoSolid);
    QCOMPARE(w.document()->scene().world.simulation.integrator, IntegratorKind::ImplicitEuler);
    QCOMPARE(IntegratorKind(integrator->currentData().toInt()), IntegratorKind::ImplicitEuler);
    QVERIFY2(live->text().contains("Not applied") && live->text().contains("xpbd"), qPrintable(live->text()));

    const QString saved = m_dir->filePath("solid.softtouch");
    QVERIFY(w.document()->saveAs(saved).ok());
    auto reloaded = io::loadProject(saved.toStdString());
    QVERIFY2(reloaded, reloaded.message().c_str());
    QCOMPARE(reloaded->scene.objects[0].material.element, BodyElement::Solid);
    w.document()->undoStack()->undo();
    QCOMPARE(w.document()->scene().objects[0].material.element, BodyElement::Springs);
    QCOMPARE(BodyElement(element->currentData().toInt()), BodyElement::Springs);
}

// "Show" beside a mode animates its shape in the viewport: the lattice nodes drawn are rest + a·φ with
// a = A·sin(2π·1 Hz·t), A = 12% of the box's largest side, and the mesh follows; nothing in the
// document, its undo stack or the simulation changes; Play or a step ends it.
void TestEditor::modeViewAnimatesTheShapeWithoutEditing() {
    MainWindow& w = *m_window;
    Viewport* view = w.viewport();
    view->setOverlayVisible(false);
    auto* show1 = w.findChild<QPushButton*>("showMode1");
    auto* show2 = w.findChild<QPushButton*>("showMode2");
    auto* caption = w.findChild<QLabel*>("modeCaption");
    QVERIFY(show1 && show2 && caption);
    const SceneObject fish = w.document()->scene().objects[0];
    auto body = buildLatticeBody(fish.lattice, fish.material);
    QVERIFY(body.ok());
    const auto modes = analyseModes(*body.value(), 3);
    QVERIFY(modes.ok() && modes->modes.size() == 3);
    const std::vector<Vec3> rest = fish.lattice.restNodes();
    const double amplitude = kModeDisplayFraction * fish.lattice.box().size.maxCoeff();
    const std::vector<Vec3> stateBefore = w.simulation()->simulation()->simulator(0).state().position;
    const long long stepsBefore = w.simulation()->simulation()->stepCount();
    const int undoBefore = w.document()->undoStack()->count();
    const QImage still = view->grabFramebuffer();

    waitForModes(w);
    show1->click();
    QCOMPARE(view->shownMode(), 1);
    QVERIFY(show1->isChecked());
    QVERIFY(caption->isVisible());
    QVERIFY2(caption->text().contains(QString::number(modes->modes[0].frequencyHz, 'f', 3)), qPrintable(caption->text()));
    // An eighth of a cycle in: a = A·sin(π/4), and every node sits at rest + a·φ.
    for (const double seconds : {0.125, 0.25, 0.6}) {
        view->holdModeView(seconds);
        const double a = view->modeDisplacement();
        QVERIFY(std::abs(a - amplitude * std::sin(2.0 * std::numbers::pi * seconds)) < 1e-12);
        const std::vector<Vec3> drawn = view->displayedNodes(0);
        QCOMPARE(drawn.size(), rest.size());
        double error = 0.0, largest = 0.0;
        for (std::size_t n = 0; n < rest.size(); ++n) {
            error = std::max(error, (drawn[n] - (rest[n] + a * modes->modes[0].shape[n])).norm());
            largest = std::max(largest, (drawn[n] - rest[n]).norm());
        }
        QVERIFY2(error < 1e-12, qPrintable(QString::number(error)));
        QVERIFY(std::abs(largest - std::abs(a)) < 1e-12);  // max |φ| = 1: the largest node moves by |a|
    }
    // The mesh on screen moves with it: at the largest displacement the picture differs from rest.
    view->holdModeView(0.25);
    const QImage swung = view->grabFramebuffer();
    QCOMPARE(swung.size(), still.size());
    int changed = 0;
    for (int y = 0; y < still.height(); y += 2)
        for (int x = 0; x < still.width(); x += 2)
            changed += still.pixel(x, y) != swung.pixel(x, y) ? 1 : 0;
    QVERIFY2(changed > still.width() * still.height() / 4 / 100, qPrintable(QString::number(changed)));
    // On the clock it keeps moving.
    view->holdModeView(-1.0);
    const double a0 = view->modeDisplacement();
    QTest::qWait(150);
    QVERIFY(view->modeDisplacement() != a0);
    // One mode at a time.
    show2->click();
    QCOMPARE(view->shownMode(), 2);
    QVERIFY(!show1->isChecked() && show2->isChecked());
    view->holdModeView(0.25);
    QVERIFY((view->displayedNodes(0)[0] - (rest[0] + amplitude * modes->modes[1].shape[0])).norm() < 1e-12);

    // Display only: the document, its undo stack and the simulation are as they were.
    QCOMPARE(w.document()->undoStack()->count(), undoBefore);
    QVERIFY(!w.document()->isModified());
    QVERIFY(sameMaterial(w.document()->scene().objects[0].material, fish.material));
    QVERIFY(w.simulation()->simulation()->simulator(0).state().position == stateBefore);
    QCOMPARE(w.simulation()->simulation()->stepCount(), stepsBefore);

    // A painted edit changes the shape; the view follows it (same mode, same clock).
    LatticeMaterial stiffTail = fish.material;
    for (std::size_t n = 0; n < stiffTail.stiffness.size(); ++n)
        if (fish.lattice.coords(int(n))[0] == 0)
            stiffTail.stiffness[n] *= 4.0;
    w.document()->undoStack()->push(new MaterialEditCommand(w.document(), 0, fish.material, stiffTail, "stiff tail"));
    QCOMPARE(view->shownMode(), 2);
    waitForModes(w);  // the view follows once the new modes are analysed
    auto stiffBody = buildLatticeBody(fish.lattice, stiffTail);
    QVERIFY(stiffBody.ok());
    const auto stiffModes = analyseModes(*stiffBody.value(), 3);
    QVERIFY(stiffModes.ok());
    double shapeChange = 0.0, followError = 0.0;
    const std::vector<Vec3> followed = view->displayedNodes(0);
    for (std::size_t n = 0; n < rest.size(); ++n) {
        shapeChange = std::max(shapeChange, std::min((stiffModes->modes[1].shape[n] - modes->modes[1].shape[n]).norm(),
                                                     (stiffModes->modes[1].shape[n] + modes->modes[1].shape[n]).norm()));
        followError = std::max(followError, (followed[n] - (rest[n] + amplitude * stiffModes->modes[1].shape[n])).norm());
    }
    QVERIFY2(shapeChange > 0.01, qPrintable(QString::number(shapeChange)));
    QVERIFY2(followError < 1e-12, qPrintable(QString::number(followError)));
    w.document()->undoStack()->undo();

    // Play ends it, and the simulation's pose is drawn again.
    w.simulation()->play();
    QCOMPARE(view->shownMode(), 0);
    QVERIFY(!show2->isChecked() && !caption->isVisible());
    w.simulation()->pause();
    QVERIFY(view->displayedNodes(0) == w.simulation()->simulation()->simulator(0).state().position);
    // So does a step, and the toggle turns it off too.
    show1->click();
    QCOMPARE(view->shownMode(), 1);
    w.simulation()->stepOnce();
    QCOMPARE(view->shownMode(), 0);
    show1->click();
    show1->click();
    QCOMPARE(view->shownMode(), 0);
    view->holdModeView(-1.0);
}

void TestEditor::viewportDrawsTheFish_data() {
    QTest::addColumn<int>("mode");
    QTest::addColumn<double>("minCoverage");
    QTest::newRow("shaded") << int(render::ShadeMode::Shaded) << 0.35;
    QTest::newRow("wireframe") << int(render::ShadeMode::Wireframe) << 0.05;
}

void TestEditor::viewportDrawsTheFish() {
    QFETCH(int, mode);
    QFETCH(double, minCoverage);
    MainWindow& w = *m_window;
    Viewport* view = w.viewport();
    view->setOverlayVisible(false);
    view->setShadeMode(render::ShadeMode(mode));
    const QImage image = view->grabFramebuffer().convertToFormat(QImage::Format_RGB32);
    QVERIFY(!image.isNull());
    const qreal scale = double(image.width()) / view->width();
    // Where the fish is: the screen box of its vertices, shrunk to its middle half.
    QRectF box;
    for (const Vec3f& p : w.document()->scene().objects[0].mesh->positions)
        box |= QRectF(view->toWidget(p.cast<double>()) * scale, QSizeF(1, 1));
    const QRect middle = QRectF(box.center() - QPointF(box.width(), box.height()) / 4.0,
                                QSizeF(box.width(), box.height()) / 2.0).toRect();
    const double inside = coverage(image, middle);
    QVERIFY2(inside > minCoverage, qPrintable(QString("only %1 of the fish's middle differs from the background").arg(inside)));
    // Far from the fish (the corners) the background shows.
    const QRect corner(image.width() - 40, 5, 30, 30);
    QVERIFY(!box.intersects(corner));
    QVERIFY2(coverage(image, corner) < 0.01, "the corner is not background");
}

void TestEditor::propertiesFieldsFitTheDock_data() {
    QTest::addColumn<QSize>("window");
    QTest::newRow("1280x800") << QSize(1280, 800);
    QTest::newRow("1600x1000") << QSize(1600, 1000);
    QTest::newRow("1920x1080") << QSize(1920, 1080);
}

// #42: the wheel over a number field or a drop-down that has no focus scrolls the panel and edits nothing (an
// animator scrolling Properties once set the total mass from 0.2373 to 0.0373 kg); once the field has the focus,
// the wheel edits it as before, one undoable step.
void TestEditor::wheelScrollsPropertiesWithoutEditing() {
    MainWindow& w = *m_window;
    w.findChild<QDockWidget*>("propertiesDock")->raise();
    QApplication::processEvents();
    auto* scroll = qobject_cast<QScrollArea*>(w.properties()->parentWidget()->parentWidget());
    QVERIFY(scroll && scroll->verticalScrollBar()->maximum() > 0);  // the panel is taller than its dock
    auto* frequency = w.findChild<QDoubleSpinBox*>("frequency");
    auto* integrator = w.findChild<QComboBox*>("integrator");
    QVERIFY(frequency && integrator && frequency->isVisible());
    w.activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(&w));
    w.viewport()->setFocus();
    QVERIFY(!frequency->hasFocus() && !integrator->hasFocus());
    QUndoStack* undo = w.document()->undoStack();
    const int steps = undo->count();
    waitForModes(w);
    const double hz = frequency->value();
    const int scheme = integrator->currentIndex();
    // To the widget under the pointer (a spin box's line edit), or to the field itself, where the window system's
    // wheel arrives once the line edit has passed it on (a synthetic one is not passed on).
    const auto wheel = [](QWidget* target, int delta, bool toField = false) {
        const QPoint centre = target->rect().center();
        QWidget* under = !toField && target->childAt(centre) ? target->childAt(centre) : target;
        const QPoint at = under->mapFrom(target, centre);
        QWheelEvent event(at, under->mapToGlobal(at), QPoint(), QPoint(0, delta), Qt::NoButton, Qt::NoModifier,
                          Qt::NoScrollPhase, false);
        QApplication::sendEvent(under, &event);
    };
    scroll->verticalScrollBar()->setValue(0);
    wheel(frequency, -120);
    wheel(integrator, -120);
    QCOMPARE(frequency->value(), hz);
    QCOMPARE(integrator->currentIndex(), scheme);
    QCOMPARE(undo->count(), steps);
    QVERIFY2(scroll->verticalScrollBar()->value() > 0, "the panel did not scroll");
    // Focused, the field takes the wheel.
    w.activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(&w));
    frequency->setFocus();
    QTRY_VERIFY(frequency->hasFocus());
    wheel(frequency, 120, true);
    QVERIFY2(frequency->value() > hz, qPrintable(QString::number(frequency->value())));
    QCOMPARE(undo->count(), steps + 1);
    undo->undo();
}

void TestEditor::propertiesFieldsFitTheDock() {
    // Every field of Properties lies inside the dock's visible width at common window sizes (the dock
    // scrolls vertically only, so a field past its right edge would be cut off, as combo arrows once were).
    QFETCH(QSize, window);
    MainWindow& w = *m_window;
    w.resize(window);
    QTest::qWait(50);
    QApplication::processEvents();
    auto* scroll = qobject_cast<QScrollArea*>(w.properties()->parentWidget()->parentWidget());
    QVERIFY(scroll);
    const int visibleWidth = scroll->viewport()->width();
    QStringList cut;
    for (QWidget* field : w.properties()->findChildren<QWidget*>()) {
        if (!field->isVisibleTo(w.properties()) ||
            !(qobject_cast<QAbstractSpinBox*>(field) || qobject_cast<QComboBox*>(field) || qobject_cast<QAbstractButton*>(field) ||
              qobject_cast<QLineEdit*>(field) || qobject_cast<QSlider*>(field)))
            continue;
        const QPoint right = field->mapTo(scroll->viewport(), QPoint(field->width(), 0));
        if (right.x() > visibleWidth + 1)
            cut << QString("%1 '%2' ends at %3").arg(field->metaObject()->className(), field->objectName()).arg(right.x());
    }
    QVERIFY2(cut.isEmpty(), qPrintable(QString("visible width %1: ").arg(visibleWidth) + cut.join("; ")));
    w.resize(1280, 800);
}

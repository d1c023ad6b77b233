// The editor driven through its real widgets (under Xvfb). Files: open, new, save and reopen, autosave
// recovery, corrupt projects, screenshots.
#include "editor_fixture.h"
#include <QFileDialog>

void TestEditor::opensDefaultScene() {
    MainWindow& w = *m_window;
    QCOMPARE(w.document()->scene().objects.size(), std::size_t(1));
    QCOMPARE(QString::fromStdString(w.document()->scene().objects[0].name), QString("angelfish"));
    QVERIFY(w.simulation()->simulation() != nullptr);
    QVERIFY2(w.viewport()->renderProblem().isEmpty(), qPrintable(w.viewport()->renderProblem()));
    QVERIFY(w.windowTitle().contains("angelfish-swim.softtouch"));
    QVERIFY(!w.document()->isModified());
    // A project opens paused (the guide: "Press Space to run"); Space starts it.
    QVERIFY(w.openFile(kDefaultScene));
    QVERIFY(!w.simulation()->isPlaying());
    QCOMPARE(w.findChild<QAction*>("actionPlay")->text(), QString("Play"));
    w.activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(&w));
    QTest::keyClick(&w, Qt::Key_Space);
    QVERIFY(w.simulation()->isPlaying());
    w.simulation()->pause();
}

// File ▸ New (Ctrl+N): an untitled, empty scene with nothing to undo (#42 item 10), which every tool, the
// transport, a take and a key survive, saying what is missing; Add Mesh puts the first body in it and makes it
// current, on the step a new scene of it would take. Deleting the last object empties the scene again, and an
// empty project saves and opens.
void TestEditor::fileNewStartsAnUntitledProject() {
    MainWindow& w = *m_window;
    QAction* action = w.findChild<QAction*>("actionNew");
    QVERIFY(action);
    QCOMPARE(action->shortcut(), QKeySequence(QKeySequence::New));
    QVERIFY(!w.document()->filePath().isEmpty());
    QVERIFY(!w.document()->project().clips.clips.empty());
    action->trigger();
    const Scene& scene = w.document()->scene();
    QVERIFY(scene.objects.empty());
    QVERIFY(w.document()->filePath().isEmpty());
    QVERIFY(w.document()->project().clips.clips.empty());  // the swim clip was the old project's
    QVERIFY(!w.document()->undoStack()->canUndo());
    QCOMPARE(scene.world.simulation.integrator, IntegratorKind::Verlet);
    auto* hint = w.findChild<QLabel*>("noObjectHint");
    QVERIFY(hint && hint->isVisible());

    // Every tool, a click and a drag in the view, play, step, a take and a key: nothing to act on, nothing breaks.
    Viewport* view = w.viewport();
    for (const char* tool : {"Drag", "Paint", "Anchor", "Void", "Select", "Pose", "Lattice", "Collider"}) {
        for (QAction* a : w.findChildren<QAction*>())
            if (a->text().remove('&') == tool)
                a->trigger();
        const QPoint middle = view->rect().center();
        QTest::mouseClick(view, Qt::LeftButton, {}, middle);
        QTest::mousePress(view, Qt::LeftButton, {}, middle);
        QTest::mouseMove(view, middle + QPoint(30, 20));
        QTest::mouseRelease(view, Qt::LeftButton, {}, middle + QPoint(30, 20));
    }
    w.simulation()->play();
    QTest::qWait(100);
    w.simulation()->pause();
    w.timeline()->toggleRecording();
    w.timeline()->toggleRecording();
    QVERIFY(!w.keyframes()->keyPose(0.0));
    QVERIFY(w.document()->project().clips.sessions.empty());

    // The first body: current, fitted, on a new scene's step; the tools act on it.
    QVERIFY(w.addMeshFile(QStringLiteral(SOFTTOUCH_SOURCE_DIR "/presets/meshes/guppy.obj")).ok());
    QCOMPARE(scene.objects.size(), std::size_t(1));
    QCOMPARE(view->currentObject(), 0);
    QVERIFY(!hint->isVisible());
    QCOMPARE(scene.objects[0].lattice.count(0), 4);
    QVERIFY(scene.objects[0].drivers.empty());
    QVERIFY(w.keyframes()->keyPose(0.0));
    // Deleting it empties the scene; undo brings it back.
    QVERIFY(w.findChild<QAction*>("actionDeleteObject"));
    w.findChild<QAction*>("actionDeleteObject")->trigger();
    QVERIFY(scene.objects.empty());
    QVERIFY(hint->isVisible());
    w.document()->undoStack()->undo();
    QCOMPARE(scene.objects.size(), std::size_t(1));
    // It is a working project: it saves and opens again, and so does an empty one.
    const QString path = m_dir->filePath("new.softtouch");
    QVERIFY(w.document()->saveAs(path).ok());
    QVERIFY(w.openFile(path));
    QCOMPARE(w.document()->scene().objects.size(), std::size_t(1));
    action->trigger();
    const QString empty = m_dir->filePath("empty.softtouch");
    QVERIFY(w.document()->saveAs(empty).ok());
    QVERIFY(w.openFile(empty));
    QVERIFY(w.document()->scene().objects.empty());
}

void TestEditor::saveAndReopenGivesTheSameScene() {
    MainWindow& w = *m_window;
    // Edit something of each kind: painted values, an anchor, a world setting.
    Document* doc = w.document();
    LatticeMaterial m = doc->scene().objects[0].material;
    m.stiffness[5] = 123.456789;
    m.anchor[0] = AnchorMode::Heavy;
    doc->undoStack()->push(new MaterialEditCommand(doc, 0, doc->scene().objects[0].material, m, "edit"));
    WorldSettings world = doc->scene().world;
    world.gravity = Vec3(0, -9.81, 0);
    doc->undoStack()->push(new WorldEditCommand(doc, doc->scene().world, world, "gravity"));
    const QString path = m_dir->filePath("saved/fish.softtouch");
    QDir().mkpath(m_dir->filePath("saved"));
    QVERIFY(doc->saveAs(path).ok());
    QVERIFY(!doc->isModified());
    QVERIFY(w.windowTitle().startsWith("fish.softtouch"));

    auto other = makeWindow();
    QVERIFY(other->openFile(path));
    const Scene& a = doc->scene();
    const Scene& b = other->document()->scene();
    QVERIFY(sameMaterial(a.objects[0].material, b.objects[0].material));
    QVERIFY(a.objects[0].mesh->positions == b.objects[0].mesh->positions);
    QVERIFY(a.objects[0].lattice.restNodes() == b.objects[0].lattice.restNodes());
    QVERIFY(a.world.gravity == b.world.gravity);
    QCOMPARE(a.world.simulation.dt, b.world.simulation.dt);
    QCOMPARE(a.objects[0].drivers.size(), b.objects[0].drivers.size());
    other->document()->undoStack()->setClean();
}

// Ctrl+Shift+S is Save As, as in Blender, Maya and most editors (Qt's generic X11 theme binds nothing to
// QKeySequence::SaveAs, so the menu showed no shortcut and the keys did nothing).
void TestEditor::ctrlShiftSAsksWhereToSave() {
    MainWindow& w = *m_window;
    QString title;
    QTimer poll;
    connect(&poll, &QTimer::timeout, this, [&] {
        if (auto* dialog = qobject_cast<QFileDialog*>(QApplication::activeModalWidget())) {
            title = dialog->windowTitle();
            dialog->reject();
        }
    });
    poll.start(50);
    QAction* action = w.findChild<QAction*>("actionSaveAs");
    QVERIFY(action);
    QCOMPARE(action->shortcut(), QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_S));  // and the menu shows it
    w.activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(&w));
    QTest::keyClick(&w, Qt::Key_S, Qt::ControlModifier | Qt::ShiftModifier);
    poll.stop();
    QCOMPARE(title, QString("Save Project As"));
    QVERIFY(!w.document()->isModified());
}

void TestEditor::recoversAutosaveAfterKill() {
    auto w = makeWindow();
    QVERIFY(w->openFile(kDefaultScene));
    w->simulation()->pause();
    Document* doc = w->document();
    LatticeMaterial m = doc->scene().objects[0].material;
    m.damping[7] = 3.25;
    doc->undoStack()->push(new MaterialEditCommand(doc, 0, doc->scene().objects[0].material, m, "edit"));
    QString autosaveProblem;
    connect(w->autosave(), &Autosave::failed, this, [&](const QString& message) { autosaveProblem = message; });
    QTRY_VERIFY_WITH_TIMEOUT(QFile::exists(m_dir->filePath("autosave/autosave.softtouch")) || !autosaveProblem.isEmpty(), 3000);
    QVERIFY2(autosaveProblem.isEmpty(), qPrintable(autosaveProblem));
    // Killed: no close event, no prompt, nothing discarded — the autosave stays on disk.
    w.reset();
    QVERIFY(QFile::exists(m_dir->filePath("autosave/autosave.softtouch")));

    auto next = makeWindow();
    DialogAnswerer yes(QMessageBox::Yes);
    QVERIFY(next->offerRecovery());
    QVERIFY(yes.seen);
    QVERIFY2(yes.text.contains("angelfish-swim.softtouch"), qPrintable(yes.text));
    QCOMPARE(next->document()->scene().objects[0].material.damping[7], 3.25);
    QVERIFY(next->document()->isModified());
    QCOMPARE(QFileInfo(next->document()->filePath()).canonicalFilePath(), QFileInfo(kDefaultScene).canonicalFilePath());
    // The recovered scene still finds its mesh through the original file's location.
    QVERIFY(next->simulation()->simulation() != nullptr);
    next->document()->undoStack()->setClean();
}

void TestEditor::recoversAutosaveAfterRealKill() {
    // A real editor process records a take (an edit), autosaves it, and is killed with SIGKILL.
    const QString folder = m_dir->filePath("killed");
    QProcess editor;
    editor.setProcessChannelMode(QProcess::MergedChannels);
    QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
    env.insert("XDG_CONFIG_HOME", m_dir->filePath("config"));  // the child's settings stay in the test folder
    env.insert("XDG_DATA_HOME", m_dir->filePath("data"));
    editor.setProcessEnvironment(env);
    editor.start(SOFTTOUCH_BIN_DIR "/softtouch", {"--no-recovery", "--autosave-folder", folder, "--autosave-seconds", "0.2",
                                                  "--drag=-100,-80", "--seconds", "0.3", kDefaultScene});
    QVERIFY(editor.waitForStarted(10000));
    QTRY_VERIFY_WITH_TIMEOUT(QFile::exists(folder + "/autosave.softtouch") && QFile::exists(folder + "/autosave.json"), 30000);
    editor.kill();
    QVERIFY(editor.waitForFinished(10000));
    QCOMPARE(editor.exitStatus(), QProcess::CrashExit);
    // The next start offers it; accepting brings the take back, on the original file, unsaved.
    MainWindowOptions options;
    options.autosaveFolder = folder;
    MainWindow next(options);
    next.show();
    DialogAnswerer yes(QMessageBox::Yes);
    QVERIFY(next.offerRecovery());
    QVERIFY(yes.seen);
    QCOMPARE(next.document()->project().clips.sessions.size(), std::size_t(1));
    // ... and shows it: the timeline lists the recovered take (and the scene's clips) at once, not after a save.
    auto* takes = next.timeline()->findChild<QListWidget*>("takes");
    auto* clips = next.timeline()->findChild<QListWidget*>("clips");
    QVERIFY(takes && clips);
    QCOMPARE(takes->count(), 1);
    QCOMPARE(clips->count(), int(next.document()->project().clips.clips.size()));
    QVERIFY(next.document()->isModified());
    QCOMPARE(QFileInfo(next.document()->filePath()).canonicalFilePath(), QFileInfo(kDefaultScene).canonicalFilePath());
    next.document()->undoStack()->setClean();
}

void TestEditor::corruptProjectShowsErrorAndEditorStaysUsable() {
    MainWindow& w = *m_window;
    const QString path = m_dir->filePath("corrupt.softtouch");
    QFile file(path);
    QVERIFY(file.open(QIODevice::WriteOnly));
    file.write(R"({"format": "softtouch-project", "version": 1, "objects": [{"name": "x", "mesh": "../nowhere.obj",)"
               R"( "material": {"mass": -1}}]})");
    file.close();
    const LatticeMaterial before = w.document()->scene().objects[0].material;
    DialogAnswerer ok(QMessageBox::Ok);
    QVERIFY(!w.openFile(path));
    QVERIFY(ok.seen);
    QVERIFY2(ok.text.contains("corrupt.softtouch"), qPrintable(ok.text));
    // The open scene is untouched and still editable.
    QVERIFY(sameMaterial(w.document()->scene().objects[0].material, before));
    QVERIFY(w.simulation()->simulation() != nullptr);
    w.findChild<QAction*>("toolAnchor")->trigger();
    const int node = isolatedNode(w, 0);
    QVERIFY(node >= 0);
    QTest::mouseClick(w.viewport(), Qt::LeftButton, {}, screenOfNode(w, node));
    QCOMPARE(w.document()->scene().objects[0].material.anchor[std::size_t(node)], AnchorMode::Pinned);
}

void TestEditor::screenshotCommandWritesPng() {
    const QString png = m_dir->filePath("shot.png");
    QProcess editor;
    editor.setProcessChannelMode(QProcess::MergedChannels);
    editor.start(SOFTTOUCH_BIN_DIR "/softtouch", {"--screenshot", png, "--mode", "wireframe", kDefaultScene});
    QVERIFY(editor.waitForFinished(60000));
    QVERIFY2(editor.exitCode() == 0, editor.readAll().constData());
    QImage image(png);
    QVERIFY(!image.isNull());
    QVERIFY(image.width() >= 640 && image.height() >= 400);
    // The window's size and the active tool can be chosen (the guide's pictures; a 1280x800 check).
    const QString sized = m_dir->filePath("sized.png");
    editor.start(SOFTTOUCH_BIN_DIR "/softtouch", {"--screenshot", sized, "--window", "1280x800", "--tool", "paint", kDefaultScene});
    QVERIFY(editor.waitForFinished(60000));
    QVERIFY2(editor.exitCode() == 0, editor.readAll().constData());
    QCOMPARE(QImage(sized).size(), QSize(1280, 800));
    for (const QStringList& bad : {QStringList{"--window", "10x10"}, QStringList{"--tool", "hammer"}, QStringList{"--click", "noSuchButton"}}) {
        editor.start(SOFTTOUCH_BIN_DIR "/softtouch", QStringList{"--screenshot", m_dir->filePath("bad.png")} + bad + QStringList{kDefaultScene});
        QVERIFY(editor.waitForFinished(60000));
        QCOMPARE(editor.exitCode(), 2);
        QVERIFY2(editor.readAll().contains(bad.front().toUtf8()), qPrintable(bad.join(' ')));
        QVERIFY(!QFile::exists(m_dir->filePath("bad.png")));
    }
    // A missing project is an error with a non-zero exit and no picture.
    const QString none = m_dir->filePath("none.png");
    editor.start(SOFTTOUCH_BIN_DIR "/softtouch", {"--screenshot", none, m_dir->filePath("missing.softtouch")});
    QVERIFY(editor.waitForFinished(60000));
    QCOMPARE(editor.exitCode(), 1);
    QVERIFY(editor.readAll().contains("missing.softtouch"));
    QVERIFY(!QFile::exists(none));
}

void TestEditor::editorWithoutADisplaySaysWhatToDo() {
    // Over ssh or on a farm node: --help and --version answer without a window system, and the editor
    // itself stops with what to do instead of Qt's abort about its xcb plugin.
    QProcess editor;
    editor.setProcessChannelMode(QProcess::MergedChannels);
    QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
    for (const char* name : {"DISPLAY", "WAYLAND_DISPLAY", "QT_QPA_PLATFORM"})
        env.remove(name);
    editor.setProcessEnvironment(env);
    editor.start(SOFTTOUCH_BIN_DIR "/softtouch", {"--help"});
    QVERIFY(editor.waitForFinished(30000));
    const QByteArray help = editor.readAll();
    QCOMPARE(editor.exitStatus(), QProcess::NormalExit);
    QVERIFY2(editor.exitCode() == 0 && help.contains("--screenshot"), help.constData());
    editor.start(SOFTTOUCH_BIN_DIR "/softtouch", {"--version"});
    QVERIFY(editor.waitForFinished(30000));
    QVERIFY(editor.exitCode() == 0 && editor.readAll().contains("0.1.0"));
    const QString png = m_dir->filePath("headless.png");
    editor.start(SOFTTOUCH_BIN_DIR "/softtouch", {"--screenshot", png, kDefaultScene});
    QVERIFY(editor.waitForFinished(30000));
    const QByteArray refusal = editor.readAll();
    QCOMPARE(editor.exitStatus(), QProcess::NormalExit);
    QCOMPARE(editor.exitCode(), 2);
    QVERIFY2(refusal.contains("no display") && refusal.contains("xvfb-run") && refusal.contains("softtouch-cli"),
             refusal.constData());
    QVERIFY(!QFile::exists(png));
}

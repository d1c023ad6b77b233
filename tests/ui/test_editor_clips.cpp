// The editor driven through its real widgets (under Xvfb). Takes, keys and clips: record, scrub, key poses,
// retime, export and render.
#include "editor_fixture.h"
#include "helpers/gltf_read.h"
#include <QFileDialog>
#include <numbers>
#include <QCheckBox>
#include <QComboBox>
#include <QContextMenuEvent>
#include <QMenu>
#include <QSpinBox>

// Render video draws from the viewport's view when asked (the animator framed it), from the CLI's ¾ view
// otherwise, whatever the viewport shows.
void TestEditor::renderVideoFollowsTheViewportsView() {
    MainWindow& w = *m_window;
    Viewport* view = w.viewport();
    QVERIFY(!w.document()->project().clips.clips.empty());
    const auto firstFrame = [&](const QString& name, std::optional<render::CameraPlacement> camera) {
        const QString folder = m_dir->filePath(name) + "/";
        const Status s = w.timeline()->renderClipTo(0, folder, 160, 90, camera);
        if (!s)
            qFatal("%s", s.message().c_str());
        return QImage(folder + "frame_0000.png").convertToFormat(QImage::Format_RGB32);
    };
    /// Centre of the orange pixels (the fish on the grey background), in pixels.
    const auto fishCentre = [](const QImage& image) {
        double x = 0, y = 0, n = 0;
        for (int j = 0; j < image.height(); ++j)
            for (int i = 0; i < image.width(); ++i) {
                const QColor c = image.pixelColor(i, j);
                if (c.red() > c.blue() + 60) {
                    x += i;
                    y += j;
                    n += 1;
                }
            }
        return n > 0 ? QPointF(x / n, y / n) : QPointF(-1, -1);
    };
    view->viewTop();
    const QImage top = firstFrame("top", view->camera().placement());
    const QImage defaultA = firstFrame("defaultA", std::nullopt);
    view->viewFront();
    view->camera().pan(0.3 * view->width(), 0, view->height());  // the fish off-centre, as an animator may frame it
    const render::CameraPlacement framed = view->camera().placement();
    const QImage front = firstFrame("front", framed);
    const QImage defaultB = firstFrame("defaultB", std::nullopt);
    QVERIFY(!top.isNull() && !front.isNull());
    QCOMPARE(defaultA, defaultB);  // the ¾ view ignores the viewport
    QVERIFY(top != front);
    // The fish lands where the viewport's camera projects it.
    const Bounds bounds = w.document()->scene().objects[0].mesh->bounds();
    const Eigen::Vector3f centre = (0.5 * (bounds.min + bounds.max)).cast<float>();
    const render::Camera camera = render::cameraFor(framed, 160.0f / 90.0f);
    const Eigen::Vector4f clip = camera.projection * camera.view * Eigen::Vector4f(centre.x(), centre.y(), centre.z(), 1.0f);
    const QPointF expected(80.0 * (1.0 + clip.x() / clip.w()), 45.0 * (1.0 - clip.y() / clip.w()));
    const QPointF found = fishCentre(front);
    QVERIFY2((found - expected).manhattanLength() < 16.0,
             qPrintable(QString("fish at (%1, %2), projected centre (%3, %4)").arg(found.x()).arg(found.y()).arg(expected.x()).arg(expected.y())));
    QVERIFY2((fishCentre(defaultA) - expected).manhattanLength() > 16.0, "the ¾ view should not frame it the same way");
    view->frameAll();

    // The dialog asks for the size and the camera first, this view offered first.
    QStringList cameras;
    QString size;
    QTimer::singleShot(200, [&] {
        if (auto* dialog = qobject_cast<QDialog*>(QApplication::activeModalWidget())) {
            auto* choice = dialog->findChild<QComboBox*>("renderCamera");
            for (int i = 0; choice && i < choice->count(); ++i)
                cameras << choice->itemText(i);
            if (auto* sizes = dialog->findChild<QComboBox*>("renderSize"))
                size = sizes->currentText();
            dialog->reject();
        }
    });
    w.timeline()->renderClip(0);
    QCOMPARE(cameras.size(), 2);
    QVERIFY2(cameras.front().startsWith("This view"), qPrintable(cameras.join("; ")));
    QCOMPARE(size, QString("960 × 540"));
}

void TestEditor::recordedTakeScrubsAndExports() {
    MainWindow& w = *m_window;
    SimulationController* sim = w.simulation();
    QWidget* cue = w.viewport()->findChild<QWidget*>("recordingCue");
    QVERIFY(cue && !cue->isVisible());
    sim->startRecording();
    sim->pause();
    sim->advance(0.5);
    const BodyState atHalf = sim->simulation()->simulator(0).state();
    sim->advance(0.5);
    // While recording, the viewport wears a red frame with "● REC" (red pixels at its edge).
    QVERIFY(cue->isVisible());
    QCOMPARE(cue->size(), w.viewport()->size());
    const QImage frame = cue->grab().toImage();
    const QColor edge = frame.pixelColor(frame.width() / 2, 1);
    QVERIFY2(edge.red() > 180 && edge.green() < 80, qPrintable(edge.name()));
    QVERIFY(sim->stopRecording().has_value());
    QVERIFY(!cue->isVisible());
    QCOMPARE(w.timeline()->takeCount(), 1);  // the take is in the project (undoable, saved with it)
    QVERIFY(w.document()->isModified());
    // Scrubbing to 0.5 s replays the take and shows exactly the state recorded there.
    w.timeline()->scrubTo(0, int(0.5 * w.timeline()->fps()));
    QVERIFY(sim->simulation()->simulator(0).state().position == atHalf.position);
    // A looping clip of the take, exported as a point cache the CLI's reader accepts.
    const std::size_t clipsBefore = w.document()->project().clips.clips.size();
    QVERIFY(w.timeline()->makeClip(0, true));
    QCOMPARE(w.document()->project().clips.clips.size(), clipsBefore + 1);
    const int clip = int(clipsBefore);
    // The dialogs start beside the project, named after it and the clip.
    const QString suggested = w.timeline()->suggestedOutputPath(clip, "pc2");
    QCOMPARE(QFileInfo(suggested).absolutePath(), QFileInfo(w.document()->filePath()).absolutePath());
    // The clip is "take 1 clip": the file name has no spaces, one word for a shell or an engine's importer.
    QCOMPARE(QString::fromStdString(w.document()->project().clips.clips[std::size_t(clip)].name), QString("take 1 clip"));
    QCOMPARE(QFileInfo(suggested).fileName(), QFileInfo(w.document()->filePath()).completeBaseName() + "-take-1-clip.pc2");
    const QString pc2 = m_dir->filePath("take.pc2");
    const Status exported = w.timeline()->exportClipTo(clip, pc2);
    QVERIFY2(exported.ok(), exported.message().c_str());
    QVERIFY2(w.timeline()->statusText().contains("rest mesh take.obj"), qPrintable(w.timeline()->statusText()));
    // The same clip as bones for a game engine (the dialog's "skinned" file type): a GLB with a skin, and
    // the status line says how close it is.
    // The dialog offers every export of the registry, in its order, each once.
    const QStringList filters = TimelinePanel::exportFilters();
    QCOMPARE(std::size_t(filters.size()), io::exportFormats().size());
    QCOMPARE(filters.front(), QString("Point cache (*.pc2)"));
    QVERIFY2(filters.contains("glTF binary, skinned: bones for game engines (*.glb *.gltf)"), qPrintable(filters.join("; ")));
    QVERIFY2(filters.contains("Lattice cache (base name) (*)"), qPrintable(filters.join("; ")));
    QCOMPARE(QSet<QString>(filters.begin(), filters.end()).size(), filters.size());
    const QString glb = m_dir->filePath("take-skin.glb");
    const Status skin = w.timeline()->exportClipTo(clip, glb, *io::findExportFormat("skin"));
    QVERIFY2(skin.ok(), skin.message().c_str());
    QFile glbFile(glb);
    QVERIFY(glbFile.open(QIODevice::ReadOnly));
    QVERIFY(glbFile.readAll().contains("\"skins\""));
    QVERIFY2(w.timeline()->statusText().contains("rigid bones"), qPrintable(w.timeline()->statusText()));
    // Packed for shipping (the export options' "Pack for shipping"): under half the size, and the
    // status line says how large it is against a PC2. A PC2 cannot be packed, and says so.
    const QString packedGlb = m_dir->filePath("take-skin-packed.glb");
    ExportChoices packed;
    packed.compress = true;
    const Status packedSkin = w.timeline()->exportClipTo(clip, packedGlb, *io::findExportFormat("skin"), packed);
    QVERIFY2(packedSkin.ok(), packedSkin.message().c_str());
    QFile packedFile(packedGlb);
    QVERIFY(packedFile.open(QIODevice::ReadOnly));
    QVERIFY(io::usesMeshoptCompression(packedFile.readAll().toStdString()));
    QVERIFY2(QFileInfo(packedGlb).size() * 2 < QFileInfo(glb).size(), qPrintable(QString::number(QFileInfo(packedGlb).size())));
    QVERIFY2(w.timeline()->statusText().contains("of a PC2"), qPrintable(w.timeline()->statusText()));
    const Status packedPc2 = w.timeline()->exportClipTo(clip, m_dir->filePath("packed.pc2"), *io::findExportFormat("pc2"), packed);
    QVERIFY(!packedPc2.ok());
    QVERIFY2(packedPc2.message().find("--compress") != std::string::npos, packedPc2.message().c_str());
    auto cache = io::readPc2(pc2.toStdString());
    QVERIFY2(cache.ok(), cache.message().c_str());
    QCOMPARE(int(cache->frames.size()), w.document()->project().clips.clips[std::size_t(clip)].frames);
    QCOMPARE(cache->info.pointCount, w.document()->scene().objects[0].mesh->positions.size());
    // The same clip rendered as a video from the editor (headless EGL beside the viewport's context).
    const QString mp4 = m_dir->filePath("take.mp4");
    const Status rendered = w.timeline()->renderClipTo(clip, mp4, 160, 96);
    QVERIFY2(rendered.ok(), rendered.message().c_str());
    auto probe = io::probeVideo(mp4.toStdString());
    QVERIFY2(probe.ok(), probe.message().c_str());
    QCOMPARE(probe->frames, w.document()->project().clips.clips[std::size_t(clip)].frames);
    QCOMPARE(probe->width, 160);
    // The viewport still draws afterwards.
    QVERIFY(!w.viewport()->grabFramebuffer().isNull());
    QVERIFY(w.viewport()->renderProblem().isEmpty());
    // Undo removes the clip, then the take.
    w.document()->undoStack()->undo();
    QCOMPARE(w.document()->project().clips.clips.size(), clipsBefore);
    w.document()->undoStack()->undo();
    QCOMPARE(w.timeline()->takeCount(), 0);
}

namespace {

/// Export… the way a person goes: the button, the file dialog (the export type whose filter mentions `kind`, and
/// `path`), then Export Options with the check box `tick` ticked. Each modal dialog is answered as it opens.
/// False when a dialog did not come.
bool exportThroughDialogs(MainWindow& w, const QString& kind, const QString& path, const QString& tick) {
    auto* clips = w.timeline()->findChild<QListWidget*>("clips");
    if (!clips || clips->count() == 0)
        return false;
    clips->setCurrentRow(0);
    QPushButton* exportButton = nullptr;
    for (QPushButton* b : w.timeline()->findChildren<QPushButton*>())
        if (b->text() == QString("Export…"))
            exportButton = b;
    QString filter;
    for (const QString& f : TimelinePanel::exportFilters())
        if (f.contains(kind, Qt::CaseInsensitive))
            filter = f;
    if (!exportButton || filter.isEmpty())
        return false;
    bool answeredFile = false, answeredOptions = false;
    QTimer answer;
    QObject::connect(&answer, &QTimer::timeout, [&] {
        QWidget* modal = QApplication::activeModalWidget();
        if (auto* files = qobject_cast<QFileDialog*>(modal); files && !answeredFile) {
            answeredFile = true;
            answerSaveDialog(*files, filter, path);
        } else if (auto* options = qobject_cast<QDialog*>(modal); options && !answeredOptions) {
            if (auto* box = options->findChild<QCheckBox*>(tick)) {
                answeredOptions = true;
                box->setChecked(true);
                options->accept();
            }
        }
    });
    answer.start(50);
    exportButton->click();
    answer.stop();
    return answeredFile && answeredOptions;
}

}  // namespace

void TestEditor::exportDialogsPackAGlbForShipping() {
    // The whole way a person goes: Export…, the file dialog (the skinned GLB type and a name), then Export
    // Options' "Pack for shipping".
    const QString glb = m_dir->filePath("shipped.glb");
    QVERIFY(exportThroughDialogs(*m_window, "skin", glb, "exportCompress"));
    QVERIFY2(QFile::exists(glb), qPrintable(QString("%1 not written; the folder holds %2").arg(glb, QDir(m_dir->path()).entryList(QDir::Files).join(", "))));
    QVERIFY2(io::fileUsesMeshoptCompression(glb.toStdString()), "the file is not packed");
    // No preview page unless asked for.
    QVERIFY(!QFileInfo::exists(m_dir->filePath("shipped-preview")));
    QVERIFY(m_desktopOpened.isEmpty());
}

// #42: the preview page from the editor. Export Options' "Open a preview page" writes the page softtouch-cli
// preview writes, beside the export, and asks the desktop to open it; the status line says where it is.
void TestEditor::exportWritesAndOpensAPreviewPage() {
    const QString glb = m_dir->filePath("fish-swim.glb");
    QVERIFY(exportThroughDialogs(*m_window, "skin", glb, "exportPreview"));
    QVERIFY(QFile::exists(glb));
    const QString index = m_dir->filePath("fish-swim-preview/index.html");
    QFile page(index);
    QVERIFY2(page.open(QIODevice::ReadOnly), qPrintable(index));
    const QByteArray html = page.readAll();
    QVERIFY(html.contains("id=\"softtouch-clip\""));
    QVERIFY(html.contains("\"kind\":\"skinned\"") || html.contains("\"kind\": \"skinned\""));
    QCOMPARE(m_desktopOpened, QList<QUrl>{QUrl::fromLocalFile(index)});
    QVERIFY2(m_window->timeline()->statusText().contains(index), qPrintable(m_window->timeline()->statusText()));
    // The same page as the command line's for the same file.
    const auto cli = softtouch::test::runCli({"preview", glb, "--out", m_dir->filePath("cli"), "--quiet"});
    QCOMPARE(cli.exitCode, 0);
    QFile cliPage(m_dir->filePath("cli/index.html"));
    QVERIFY(cliPage.open(QIODevice::ReadOnly));
    QVERIFY(cliPage.readAll() == html);
}

void TestEditor::exportDialogPutsTheRiggedGuppyOnItsOwnRig() {
    // The rigged guppy's swim exported as a skinned GLB from Export…: Export Options offers the bones, its own rig
    // first. On it the file's skin is the guppy's six spine joints (plus helpers); fitted, it is bones of its own.
    MainWindow& w = *m_window;
    QVERIFY(w.openFile(QStringLiteral(SOFTTOUCH_SOURCE_DIR "/presets/scenes/guppy-rigged.softtouch")));
    auto* clips = w.timeline()->findChild<QListWidget*>("clips");
    QVERIFY(clips && clips->count() > 0);
    clips->setCurrentRow(0);
    QPushButton* exportButton = nullptr;
    for (QPushButton* b : w.timeline()->findChildren<QPushButton*>())
        if (b->text() == QString("Export…"))
            exportButton = b;
    QVERIFY(exportButton);
    QString skinFilter;
    for (const QString& f : TimelinePanel::exportFilters())
        if (f.contains("skin", Qt::CaseInsensitive))
            skinFilter = f;
    // Answers the file dialog with `glb` and Export Options with bones choice `choice`; returns the choices offered.
    auto exportAs = [&](const QString& glb, int choice) {
        QStringList offered;
        bool answeredFile = false, answeredOptions = false;
        QTimer answer;
        connect(&answer, &QTimer::timeout, this, [&] {
            QWidget* modal = QApplication::activeModalWidget();
            if (auto* files = qobject_cast<QFileDialog*>(modal); files && !answeredFile) {
                answeredFile = true;
                answerSaveDialog(*files, skinFilter, glb);
            } else if (auto* options = qobject_cast<QDialog*>(modal); options && !answeredOptions) {
                if (auto* bones = options->findChild<QComboBox*>("exportBones")) {
                    answeredOptions = true;
                    for (int i = 0; i < bones->count(); ++i)
                        offered << bones->itemText(i);
                    bones->setCurrentIndex(choice);
                    options->accept();
                }
            }
        });
        answer.start(50);
        exportButton->click();
        answer.stop();
        return offered;
    };
    const QString own = m_dir->filePath("guppy-own-rig.glb");
    const QStringList offered = exportAs(own, 0);
    QCOMPARE(offered.size(), 2);
    QVERIFY2(offered[0].contains("own rig"), qPrintable(offered.join(" | ")));
    QVERIFY(QFile::exists(own));
    const tinygltf::Model onRig = softtouch::test::loadGlb(own.toStdString());
    QStringList joints;
    for (int j : onRig.skins.front().joints)
        joints << QString::fromStdString(onRig.nodes[std::size_t(j)].name);
    QCOMPARE(joints.mid(0, 6), (QStringList{"spine0", "spine1", "spine2", "spine3", "spine4", "spine5"}));
    QVERIFY(joints.size() <= 6 + 16);

    const QString fitted = m_dir->filePath("guppy-fitted.glb");
    exportAs(fitted, 1);
    QVERIFY(QFile::exists(fitted));
    const tinygltf::Model free = softtouch::test::loadGlb(fitted.toStdString());
    QVERIFY(QString::fromStdString(free.nodes[std::size_t(free.skins.front().joints.front())].name).startsWith("bone_"));
}

void TestEditor::keyframesFromPosesMakeAClip() {
    MainWindow& w = *m_window;
    KeyframePanel* keys = w.keyframes();
    SimulationController* sim = w.simulation();
    sim->setDriversEnabled(false);
    // Key the rest pose at 0 s, pull the tail, key that pose at 1 s.
    QVERIFY(keys->keyPose(0.0));
    const Lattice& lattice = w.document()->scene().objects[0].lattice;
    Grab grab;
    grab.drag.support = lattice.weights(Vec3(0.1, 0.5, 0.5));
    grab.drag.target = lattice.evaluate(Vec3(0.1, 0.5, 0.5), lattice.restNodes()) + Vec3(0, 0.3, 0);
    grab.drag.stiffness = 200;
    sim->setGrab(0, grab);
    sim->advance(1.0);
    const std::vector<Vec3> pulled = sim->simulation()->simulator(0).state().position;
    QVERIFY(keys->keyPose(1.0));
    QCOMPARE(keys->keys().size(), std::size_t(2));
    QCOMPARE(keys->keys()[1].nodes.size(), std::size_t(lattice.nodeCount()));
    // Previewing a key shows its pose.
    sim->setGrab(0, std::nullopt);
    keys->showKey(1);
    const std::vector<Vec3>& shown = sim->simulation()->simulator(0).state().position;
    for (std::size_t n = 0; n < shown.size(); ++n)
        QVERIFY((shown[n] - pulled[n]).norm() < 1e-9);
    // Move, copy and delete are single undo steps.
    QVERIFY(keys->moveKey(1, 2.0, false));
    QCOMPARE(keys->keys()[1].seconds, 2.0);
    QVERIFY(keys->moveKey(1, 3.0, true));
    QCOMPARE(keys->keys().size(), std::size_t(3));
    QVERIFY(keys->deleteKey(2));
    w.document()->undoStack()->undo();
    QCOMPARE(keys->keys().size(), std::size_t(3));
    w.document()->undoStack()->undo();
    w.document()->undoStack()->undo();
    QCOMPARE(keys->keys()[1].seconds, 1.0);
    // A keyed clip plays the keys: its last frame is the pulled pose.
    QVERIFY(keys->makeClip(false));
    const ClipLibrary& library = w.document()->project().clips;
    const Clip& clip = library.clips.back();
    QCOMPARE(clip.source, ClipSource::Keyframes);
    auto frames = evaluateClip(w.document()->scene(), library, clip);
    QVERIFY2(frames.ok(), frames.message().c_str());
    const auto& last = frames->nodes.back()[0];
    for (std::size_t n = 0; n < last.size(); ++n)
        QVERIFY((last[n] - pulled[n]).norm() < 1e-6);
    // As goals, the simulated body follows the keys with physics (a valid clip that evaluates).
    QVERIFY(keys->makeClip(true));
    auto goalFrames = evaluateClip(w.document()->scene(), w.document()->project().clips, w.document()->project().clips.clips.back());
    QVERIFY2(goalFrames.ok(), goalFrames.message().c_str());
}

// A keyed clip becomes a cycle from its own menu or the Loop box beside the clips (one undo step each), the way a
// swim cycle is made from keys: the last key, the first pose again, starts the next pass, so the seam steps like
// any other frame. (Loop once applied only when cutting a clip from a take.)
void TestEditor::aKeyedClipLoopsFromItsMenuAndTheLoopBox() {
    MainWindow& w = *m_window;
    KeyframePanel* keys = w.keyframes();
    SimulationController* sim = w.simulation();
    QUndoStack* undo = w.document()->undoStack();
    sim->setDriversEnabled(false);
    const Lattice& lattice = w.document()->scene().objects[0].lattice;
    const std::vector<Vec3> rest = lattice.restNodes();
    // One second of a tail swing keyed every quarter second: lift = A sin(2 pi t), the last key the first pose.
    for (int k = 0; k <= 4; ++k) {
        const double t = 0.25 * k, lift = 0.05 * std::sin(2.0 * std::numbers::pi * t);
        std::vector<Vec3> pose = rest;
        for (std::size_t n = 0; n < pose.size(); ++n)
            pose[n].y() += lift * std::max(0.0, lattice.box().toParameters(rest[n]).x() - 0.5);
        QVERIFY(sim->setObjectPose(0, pose));
        QVERIFY(keys->keyPose(t));
    }
    QVERIFY(keys->makeClip(false));
    const ClipLibrary& library = w.document()->project().clips;
    const int row = int(library.clips.size()) - 1;
    const double fps = library.clips.back().fps;
    QCOMPARE(library.clips.back().frames, int(std::lround(fps)) + 1);  // to the last key, held
    auto* list = w.timeline()->findChild<QListWidget*>("clips");
    auto* loopBox = w.timeline()->findChild<QCheckBox*>("clipLoop");
    QVERIFY(list && loopBox);
    const QPoint at = list->visualItemRect(list->item(row)).center();
    QTest::mouseClick(list->viewport(), Qt::LeftButton, {}, at);
    QCOMPARE(list->currentRow(), row);
    QVERIFY(!loopBox->isChecked());

    // The clip's menu: Loop, checked by a person choosing it in the open menu.
    const int steps = undo->index();
    bool chosen = false;
    QTimer::singleShot(0, this, [&] {
        auto* menu = qobject_cast<QMenu*>(QApplication::activePopupWidget());
        QVERIFY(menu);
        for (QAction* action : menu->actions())
            if (action->text() == "Loop") {
                QVERIFY(action->isCheckable() && !action->isChecked());
                chosen = true;
                action->trigger();
            }
        menu->close();
    });
    QContextMenuEvent menuEvent(QContextMenuEvent::Mouse, at, list->viewport()->mapToGlobal(at));
    QApplication::sendEvent(list->viewport(), &menuEvent);
    QVERIFY(chosen);
    QCOMPARE(undo->index(), steps + 1);
    const Clip& looped = w.document()->project().clips.clips[std::size_t(row)];
    QVERIFY(looped.loop);
    QCOMPARE(looped.frames, int(std::lround(fps)));  // frame N is frame 0 again: the last key starts the next pass
    QVERIFY(looped.blendFrames > 0);
    QVERIFY(loopBox->isChecked());
    QVERIFY2(list->item(row)->text().contains("loop"), qPrintable(list->item(row)->text()));
    auto frames = evaluateClip(w.document()->scene(), w.document()->project().clips, looped);
    QVERIFY2(frames.ok(), frames.message().c_str());
    const SeamMeasure seam = measureSeam(frames.value());
    qInfo("keyed loop seam: %.3f of the neighbouring steps, %.3f of the median step", seam.localRatio, seam.ratio);
    QVERIFY2(seam.localRatio < 1.2 && seam.ratio < 1.2, qPrintable(QString::number(seam.localRatio)));

    // The Loop box beside the clips says and sets the selected clip's loop: off gives the held last key back.
    QTest::mouseClick(loopBox, Qt::LeftButton);
    QCOMPARE(undo->index(), steps + 2);
    QVERIFY(!w.document()->project().clips.clips[std::size_t(row)].loop);
    QCOMPARE(w.document()->project().clips.clips[std::size_t(row)].frames, int(std::lround(fps)) + 1);
    undo->undo();
    QVERIFY(w.document()->project().clips.clips[std::size_t(row)].loop);
    QVERIFY(loopBox->isChecked());
}

// #42's must-show: a one-second guppy swim cycle keyed entirely in the editor, as docs/user-guide.md tells it.
// Front view (1); a box dragged round the tail's column of lattice nodes selects it; G Z 0.1 Enter (the tail
// 10 cm to the side) and I key it at frame 0; a click on the ruler at frame 12 moves the Key frame there, the
// pointer back over the view, G Z -0.2 Enter, I; frame 24, G Z 0.2 Enter, I. As goals at strength 2, Clip from
// keys, Loop: the body swims through the keys with physics and the loop's seam steps like the rest of the cycle.
void TestEditor::aGuppySwimCycleIsKeyedInTheEditorAlone() {
    MainWindow& w = *m_window;
    QVERIFY(w.openFile(QStringLiteral(SOFTTOUCH_SOURCE_DIR "/presets/scenes/guppy-swim.softtouch")));
    w.simulation()->pause();
    Viewport* view = startPosing(w);
    KeyframePanel* keys = w.keyframes();
    FrameRuler* ruler = w.timeline()->ruler();
    auto* keyFrame = keys->findChild<QSpinBox*>("keyFrame");
    QVERIFY(keyFrame && keyFrame->isVisible() && ruler->isVisible());  // the Keys panel does not hide the ruler
    QTest::keyClick(view, Qt::Key_1);
    const Lattice& lattice = w.document()->scene().objects[0].lattice;
    const auto nodes = [&] { return w.simulation()->simulation()->simulator(0).state().position; };
    std::set<int> tail;
    QRectF around;
    for (int n = 0; n < lattice.nodeCount(); ++n)
        if (lattice.coords(n)[0] == 0) {  // the guppy's tail fan is at the low-x end of its box
            tail.insert(n);
            const QPointF p = view->toWidget(nodes()[std::size_t(n)]);
            around = around.isNull() ? QRectF(p, QSizeF(1, 1)) : around.united(QRectF(p, QSizeF(1, 1)));
        }
    around.adjust(-8, -8, 8, 8);
    for (int n = 0; n < lattice.nodeCount(); ++n)
        QVERIFY2(tail.count(n) || !around.contains(view->toWidget(nodes()[std::size_t(n)])), "the box holds only the tail");
    QTest::mousePress(view, Qt::LeftButton, {}, around.topLeft().toPoint());
    QTest::mouseMove(view, around.center().toPoint());
    QTest::mouseMove(view, around.bottomRight().toPoint());
    QTest::mouseRelease(view, Qt::LeftButton, {}, around.bottomRight().toPoint());
    QCOMPARE(view->selection(), tail);

    const auto swingAndKey = [&](const char* metres) {
        QCursor::setPos(view->mapToGlobal(view->rect().center()));  // the keys go where the pointer is
        QTRY_VERIFY(view->hasFocus());
        QTest::keyClick(view, Qt::Key_G);
        QTest::keyClick(view, Qt::Key_Z);
        QTest::keyClicks(view, metres);
        QTest::keyClick(view, Qt::Key_Return);
        const int at = keyFrame->value();
        QTest::keyClick(view, Qt::Key_I);
        QCOMPARE(ruler->frame(), at);  // keying leaves the playhead, and the Key frame, where they were
        QCOMPARE(keyFrame->value(), at);
    };
    const auto clickRulerAt = [&](int frame) {
        const QPoint at(int(std::lround(ruler->xOfFrame(frame))), 30);
        QCursor::setPos(ruler->mapToGlobal(at));  // the pointer leaves the view for the ruler
        QTest::qWait(100);  // the X server's pointer events first, as a hand moving the mouse gives them
        QTest::mouseClick(ruler, Qt::LeftButton, {}, at);
        QCOMPARE(keyFrame->value(), frame);  // the Key frame follows the playhead
    };
    QCOMPARE(keyFrame->value(), 0);
    swingAndKey("0.1");
    clickRulerAt(12);
    swingAndKey("-0.2");
    clickRulerAt(24);
    swingAndKey("0.2");
    const std::vector<LatticeKey> keyed = keys->keys();
    QCOMPARE(keyed.size(), std::size_t(3));
    const double fps = w.document()->scene().world.fps;
    for (std::size_t k = 0; k < 3; ++k) {
        QCOMPARE(keyed[k].seconds, 12.0 * double(k) / fps);
        QCOMPARE(keyed[k].nodes.size(), tail.size());
    }
    QCOMPARE(ruler->keys().size(), std::size_t(3));

    // As goals, Clip from keys; then the new clip's Loop box on the timeline.
    QCheckBox* goals = nullptr;
    QPushButton* makeClip = nullptr;
    for (auto* box : keys->findChildren<QCheckBox*>())
        if (box->text().startsWith("As goals"))
            goals = box;
    for (auto* button : keys->findChildren<QPushButton*>())
        if (button->text() == "Clip from keys")
            makeClip = button;
    QVERIFY(goals && makeClip);
    auto* strength = keys->findChild<QDoubleSpinBox*>("goalStrength");
    QVERIFY(strength && !strength->isEnabled());
    QTest::mouseClick(goals, Qt::LeftButton);
    QVERIFY(goals->isChecked() && strength->isEnabled());
    QTest::mouseClick(strength, Qt::LeftButton);  // the goal springs twice as strong: typed, then Enter
    strength->selectAll();
    QTest::keyClicks(strength, "2");
    QTest::keyClick(strength, Qt::Key_Return);
    QTest::mouseClick(makeClip, Qt::LeftButton);
    const ClipLibrary& library = w.document()->project().clips;
    QCOMPARE(library.clips.back().source, ClipSource::Keyframes);
    QVERIFY(library.clips.back().goals.has_value());
    QCOMPARE(library.clips.back().goals->weight, 2.0);
    auto* list = w.timeline()->findChild<QListWidget*>("clips");
    auto* loopBox = w.timeline()->findChild<QCheckBox*>("clipLoop");
    QVERIFY(list && loopBox);
    const int row = list->count() - 1;
    QTest::mouseClick(list->viewport(), Qt::LeftButton, {}, list->visualItemRect(list->item(row)).center());
    QCOMPARE(list->currentRow(), row);
    QTest::mouseClick(loopBox, Qt::LeftButton);
    const Clip& cycle = library.clips[std::size_t(row)];
    QVERIFY(cycle.loop);
    QCOMPARE(cycle.frames, 24);  // one second at 24 fps: frame 24 is frame 0 again

    auto frames = evaluateClip(w.document()->scene(), library, cycle);
    QVERIFY2(frames.ok(), frames.message().c_str());
    const SeamMeasure seam = measureSeam(frames.value());
    // It swims: the tail swings from side to side through most of the keyed 20 cm (the goal springs lag it and
    // the material holds it back).
    double low = 1e9, high = -1e9;
    const std::size_t tip = std::size_t(*tail.begin());
    for (const auto& f : frames->nodes) {
        low = std::min(low, f[0][tip].z());
        high = std::max(high, f[0][tip].z());
    }
    qInfo("guppy keyed loop: seam %.3f of the median step (%.3f of the neighbouring steps); the tail swings %.3f m "
          "of the keyed 0.2 m",
          seam.ratio, seam.localRatio, high - low);
    QVERIFY2(high - low > 0.75 * 0.2, qPrintable(QString::number(high - low)));
    QVERIFY2(seam.ratio <= 1.2 && seam.localRatio <= 1.2, qPrintable(QString("%1 / %2").arg(seam.ratio).arg(seam.localRatio)));
}

// #42 item 8: after importing a mesh (a new project) the timeline no longer reads the old project's clip.
void TestEditor::anotherProjectLeavesNoOldClipOnShow() {
    MainWindow& w = *m_window;
    auto* list = w.timeline()->findChild<QListWidget*>("clips");
    QVERIFY(list && list->count() > 0);
    QTest::mouseClick(list->viewport(), Qt::LeftButton, {}, list->visualItemRect(list->item(0)).center());
    QVERIFY2(w.timeline()->statusText().contains("swim"), qPrintable(w.timeline()->statusText()));
    QVERIFY(w.document()->importMesh(QStringLiteral(SOFTTOUCH_SOURCE_DIR "/presets/meshes/guppy.obj")).ok());
    QCOMPARE(list->count(), 0);
    QVERIFY2(!w.timeline()->statusText().contains("swim"), qPrintable(w.timeline()->statusText()));
    QVERIFY2(w.timeline()->statusText().startsWith("Record a take"), qPrintable(w.timeline()->statusText()));
    QCOMPARE(w.timeline()->ruler()->lastFrame(), std::max(1, w.document()->scene().world.frames) - 1);
}

// #42 item 6: one transport. Space plays what the timeline shows (the selected clip), not the live simulation
// beside it; ←/→ step a frame, Shift+←/→ go to the ends, Home to the start; the status line says what plays. A
// click on empty space in the clips list puts nothing on show, and Space runs the live simulation again.
void TestEditor::oneTransportPlaysWhatTheTimelineShows() {
    MainWindow& w = *m_window;
    w.activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(&w));
    SimulationController* sim = w.simulation();
    TimelinePanel* timeline = w.timeline();
    auto* status = w.findChild<QLabel*>("simulationStatus");
    auto* list = timeline->findChild<QListWidget*>("clips");
    QVERIFY(status && list && list->count() > 0);
    sim->pause();
    QTest::mouseClick(list->viewport(), Qt::LeftButton, {}, list->visualItemRect(list->item(0)).center());
    QVERIFY(timeline->showsClipOrTake());
    const FrameRuler* ruler = timeline->ruler();
    QCOMPARE(ruler->frame(), 0);
    const auto key = [&](Qt::Key k, Qt::KeyboardModifiers m = {}) { QTest::keyClick(&w, k, m); };
    key(Qt::Key_Right);
    key(Qt::Key_Right);
    QCOMPARE(ruler->frame(), 2);
    key(Qt::Key_Left);
    QCOMPARE(ruler->frame(), 1);
    key(Qt::Key_Right, Qt::ShiftModifier);
    QCOMPARE(ruler->frame(), ruler->lastFrame());
    key(Qt::Key_Home);
    QCOMPARE(ruler->frame(), 0);
    // Space plays the clip, not the simulation; the status line says so.
    key(Qt::Key_Space);
    QVERIFY(timeline->isPlaying());
    QVERIFY(!sim->isPlaying());
    QTRY_VERIFY2(status->text().startsWith("playing clip swim"), qPrintable(status->text()));
    key(Qt::Key_Space);
    QVERIFY(!timeline->isPlaying());
    QTRY_VERIFY2(status->text().startsWith("clip swim on show, paused"), qPrintable(status->text()));
    // Nothing on show: Space runs the live simulation, Home resets it.
    QTest::mouseClick(list->viewport(), Qt::LeftButton, {}, QPoint(5, list->viewport()->height() - 5));
    QVERIFY(!timeline->showsClipOrTake());
    key(Qt::Key_Space);
    QVERIFY(sim->isPlaying());
    QVERIFY(!timeline->isPlaying());
    key(Qt::Key_Space);
    QVERIFY(!sim->isPlaying());
}

// #42 item 7: Esc out of Export…, then Space, plays; it used to press Export… again, the button keeping the keyboard
// focus from its click. The keys go where a keyboard sends them: to the focus widget.
void TestEditor::spaceAfterADialogPlaysRatherThanReopeningIt() {
    MainWindow& w = *m_window;
    w.activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(&w));
    w.simulation()->pause();
    TimelinePanel* timeline = w.timeline();
    auto* list = timeline->findChild<QListWidget*>("clips");
    QVERIFY(list && list->count() > 0);
    QTest::mouseClick(list->viewport(), Qt::LeftButton, {}, list->visualItemRect(list->item(0)).center());
    QPushButton* exportButton = nullptr;
    for (QPushButton* b : timeline->findChildren<QPushButton*>())
        if (b->text() == QString("Export…"))
            exportButton = b;
    QVERIFY(exportButton);
    int dialogs = 0;
    QTimer poll;
    connect(&poll, &QTimer::timeout, this, [&] {
        if (auto* dialog = qobject_cast<QFileDialog*>(QApplication::activeModalWidget())) {
            ++dialogs;
            QTest::keyClick(dialog, Qt::Key_Escape);  // as the user leaves it
        }
    });
    poll.start(50);
    QTest::mouseClick(exportButton, Qt::LeftButton);
    QCOMPARE(dialogs, 1);
    w.activateWindow();  // what a window manager does when the dialog is gone (Xvfb runs none)
    QVERIFY(QTest::qWaitForWindowActive(&w));
    QVERIFY(!exportButton->hasFocus());
    QWidget* focus = QApplication::focusWidget();
    QTest::keyClick(focus ? focus : static_cast<QWidget*>(&w), Qt::Key_Space);
    QTest::qWait(300);
    poll.stop();
    QCOMPARE(dialogs, 1);
    QVERIFY(timeline->isPlaying());
    timeline->togglePlayback();
}

// The timeline's ruler shows the pose keys as ticks (#15 item 1): dragging a tick retimes its key, Ctrl+drag
// copies it, a click and Delete removes it; each is one undo step of the keys panel.
void TestEditor::rulerTicksRetimeCopyAndDeleteKeys() {
    MainWindow& w = *m_window;
    KeyframePanel* keys = w.keyframes();
    SimulationController* sim = w.simulation();
    FrameRuler* ruler = w.timeline()->ruler();
    QUndoStack* undo = w.document()->undoStack();
    sim->setDriversEnabled(false);
    QVERIFY(keys->keyPose(0.0));
    const Lattice& lattice = w.document()->scene().objects[0].lattice;
    std::vector<Vec3> pose = lattice.restNodes();
    pose[0] += Vec3(0, 0.05, 0);
    QVERIFY(sim->setObjectPose(0, pose));
    QVERIFY(keys->keyPose(1.0));
    QCOMPARE(ruler->keys(), (std::vector<double>{0.0, 1.0}));
    const double fps = ruler->fps();
    QVERIFY(ruler->lastFrame() >= int(1.5 * fps));
    const int undo0 = undo->index();
    const auto drag = [&](QPointF from, int toFrame, Qt::KeyboardModifiers modifiers) {
        dragWith(ruler, from.toPoint(), QPoint(int(std::lround(ruler->xOfFrame(toFrame))), from.toPoint().y()), modifiers);
    };
    // Drag the 1 s key to 1.5 s: one undo step, the keyed pose kept.
    drag(ruler->keyPoint(1), int(std::lround(1.5 * fps)), {});
    QCOMPARE(keys->keys().size(), std::size_t(2));
    QCOMPARE(keys->keys()[1].seconds, std::lround(1.5 * fps) / fps);
    QCOMPARE(ruler->keys()[1], keys->keys()[1].seconds);
    QCOMPARE(undo->index(), undo0 + 1);
    // Ctrl+drag copies the first key to half a second.
    drag(ruler->keyPoint(0), int(std::lround(0.5 * fps)), Qt::ControlModifier);
    QCOMPARE(keys->keys().size(), std::size_t(3));
    QCOMPARE(keys->keys()[0].seconds, 0.0);
    QCOMPARE(keys->keys()[1].seconds, std::lround(0.5 * fps) / fps);
    QCOMPARE(undo->index(), undo0 + 2);
    // Click a tick and press Delete.
    QTest::mouseClick(ruler, Qt::LeftButton, {}, ruler->keyPoint(1).toPoint());
    QCOMPARE(ruler->selectedKey(), 1);
    QTest::keyClick(ruler, Qt::Key_Delete);
    QCOMPARE(keys->keys().size(), std::size_t(2));
    QCOMPARE(keys->keys()[1].seconds, std::lround(1.5 * fps) / fps);
    QCOMPARE(undo->index(), undo0 + 3);
    // A click on the ruler away from the ticks moves no key.
    QTest::mouseClick(ruler, Qt::LeftButton, {}, QPoint(int(ruler->xOfFrame(3)), 30));
    QCOMPARE(undo->index(), undo0 + 3);
    while (undo->index() > undo0)
        undo->undo();
    QCOMPARE(ruler->keys(), (std::vector<double>{0.0, 1.0}));
}

// Each key says how it moves on to the next: picked from its right-click menu on the ruler or in the Keys panel
// (one undo step each), and the keyed clip moves so: a constant key holds its pose until the next key, a linear
// one goes straight, at constant speed, to it.
void TestEditor::keysHoldOrGoStraightAsTheRulerMenuSays() {
    MainWindow& w = *m_window;
    KeyframePanel* keys = w.keyframes();
    SimulationController* sim = w.simulation();
    FrameRuler* ruler = w.timeline()->ruler();
    QUndoStack* undo = w.document()->undoStack();
    sim->setDriversEnabled(false);
    const Lattice& lattice = w.document()->scene().objects[0].lattice;
    const std::vector<Vec3> rest = lattice.restNodes();
    std::vector<Vec3> raised = rest;
    const Vec3 lift(0, 0.05, 0);
    raised[0] += lift;
    QVERIFY(keys->keyPose(0.0));  // rest at 0 s, raised at 1 s, rest again at 2 s
    QVERIFY(sim->setObjectPose(0, raised));
    QVERIFY(keys->keyPose(1.0));
    QVERIFY(sim->setObjectPose(0, rest));
    QVERIFY(keys->keyPose(2.0));
    const int undo0 = undo->index();
    // Right-click the 1 s key on the ruler and pick Constant (hold) from its menu.
    const QStringList offered = chooseFromMenu(ruler, ruler->keyPoint(1).toPoint(), "keyMenu", "Constant (hold)");
    QVERIFY2(offered.contains("Linear") && offered.contains("Delete key"), qPrintable(offered.join(", ")));
    QCOMPARE(keys->keys()[1].interpolation, KeyInterpolation::Constant);
    QCOMPARE(undo->index(), undo0 + 1);
    // In the Keys panel, the first key becomes linear: select it, then the arrow key on the Interpolation box.
    auto* list = keys->findChild<QListWidget*>("keys");
    auto* how = keys->findChild<QComboBox*>("keyInterpolation");
    QVERIFY(list && how);
    list->setCurrentRow(0);
    QVERIFY(how->isEnabled());
    QCOMPARE(how->currentText(), QString("Smooth"));
    QTest::keyClick(how, Qt::Key_Down);
    QCOMPARE(keys->keys()[0].interpolation, KeyInterpolation::Linear);
    QCOMPARE(undo->index(), undo0 + 2);
    QVERIFY2(list->item(0)->text().contains("linear") && list->item(1)->text().contains("constant"),
             qPrintable(list->item(0)->text() + " | " + list->item(1)->text()));
    list->setCurrentRow(1);
    QCOMPARE(how->currentText(), QString("Constant (hold)"));
    // The clip from the keys: straight up to the lift over the first second, held through the second, then the
    // snap back to rest at 2 s.
    QVERIFY(keys->makeClip(false));
    const ClipLibrary& library = w.document()->project().clips;
    auto frames = evaluateClip(w.document()->scene(), library, library.clips.back());
    QVERIFY2(frames.ok(), frames.message().c_str());
    const double fps = library.clips.back().fps;
    const int count = int(frames->nodes.size());
    QVERIFY(count >= int(2 * fps));
    for (int f = 0; f < count; ++f) {
        const double t = f / fps;
        const Vec3 expected = rest[0] + (t <= 1.0 ? t * lift : t < 2.0 - 1e-9 ? lift : Vec3::Zero().eval());
        const double off = (frames->nodes[std::size_t(f)][0][0] - expected).norm();
        QVERIFY2(off < 1e-9, qPrintable(QString("frame %1 (%2 s) is %3 m off").arg(f).arg(t).arg(off)));
    }
    // Undo takes both choices back: the clip, then the linear key, then the held key.
    undo->undo();
    undo->undo();
    undo->undo();
    QCOMPARE(undo->index(), undo0);
    QCOMPARE(keys->keys()[0].interpolation, KeyInterpolation::Smooth);
    QCOMPARE(keys->keys()[1].interpolation, KeyInterpolation::Smooth);
}

// A take's in/out range, trimmed by dragging its ends on the ruler, is what "Clip from take" cuts: the clip
// starts at the in frame and its exported cache holds out - in frames, the first one the take's state at in.
void TestEditor::trimmedTakeClipExportsItsRange() {
    MainWindow& w = *m_window;
    SimulationController* sim = w.simulation();
    FrameRuler* ruler = w.timeline()->ruler();
    sim->startRecording();
    sim->pause();
    sim->advance(1.0);
    QVERIFY(sim->stopRecording().has_value());
    auto* takes = w.timeline()->findChild<QListWidget*>("takes");
    takes->setCurrentRow(0);
    const double fps = w.timeline()->fps();
    const int last = ruler->lastFrame();
    QCOMPARE(last, int(std::floor(1.0 * fps + 1e-9)));
    QCOMPARE(ruler->inOut(), std::optional(std::pair(0, last)));
    const auto dragHandle = [&](int from, int to) {
        const QPoint a(int(std::lround(ruler->xOfFrame(from))), 29), b(int(std::lround(ruler->xOfFrame(to))), 29);
        QTest::mousePress(ruler, Qt::LeftButton, {}, a);
        QTest::mouseMove(ruler, b);
        QTest::mouseRelease(ruler, Qt::LeftButton, {}, b);
    };
    dragHandle(0, 6);
    dragHandle(last, last - 6);
    QCOMPARE(ruler->inOut(), std::optional(std::pair(6, last - 6)));
    const std::size_t before = w.document()->project().clips.clips.size();
    QPushButton* cut = nullptr;
    for (auto* b : w.timeline()->findChildren<QPushButton*>())
        if (b->text() == "Clip from take")
            cut = b;
    QVERIFY(cut);
    cut->click();
    QCOMPARE(w.document()->project().clips.clips.size(), before + 1);
    const Clip clip = w.document()->project().clips.clips.back();
    QCOMPARE(clip.frames, last - 12);
    QCOMPARE(clip.startSeconds, 6.0 / fps);
    // Back on the take, the clip cut from it is a range on the ruler.
    takes->setCurrentRow(0);
    QCOMPARE(ruler->ranges().size(), std::size_t(1));
    QCOMPARE(ruler->ranges()[0].label, QString::fromStdString(clip.name));
    QCOMPARE(ruler->ranges()[0].fromSeconds, clip.startSeconds);
    QCOMPARE(ruler->ranges()[0].toSeconds, clip.startSeconds + clip.seconds());
    // Exported: out - in frames, the first the take's state at the in frame, shown by the take's scrub.
    const QString pc2 = m_dir->filePath("trimmed.pc2");
    const Status exported = w.timeline()->exportClipTo(int(before), pc2);
    QVERIFY2(exported.ok(), exported.message().c_str());
    auto cache = io::readPc2(pc2.toStdString());
    QVERIFY2(cache.ok(), cache.message().c_str());
    QCOMPARE(int(cache->frames.size()), last - 12);
    w.timeline()->scrubTo(0, 6);
    const std::vector<Vec3f> atIn = w.viewport()->deformedPositions(0);
    QVERIFY2(maxDistance(cache->frames.front(), atIn) < 1e-5, qPrintable(QString::number(maxDistance(cache->frames.front(), atIn))));
}

// Clips from the timeline's list: rename (a taken name is refused), duplicate, retime to another frame rate
// over the same seconds, delete with the Delete key, each one undo step; the transport plays the selected
// clip in a loop and steps frames.
void TestEditor::clipsRenameDuplicateRetimeDeleteAndPlay() {
    MainWindow& w = *m_window;
    TimelinePanel* timeline = w.timeline();
    QUndoStack* undo = w.document()->undoStack();
    const auto clips = [&] { return w.document()->project().clips.clips; };
    auto* list = timeline->findChild<QListWidget*>("clips");
    QVERIFY(!clips().empty());
    const Clip swim = clips().front();
    const int undo0 = undo->index();
    QVERIFY(timeline->renameClip(0, "cruise"));
    QCOMPARE(clips().front().name, std::string("cruise"));
    QVERIFY(timeline->duplicateClip(0));
    QCOMPARE(clips()[1].name, std::string("cruise copy"));
    QVERIFY(!timeline->renameClip(1, "cruise"));  // taken
    QVERIFY2(timeline->statusText().contains("already a clip named"), qPrintable(timeline->statusText()));
    QVERIFY(!timeline->renameClip(1, "  "));
    QVERIFY(timeline->retimeClip(1, 2.0 * swim.fps));
    QCOMPARE(clips()[1].fps, 2.0 * swim.fps);
    QCOMPARE(clips()[1].frames, 2 * swim.frames);
    QCOMPARE(clips()[1].seconds(), swim.seconds());
    QCOMPARE(clips()[1].blendFrames, 2 * swim.blendFrames);
    QCOMPARE(undo->index(), undo0 + 3);
    list->setCurrentRow(1);
    list->setFocus();
    QTest::keyClick(list, Qt::Key_Delete);
    QCOMPARE(clips().size(), std::size_t(1));
    QCOMPARE(undo->index(), undo0 + 4);

    // Play: the selected clip advances at its rate and wraps in a loop; the steps move one frame.
    list->setCurrentRow(0);
    FrameRuler* ruler = timeline->ruler();
    QCOMPARE(ruler->lastFrame(), swim.frames - 1);
    timeline->findChild<QPushButton*>("playClip")->click();
    QVERIFY(timeline->isPlaying());
    // The transport's glyphs, pause included, are in the buttons' font: none is drawn as an empty box.
    for (const char* name : {"firstFrame", "stepBack", "playClip", "stepForward"}) {
        const auto* button = timeline->findChild<QPushButton*>(name);
        QVERIFY2(button, name);
        const QFontMetrics metrics(button->font());
        for (const char32_t c : button->text().toUcs4())
            QVERIFY2(metrics.inFontUcs4(c), qPrintable(QString("%1: U+%2").arg(name).arg(uint(c), 4, 16, QChar('0'))));
    }
    timeline->advancePlayback(0.5);
    QCOMPARE(ruler->frame(), int(0.5 * swim.fps));
    const auto shown = w.simulation()->simulation()->simulator(0).state().position;
    QVERIFY(shown == evaluateClip(w.document()->scene(), w.document()->project().clips, clips()[0]).value().nodes[std::size_t(ruler->frame())][0]);
    timeline->advancePlayback(swim.seconds());  // once round: the same frame again
    QCOMPARE(ruler->frame(), int(0.5 * swim.fps));
    timeline->findChild<QPushButton*>("playClip")->click();
    QVERIFY(!timeline->isPlaying());
    timeline->findChild<QPushButton*>("stepForward")->click();
    QCOMPARE(ruler->frame(), int(0.5 * swim.fps) + 1);
    timeline->findChild<QPushButton*>("firstFrame")->click();
    timeline->findChild<QPushButton*>("stepBack")->click();
    QCOMPARE(ruler->frame(), swim.frames - 1);  // looping: back from the first frame is the last

    while (undo->index() > undo0)
        undo->undo();
    QCOMPARE(clips().size(), std::size_t(1));
    QCOMPARE(clips().front().name, swim.name);
}

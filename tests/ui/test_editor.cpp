// The editor driven through its real widgets (under Xvfb): the default scene opens, a brush stroke is
// one undo step, anchors are set by clicking nodes, a mouse drag pulls the fish and it swings back,
// projects survive save and reopen, an autosave survives a killed session, a corrupt project gives
// an error dialog, the speed/accuracy dock measures the open scene and applies its pick, and the
// viewport draws the fish in shaded and wireframe modes.
#include "core/geometry/mesh_surface.h"
#include "io/documents/trajectory_file.h"
#include "io/export/vertex_cache.h"
#include "io/export/video_encoder.h"
#include "io/import/gltf_meshopt.h"
#include "io/pipeline/bake.h"
#include "io/pipeline/reference_cache.h"
#include "ui/edit_commands.h"
#include "ui/frame_ruler.h"
#include "ui/haptic_controller.h"
#include "ui/keyframe_panel.h"
#include "ui/main_window.h"
#include "ui/presets_panel.h"
#include "ui/properties_panel.h"
#include "ui/study_chart_view.h"
#include "ui/study_panel.h"
#include "ui/take_dialog.h"
#include "ui/timeline_panel.h"
#include "ui/tool_options_bar.h"

#include <QAbstractButton>
#include <QAction>
#include <QCheckBox>
#include <QListWidget>
#include <QApplication>
#include <QScrollArea>
#include <QScrollBar>
#include <QWheelEvent>
#include <QAbstractSpinBox>
#include <QSlider>
#include <QStackedWidget>
#include <QLineEdit>
#include <QDir>
#include <QFileDialog>
#include <QFileInfo>
#include <QElapsedTimer>
#include <QFile>
#include <QMessageBox>
#include <QProcess>
#include <QPushButton>
#include <QSettings>
#include <QStandardItemModel>
#include <QStandardPaths>
#include <QSurfaceFormat>
#include <QTabletEvent>
#include <QTemporaryDir>
#include <QStatusBar>
#include <QTimer>
#include <QtTest/QtTest>

#include <Eigen/Geometry>

#include <memory>
#include <numbers>

#include "../cli/cli_run.h"
#include "../io/rigged_gltf.h"
#include "core/geometry/primitives.h"
#include "core/modes/modes.h"
#include "core/modes/solid_modes.h"
#include "ui/material_tuning.h"

#include <QComboBox>
#include <QDialog>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QLabel>
#include <QRegularExpression>
#include <QTreeWidget>

using namespace softtouch;
using namespace softtouch::test;
using namespace softtouch::ui;

namespace {

/// Longest wait for a measurement of the speed/accuracy dock: seconds in a release build, about 100 s
/// under the sanitizers.
constexpr int kStudyWaitMs = 300000;

const QString kDefaultScene = QStringLiteral(SOFTTOUCH_SOURCE_DIR "/presets/scenes/angelfish-swim.softtouch");

/// Clicks `button` of the next modal message box and returns its text (the dialog is modal, so
/// the click has to come from a timer while exec() runs).
class DialogAnswerer : public QObject {
public:
    explicit DialogAnswerer(QMessageBox::StandardButton button) : m_button(button) {
        QTimer::singleShot(50, this, &DialogAnswerer::poll);
    }
    QString text;
    bool seen = false;

private:
    void poll() {
        if (auto* box = qobject_cast<QMessageBox*>(QApplication::activeModalWidget())) {
            seen = true;
            text = box->text();
            box->button(m_button)->click();
            return;
        }
        QTimer::singleShot(50, this, &DialogAnswerer::poll);
    }
    QMessageBox::StandardButton m_button;
};

/// Largest distance between two vertex sets.
double maxDistance(const std::vector<Vec3f>& a, const std::vector<Vec3f>& b) {
    double d = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i)
        d = std::max(d, double((a[i] - b[i]).norm()));
    return d;
}

bool sameMaterial(const LatticeMaterial& a, const LatticeMaterial& b) {
    return a.mass == b.mass && a.stiffness == b.stiffness && a.damping == b.damping && a.nodeDamping == b.nodeDamping &&
           a.anchor == b.anchor && a.isVoid == b.isVoid && a.anisotropy == b.anisotropy && a.kindScale == b.kindScale &&
           a.volumePreservation == b.volumePreservation;
}

/// Fraction of pixels inside `region` that differ from the background of their row (the background
/// is a vertical gradient, sampled at the left edge).
double coverage(const QImage& image, const QRect& region) {
    int differ = 0, total = 0;
    for (int y = std::max(region.top(), 0); y <= std::min(region.bottom(), image.height() - 1); ++y) {
        const QColor background = image.pixelColor(1, y);
        for (int x = std::max(region.left(), 0); x <= std::min(region.right(), image.width() - 1); ++x) {
            const QColor c = image.pixelColor(x, y);
            const int d = std::abs(c.red() - background.red()) + std::abs(c.green() - background.green()) +
                          std::abs(c.blue() - background.blue());
            differ += d > 24 ? 1 : 0;
            ++total;
        }
    }
    return total > 0 ? double(differ) / total : 0.0;
}

/// One brush stroke across the middle of the viewport: press, six moves of 20 px, release, with the
/// brush at strength 0.8 and an 80 px radius (the field and value are the caller's).
void paintStroke(Viewport* view) {
    view->brush().strength = 0.8;
    view->brush().radiusPixels = 80.0;
    const QPoint start = view->rect().center() - QPoint(60, 0);
    QTest::mousePress(view, Qt::LeftButton, {}, start);
    for (int i = 1; i <= 6; ++i)
        QTest::mouseMove(view, start + QPoint(20 * i, 0));
    QTest::mouseRelease(view, Qt::LeftButton, {}, start + QPoint(120, 0));
}

/// The properties panel analyses the modes off the UI thread: waits until the latest edit's are shown.
void waitForModes(MainWindow& w) {
    auto* modes = w.findChild<QLabel*>("modes");
    QVERIFY(modes);
    QTRY_VERIFY_WITH_TIMEOUT(!modes->property("analysing").toBool(), 30000);
}

}  // namespace

class TestEditor : public QObject {
    Q_OBJECT
private slots:
    void initTestCase();
    void init();
    void cleanup();
    void opensDefaultScene();
    void clipPreviewFollowsAMaterialEdit();
    void paintStrokeIsOneUndoStep();
    void modesFollowAStrokeOffTheUiThread();
    void redoWithCtrlYAndCtrlShiftZ();
    void paintsNodeDamping();
    void fixedColourRangeKeepsOneColourPerValue();
    void toolOptionsFollowTheActiveTool();
    void renderVideoFollowsTheViewportsView();
    void fileNewStartsAnUntitledProject();
    void paintsVolumePreservation();
    void strainLimitsFromTheProperties();
    void rockSceneListsItsCollider();
    void importAnimatedMeshAddsAFollowingObject();
    void takeDialogChoosesTheTakeAndItsRange();
    void anchorToolPinsAClickedNode();
    void latticeToolMovesAndScalesTheBox();
    void poseToolMovesRotatesScalesAndKeys();
    void poseAsRestShapeSavesAndUndoes();
    void poseGizmoScalesAndTurns();
    void objectsAddDuplicatePickAndDelete();
    void colliderToolAddsMovesScalesAndDeletes();
    void openMeshColliderIsOfferedAsOneSided();
    void pairSceneTogglesBodyCollisions();
    void mouseDragPullsAndReleaseSwingsBack();
    void restingFishIsNotRedrawn();
    void secondHandHoldsAndPenPressureScalesTheSpring();
    void saveAndReopenGivesTheSameScene();
    void recoversAutosaveAfterKill();
    void recoversAutosaveAfterRealKill();
    void corruptProjectShowsErrorAndEditorStaysUsable();
    void presetAppliesAsOneUndoStep();
    void recordedTakeScrubsAndExports();
    void exportDialogsPackAGlbForShipping();
    void keyframesFromPosesMakeAClip();
    void rulerTicksRetimeCopyAndDeleteKeys();
    void trimmedTakeClipExportsItsRange();
    void clipsRenameDuplicateRetimeDeleteAndPlay();
    void scriptedDeviceDrivesTheFishAtHapticRate();
    void studyDockMeasuresTheOpenSceneAndAppliesAPick();
    void studyDockCancelsAndStopsWithTheWindow();
    void propertiesShowTheBodysModes();
    void propertiesCompareTheLatticeWithTheSolid();
    void wheelScrollsPropertiesWithoutEditing();
    void elementChoiceRunsTheSolidAndSaysWhatItCannot();
    void modeViewAnimatesTheShapeWithoutEditing();
    void importedMeshStartsOnVerletAndSavesIt();
    void viewportDrawsTheFish_data();
    void viewportDrawsTheFish();
    void screenshotCommandWritesPng();
    void editorWithoutADisplaySaysWhatToDo();
    void propertiesFieldsFitTheDock_data();
    void propertiesFieldsFitTheDock();

private:
    std::unique_ptr<MainWindow> makeWindow();
    /// Readies the window for posing: active and focused on the viewport (keys reach it), the drivers
    /// off and the body at rest, the pose tool picked. Returns the viewport.
    Viewport* startPosing(MainWindow& w) const;
    QPoint screenOfNode(MainWindow& w, int node) const;
    int isolatedNode(MainWindow& w, int object) const;

    std::unique_ptr<QTemporaryDir> m_dir;
    std::unique_ptr<MainWindow> m_window;
};

void TestEditor::initTestCase() {
    QStandardPaths::setTestModeEnabled(true);
    QApplication::setOrganizationName("SoftTouchTests");
    QApplication::setApplicationName("test_editor");
}

void TestEditor::init() {
    m_dir = std::make_unique<QTemporaryDir>();
    QVERIFY(m_dir->isValid());
    QSettings().clear();
    m_window = makeWindow();
    QVERIFY(m_window->openFile(kDefaultScene));
    m_window->simulation()->pause();  // tests advance time themselves
}

void TestEditor::cleanup() {
    if (m_window)
        m_window->document()->undoStack()->setClean();  // no unsaved-changes prompt on close
    m_window.reset();
    m_dir.reset();
}

std::unique_ptr<MainWindow> TestEditor::makeWindow() {
    MainWindowOptions options;
    options.autosaveFolder = m_dir->filePath("autosave");
    options.autosaveMilliseconds = 100;
    options.presetFolder = QStringLiteral(SOFTTOUCH_SOURCE_DIR "/presets/materials");
    auto w = std::make_unique<MainWindow>(options);
    w->resize(1280, 800);
    w->show();
    if (!QTest::qWaitForWindowExposed(w.get()))
        qWarning("window not exposed");
    return w;
}

Viewport* TestEditor::startPosing(MainWindow& w) const {
    w.activateWindow();
    if (!QTest::qWaitForWindowActive(&w))
        qWarning("window not active");
    w.simulation()->setDriversEnabled(false);
    w.simulation()->reset();
    w.findChild<QAction*>("toolPose")->trigger();
    w.viewport()->setFocus();
    return w.viewport();
}

QPoint TestEditor::screenOfNode(MainWindow& w, int node) const {
    const auto& x = w.simulation()->simulation()->simulator(0).state().position;
    return w.viewport()->toWidget(x[std::size_t(node)]).toPoint();
}

int TestEditor::isolatedNode(MainWindow& w, int object) const {
    // A node whose screen position is far from every other node's, so a click picks it unambiguously.
    const auto& x = w.simulation()->simulation()->simulator(std::size_t(object)).state().position;
    int best = -1;
    double bestGap = 0.0;
    for (std::size_t n = 0; n < x.size(); ++n) {
        const QPointF p = w.viewport()->toWidget(x[n]);
        if (!w.viewport()->rect().adjusted(20, 20, -20, -20).contains(p.toPoint()))
            continue;
        double gap = 1e9;
        for (std::size_t m = 0; m < x.size(); ++m)
            if (m != n)
                gap = std::min(gap, QLineF(p, w.viewport()->toWidget(x[m])).length());
        if (gap > bestGap && w.document()->scene().objects[0].material.anchor[n] == AnchorMode::Free) {
            bestGap = gap;
            best = int(n);
        }
    }
    return bestGap > 4.0 ? best : -1;
}

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
    // Play says what it does next and is never shown checked.
    QAction* play = w.findChild<QAction*>("actionPlay");
    QVERIFY(!play->isCheckable());
    w.simulation()->play();
    QCOMPARE(play->text(), QString("Pause"));
    w.simulation()->pause();
    QCOMPARE(play->text(), QString("Play"));
}

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

// The rock scene opens with its collider in the Outliner (shape, size, where) and the running body tests
// contact at the fish's surface points.
void TestEditor::rockSceneListsItsCollider() {
    MainWindow& w = *m_window;
    QVERIFY(w.openFile(QStringLiteral(SOFTTOUCH_SOURCE_DIR "/presets/scenes/angelfish-rock.softtouch")));
    auto* outliner = w.findChild<QTreeWidget*>("outliner");
    QVERIFY(outliner);
    const auto found = outliner->findItems("Colliders", Qt::MatchExactly);
    QCOMPARE(found.size(), 1);
    QCOMPARE(found[0]->text(1), QString("1"));
    QCOMPARE(found[0]->childCount(), 1);
    QCOMPARE(found[0]->child(0)->text(0), QString("sphere 1"));
    QVERIFY2(found[0]->child(0)->text(1).startsWith("r 0.2 m at (-0.42, 0, 0.3)"), qPrintable(found[0]->child(0)->text(1)));
    QVERIFY(w.simulation()->simulation()->simulator(0).model().contacts().size() > 100);
    // A scene without colliders lists none.
    QVERIFY(w.openFile(kDefaultScene));
    QVERIFY(outliner->findItems("Colliders", Qt::MatchExactly).isEmpty());
}

// File ▸ Import Animated Mesh adds an object beside the open one (one undo step) that plays its file's own
// animation with secondary motion on top: as the simulation runs, the viewport's mesh follows the swim; the
// goal weight is painted like the material.
void TestEditor::takeDialogChoosesTheTakeAndItsRange() {
    // A rig with two takes: the rigged guppy's swim and a dash (the swim twice as fast, 0.5 s). File ▸ Import
    // Animated Mesh lists both; the user picks the dash, 0.1 to 0.4 s of it, played once.
    const QString two = m_dir->filePath("two-takes.glb");
    QVERIFY(softtouch::test::writeWithSecondTake(SOFTTOUCH_SOURCE_DIR "/presets/meshes/guppy-rigged.glb", two.toStdString(),
                                                 "dash", 2.0));
    auto takes = io::animationTakes(two.toStdString());
    QVERIFY2(takes, takes.message().c_str());
    TakeDialog dialog(takes.value(), "two-takes.glb");
    auto* take = dialog.findChild<QComboBox*>("animationTake");
    auto* start = dialog.findChild<QDoubleSpinBox*>("animationStart");
    auto* end = dialog.findChild<QDoubleSpinBox*>("animationEnd");
    auto* loop = dialog.findChild<QCheckBox*>("animationLoop");
    QVERIFY(take && start && end && loop);
    QCOMPARE(take->count(), 2);
    QCOMPARE(take->itemText(0), QString("swim (1 s)"));
    QCOMPARE(take->itemText(1), QString("dash (0.5 s)"));
    // As it opens: the first take, whole and looping, which is what an import without the dialog does.
    io::AnimationRequest whole = dialog.request();
    QCOMPARE(QString::fromStdString(whole.take), QString("swim"));
    QVERIFY(whole.start == 0.0 && whole.end < 0.0 && whole.loop);
    take->setCurrentIndex(1);
    QCOMPARE(end->value(), 0.5);
    QCOMPARE(end->maximum(), 0.5);
    start->setValue(0.1);
    end->setValue(0.4);
    loop->setChecked(false);
    end->setValue(0.05);  // the range stays a range: the end keeps clear of the start
    QVERIFY(end->value() > start->value());
    end->setValue(0.4);
    const io::AnimationRequest part = dialog.request();
    QCOMPARE(QString::fromStdString(part.take), QString("dash"));
    QCOMPARE(part.start, 0.1);
    QCOMPARE(part.end, 0.4);
    QVERIFY(!part.loop);

    // A take is chosen by name: an unnamed take after the first, or a second take of one name, cannot be.
    TakeDialog clashing({{"", 1.0}, {"", 2.0}, {"swim", 1.0}, {"swim", 3.0}}, "clash.glb");
    auto* listed = qobject_cast<QStandardItemModel*>(clashing.findChild<QComboBox*>("animationTake")->model());
    QVERIFY(listed);
    QCOMPARE(listed->rowCount(), 4);
    for (int t = 0; t < 4; ++t)
        QCOMPARE(listed->item(t)->isEnabled(), t == 0 || t == 2);

    MainWindow& w = *m_window;
    QVERIFY(w.importAnimatedMeshFile(two, part).ok());
    const SceneObject& dash = w.document()->scene().objects.back();
    QVERIFY(dash.baseAnimation);
    QCOMPARE(QString::fromStdString(dash.baseAnimation->take), QString("dash"));
    QCOMPARE(dash.baseAnimation->start, 0.1);
    QVERIFY(!dash.baseAnimation->loop);
    QVERIFY2(std::abs(dash.baseAnimation->duration() - 0.3) < 1e-9, qPrintable(QString::number(dash.baseAnimation->duration())));
    QVERIFY2(w.statusBar()->currentMessage().contains("take \"dash\", 0.3 s"), qPrintable(w.statusBar()->currentMessage()));
    // The choice is the project's: saved and opened again, the object plays the same part of the same take.
    const std::size_t samples = dash.baseAnimation->samples.size();  // `dash` goes with the document opened next
    const QString saved = m_dir->filePath("dash.softtouch");
    QVERIFY(w.document()->saveAs(saved).ok());
    QVERIFY(w.openFile(saved));
    const SceneObject& reopened = w.document()->scene().objects.back();
    QVERIFY(reopened.baseAnimation);
    QCOMPARE(QString::fromStdString(reopened.baseAnimation->take), QString("dash"));
    QCOMPARE(reopened.baseAnimation->start, 0.1);
    QVERIFY(!reopened.baseAnimation->loop);
    QCOMPARE(reopened.baseAnimation->samples.size(), samples);
}

void TestEditor::importAnimatedMeshAddsAFollowingObject() {
    MainWindow& w = *m_window;
    QVERIFY(w.openFile(kDefaultScene));
    QVERIFY(w.findChild<QAction*>("importAnimatedMesh"));
    const int undoBefore = w.document()->undoStack()->index();
    QVERIFY(w.importAnimatedMeshFile(QStringLiteral(SOFTTOUCH_SOURCE_DIR "/presets/meshes/guppy-rigged.glb")).ok());
    QCOMPARE(w.document()->scene().objects.size(), std::size_t(2));
    QCOMPARE(w.document()->undoStack()->index(), undoBefore + 1);
    const SceneObject& guppy = w.document()->scene().objects[1];
    QVERIFY(guppy.baseAnimation);
    QCOMPARE(QString::fromStdString(guppy.baseAnimation->take), QString("swim"));
    QCOMPARE(guppy.material.goalWeight, std::vector<double>(guppy.material.mass.size(), 0.5));
    QVERIFY(w.simulation()->simulation()->followsBaseAnimation(1));
    QVERIFY2(w.statusBar()->currentMessage().contains("take \"swim\""), qPrintable(w.statusBar()->currentMessage()));
    const auto listed = w.findChild<QTreeWidget*>("outliner")->findItems("Base animation", Qt::MatchExactly | Qt::MatchRecursive);
    QCOMPARE(listed.size(), 1);
    QCOMPARE(listed[0]->text(1), QString("\"swim\", 1 s, loops"));
    auto* range = w.findChild<QLabel*>("baseAnimationRange");
    QVERIFY(range && range->isVisibleTo(&w));
    QCOMPARE(range->text(), QString("Base animation: guppy-rigged follows \"swim\" from 0 to 1 s of its take, looping"));
    // The ruler shows the looping base animation cycle by cycle over its span, so its loop points show.
    {
        const FrameRuler* ruler = w.timeline()->ruler();
        const double span = ruler->lastFrame() / ruler->fps();
        const auto& ranges = ruler->ranges();
        QCOMPARE(int(ranges.size()), int(std::floor(span / 1.0)) + 1);
        for (std::size_t k = 0; k < ranges.size(); ++k) {
            QCOMPARE(ranges[k].label, QString("base: swim"));
            QCOMPARE(ranges[k].fromSeconds, double(k));
            QCOMPARE(ranges[k].toSeconds, double(k + 1));
        }
    }
    // It plays: a quarter of a second later the tail has swung.
    const std::vector<Vec3f> before = w.viewport()->deformedPositions(1);
    w.simulation()->advance(0.25);
    const std::vector<Vec3f> after = w.viewport()->deformedPositions(1);
    double moved = 0.0;
    for (std::size_t v = 0; v < before.size(); ++v)
        moved = std::max(moved, double((after[v] - before[v]).norm()));
    QVERIFY2(moved > 0.05, qPrintable(QString("the swim moved the mesh by %1 m").arg(moved)));
    // On goal weight ½ everywhere its lowest mode is the whole fish swinging on its goal springs, at their
    // 2 Hz whatever its material: typing another wobble frequency leaves the material as it was. On the
    // sample's painted goals (head pinned, spine 0.7, belly and tail loose) the material decides, and a
    // typed frequency lands its lowest mode, goal springs included.
    {
        QCOMPARE(objectModes(guppy, 1)->modes.front().frequencyHz, 2.0);
        LatticeMaterial tuned = guppy.material;
        QVERIFY(!setFrequency(guppy.lattice, tuned, 3.0, &guppy.follow));
        QCOMPARE(tuned.stiffness, guppy.material.stiffness);
        auto sample = io::loadProject(SOFTTOUCH_SOURCE_DIR "/presets/scenes/guppy-rigged.softtouch");
        QVERIFY(sample.ok());
        const SceneObject& painted = sample->scene.objects[0];
        const double was = objectModes(painted, 1)->modes.front().frequencyHz;
        tuned = painted.material;
        QVERIFY(setFrequency(painted.lattice, tuned, 1.5 * was, &painted.follow));
        SceneObject retuned = painted;
        retuned.material = tuned;
        const double landed = objectModes(retuned, 1)->modes.front().frequencyHz;
        qInfo("lowest mode with its goal springs %.4f Hz, typed %.4f Hz, lands at %.4f Hz", was, 1.5 * was, landed);
        QVERIFY(std::abs(landed / (1.5 * was) - 1.0) < 1e-3);
    }
    // The goal weight is a Paint field.
    auto* field = w.findChild<QComboBox*>("brushField");
    QVERIFY(field && field->findData(int(PaintField::GoalWeight)) >= 0);
    w.document()->undoStack()->undo();
    QCOMPARE(w.document()->scene().objects.size(), std::size_t(1));
    // A still mesh is refused, saying why (in an error box, closed here once it shows).
    QString shown;
    QTimer::singleShot(200, [&shown] {
        if (auto* box = qobject_cast<QMessageBox*>(QApplication::activeModalWidget())) {
            shown = box->text();
            box->accept();
        }
    });
    QVERIFY(!w.importAnimatedMeshFile(QStringLiteral(SOFTTOUCH_SOURCE_DIR "/presets/meshes/guppy.obj")).ok());
    QVERIFY2(shown.contains("has no animation"), qPrintable(shown));
    QCOMPARE(w.document()->scene().objects.size(), std::size_t(1));
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

// File ▸ New (Ctrl+N): an untitled project from the bundled fish mesh, a fresh lattice and material,
// nothing to undo; Save then asks where.
void TestEditor::fileNewStartsAnUntitledProject() {
    MainWindow& w = *m_window;
    QAction* action = w.findChild<QAction*>("actionNew");
    QVERIFY(action);
    QCOMPARE(action->shortcut(), QKeySequence(QKeySequence::New));
    QVERIFY(!w.document()->filePath().isEmpty());
    const std::size_t clipsBefore = w.document()->project().clips.clips.size();
    QVERIFY(clipsBefore > 0);
    action->trigger();
    const Scene& scene = w.document()->scene();
    QCOMPARE(scene.objects.size(), std::size_t(1));
    QCOMPARE(QString::fromStdString(scene.objects[0].name), QString("angelfish"));
    QVERIFY(w.document()->filePath().isEmpty());
    QVERIFY(w.windowTitle().contains("unsaved"));
    QVERIFY(w.document()->project().clips.clips.empty());  // the swim clip was the old project's
    QVERIFY(!w.document()->undoStack()->canUndo());
    QCOMPARE(scene.objects[0].lattice.count(0), 4);
    QVERIFY(scene.objects[0].drivers.empty());
    // It is a working project: it saves and opens again.
    const QString path = m_dir->filePath("new.softtouch");
    QVERIFY(w.document()->saveAs(path).ok());
    QVERIFY(w.openFile(path));
    QCOMPARE(w.document()->scene().objects.size(), std::size_t(1));
}

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
    const NamedKeyframes* set = w.document()->project().clips.findKeyframes(KeyframePanel::kSetName);
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

// Several objects (#15 item 3): File ▸ Add Mesh puts a guppy beside the angelfish (it overlapped it where
// its file puts it) and makes it current, the outliner following; Edit ▸ Duplicate Object copies it along x;
// a double-click on the angelfish makes it current again; Edit ▸ Delete Object removes the copy. The take and
// the keys recorded before stay valid through every step (the objects are added to and removed from them),
// and the project saved with three objects reopens with them where they were.
void TestEditor::objectsAddDuplicatePickAndDelete() {
    MainWindow& w = *m_window;
    SimulationController* sim = w.simulation();
    Viewport* view = w.viewport();
    QUndoStack* undo = w.document()->undoStack();
    sim->setDriversEnabled(false);
    sim->startRecording();
    sim->pause();
    sim->advance(0.25);
    QVERIFY(sim->stopRecording().has_value());
    QVERIFY(w.keyframes()->keyPose(0.0));
    const int undo0 = undo->index();
    const auto fits = [&] { return w.document()->project().clips.validate(w.document()->scene()); };
    auto* outliner = w.findChild<QTreeWidget*>("outliner");

    const QString guppy = QStringLiteral(SOFTTOUCH_SOURCE_DIR "/presets/meshes/guppy.obj");
    QVERIFY(w.addMeshFile(guppy).ok());
    const Scene& scene = w.document()->scene();
    QCOMPARE(scene.objects.size(), std::size_t(2));
    QCOMPARE(scene.objects[1].name, std::string("guppy"));
    QCOMPARE(undo->index(), undo0 + 1);
    QCOMPARE(view->currentObject(), 1);
    QCOMPARE(outliner->currentItem()->text(0), QString("guppy"));
    QVERIFY(scene.objects[1].mesh->bounds().min.x() > scene.objects[0].mesh->bounds().max.x());  // beside, not inside
    QVERIFY2(fits().ok(), fits().message().c_str());
    QCOMPARE(w.document()->project().clips.sessions[0].session.start.bodies.size(), std::size_t(2));
    w.timeline()->scrubTo(0, 3);  // the take replays with the guppy at rest
    QVERIFY2(w.timeline()->statusText().contains("frame 3"), qPrintable(w.timeline()->statusText()));

    w.findChild<QAction*>("actionDuplicateObject")->trigger();
    QCOMPARE(scene.objects.size(), std::size_t(3));
    QCOMPARE(scene.objects[2].name, std::string("guppy 2"));
    QCOMPARE(view->currentObject(), 2);
    const float shift = scene.objects[2].mesh->positions[0].x() - scene.objects[1].mesh->positions[0].x();
    QVERIFY(shift > 0.0f);
    for (std::size_t v = 0; v < scene.objects[1].mesh->positions.size(); v += 97)
        QVERIFY((scene.objects[2].mesh->positions[v] - scene.objects[1].mesh->positions[v] - Vec3f(shift, 0, 0)).norm() < 1e-5f);
    QVERIFY2(fits().ok(), fits().message().c_str());

    // The swim clip exported with each object in its own cache, and as one OBJ sequence with a group per object.
    const int swim = 0;
    QVERIFY(w.document()->project().clips.clips[std::size_t(swim)].name == "swim");
    const Status each = w.timeline()->exportClipTo(swim, m_dir->filePath("swim.pc2"), *io::findExportFormat("pc2"),
                                                   ExportChoices{{}, true, false, false});
    QVERIFY2(each.ok(), each.message().c_str());
    for (std::size_t i = 0; i < 3; ++i) {
        const QString file = QString::fromStdString(io::perObjectPath((m_dir->filePath("swim.pc2")).toStdString(), scene.objects[i].name).string());
        auto cache = io::readPc2(file.toStdString());
        QVERIFY2(cache.ok(), qPrintable(file));
        QCOMPARE(cache->info.pointCount, scene.objects[i].mesh->positions.size());
    }
    QVERIFY2(w.timeline()->statusText().contains("swim-guppy_2.pc2"), qPrintable(w.timeline()->statusText()));
    QDir(m_dir->path()).mkdir("seq");
    const QString sequence = m_dir->filePath("seq/swim.obj");
    const Status grouped = w.timeline()->exportClipTo(swim, sequence, *io::findExportFormat("objseq"),
                                                      ExportChoices{{}, false, true, false});
    QVERIFY2(grouped.ok(), grouped.message().c_str());
    QFile first(QString::fromStdString(io::objSequenceFramePath(sequence.toStdString(), 0).string()));
    QVERIFY(first.open(QIODevice::ReadOnly));
    const QByteArray obj = first.readAll();
    QVERIFY(obj.contains("\ng angelfish\n") && obj.contains("\ng guppy\n") && obj.contains("\ng guppy_2\n"));

    // Saved with three objects and reopened: the same meshes in the same places.
    const QString path = m_dir->filePath("three.softtouch");
    QVERIFY(w.document()->saveAs(path).ok());
    Document reopened;
    QVERIFY(reopened.open(path).ok());
    QCOMPARE(reopened.scene().objects.size(), std::size_t(3));
    for (std::size_t i = 0; i < 3; ++i)
        QVERIFY(maxDistance(reopened.scene().objects[i].mesh->positions, scene.objects[i].mesh->positions) < 1e-6);

    // A double-click on the angelfish's front-most face makes it current.
    view->frameAll();
    const std::vector<Vec3f> fish = view->deformedPositions(0);
    const Vec3 eye = view->camera().eye();
    std::size_t front = 0;
    double nearest = 1e300;
    for (std::size_t t = 0; t < scene.objects[0].mesh->triangles.size(); ++t) {
        const auto& tri = scene.objects[0].mesh->triangles[t];
        const Vec3 centre = (fish[tri[0]] + fish[tri[1]] + fish[tri[2]]).cast<double>() / 3.0;
        if ((centre - eye).norm() < nearest) {
            nearest = (centre - eye).norm();
            front = t;
        }
    }
    const auto& tri = scene.objects[0].mesh->triangles[front];
    const QPoint at = view->toWidget((fish[tri[0]] + fish[tri[1]] + fish[tri[2]]).cast<double>() / 3.0).toPoint();
    QTest::mouseDClick(view, Qt::LeftButton, {}, at);
    QCOMPARE(view->currentObject(), 0);
    QCOMPARE(outliner->currentItem()->text(0), QString("angelfish"));

    view->setCurrentObject(2);
    w.findChild<QAction*>("actionDeleteObject")->trigger();
    QCOMPARE(scene.objects.size(), std::size_t(2));
    QCOMPARE(scene.objects[1].name, std::string("guppy"));
    QVERIFY2(fits().ok(), fits().message().c_str());
    QCOMPARE(w.document()->project().clips.keyframes[0].objects.size(), std::size_t(2));
    // The last object is never deleted.
    while (undo->index() > undo0)
        undo->undo();
    QCOMPARE(scene.objects.size(), std::size_t(1));
    QVERIFY(fits().ok());
    DialogAnswerer answer(QMessageBox::Ok);
    QVERIFY(!w.deleteCurrentObject().ok());
    QVERIFY(answer.seen);
    QCOMPARE(scene.objects.size(), std::size_t(1));
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

// Edit ▸ Add Collider puts a sphere below the fish and picks the collider tool; dragging it moves it with the
// cursor, Shift+drag scales it, Delete removes it, each one undo step; a mesh collider reads its file.
void TestEditor::colliderToolAddsMovesScalesAndDeletes() {
    MainWindow& w = *m_window;
    Viewport* view = w.viewport();
    const std::size_t before = w.document()->scene().world.colliders.size();
    w.findChild<QAction*>("actionAddSphereCollider")->trigger();
    const auto& colliders = [&]() -> const std::vector<Collider>& { return w.document()->scene().world.colliders; };
    QCOMPARE(colliders().size(), before + 1);
    QCOMPARE(view->tool(), Tool::Collider);
    QCOMPARE(view->currentCollider(), int(before));
    const Collider added = colliders().back();
    QCOMPARE(added.shape, ColliderShape::Sphere);
    const Bounds fish = w.document()->scene().objects[0].mesh->bounds();
    QVERIFY(added.centre.y() + added.radius < fish.min.y());  // below the fish, not touching it
    QTRY_VERIFY(view->isVisible());

    view->frameAll();
    const QPoint start = view->toWidget(added.centre).toPoint();
    const int undoBefore = w.document()->undoStack()->index();
    QTest::mousePress(view, Qt::LeftButton, {}, start);
    for (int i = 1; i <= 4; ++i)
        QTest::mouseMove(view, start + QPoint(10 * i, 0));
    QTest::mouseRelease(view, Qt::LeftButton, {}, start + QPoint(40, 0));
    const QPointF now = view->toWidget(colliders().back().centre);
    QVERIFY2(std::abs(now.x() - (start.x() + 40)) < 2.0 && std::abs(now.y() - start.y()) < 2.0,
             qPrintable(QString("centre at %1,%2").arg(now.x()).arg(now.y())));
    QCOMPARE(colliders().back().radius, added.radius);
    QCOMPARE(w.document()->undoStack()->index(), undoBefore + 1);

    QTest::mousePress(view, Qt::LeftButton, Qt::ShiftModifier, now.toPoint());
    QTest::mouseMove(view, now.toPoint() + QPoint(0, -40));
    QTest::mouseRelease(view, Qt::LeftButton, Qt::ShiftModifier, now.toPoint() + QPoint(0, -40));
    QVERIFY(colliders().back().radius > added.radius * 1.1);
    QCOMPARE(w.document()->undoStack()->index(), undoBefore + 2);

    QTest::keyClick(view, Qt::Key_Delete);
    QCOMPARE(colliders().size(), before);
    w.document()->undoStack()->undo();  // back, where it was scaled
    QCOMPARE(colliders().size(), before + 1);
    w.document()->undoStack()->undo();
    w.document()->undoStack()->undo();
    QVERIFY(colliders().back().centre == added.centre);

    // A mesh collider: an OBJ cube, scaled to half the fish's size, its top just below the fish.
    const QString cube = m_dir->filePath("cube.obj");
    QFile file(cube);
    QVERIFY(file.open(QIODevice::WriteOnly));
    file.write("v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
               "f 1 4 3\nf 1 3 2\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 4 8 7\nf 4 7 3\nf 1 5 8\nf 1 8 4\nf 2 3 7\nf 2 7 6\n");
    file.close();
    QVERIFY(w.addCollider(ColliderShape::Mesh, cube).ok());
    const Collider& rock = colliders().back();
    QCOMPARE(rock.shape, ColliderShape::Mesh);
    QCOMPARE(int(rock.surface->mesh().triangles.size()), 12);
    Vec3 n;
    QVERIFY(colliderDistance(rock, Vec3(0.5 * (fish.min.x() + fish.max.x()), fish.min.y(), 0.5 * (fish.min.z() + fish.max.z())), n) > 0.0);
    w.document()->undoStack()->undo();
    QCOMPARE(colliders().size(), before + 1);  // the sphere's own add is still done
    w.document()->undoStack()->undo();          // and the scene is as the next test expects it
    QCOMPARE(colliders().size(), before);
}

// An open mesh (a ground of two triangles) is not a solid: Add mesh collider says why and offers it as a
// one-sided surface. Declined, nothing is added; accepted, the collider pushes along the plane's normal and the
// project saves it as "oneSided": true.
void TestEditor::openMeshColliderIsOfferedAsOneSided() {
    MainWindow& w = *m_window;
    QVERIFY(w.openFile(kDefaultScene));
    const QString plane = m_dir->filePath("ground.obj");
    QFile file(plane);
    QVERIFY(file.open(QIODevice::WriteOnly));
    file.write("v -1 0 -1\nv -1 0 1\nv 1 0 1\nv 1 0 -1\nf 1 2 3\nf 1 3 4\n");
    file.close();
    const std::size_t before = w.document()->scene().world.colliders.size();
    {
        DialogAnswerer no(QMessageBox::No);
        QVERIFY(!w.addCollider(ColliderShape::Mesh, plane).ok());
        QVERIFY(no.seen);
        QVERIFY2(no.text.contains("4 open edges") && no.text.contains("one-sided"), qPrintable(no.text));
    }
    QCOMPARE(w.document()->scene().world.colliders.size(), before);
    DialogAnswerer yes(QMessageBox::Yes);
    QVERIFY(w.addCollider(ColliderShape::Mesh, plane).ok());
    QVERIFY(yes.seen);
    const Collider& ground = w.document()->scene().world.colliders.back();
    QCOMPARE(ground.surface->sides(), SurfaceSides::OneSided);
    Vec3 n;  // just behind the sheet, inside its rim: inside, pushed out along +y (the plane's normal, scaled)
    const Vec3 under = ground.centre + ground.axes * (ground.scale * Vec3(0.2, -0.01, 0.3));
    QVERIFY(colliderDistance(ground, under, n) < 0.0);
    QVERIFY((n - ground.axes * Vec3::UnitY()).norm() < 1e-6);
    const QString saved = m_dir->filePath("ground.softtouch");
    QVERIFY(w.document()->saveAs(saved).ok());
    QFile project(saved);
    QVERIFY(project.open(QIODevice::ReadOnly));
    QVERIFY(project.readAll().contains("\"oneSided\": true"));
    w.document()->undoStack()->undo();
    QCOMPARE(w.document()->scene().world.colliders.size(), before);
}

// The pair sample opens with its objects colliding (Properties and Outliner say so); the checkbox turns it
// off as one undo step. A scene of one object does not offer it.
void TestEditor::pairSceneTogglesBodyCollisions() {
    MainWindow& w = *m_window;
    QVERIFY(w.openFile(QStringLiteral(SOFTTOUCH_SOURCE_DIR "/presets/scenes/angelfish-pair.softtouch")));
    auto* box = w.findChild<QCheckBox*>("bodiesCollide");
    QVERIFY(box);
    QVERIFY(box->isVisibleTo(&w) && box->isChecked());
    auto* outliner = w.findChild<QTreeWidget*>("outliner");
    const auto row = outliner->findItems("Bodies collide", Qt::MatchExactly);
    QCOMPARE(row.size(), 1);
    QVERIFY(row[0]->text(1).startsWith("yes"));
    box->click();
    QVERIFY(!w.document()->scene().world.bodyCollisions.enabled);
    QVERIFY(outliner->findItems("Bodies collide", Qt::MatchExactly)[0]->text(1).startsWith("no"));
    w.document()->undoStack()->undo();
    QVERIFY(w.document()->scene().world.bodyCollisions.enabled);
    QVERIFY(box->isChecked());
    QVERIFY(w.openFile(QStringLiteral(SOFTTOUCH_SOURCE_DIR "/presets/scenes/angelfish-rock.softtouch")));
    QVERIFY(!box->isVisibleTo(&w));
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
    QCOMPARE(QFileInfo(suggested).fileName(), QFileInfo(w.document()->filePath()).completeBaseName() + "-" +
                                                  QString::fromStdString(w.document()->project().clips.clips[std::size_t(clip)].name) + ".pc2");
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

void TestEditor::exportDialogsPackAGlbForShipping() {
    // The whole way a person goes: Export…, the file dialog (the skinned GLB type and a name), then Export
    // Options' "Pack for shipping". Each modal dialog is answered as it opens, as a person would.
    MainWindow& w = *m_window;
    auto* clips = w.timeline()->findChild<QListWidget*>("clips");
    QVERIFY(clips && clips->count() > 0);
    clips->setCurrentRow(0);
    QPushButton* exportButton = nullptr;
    for (QPushButton* b : w.timeline()->findChildren<QPushButton*>())
        if (b->text() == QString("Export…"))
            exportButton = b;
    QVERIFY(exportButton);
    const QString glb = m_dir->filePath("shipped.glb");
    QString skinFilter;
    for (const QString& f : TimelinePanel::exportFilters())
        if (f.contains("skin", Qt::CaseInsensitive))
            skinFilter = f;
    QVERIFY(!skinFilter.isEmpty());
    bool answeredFile = false, answeredOptions = false;
    QTimer answer;
    connect(&answer, &QTimer::timeout, this, [&] {
        QWidget* modal = QApplication::activeModalWidget();
        if (auto* files = qobject_cast<QFileDialog*>(modal); files && !answeredFile) {
            answeredFile = true;
            files->selectNameFilter(skinFilter);
            files->selectFile(glb);
            static_cast<QDialog*>(files)->accept();  // QFileDialog::accept, through its public base
        } else if (auto* options = qobject_cast<QDialog*>(modal); options && !answeredOptions) {
            if (auto* pack = options->findChild<QCheckBox*>("exportCompress")) {
                answeredOptions = true;
                pack->setChecked(true);
                options->accept();
            }
        }
    });
    answer.start(50);
    exportButton->click();
    answer.stop();
    QVERIFY(answeredFile);
    QVERIFY(answeredOptions);
    QVERIFY(QFile::exists(glb));
    QVERIFY2(io::fileUsesMeshoptCompression(glb.toStdString()), "the file is not packed");
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
        const QPoint a = from.toPoint(), b(int(std::lround(ruler->xOfFrame(toFrame))), a.y());
        QTest::mousePress(ruler, Qt::LeftButton, modifiers, a);
        QTest::mouseMove(ruler, (a + b) / 2);
        QTest::mouseMove(ruler, b);
        QTest::mouseRelease(ruler, Qt::LeftButton, modifiers, b);
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
/// The study dock keeps its references in the test's own folder: none from another run is found there.
static void keepReferencesIn(const QTemporaryDir& dir) {
    QVERIFY(QDir().mkpath(dir.filePath("cache")));
    qputenv("XDG_CACHE_HOME", dir.filePath("cache").toUtf8());
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
    auto* chart = study->findChild<StudyChartView*>("studyPlot");
    QVERIFY(chart != nullptr && chart->studyChart()->hasPoints());
    QCOMPARE(static_cast<QStackedWidget*>(chart->parentWidget())->currentWidget(), chart);
    // The clip moves the mesh, so doing nothing has a price the settings are compared with.
    QVERIFY(study->study().motionAmplitude > 0.0 && study->study().restError > 0.0);

    // The reference is kept by content, as `softtouch-cli study` keeps it; a full study's reference of the same
    // scene and clip, when one is kept, is measured against instead (it certifies lower targets).
    {
        const auto clip = analysis::clipToPlay(scene, w.document()->project().clips, {});
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

// Import Mesh makes a new scene on Verlet (it keeps the wobble the material gives; implicit Euler at the
// same step would lose part of it), shows it in Properties, and Save As writes it into the file, so the
// project reopens on it (a file that names no integrator still opens on implicit Euler).
void TestEditor::importedMeshStartsOnVerletAndSavesIt() {
    MainWindow& w = *m_window;
    QVERIFY(w.document()->importMesh(QStringLiteral(SOFTTOUCH_SOURCE_DIR "/presets/meshes/guppy.obj")).ok());
    const Scene& scene = w.document()->scene();
    QCOMPARE(scene.world.simulation.integrator, IntegratorKind::Verlet);
    {
        // Unanchored under gravity it falls out of view; Frame All finds it where it is now.
        WorldSettings world = scene.world;
        world.gravity = Vec3(0, -9.81, 0);
        w.document()->setWorld(world);
        w.simulation()->advance(3.0);  // some 17 m down (node damping slows the fall)
        const std::vector<Vec3>& nodes = w.simulation()->simulation()->simulator(0).state().position;
        Vec3 centre = Vec3::Zero();
        for (const Vec3& x : nodes)
            centre += x / double(nodes.size());
        QVERIFY2(centre.y() < -10.0, qPrintable(QString::number(centre.y())));
        QVERIFY(!QRectF(w.viewport()->rect()).contains(w.viewport()->toWidget(centre)));
        w.viewport()->frameAll();
        QVERIFY(QRectF(w.viewport()->rect()).contains(w.viewport()->toWidget(centre)));
        w.document()->undoStack()->undo();  // gravity off again
    }
    auto* integrator = w.findChild<QComboBox*>("integrator");
    QVERIFY(integrator);
    QCOMPARE(IntegratorKind(integrator->currentData().toInt()), IntegratorKind::Verlet);
    auto* modes = w.findChild<QLabel*>("modes");
    waitForModes(w);
    QVERIFY2(modes->text().contains("verlet at 240 steps/s"), qPrintable(modes->text()));
    const QString path = m_dir->filePath("imported.softtouch");
    QVERIFY(w.document()->saveAs(path).ok());
    auto saved = io::loadProject(path.toStdString());
    QVERIFY2(saved.ok(), saved.message().c_str());
    QCOMPARE(saved->scene.world.simulation.integrator, IntegratorKind::Verlet);
    QFile file(path);
    QVERIFY(file.open(QIODevice::ReadOnly));
    QVERIFY(file.readAll().contains("\"integrator\": \"verlet\""));
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

int main(int argc, char** argv) {
    QSurfaceFormat format;
    format.setVersion(3, 3);
    format.setProfile(QSurfaceFormat::CoreProfile);
    format.setDepthBufferSize(24);
    QSurfaceFormat::setDefaultFormat(format);
    QApplication app(argc, argv);
    TestEditor test;
    return QTest::qExec(&test, argc, argv);
}

#include "test_editor.moc"

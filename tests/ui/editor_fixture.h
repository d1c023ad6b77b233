#pragma once
// What every editor suite shares: the window each test opens on the default scene, and the helpers that
// drive it. The editor's tests are one program (test_editor), one file per feature (tests/ui/test_editor_*.cpp).
#include "core/geometry/mesh_surface.h"
#include "core/geometry/primitives.h"
#include "core/modes/modes.h"
#include "core/modes/solid_modes.h"
#include "helpers/cli_run.h"
#include "helpers/rigged_gltf.h"
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
#include "ui/material_tuning.h"
#include "ui/presets_panel.h"
#include "ui/properties_panel.h"
#include "ui/study_chart_view.h"
#include "ui/study_panel.h"
#include "ui/take_dialog.h"
#include "ui/timeline_panel.h"
#include "ui/tool_options_bar.h"

#include <QAbstractButton>
#include <QAbstractSpinBox>
#include <QAction>
#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QDialog>
#include <QDir>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QElapsedTimer>
#include <QFile>
#include <QDesktopServices>
#include <QFileDialog>
#include <QFileInfo>
#include <QLabel>
#include <QLineEdit>
#include <QListWidget>
#include <QMenu>
#include <QMessageBox>
#include <QPointer>
#include <QProcess>
#include <QPushButton>
#include <QRegularExpression>
#include <QScrollArea>
#include <QScrollBar>
#include <QSettings>
#include <QSlider>
#include <QStackedWidget>
#include <QStandardItemModel>
#include <QStandardPaths>
#include <QStatusBar>
#include <QSurfaceFormat>
#include <QTabletEvent>
#include <QTemporaryDir>
#include <QTimer>
#include <QTreeWidget>
#include <QWheelEvent>
#include <QtTest/QtTest>

#include <Eigen/Geometry>

#include <memory>
#include <numbers>

using namespace softtouch;
using namespace softtouch::test;
using namespace softtouch::ui;

namespace softtouch::test::editor {

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
double maxDistance(const std::vector<Vec3f>& a, const std::vector<Vec3f>& b);

/// A left-button drag on `widget` from `from` through the middle to `to`, `modifiers` held throughout.
void dragWith(QWidget* widget, QPoint from, QPoint to, Qt::KeyboardModifiers modifiers = {});

/// Right-clicks `at` on `widget` and, in the menu named `menuName` that opens, triggers the item `text`. Returns
/// every item that menu offered (none when no such menu opened).
QStringList chooseFromMenu(QWidget* widget, QPoint at, const QString& menuName, const QString& text);

bool sameMaterial(const LatticeMaterial& a, const LatticeMaterial& b);

/// Fraction of pixels inside `region` that differ from the background of their row (the background
/// is a vertical gradient, sampled at the left edge).
double coverage(const QImage& image, const QRect& region);

/// One brush stroke across the middle of the viewport: press, six moves of 20 px, release, with the
/// brush at strength 0.8 and an 80 px radius (the field and value are the caller's).
void paintStroke(Viewport* view);

/// The properties panel analyses the modes off the UI thread: waits until the latest edit's are shown.
void waitForModes(MainWindow& w);

/// The study dock keeps its references in the test's own folder: none from another run is found there.
/// TestEditor::cleanup() puts XDG_CACHE_HOME back.
void keepReferencesIn(const QTemporaryDir& dir);

/// Answers a save dialog as a person does: the file type, the folder, the name typed into the name field, then
/// Save. (selectFile() leaves a name typed before in place when the folder already holds an export, and the
/// dialog opens in the last folder any earlier test visited.)
void answerSaveDialog(QFileDialog& dialog, const QString& nameFilter, const QString& path);

}  // namespace softtouch::test::editor

using namespace softtouch::test::editor;

class TestEditor : public QObject {
    Q_OBJECT
private slots:
    void initTestCase();
    void init();
    void cleanup();
    void opensDefaultScene();
    void clipPreviewFollowsAMaterialEdit();
    void paintStrokeIsOneUndoStep();
    void paintBrushFollowsTheSceneAndItsMaterial();
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
    void poseKeysGoWhereThePointerIs();
    void poseAsRestShapeSavesAndUndoes();
    void poseGizmoScalesAndTurns();
    void objectsAddDuplicatePickAndDelete();
    void colliderToolAddsMovesScalesAndDeletes();
    void pickedColliderShowsItsNumbersInProperties();
    void theCurrentObjectIsDrawnInColourTheOthersGreyed();
    void openMeshColliderIsOfferedAsOneSided();
    void pairSceneTogglesBodyCollisions();
    void mouseDragPullsAndReleaseSwingsBack();
    void restingFishIsNotRedrawn();
    void secondHandHoldsAndPenPressureScalesTheSpring();
    void saveAndReopenGivesTheSameScene();
    void ctrlShiftSAsksWhereToSave();
    void recoversAutosaveAfterKill();
    void recoversAutosaveAfterRealKill();
    void corruptProjectShowsErrorAndEditorStaysUsable();
    void presetAppliesAsOneUndoStep();
    void recordedTakeScrubsAndExports();
    void exportDialogsPackAGlbForShipping();
    void exportWritesAndOpensAPreviewPage();
    void exportDialogPutsTheRiggedGuppyOnItsOwnRig();
    void keyframesFromPosesMakeAClip();
    void aKeyedClipLoopsFromItsMenuAndTheLoopBox();
    void aGuppySwimCycleIsKeyedInTheEditorAlone();
    void anotherProjectLeavesNoOldClipOnShow();
    void oneTransportPlaysWhatTheTimelineShows();
    void spaceAfterADialogPlaysRatherThanReopeningIt();
    void rulerTicksRetimeCopyAndDeleteKeys();
    void keysHoldOrGoStraightAsTheRulerMenuSays();
    void dopeSheetShowsEveryObjectsKeysAndTheirClips();
    void dopeSheetEditsSeveralKeysAsOne();
    void keySetsAreMadeAndChosenInTheKeysPanel();
    void trimmedTakeClipExportsItsRange();
    void clipsRenameDuplicateRetimeDeleteAndPlay();
    void scriptedDeviceDrivesTheFishAtHapticRate();
    void studyDockMeasuresTheOpenSceneAndAppliesAPick();
    void studyDockCancelsAndStopsWithTheWindow();
    void propertiesShowTheBodysModes();
    void wobbleIsBlankUntilTheNewSceneIsMeasured();
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

public slots:
    /// Where the editor asked the desktop to open a file (QDesktopServices' handler for file: URLs in this suite,
    /// so no browser starts).
    void desktopOpened(const QUrl& url) { m_desktopOpened << url; }

private:
    std::unique_ptr<MainWindow> makeWindow();
    /// Readies the window for posing: active and focused on the viewport (keys reach it), the drivers
    /// off and the body at rest, the pose tool picked. Returns the viewport.
    Viewport* startPosing(MainWindow& w) const;
    QPoint screenOfNode(MainWindow& w, int node) const;
    int isolatedNode(MainWindow& w, int object) const;

    std::unique_ptr<QTemporaryDir> m_dir;
    QByteArray m_cacheHome;  ///< XDG_CACHE_HOME as the suite found it (null: unset).
    QList<QUrl> m_desktopOpened;
    std::unique_ptr<MainWindow> m_window;
    /// Closes a modal dialog that no test answered (an error box in init(), say) once it has stood open for
    /// two of its ticks, saying what it showed: the test then fails on what the dialog said instead of
    /// waiting out QTest's five-minute watchdog.
    QTimer m_unansweredDialogs;
    QPointer<QWidget> m_openSinceLastTick;
};

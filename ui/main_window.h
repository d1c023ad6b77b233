#pragma once
/// The editor's main window: the viewport in the middle; outliner, properties, presets and timeline
/// docks around it (rearrangeable; layout kept in QSettings); menus and a tool bar for files, edits,
/// views, tools and the simulation; a status bar with the live figures. Owns the document, its
/// simulation and its autosave.

#include "io/import/animation_import.h"
#include "ui/autosave.h"
#include "ui/viewport.h"

#include <QMainWindow>

class QLabel;
class QMenu;
class QTreeWidget;

namespace softtouch::ui {

class HapticController;
class KeyframePanel;
class PropertiesPanel;
class StudyPanel;
class PresetsPanel;
class TimelinePanel;
class ToolOptionsBar;

/// Options the application passes in (tests point them at temporary folders).
struct MainWindowOptions {
    QString autosaveFolder;          ///< Empty: <AppDataLocation>/autosave.
    int autosaveMilliseconds = 60000;///< Autosave interval.
    QString presetFolder;            ///< Shipped presets (presets/materials); empty: found next to the binary.
    QString webFolder;               ///< The preview page's player and three.js (web/); empty: Export… offers no preview.
    QString shaderFolder;            ///< The shipped engine shaders the page embeds (io/shaders/).
};

/// The editor window.
class MainWindow : public QMainWindow {
    Q_OBJECT
public:
    explicit MainWindow(const MainWindowOptions& options = {}, QWidget* parent = nullptr);
    ~MainWindow() override;

    Document* document() { return m_document; }
    SimulationController* simulation() { return m_simulation; }
    Viewport* viewport() { return m_viewport; }
    Autosave* autosave() { return m_autosave; }
    PropertiesPanel* properties() { return m_properties; }
    TimelinePanel* timeline() { return m_timeline; }
    ToolOptionsBar* toolOptions() { return m_toolOptions; }
    /// Every action with a keyboard shortcut, read from the actions themselves (so Help ▸ Keyboard
    /// Shortcuts cannot drift from the code): (menu ▸ action, shortcuts), sorted.
    QList<QPair<QString, QString>> shortcutTable() const;
    PresetsPanel* presets() { return m_presets; }
    HapticController* haptics() { return m_haptics; }
    StudyPanel* study() { return m_study; }
    KeyframePanel* keyframes() { return m_keyframes; }

    /// Opens a project; on failure shows the error in a dialog and keeps the current document.
    bool openFile(const QString& path);
    /// Offers an autosave left by a crashed or killed run; returns true when it was recovered.
    bool offerRecovery();

public slots:
    /// Updates the status bar and live readouts (every 250 ms while running).
    void refreshStatus();
    bool save();
    bool saveAs();
    /// File ▸ New: after the unsaved-changes prompt, an untitled project of the bundled angelfish mesh on a
    /// fresh 4x4x4 lattice with the default material (as Import Mesh makes it), to build up from scratch.
    Status newProject();
    void open();
    void importMesh();
    /// File ▸ Import Animated Mesh: adds an object that follows the file's own animation (a rig, keyed
    /// transforms or blend shapes) with secondary motion on top; the status bar reports what was found.
    void importAnimatedMesh();
    /// Adds a collider of `shape` below the current object (a mesh collider reads `meshPath`), selects it
    /// for the collider tool and switches to that tool; one undo step. Errors are shown and returned.
    Status addCollider(ColliderShape shape, const QString& meshPath = {});
    /// Adds an object from a mesh file with its own animation, the take and range of `request` (what File ▸
    /// Import Animated Mesh does after its file dialog and its take dialog, ui/take_dialog.h); errors are shown
    /// and returned.
    Status importAnimatedMeshFile(const QString& path, const io::AnimationRequest& request = {});
    /// File ▸ Add Mesh (after its file dialog): a new object from a mesh file beside the others, made the
    /// current object; errors are shown and returned.
    Status addMeshFile(const QString& path);
    /// Edit ▸ Duplicate Object and Delete Object on the current object; errors are shown and returned.
    Status duplicateCurrentObject();
    Status deleteCurrentObject();

protected:
    void closeEvent(QCloseEvent* event) override;

private:
    void buildActions();
    void buildDocks();
    void buildDeviceMenu(QMenu* menu);
    void refreshOutliner();
    /// Makes the current object's row the outliner's current item.
    void showCurrentObjectInOutliner();
    void updateTitle();
    void addRecentFile(const QString& path);
    void refreshRecentMenu();
    bool maybeSave();
    void showError(const QString& title, const QString& message);

    Document* m_document;
    SimulationController* m_simulation;
    Viewport* m_viewport;
    Autosave* m_autosave;
    HapticController* m_haptics = nullptr;
    PropertiesPanel* m_properties = nullptr;
    PresetsPanel* m_presets = nullptr;
    TimelinePanel* m_timeline = nullptr;
    ToolOptionsBar* m_toolOptions = nullptr;
    StudyPanel* m_study = nullptr;
    KeyframePanel* m_keyframes = nullptr;
    QTreeWidget* m_outliner = nullptr;
    QMenu* m_recentMenu = nullptr;
    QLabel* m_statusSim = nullptr;
    QLabel* m_statusFrame = nullptr;
    QLabel* m_statusMesh = nullptr;
    QLabel* m_statusHaptic = nullptr;
    MainWindowOptions m_options;
};

}  // namespace softtouch::ui

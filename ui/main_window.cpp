#include "ui/main_window.h"

#include "core/geometry/mesh_surface.h"
#include "io/import/mesh_import.h"
#include "ui/dope_sheet.h"
#include "ui/edit_commands.h"
#include "ui/frame_ruler.h"
#include "ui/haptic_controller.h"
#include "ui/keyframe_panel.h"
#include "ui/panel_input_guard.h"
#include "ui/presets_panel.h"
#include "ui/properties_panel.h"
#include "ui/study_panel.h"
#include "ui/take_dialog.h"
#include "ui/timeline_panel.h"
#include "ui/tool_options_bar.h"

#include <algorithm>

#include <QActionGroup>
#include <QApplication>
#include <QVBoxLayout>
#include <QTextBrowser>
#include <QDialogButtonBox>
#include <QDialog>
#include <QCloseEvent>
#include <QDockWidget>
#include <QDir>
#include <QFileDialog>
#include <QFileInfo>
#include <QInputDialog>
#include <QLabel>
#include <QMenuBar>
#include <QMessageBox>
#include <QScrollArea>
#include <QSettings>
#include <QStatusBar>
#include <QTimer>
#include <QToolBar>
#include <QTreeWidget>

namespace softtouch::ui {

MainWindow::MainWindow(const MainWindowOptions& options, QWidget* parent)
    : QMainWindow(parent), m_options(options) {
    setObjectName("SoftTouchMainWindow");
    // Scrolling a panel edits nothing; a clicked button keeps no keys.
    QApplication::instance()->installEventFilter(new PanelInputGuard(this));
    m_document = new Document(this);
    m_simulation = new SimulationController(m_document, this);
    m_viewport = new Viewport(m_document, m_simulation, this);
    m_viewport->setObjectName("viewport");
    setCentralWidget(m_viewport);
    m_autosave = new Autosave(m_document, options.autosaveFolder, this);
    m_autosave->setInterval(options.autosaveMilliseconds);
    connect(m_autosave, &Autosave::failed, this, [this](const QString& m) { statusBar()->showMessage(m, 8000); });

    m_haptics = new HapticController(m_document, m_simulation, this);
    buildDocks();
    buildActions();

    m_statusSim = new QLabel;
    m_statusSim->setObjectName("simulationStatus");
    m_statusFrame = new QLabel;
    m_statusMesh = new QLabel;
    m_statusHaptic = new QLabel;
    for (QLabel* l : {m_statusSim, m_statusFrame, m_statusMesh, m_statusHaptic}) {
        l->setSizePolicy(QSizePolicy::Preferred, QSizePolicy::Preferred);
        statusBar()->addPermanentWidget(l);
    }
    m_statusSim->setMinimumWidth(300);
    m_statusFrame->setMinimumWidth(110);
    m_statusMesh->setMinimumWidth(110);
    auto* statusTimer = new QTimer(this);
    connect(statusTimer, &QTimer::timeout, this, &MainWindow::refreshStatus);
    statusTimer->start(250);
    connect(m_simulation, &SimulationController::rebuilt, this, &MainWindow::refreshStatus);  // at once, not in 250 ms
    refreshStatus();

    connect(m_document, &Document::sceneReplaced, this, &MainWindow::refreshOutliner);
    connect(m_document, &Document::latticeChanged, this, &MainWindow::refreshOutliner);
    connect(m_document, &Document::worldChanged, this, &MainWindow::refreshOutliner);
    connect(m_document, &Document::filePathChanged, this, &MainWindow::updateTitle);
    connect(m_document->undoStack(), &QUndoStack::cleanChanged, this, &MainWindow::updateTitle);
    connect(m_viewport, &Viewport::hint, this, [this](const QString& t) { statusBar()->showMessage(t, 5000); });
    connect(m_simulation, &SimulationController::problemReported, this,
            [this](const QString& t) { statusBar()->showMessage(t, 8000); });

    QSettings settings;
    resize(1400, 860);
    restoreGeometry(settings.value("window/geometry").toByteArray());
    restoreState(settings.value("window/state").toByteArray());
    m_viewport->setNavigationStyle(NavigationStyle(settings.value("view/navigation", int(NavigationStyle::Maya)).toInt()));
    updateTitle();
}

MainWindow::~MainWindow() = default;

void MainWindow::buildDocks() {
    auto dock = [this](const QString& title, const QString& name, QWidget* widget, Qt::DockWidgetArea area) {
        auto* d = new QDockWidget(title, this);
        d->setObjectName(name);
        d->setWidget(widget);
        addDockWidget(area, d);
        return d;
    };
    m_outliner = new QTreeWidget;
    m_outliner->setObjectName("outliner");
    m_outliner->setHeaderLabels({tr("Scene"), tr("")});
    dock(tr("Outliner"), "outlinerDock", m_outliner, Qt::LeftDockWidgetArea);
    connect(m_outliner, &QTreeWidget::currentItemChanged, this, [this](QTreeWidgetItem* item) {
        if (item && item->data(0, Qt::UserRole).isValid())
            m_viewport->setCurrentObject(item->data(0, Qt::UserRole).toInt());
    });
    connect(m_viewport, &Viewport::currentObjectChanged, this, &MainWindow::showCurrentObjectInOutliner);

    m_properties = new PropertiesPanel(m_document, m_simulation, m_viewport);
    auto* scroll = new QScrollArea;
    scroll->setWidget(m_properties);
    scroll->setWidgetResizable(true);
    scroll->setMinimumWidth(300);
    scroll->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
    auto* propertiesDock = dock(tr("Properties"), "propertiesDock", scroll, Qt::RightDockWidgetArea);

    m_presets = new PresetsPanel(m_document, m_viewport, m_options.presetFolder);
    auto* presetsDock = dock(tr("Presets"), "presetsDock", m_presets, Qt::RightDockWidgetArea);
    tabifyDockWidget(propertiesDock, presetsDock);
    m_study = new StudyPanel(m_document);
    // Scrolls rather than squeezes: its text grows with what was measured (a squeezed layout overlaps).
    auto* studyScroll = new QScrollArea;
    studyScroll->setWidget(m_study);
    studyScroll->setWidgetResizable(true);
    studyScroll->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
    auto* studyDock = dock(tr("Speed vs accuracy"), "studyDock", studyScroll, Qt::RightDockWidgetArea);
    tabifyDockWidget(presetsDock, studyDock);
    propertiesDock->raise();

    m_timeline = new TimelinePanel(m_document, m_simulation);
    if (!m_options.webFolder.isEmpty())
        m_timeline->setPreviewAssets({m_options.webFolder.toStdString(), m_options.shaderFolder.toStdString()});
    m_timeline->setViewCamera([this] { return m_viewport->camera().placement(); });
    m_timeline->setCurrentObjectSource([this] { return m_viewport->currentObject(); });
    m_study->setClipSource([this] { return m_timeline->exportedClipName(); });
    auto* timelineDock = dock(tr("Timeline"), "timelineDock", m_timeline, Qt::BottomDockWidgetArea);
    timelineDock->setMaximumHeight(300);  // the ruler and a dope sheet of a few rows
    m_keyframes = new KeyframePanel(m_document, m_simulation, m_viewport);
    m_timeline->setKeySetSource([this] { return m_keyframes->keySet(); });
    connect(m_timeline, &TimelinePanel::keyedClipChosen, m_keyframes, &KeyframePanel::setKeySet);
    auto* keysDock = dock(tr("Keys"), "keysDock", m_keyframes, Qt::BottomDockWidgetArea);
    keysDock->setMaximumHeight(220);
    // Beside the timeline, not a tab behind it: an animator keys while looking at the ruler.
    splitDockWidget(timelineDock, keysDock, Qt::Horizontal);
    resizeDocks({timelineDock, keysDock}, {940, 420}, Qt::Horizontal);
    // The pose keys of the current object as ticks on the timeline's ruler: click one to see its pose, drag
    // it to retime (Ctrl+drag copies), Delete removes it; the keys panel makes each edit (one undo step).
    FrameRuler* ruler = m_timeline->ruler();
    const auto showKeys = [this, ruler] {
        std::vector<double> seconds;
        std::vector<KeyInterpolation> interpolation;
        for (const LatticeKey& k : m_keyframes->keys()) {
            seconds.push_back(k.seconds);
            interpolation.push_back(k.interpolation);
        }
        ruler->setKeys(std::move(seconds), std::move(interpolation));
        ruler->setKeysLabel(QString::fromStdString(m_keyframes->keySet()));
    };
    connect(m_document, &Document::clipsChanged, ruler, showKeys);
    connect(m_document, &Document::sceneReplaced, ruler, showKeys);
    connect(m_viewport, &Viewport::selectionChanged, ruler, showKeys);  // also sent when the current object changes
    connect(m_keyframes, &KeyframePanel::keySetChanged, ruler, showKeys);
    connect(ruler, &FrameRuler::keySelected, m_keyframes, &KeyframePanel::showKey);
    connect(ruler, &FrameRuler::playheadMoved, m_keyframes,
            [this, ruler](int frame) { m_keyframes->setKeyTime(ruler->secondsOfFrame(frame)); });
    connect(ruler, &FrameRuler::keyMoved, m_keyframes, [this](int index, double seconds, bool copy) {
        m_keyframes->moveKey(index, seconds, copy);
    });
    connect(ruler, &FrameRuler::keyDeleted, m_keyframes, [this](int index) { m_keyframes->deleteKey(index); });
    connect(ruler, &FrameRuler::keyInterpolationChosen, m_keyframes,
            [this](int index, KeyInterpolation how) { m_keyframes->setInterpolation(index, how); });
    showKeys();
    // The dope sheet under the ruler: every object's keys and the keyed clips; the current object's keys are
    // edited there several at a time, each edit one undo step of the keys panel.
    DopeSheet* sheet = m_timeline->dopeSheet();
    connect(m_viewport, &Viewport::selectionChanged, m_timeline, &TimelinePanel::refreshDopeSheet);
    connect(m_keyframes, &KeyframePanel::keySetChanged, m_timeline, &TimelinePanel::refreshDopeSheet);
    connect(sheet, &DopeSheet::keySelected, m_keyframes, &KeyframePanel::showKey);
    connect(sheet, &DopeSheet::keysMoved, m_keyframes,
            [this](const QList<int>& keys, double seconds, bool copy) { m_keyframes->moveKeys(keys, seconds, copy); });
    connect(sheet, &DopeSheet::keysDeleted, m_keyframes, [this](const QList<int>& keys) { m_keyframes->deleteKeys(keys); });
    connect(sheet, &DopeSheet::keysInterpolationChosen, m_keyframes,
            [this](const QList<int>& keys, KeyInterpolation how) { m_keyframes->setInterpolation(keys, how); });
    connect(sheet, &DopeSheet::objectChosen, m_viewport, &Viewport::setCurrentObject);
    m_timeline->refreshDopeSheet();
}

void MainWindow::buildActions() {
    QMenu* file = menuBar()->addMenu(tr("&File"));
    QAction* newAction = file->addAction(tr("&New"), QKeySequence::New, this, [this] { (void)newProject(); });  // errors shown there
    newAction->setObjectName("actionNew");
    file->addAction(tr("&Open…"), QKeySequence::Open, this, &MainWindow::open);
    m_recentMenu = file->addMenu(tr("Open &Recent"));
    file->addAction(tr("&Import Mesh…"), QKeySequence(tr("Ctrl+I")), this, &MainWindow::importMesh);
    file->addAction(tr("Import &Animated Mesh…"), QKeySequence(tr("Ctrl+Shift+I")), this, &MainWindow::importAnimatedMesh)
        ->setObjectName("importAnimatedMesh");
    file->addAction(tr("A&dd Mesh…"), QKeySequence(tr("Ctrl+Shift+A")), this, [this] {
        const QString path = QFileDialog::getOpenFileName(
            this, tr("Add Mesh"), QFileInfo(m_document->filePath()).path(),
            tr("Meshes (*.obj *.fbx *.gltf *.glb *.ply *.stl *.dae *.3ds *.blend);;All files (*)"));
        if (!path.isEmpty())
            (void)addMeshFile(path);  // errors shown there
    })->setObjectName("actionAddMesh");
    file->addSeparator();
    file->addAction(tr("&Save"), QKeySequence::Save, this, &MainWindow::save);
    // Ctrl+Shift+S as Blender, Maya and most editors have it: Qt's generic X11 theme binds nothing to SaveAs.
    QAction* saveAsAction = file->addAction(tr("Save &As…"), this, &MainWindow::saveAs);
    saveAsAction->setObjectName("actionSaveAs");
    saveAsAction->setShortcut(QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_S));
    file->addSeparator();
    file->addAction(tr("&Quit"), QKeySequence::Quit, this, &QWidget::close);
    refreshRecentMenu();

    QMenu* edit = menuBar()->addMenu(tr("&Edit"));
    QAction* undo = m_document->undoStack()->createUndoAction(this, tr("&Undo"));
    undo->setShortcut(QKeySequence::Undo);
    QAction* redo = m_document->undoStack()->createRedoAction(this, tr("&Redo"));
    redo->setObjectName("actionRedo");
    // Both conventions: Ctrl+Y (Windows, Maya) and Ctrl+Shift+Z (Blender, macOS, GNOME).
    redo->setShortcuts({QKeySequence(tr("Ctrl+Y")), QKeySequence(tr("Ctrl+Shift+Z"))});
    edit->addAction(undo);
    edit->addAction(redo);
    edit->addSeparator();
    QAction* duplicate = edit->addAction(tr("D&uplicate Object"), QKeySequence(tr("Shift+D")), this,
                                         [this] { (void)duplicateCurrentObject(); });
    duplicate->setObjectName("actionDuplicateObject");
    QAction* remove = edit->addAction(tr("Delete &Object"), QKeySequence(tr("Shift+Del")), this,
                                      [this] { (void)deleteCurrentObject(); });
    remove->setObjectName("actionDeleteObject");
    edit->addSeparator();
    QMenu* addCollider = edit->addMenu(tr("Add &Collider"));
    for (ColliderShape shape : {ColliderShape::Sphere, ColliderShape::Capsule, ColliderShape::Box, ColliderShape::Mesh}) {
        const QString name = QString::fromUtf8(colliderShapeName(shape));
        QAction* a = addCollider->addAction(shape == ColliderShape::Mesh ? tr("Mesh…") : name.left(1).toUpper() + name.mid(1));
        a->setObjectName("actionAdd" + name.left(1).toUpper() + name.mid(1) + "Collider");
        connect(a, &QAction::triggered, this, [this, shape] {
            if (shape != ColliderShape::Mesh) {
                (void)this->addCollider(shape);  // shown to the user when it fails
                return;
            }
            const QString path = QFileDialog::getOpenFileName(
                this, tr("Mesh Collider"), QFileInfo(m_document->filePath()).path(),
                tr("Meshes (*.obj *.fbx *.gltf *.glb *.ply *.stl *.dae *.3ds *.blend);;All files (*)"));
            if (!path.isEmpty())
                (void)this->addCollider(shape, path);
        });
    }

    QMenu* view = menuBar()->addMenu(tr("&View"));
    auto* shading = new QActionGroup(this);
    const std::pair<QString, render::ShadeMode> modes[] = {{tr("&Shaded"), render::ShadeMode::Shaded},
                                                           {tr("&Wireframe"), render::ShadeMode::Wireframe},
                                                           {tr("&X-ray"), render::ShadeMode::XRay}};
    for (const auto& [name, mode] : modes) {
        QAction* a = view->addAction(name, this, [this, m = mode] { m_viewport->setShadeMode(m); });
        a->setCheckable(true);
        a->setChecked(mode == render::ShadeMode::Shaded);
        shading->addAction(a);
    }
    QAction* overlay = view->addAction(tr("Lattice &Overlay"), m_viewport, &Viewport::setOverlayVisible);
    overlay->setCheckable(true);
    overlay->setChecked(true);
    view->addSeparator();
    view->addAction(tr("&Frame Selection (F)"), m_viewport, &Viewport::frameSelection);
    view->addAction(tr("Frame &All"), m_viewport, &Viewport::frameAll);
    view->addAction(tr("Front (1)"), m_viewport, &Viewport::viewFront);
    view->addAction(tr("Side (3)"), m_viewport, &Viewport::viewSide);
    view->addAction(tr("Top (7)"), m_viewport, &Viewport::viewTop);
    view->addSeparator();
    QMenu* navigation = view->addMenu(tr("&Navigation"));
    auto* navGroup = new QActionGroup(this);
    const std::pair<QString, NavigationStyle> styles[] = {{tr("Maya (Alt + mouse)"), NavigationStyle::Maya},
                                                          {tr("Blender (middle mouse)"), NavigationStyle::Blender}};
    const int currentStyle = QSettings().value("view/navigation", int(NavigationStyle::Maya)).toInt();
    for (const auto& [name, style] : styles) {
        QAction* a = navigation->addAction(name, this, [this, s = style] {
            m_viewport->setNavigationStyle(s);
            QSettings().setValue("view/navigation", int(s));
        });
        a->setCheckable(true);
        a->setChecked(int(style) == currentStyle);
        navGroup->addAction(a);
    }

    QToolBar* tools = addToolBar(tr("Tools"));
    tools->setObjectName("toolsToolBar");
    QMenu* toolMenu = menuBar()->addMenu(tr("&Tools"));
    auto* toolGroup = new QActionGroup(this);
    const std::tuple<QString, Tool, QString, QString> toolList[] = {
        {tr("Drag"), Tool::Drag, "D", tr("Pull the surface with a spring; Ctrl+drag adds a second hand that holds.")},
        {tr("Paint"), Tool::Paint, "P", tr("Paint mass, stiffness, damping or volume preservation on lattice nodes; one stroke is one undo step.")},
        {tr("Anchor"), Tool::Anchor, "A", tr("Click a node to pin it (or make it heavy); drag a box for many, Ctrl+box clears.")},
        {tr("Void"), Tool::Void, "V", tr("Click a node to remove it and its springs; drag a box for many, Ctrl+box clears.")},
        {tr("Select"), Tool::Select, "S", tr("Select nodes for numeric entry and smoothing; Shift adds.")},
        {tr("Pose"), Tool::Pose, "T",
         tr("Pose the lattice: select nodes, then G moves, R rotates, S scales (X/Y/Z hold an axis, type an amount, "
            "Enter applies), or drag the gizmo: arrows move, squares scale, rings turn; I keys the pose.")},
        {tr("Lattice"), Tool::Lattice, "L", tr("Drag to move the lattice box; Shift+drag scales it, Ctrl+drag turns it.")},
        {tr("Collider"), Tool::Collider, "C",
         tr("Drag a collider to move it; Shift+drag scales it, Delete removes it (Edit ▸ Add Collider adds one).")}};
    for (const auto& [name, tool, key, tip] : toolList) {
        QAction* a = new QAction(name, this);
        a->setObjectName("tool" + name);
        a->setShortcut(QKeySequence(key));
        a->setToolTip(tip + " (" + key + ")");
        a->setCheckable(true);
        a->setChecked(tool == Tool::Drag);
        connect(a, &QAction::triggered, m_viewport, [this, t = tool] { m_viewport->setTool(t); });
        toolGroup->addAction(a);
        tools->addAction(a);
        toolMenu->addAction(a);
    }

    QToolBar* simBar = addToolBar(tr("Simulation"));
    simBar->setObjectName("simulationToolBar");
    QMenu* simMenu = menuBar()->addMenu(tr("&Simulation"));
    QAction* play = new QAction(tr("Play"), this);
    play->setObjectName("actionPlay");
    play->setShortcut(QKeySequence(Qt::Key_Space));
    // Not checkable: its text says what it does next ("Pause" while running); a checked "Pause" read
    // as "paused" while the simulation ran.
    // One transport: Space plays what the timeline shows (the clip or take selected), else the live simulation.
    connect(play, &QAction::triggered, this, [this] {
        if (m_timeline->showsClipOrTake())
            m_timeline->togglePlayback();
        else
            m_simulation->togglePlay();
        refreshStatus();
    });
    connect(m_simulation, &SimulationController::playingChanged, play, [play](bool on) {
        play->setText(on ? tr("Pause") : tr("Play"));
    });
    QAction* step = new QAction(tr("Step"), this);
    step->setShortcut(QKeySequence(Qt::Key_Period));
    connect(step, &QAction::triggered, m_simulation, &SimulationController::stepOnce);
    QAction* reset = new QAction(tr("Reset"), this);
    reset->setObjectName("actionReset");
    reset->setShortcut(QKeySequence(Qt::Key_Home));
    reset->setToolTip(tr("To the start (Home): the first frame of the clip or take on show, else the simulation from rest."));
    connect(reset, &QAction::triggered, this, [this] {
        if (m_timeline->showsClipOrTake())
            m_timeline->goToEnd(false);
        else
            m_simulation->reset();
    });
    // Frame by frame through what the timeline shows (→ steps the live simulation when nothing is on show).
    QAction* previousFrame = new QAction(tr("Previous Frame"), this);
    previousFrame->setObjectName("actionPreviousFrame");
    previousFrame->setShortcut(QKeySequence(Qt::Key_Left));
    connect(previousFrame, &QAction::triggered, this, [this] { m_timeline->stepFrame(-1); });
    QAction* nextFrame = new QAction(tr("Next Frame"), this);
    nextFrame->setObjectName("actionNextFrame");
    nextFrame->setShortcut(QKeySequence(Qt::Key_Right));
    connect(nextFrame, &QAction::triggered, this, [this] {
        if (m_timeline->showsClipOrTake())
            m_timeline->stepFrame(1);
        else
            m_simulation->stepOnce();
    });
    QAction* firstFrame = new QAction(tr("First Frame"), this);
    firstFrame->setObjectName("actionFirstFrame");
    firstFrame->setShortcut(QKeySequence(Qt::SHIFT | Qt::Key_Left));
    connect(firstFrame, &QAction::triggered, this, [this] { m_timeline->goToEnd(false); });
    QAction* lastFrame = new QAction(tr("Last Frame"), this);
    lastFrame->setObjectName("actionLastFrame");
    lastFrame->setShortcut(QKeySequence(Qt::SHIFT | Qt::Key_Right));
    connect(lastFrame, &QAction::triggered, this, [this] { m_timeline->goToEnd(true); });
    QAction* record = new QAction(tr("Record"), this);
    record->setShortcut(QKeySequence(tr("Ctrl+R")));
    connect(record, &QAction::triggered, m_timeline, &TimelinePanel::toggleRecording);
    QAction* keyPose = new QAction(tr("Key Pose"), this);
    keyPose->setObjectName("actionKeyPose");
    keyPose->setShortcut(QKeySequence(Qt::Key_I));
    keyPose->setToolTip(tr("Key the current pose (the selected nodes, or all) at the Keys dock's time (I)."));
    connect(keyPose, &QAction::triggered, m_keyframes, [this] { m_keyframes->keyPose(m_keyframes->keyTime()); });
    for (QAction* a : {play, step, reset, record, keyPose}) {
        simBar->addAction(a);
        simMenu->addAction(a);
    }
    simMenu->addSeparator();
    for (QAction* a : {previousFrame, nextFrame, firstFrame, lastFrame}) {
        simMenu->addAction(a);
        addAction(a);  // the keys work with the menu closed
    }
    simMenu->addSeparator();
    buildDeviceMenu(simMenu->addMenu(tr("Input &Device")));

    // The active tool's settings on a row of their own under the tool buttons.
    addToolBarBreak();
    m_toolOptions = new ToolOptionsBar(m_document, m_viewport, this);
    addToolBar(m_toolOptions);

    QMenu* help = menuBar()->addMenu(tr("&Help"));
    QAction* shortcuts = help->addAction(tr("&Keyboard Shortcuts"));
    shortcuts->setObjectName("actionShortcuts");
    shortcuts->setShortcut(QKeySequence(Qt::Key_F1));
    connect(shortcuts, &QAction::triggered, this, [this] {
        QString html = "<table cellspacing=6>";
        for (const auto& [what, keys] : shortcutTable() + m_viewport->keyTable())
            html += "<tr><td>" + what.toHtmlEscaped() + "</td><td><b>" + keys.toHtmlEscaped() + "</b></td></tr>";
        // A scrolling list in a dialog that fits the window: the table is taller than a 800-pixel screen.
        QDialog dialog(this);
        dialog.setObjectName("shortcutsDialog");
        dialog.setWindowTitle(tr("Keyboard Shortcuts"));
        auto* layout = new QVBoxLayout(&dialog);
        auto* text = new QTextBrowser;
        text->setHtml(html + "</table>");
        layout->addWidget(text);
        auto* buttons = new QDialogButtonBox(QDialogButtonBox::Close);
        connect(buttons, &QDialogButtonBox::rejected, &dialog, &QDialog::reject);
        layout->addWidget(buttons);
        dialog.resize(std::min(720, width() - 40), std::max(300, int(0.8 * height())));
        dialog.exec();
    });
}

QList<QPair<QString, QString>> MainWindow::shortcutTable() const {
    QList<QPair<QString, QString>> rows;
    auto plain = [](QString text) { return text.remove('&').remove(QStringLiteral("…")).trimmed(); };
    for (QAction* menuAction : menuBar()->actions()) {
        QMenu* menu = menuAction->menu();
        if (!menu)
            continue;
        QList<QPair<QMenu*, QString>> pending = {{menu, plain(menuAction->text())}};
        while (!pending.isEmpty()) {
            const auto [current, path] = pending.takeFirst();
            for (QAction* a : current->actions()) {
                if (a->menu()) {
                    pending.append({a->menu(), path + " ▸ " + plain(a->text())});
                    continue;
                }
                QStringList keys;
                for (const QKeySequence& k : a->shortcuts())
                    keys << k.toString(QKeySequence::NativeText);
                if (!keys.isEmpty())
                    rows.append({path + " ▸ " + plain(a->text()), keys.join(", ")});
            }
        }
    }
    std::sort(rows.begin(), rows.end());
    return rows;
}

void MainWindow::buildDeviceMenu(QMenu* menu) {
    // The mouse and pen are built into the viewport; every other device is a plugin running the
    // 1 kHz haptic loop, its workspace fitted onto the current object's lattice box.
    auto* group = new QActionGroup(this);
    QAction* mouse = menu->addAction(tr("Mouse and pen (built in)"), m_haptics, &HapticController::stop);
    mouse->setCheckable(true);
    mouse->setChecked(true);
    group->addAction(mouse);
    for (const QString& name : m_haptics->deviceNames()) {
        QAction* a = menu->addAction(name);
        a->setObjectName("device_" + name);
        a->setCheckable(true);
        group->addAction(a);
        connect(a, &QAction::triggered, this, [this, name, mouse] {
            QString argument;
            if (name == "scripted") {
                argument = QFileDialog::getOpenFileName(this, tr("Device trajectory"), m_options.presetFolder + "/../devices",
                                                        tr("Trajectories (*.sttraj)"));
                if (argument.isEmpty()) {
                    mouse->setChecked(true);
                    return;
                }
            }
            if (Status s = m_haptics->start(name, argument, m_viewport->currentObject()); !s) {
                showError(tr("Cannot start the device"), QString::fromStdString(s.message()));
                mouse->setChecked(true);
            }
        });
    }
    menu->addSeparator();
    menu->addAction(tr("Workspace Scale…"), this, [this] {
        bool ok = false;
        const double factor = QInputDialog::getDouble(
            this, tr("Workspace scale"),
            tr("The device workspace is fitted onto the lattice box, then scaled by this factor\n"
               "(above 1: a small hand motion reaches further; below 1: finer control). Next device start:"),
            m_haptics->workspaceScale(), 0.01, 100.0, 2, &ok);
        if (ok)
            m_haptics->setWorkspaceScale(factor);
    });
    connect(m_haptics, &HapticController::runningChanged, mouse, [mouse](bool running) {
        if (!running)
            mouse->setChecked(true);
    });
    if (!m_haptics->pluginProblems().isEmpty())
        menu->setToolTip(m_haptics->pluginProblems().join("\n"));
}

void MainWindow::showCurrentObjectInOutliner() {
    // The object's own row, not one of its children's; without telling the viewport again.
    const QSignalBlocker block(m_outliner);
    for (int i = 0; i < m_outliner->topLevelItemCount(); ++i)
        if (QTreeWidgetItem* item = m_outliner->topLevelItem(i);
            item->childCount() > 0 && item->data(0, Qt::UserRole).toInt() == m_viewport->currentObject())
            m_outliner->setCurrentItem(item);
}

void MainWindow::refreshOutliner() {
    m_outliner->clear();
    const Scene& scene = m_document->scene();
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        const SceneObject& o = scene.objects[i];
        auto* item = new QTreeWidgetItem(m_outliner, {QString::fromStdString(o.name),
                                                      tr("%n triangles", nullptr, int(o.mesh->triangles.size()))});
        item->setData(0, Qt::UserRole, int(i));
        const LatticeShape& shape = o.lattice.shape();
        auto* lattice = new QTreeWidgetItem(item, {tr("Lattice"), tr("%1×%2×%3 %4")
                                                                      .arg(shape.nodes[0])
                                                                      .arg(shape.nodes[1])
                                                                      .arg(shape.nodes[2])
                                                                      .arg(shape.kind == LatticeKind::Bezier ? tr("Bezier") : tr("B-spline"))});
        lattice->setData(0, Qt::UserRole, int(i));
        auto* drivers = new QTreeWidgetItem(item, {tr("Drivers"), QString::number(o.drivers.size())});
        drivers->setData(0, Qt::UserRole, int(i));
        if (o.baseAnimation) {  // the mesh's own animation, with the soft body's wobble on top
            const BaseAnimation& a = *o.baseAnimation;
            auto* base = new QTreeWidgetItem(item, {tr("Base animation"), tr("\"%1\", %2 s%3")
                                                                              .arg(QString::fromStdString(a.take))
                                                                              .arg(a.duration(), 0, 'g', 3)
                                                                              .arg(a.loop ? tr(", loops") : QString())});
            base->setData(0, Qt::UserRole, int(i));
        }
        item->setExpanded(true);
    }
    if (scene.objects.size() > 1) {
        const BodyCollisionSettings& bodies = scene.world.bodyCollisions;
        new QTreeWidgetItem(m_outliner, {tr("Bodies collide"), bodies.enabled ? tr("yes (Kr %1, μ %2)").arg(bodies.restitution).arg(bodies.friction)
                                                                           : tr("no (they pass through)")});
    }
    auto* planes = new QTreeWidgetItem(m_outliner, {tr("Collision planes"), QString::number(scene.world.planes.size())});
    for (std::size_t p = 0; p < scene.world.planes.size(); ++p) {
        const CollisionPlane& plane = scene.world.planes[p];
        new QTreeWidgetItem(planes, {tr("Plane %1").arg(p + 1), tr("n = (%1, %2, %3), Kr %4")
                                                                  .arg(plane.normal.x())
                                                                  .arg(plane.normal.y())
                                                                  .arg(plane.normal.z())
                                                                  .arg(plane.restitution)});
    }
    if (!scene.world.colliders.empty()) {
        auto* colliders = new QTreeWidgetItem(m_outliner, {tr("Colliders"), QString::number(scene.world.colliders.size())});
        for (std::size_t k = 0; k < scene.world.colliders.size(); ++k) {
            const Collider& c = scene.world.colliders[k];
            const QString size = c.shape == ColliderShape::Box
                                     ? tr("%1 × %2 × %3 m").arg(2 * c.halfExtents.x()).arg(2 * c.halfExtents.y()).arg(2 * c.halfExtents.z())
                                 : c.shape == ColliderShape::Mesh
                                     ? tr("%1, %2 triangles, scale %3")
                                           .arg(QFileInfo(QString::fromStdString(c.surface->source())).fileName())
                                           .arg(c.surface->mesh().triangles.size())
                                           .arg(c.scale)
                                     : c.shape == ColliderShape::Capsule
                                           ? tr("r %1 m, %2 m long").arg(c.radius).arg(2 * c.halfLength + 2 * c.radius)
                                           : tr("r %1 m").arg(c.radius);
            new QTreeWidgetItem(colliders, {tr("%1 %2").arg(QString::fromUtf8(colliderShapeName(c.shape))).arg(k + 1),
                                            tr("%1 at (%2, %3, %4)").arg(size).arg(c.centre.x()).arg(c.centre.y()).arg(c.centre.z())});
        }
        colliders->setExpanded(true);
    }
    showCurrentObjectInOutliner();
    m_outliner->resizeColumnToContents(0);
}

void MainWindow::refreshStatus() {
    const SimulationStats& s = m_simulation->stats();
    const SceneSimulation* sim = m_simulation->simulation();
    if (m_timeline->isPlaying())
        m_statusSim->setText(tr("playing %1 (Space pauses)").arg(m_timeline->shownName()));
    else if (m_timeline->showsClipOrTake())
        m_statusSim->setText(tr("%1 on show, paused (Space plays it; click empty space in the list for the live "
                                "simulation)").arg(m_timeline->shownName()));
    else if (s.asleep)
        m_statusSim->setText(tr("asleep: nothing moves, nothing is simulated or redrawn"));
    else if (!m_simulation->isPlaying())
        m_statusSim->setText(tr("paused (Space plays)"));
    else
        m_statusSim->setText(tr("%1 steps/s · %2 µs/step · %3× real time")
                                 .arg(s.stepsPerSecond, 0, 'f', 0)
                                 .arg(s.stepMicros, 0, 'f', 1)
                                 .arg(s.realtimeFactor, 0, 'f', 2));
    m_statusFrame->setText(tr("frame %1 ms").arg(m_viewport->frameMilliseconds(), 0, 'f', 2));
    std::size_t triangles = 0;
    if (sim)
        for (std::size_t i = 0; i < sim->objectCount(); ++i)
            triangles += sim->object(i).mesh->triangles.size();
    m_statusMesh->setText(tr("%L1 tris").arg(triangles));
    m_statusHaptic->setText(m_haptics->statusText());
    m_properties->refreshLive();
}

void MainWindow::updateTitle() {
    setWindowTitle(tr("%1%2 — SoftTouch").arg(m_document->displayName(), m_document->isModified() ? "*" : ""));
}

bool MainWindow::openFile(const QString& path) {
    if (Status s = m_document->open(path); !s) {
        showError(tr("Cannot open project"), QString::fromStdString(s.message()));
        return false;
    }
    addRecentFile(path);
    // Opened paused, as the user guide says: Space (or a drag in the viewport) starts it. Running on open
    // moved the fish before the animator had looked at it.
    m_simulation->pause();
    statusBar()->showMessage(tr("Paused: press Space to play, or drag the body."), 8000);
    return true;
}

Status MainWindow::newProject() {
    if (!maybeSave())
        return Status::cancelled("the unsaved changes were kept");
    m_document->newEmptyScene();
    m_viewport->setCurrentObject(0);
    statusBar()->showMessage(tr("An empty scene: File ▸ Add Mesh… or Import Animated Mesh… puts a body in it."), 15000);
    return Status::success();
}

void MainWindow::open() {
    if (!maybeSave())
        return;
    const QString path = QFileDialog::getOpenFileName(this, tr("Open Project"), QFileInfo(m_document->filePath()).path(),
                                                      tr("SoftTouch projects (*.softtouch);;All files (*)"));
    if (!path.isEmpty())
        openFile(path);
}

void MainWindow::importMesh() {
    if (!maybeSave())
        return;
    const QString path = QFileDialog::getOpenFileName(
        this, tr("Import Mesh"), QString(),
        tr("Meshes (*.obj *.fbx *.gltf *.glb *.ply *.stl *.dae *.3ds *.blend);;All files (*)"));
    if (path.isEmpty())
        return;
    if (Status s = m_document->importMesh(path); !s)
        showError(tr("Cannot import mesh"), QString::fromStdString(s.message()));
}

void MainWindow::importAnimatedMesh() {
    const QString path = QFileDialog::getOpenFileName(
        this, tr("Import Animated Mesh"), QString(),
        tr("Animated meshes (*.gltf *.glb *.fbx *.dae);;All files (*)"));
    if (path.isEmpty())
        return;
    // Which take, which part of it, looping or not. A file that cannot be read, or has no animation, goes on
    // to the import, whose error says so.
    io::AnimationRequest request;
    if (auto takes = io::animationTakes(path.toStdString())) {
        TakeDialog choose(std::move(takes.value()), QFileInfo(path).fileName(), this);
        if (choose.exec() != QDialog::Accepted)
            return;
        request = choose.request();
    }
    (void)importAnimatedMeshFile(path, request);
}

Status MainWindow::importAnimatedMeshFile(const QString& path, const io::AnimationRequest& request) {
    QString report;
    if (Status s = m_document->importAnimatedMesh(path, request, &report); !s) {
        showError(tr("Cannot import animated mesh"), QString::fromStdString(s.message()));
        return s;
    }
    // The new object, beside the others, is the one the tools act on; it plays its base animation with the goals
    // painted at ½: Space plays it.
    m_viewport->setCurrentObject(int(m_document->scene().objects.size()) - 1);
    m_viewport->frameAll();
    m_simulation->pause();
    statusBar()->showMessage(tr("Imported %1. Paint 'Goal weight' where it should follow the animation exactly; "
                                "Space plays it.").arg(report), 15000);
    return Status::success();
}

Status MainWindow::addMeshFile(const QString& path) {
    if (Status s = m_document->addMesh(path); !s) {
        showError(tr("Cannot add mesh"), QString::fromStdString(s.message()));
        return s;
    }
    m_viewport->setCurrentObject(int(m_document->scene().objects.size()) - 1);
    m_viewport->frameAll();
    return Status::success();
}

Status MainWindow::duplicateCurrentObject() {
    const int object = m_viewport->currentObject();
    if (Status s = m_document->duplicateObject(object); !s) {
        showError(tr("Cannot duplicate"), QString::fromStdString(s.message()));
        return s;
    }
    m_viewport->setCurrentObject(object + 1);
    m_viewport->frameAll();
    return Status::success();
}

Status MainWindow::deleteCurrentObject() {
    const int object = m_viewport->currentObject();
    if (Status s = m_document->deleteObject(object); !s) {
        showError(tr("Cannot delete"), QString::fromStdString(s.message()));
        return s;
    }
    m_viewport->setCurrentObject(std::max(0, object - 1));
    return Status::success();
}

Status MainWindow::addCollider(ColliderShape shape, const QString& meshPath) {
    const Scene& scene = m_document->scene();
    if (scene.objects.empty())
        return Status::error("no object to place the collider by");
    // Below the current object, a quarter of its size: in view, and not touching it yet.
    const int current = std::clamp(m_viewport->currentObject(), 0, int(scene.objects.size()) - 1);
    const Bounds b = scene.objects[std::size_t(current)].mesh->bounds();
    const double size = std::max(b.diagonal(), 1e-3);
    const Vec3 middle = 0.5 * (b.min + b.max);
    Collider c;
    c.shape = shape;
    c.radius = 0.25 * size;
    c.halfLength = 0.25 * size;
    c.axis = Vec3::UnitX();
    c.halfExtents = Vec3(0.5 * size, 0.1 * size, 0.5 * size);
    const double below = shape == ColliderShape::Box ? c.halfExtents.y() : c.radius;
    c.centre = Vec3(middle.x(), b.min.y() - 0.1 * size - below, middle.z());
    if (shape == ColliderShape::Mesh) {
        auto mesh = io::importMesh(meshPath.toStdString());
        if (!mesh) {
            showError(tr("Cannot add the mesh collider"), QString::fromStdString(mesh.message()));
            return Status::error(mesh.message());
        }
        // The project names the file relative to itself once it has a folder, like an object's mesh.
        const QString folder = QFileInfo(m_document->filePath()).path();
        const QString reference =
            m_document->filePath().isEmpty() ? QFileInfo(meshPath).absoluteFilePath() : QDir(folder).relativeFilePath(meshPath);
        auto surface = MeshSurface::create(mesh.value(), reference.toStdString(), SurfaceSides::Closed);
        if (!surface) {
            // An open sheet (a ground, a wall) can still be a one-sided surface: offer that, saying why the
            // solid was refused, rather than sending the user to edit the project file.
            auto sheet = MeshSurface::create(std::move(mesh.value()), reference.toStdString(), SurfaceSides::OneSided);
            const QString why = QString::fromStdString(surface.message());
            const bool asSheet =
                sheet && QMessageBox::question(this, tr("Use the mesh as a one-sided surface?"),
                                               tr("%1\n\nIt can be a one-sided surface instead, like a ground or a wall: it "
                                                  "pushes bodies out along its face normals (\"oneSided\" in the "
                                                  "project). Use it that way?")
                                                   .arg(why)) == QMessageBox::Yes;
            if (!asSheet) {
                if (!sheet)
                    showError(tr("Cannot add the mesh collider"), why);
                return Status::error(surface.message());
            }
            surface = std::move(sheet);
        }
        c.surface = surface.value();
        // Scaled to half the object's size, its top just below the object.
        const Bounds m = c.surface->bounds();
        c.scale = 0.5 * size / std::max(m.diagonal(), 1e-9);
        const Vec3 meshMiddle = 0.5 * (m.min + m.max);
        c.centre = Vec3(middle.x(), b.min.y() - 0.1 * size, middle.z()) -
                   c.scale * Vec3(meshMiddle.x(), m.max.y(), meshMiddle.z());
    }
    WorldSettings after = scene.world;
    after.colliders.push_back(c);
    m_document->undoStack()->push(new WorldEditCommand(m_document, scene.world, after,
                                                       tr("Add %1 collider").arg(QString::fromUtf8(colliderShapeName(shape)))));
    if (QAction* tool = findChild<QAction*>("toolCollider"))
        tool->trigger();
    m_viewport->setCurrentCollider(int(after.colliders.size()) - 1);
    return Status::success();
}

bool MainWindow::save() {
    if (m_document->filePath().isEmpty())
        return saveAs();
    if (Status s = m_document->saveAs(m_document->filePath()); !s) {
        showError(tr("Save failed"), tr("%1\n\nThe previous file was left untouched.").arg(QString::fromStdString(s.message())));
        return false;
    }
    statusBar()->showMessage(tr("Saved %1").arg(m_document->filePath()), 4000);
    return true;
}

bool MainWindow::saveAs() {
    QString path = QFileDialog::getSaveFileName(this, tr("Save Project As"), m_document->filePath(),
                                                tr("SoftTouch projects (*.softtouch)"));
    if (path.isEmpty())
        return false;
    if (!path.endsWith(".softtouch"))
        path += ".softtouch";
    if (Status s = m_document->saveAs(path); !s) {
        showError(tr("Save failed"), tr("%1\n\nThe previous file was left untouched.").arg(QString::fromStdString(s.message())));
        return false;
    }
    addRecentFile(path);
    return true;
}

bool MainWindow::maybeSave() {
    if (!m_document->isModified())
        return true;
    const auto answer = QMessageBox::warning(this, tr("Unsaved changes"),
                                             tr("%1 has unsaved changes. Save them?").arg(m_document->displayName()),
                                             QMessageBox::Save | QMessageBox::Discard | QMessageBox::Cancel);
    if (answer == QMessageBox::Save)
        return save();
    return answer == QMessageBox::Discard;
}

bool MainWindow::offerRecovery() {
    const auto candidate = m_autosave->pending();
    if (!candidate)
        return false;
    const QString from = candidate->originalPath.isEmpty() ? tr("an unsaved scene") : candidate->originalPath;
    const auto answer = QMessageBox::question(
        this, tr("Recover unsaved work?"),
        tr("SoftTouch was not closed properly. An autosave of %1 from %2 is available.\n\nRecover it?")
            .arg(from, QLocale().toString(candidate->savedAt.toLocalTime(), QLocale::ShortFormat)),
        QMessageBox::Yes | QMessageBox::No, QMessageBox::Yes);
    if (answer != QMessageBox::Yes) {
        m_autosave->discard();
        return false;
    }
    if (Status s = m_autosave->recover(*candidate); !s) {
        showError(tr("Recovery failed"), QString::fromStdString(s.message()));
        return false;
    }
    statusBar()->showMessage(tr("Recovered the autosave; save to keep it."), 8000);
    return true;
}

void MainWindow::closeEvent(QCloseEvent* event) {
    if (!maybeSave()) {
        event->ignore();
        return;
    }
    m_autosave->discard();
    m_study->cancel();  // a measurement in flight stops now, not when the window is destroyed
    QSettings settings;
    settings.setValue("window/geometry", saveGeometry());
    settings.setValue("window/state", saveState());
    event->accept();
}

void MainWindow::addRecentFile(const QString& path) {
    QSettings settings;
    QStringList recent = settings.value("files/recent").toStringList();
    const QString absolute = QFileInfo(path).absoluteFilePath();
    recent.removeAll(absolute);
    recent.prepend(absolute);
    while (recent.size() > 10)
        recent.removeLast();
    settings.setValue("files/recent", recent);
    refreshRecentMenu();
}

void MainWindow::refreshRecentMenu() {
    m_recentMenu->clear();
    const QStringList recent = QSettings().value("files/recent").toStringList();
    for (const QString& path : recent)
        m_recentMenu->addAction(QFileInfo(path).fileName(), this, [this, path] {
            if (maybeSave())
                openFile(path);
        })->setToolTip(path);
    m_recentMenu->setEnabled(!recent.isEmpty());
}

void MainWindow::showError(const QString& title, const QString& message) {
    qWarning("%s: %s", qPrintable(title), qPrintable(message));  // also in the log, for whoever runs it unattended
    QMessageBox box(QMessageBox::Critical, title, message, QMessageBox::Ok, this);
    box.setObjectName("errorDialog");
    box.exec();
}

}  // namespace softtouch::ui

#pragma once
/// The properties dock: simulation (integrator, time step, gravity, drivers, live cost and stability
/// bound), material (animator view: frequency and damping ratio; raw view: mass, stiffness, damping,
/// anisotropy), lattice (kind and resolution) and numeric entry, fill and smooth for the selected nodes.
/// Every edit is an undo command. The tools' settings are in the tool options bar (ui/tool_options_bar.h).

#include "ui/viewport.h"

#include <QWidget>

#include <optional>
#include <utility>
#include <vector>

class QComboBox;
class QDoubleSpinBox;
class QSpinBox;
class QCheckBox;
class QLabel;
class QPushButton;

namespace softtouch::ui {

struct ModesReport;

/// Properties of the current object, the world and the tools.
class PropertiesPanel : public QWidget {
    Q_OBJECT
public:
    PropertiesPanel(Document* document, SimulationController* simulation, Viewport* viewport, QWidget* parent = nullptr);

    /// Refreshes the live figures (called by the main window's status timer).
    void refreshLive();

signals:
    /// The modes of the latest edit are shown (their analysis runs off the UI thread; the "modes" label has the
    /// property "analysing" true until then).
    void modesShown();

private:
    std::vector<QWidget*> m_objectSections;  ///< Material, lattice, selection: shown only with a current object.
    QLabel* m_noObject = nullptr;            ///< What to do in a scene with no objects.
    QWidget* buildSimulation();
    QWidget* buildMaterial();
    QWidget* buildLattice();
    QWidget* buildSelection();
    void refresh();
    /// The lowest modes of object `o` and what `settings`' integrator does to the lowest one, analysed on a
    /// worker thread and shown when done (modesShown()); a mode the viewport is showing follows the new shape
    /// (or stops when it is gone).
    void refreshModes(const SceneObject& o, const SimulationSettings& settings);
    void startModesAnalysis();
    void finishModesAnalysis(const ModesReport& report);
    /// Shows `modes` in the rows (none: rows hidden).
    /// `clipDamping[m]`: the damping ratio mode m shows in the clip under the scene's integrator (the
    /// material's and the scheme's together); NaN or absent where it was not worked out.
    void showModeRows(const std::vector<VibrationMode>& modes, const std::vector<double>& clipDamping = {});
    /// Solves the current object's material as a converged solid and shows each mode's error (on demand:
    /// a tenth of a second, too slow for every paint dab; the next edit clears it).
    void compareWithSolid();
    /// The current object's lattice (a copy, for edits that need its geometry).
    /// The current object's goal springs when it follows a base animation (their stiffness is part of its modes).
    std::optional<FollowSettings> currentFollow() const;
    Lattice currentLattice() const;
    /// What the current object's material values mean.
    MaterialModel currentModel() const;
    /// Names and units of the material fields for a model.
    void showMaterialUnits(MaterialModel model, BodyElement element);
    void editMaterial(const QString& text, int mergeKey, const std::function<void(LatticeMaterial&)>& change);
    void editWorld(const QString& text, int mergeKey, const std::function<void(WorldSettings&)>& change);
    void applyLatticeShape();
    /// Rebuilds the current object's lattice over `box` (same shape), carrying the material over.
    void applyLatticeBox(const OrientedBox& box, const QString& text);
    void transformLattice();
    void fitLattice();
    void autoVoid();
    int object() const { return m_viewport->currentObject(); }

    Document* m_document;
    SimulationController* m_simulation;
    Viewport* m_viewport;
    bool m_refreshing = false;

    QComboBox* m_integrator = nullptr;
    QComboBox* m_element = nullptr;
    QDoubleSpinBox* m_stepsPerSecond = nullptr;
    QCheckBox* m_gravity = nullptr;
    QCheckBox* m_drivers = nullptr;
    QLabel* m_live = nullptr;

    QDoubleSpinBox* m_frequency = nullptr;
    QDoubleSpinBox* m_dampingRatio = nullptr;
    QLabel* m_modes = nullptr;             ///< Rigid modes and what the integrator does to the lowest mode.
    std::array<QLabel*, 3> m_modeRows{};   ///< The three lowest modes: frequency and ζ (node + spring).
    std::array<QPushButton*, 3> m_modeShow{}; ///< "Show": animates that mode in the viewport (Viewport::showMode).
    std::vector<VibrationMode> m_analysedModes; ///< The modes the rows show (current object).
    /// The latest edit's object and settings, until its analysis starts: set while one runs, the running one's
    /// result is stale and not shown.
    std::optional<std::pair<SceneObject, SimulationSettings>> m_modesWanted;
    bool m_modesRunning = false;  ///< An analysis is on the thread pool.
    int m_modesShownFor = -1;     ///< The object whose wobble and damping the fields hold (-1: none yet).
    QPushButton* m_compareSolid = nullptr;  ///< "Compare with the solid": compareWithSolid().
    QLabel* m_solid = nullptr;              ///< Its result until the next edit (core/modes/solid_modes.h).
    QDoubleSpinBox* m_nodeDamping = nullptr;
    QDoubleSpinBox* m_stretchLimit = nullptr;  ///< Longest spring / rest length; its minimum (1.00) reads "off".
    QDoubleSpinBox* m_squashLimit = nullptr;   ///< Shortest spring / rest length; its minimum (0.00) reads "off".
    QDoubleSpinBox* m_volumePreservation = nullptr;  ///< 0 (reads "off") to 1 (hard).
    QDoubleSpinBox* m_totalMass = nullptr;
    QDoubleSpinBox* m_stiffness = nullptr;
    QDoubleSpinBox* m_damping = nullptr;
    std::array<QDoubleSpinBox*, 3> m_anisotropy{};

    QComboBox* m_latticeKind = nullptr;
    std::array<QSpinBox*, 3> m_latticeNodes{};
    std::array<QDoubleSpinBox*, 3> m_latticeMove{};
    QDoubleSpinBox* m_latticeScale = nullptr;
    QDoubleSpinBox* m_latticeTurn = nullptr;
    QCheckBox* m_groundPlane = nullptr;
    QCheckBox* m_bodiesCollide = nullptr;


    QLabel* m_selectionLabel = nullptr;
    QDoubleSpinBox* m_selectionValue = nullptr;
};

}  // namespace softtouch::ui

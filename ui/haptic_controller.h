#pragma once
/// The editor's side of the haptic loop (core/haptics/haptic_loop.h): picks a device plugin, calibrates its
/// workspace onto the current object's lattice box, runs the 1 kHz loop on its own thread, and shows
/// the loop's lock-free snapshots in the viewport at screen rate. While a device drives the body the
/// interactive simulation is paused; stopping the device hands the pose back to it.

#include "core/haptics/haptic_loop.h"
#include "ui/simulation_controller.h"

#include <QObject>
#include <QStringList>
#include <QTimer>

#include <memory>

namespace softtouch {
class DeviceRegistry;
}

namespace softtouch::ui {

/// Device choice and the running loop.
class HapticController : public QObject {
    Q_OBJECT
public:
    HapticController(Document* document, SimulationController* simulation, QObject* parent = nullptr);
    ~HapticController() override;

    /// Names of the device plugins found (null, scripted, sdl2, …).
    QStringList deviceNames() const;
    /// Problems met while loading plugins (one line each).
    QStringList pluginProblems() const;
    /// Starts plugin `device` (with `argument`, e.g. a trajectory file for "scripted") on object
    /// `object`: the workspace is fitted onto its lattice box and the material point under the device's
    /// first position is grabbed.
    Status start(const QString& device, const QString& argument, int object);
    /// Stops the loop; the editor's simulation continues from the last pose.
    void stop();
    bool isRunning() const { return m_loop != nullptr; }
    /// The last snapshot read.
    const HapticSnapshot& snapshot() const { return m_snapshot; }
    /// Workspace calibration: the device workspace is fitted onto the object's lattice box (centres
    /// matched, uniform scale), then scaled by this factor: above 1 a small hand motion moves further in
    /// the scene, below 1 it gives finer control. (0.01, 100]. Applies from the next start().
    void setWorkspaceScale(double factor) { m_workspaceScale = factor; }
    double workspaceScale() const { return m_workspaceScale; }
    /// The calibration the running (or last) loop used.
    const DeviceCalibration& calibration() const { return m_calibration; }
    /// One line for the status bar: device, rate, p99 period, force.
    QString statusText() const;

signals:
    void runningChanged(bool running);

private:
    void poll();

    Document* m_document;
    SimulationController* m_simulation;
    std::unique_ptr<DeviceRegistry> m_registry;
    std::unique_ptr<HapticLoop> m_loop;
    QString m_deviceName;
    int m_object = 0;
    double m_workspaceScale = 1.0;
    DeviceCalibration m_calibration;
    HapticSnapshot m_snapshot;
    QTimer m_timer;
};

}  // namespace softtouch::ui

#include "ui/haptic_controller.h"

#include "core/haptics/haptic_session.h"
#include "plugins/device_registry.h"

namespace softtouch::ui {

HapticController::HapticController(Document* document, SimulationController* simulation, QObject* parent)
    : QObject(parent), m_document(document), m_simulation(simulation),
      m_registry(std::make_unique<DeviceRegistry>(DeviceRegistry::defaultFolder())) {
    m_timer.setInterval(16);
    connect(&m_timer, &QTimer::timeout, this, &HapticController::poll);
    // The loop owns a copy of the body: any edit of the scene ends the session.
    connect(document, &Document::sceneReplaced, this, &HapticController::stop);
    connect(document, &Document::latticeChanged, this, &HapticController::stop);
    connect(document, &Document::materialChanged, this, &HapticController::stop);
}

HapticController::~HapticController() { stop(); }

QStringList HapticController::deviceNames() const {
    QStringList names;
    for (const InputDevicePlugin* p : m_registry->plugins())
        names << p->name();
    return names;
}

QStringList HapticController::pluginProblems() const { return m_registry->problems(); }

Status HapticController::start(const QString& device, const QString& argument, int object) {
    stop();
    const Scene& scene = m_document->scene();
    const SceneSimulation* sim = m_simulation->simulation();
    if (!sim || object < 0 || std::size_t(object) >= scene.objects.size())
        return Status::error("no object to drive");
    const SceneObject& o = scene.objects[std::size_t(object)];
    QString chosen, error;
    std::unique_ptr<InputDevice> input = m_registry->open(device, 0, argument, &chosen, &error);
    if (!input)
        return Status::error(error.toStdString());
    HapticSessionOptions options;
    options.workspaceScale = m_workspaceScale;
    auto created = createHapticSession(scene, std::size_t(object), std::move(input), options);
    if (!created)
        return Status::error(created.message());
    m_loop = std::move(created.value());
    m_calibration = m_loop->settings().calibration;
    m_simulation->pause();
    m_loop->restoreState(sim->simulator(std::size_t(object)).state(), 0);
    // One manual tick places the avatar; grab the material point under it, then run on the thread.
    m_loop->tick();
    m_loop->readSnapshot(m_snapshot);
    const Vec3 uvw = o.lattice.box().toParameters(m_snapshot.avatar).cwiseMax(0.0).cwiseMin(1.0);
    m_loop->post(HapticCommand::grab(o.lattice.weights(uvw)));
    m_loop->start();
    m_deviceName = chosen;
    m_object = object;
    m_timer.start();
    emit runningChanged(true);
    return Status::success();
}

void HapticController::stop() {
    if (!m_loop)
        return;
    m_timer.stop();
    m_loop->stop();
    m_loop.reset();
    emit runningChanged(false);
}

void HapticController::poll() {
    if (!m_loop || !m_loop->readSnapshot(m_snapshot))
        return;
    const SceneSimulation* sim = m_simulation->simulation();
    if (!sim || std::size_t(m_object) >= sim->objectCount())
        return;
    // Show the loop's body in place of the object's; the others keep their pose.
    std::vector<std::vector<Vec3>> pose;
    for (std::size_t i = 0; i < sim->objectCount(); ++i)
        pose.push_back(int(i) == m_object ? m_snapshot.positions : sim->simulator(i).state().position);
    m_simulation->showPose(pose);
}

QString HapticController::statusText() const {
    if (!m_loop)
        return tr("haptic: mouse");
    const HapticStats& s = m_snapshot.stats;
    return tr("haptic %1: %2 Hz · p99 %3 ms · %4 N")
        .arg(m_deviceName)
        .arg(s.rateHz, 0, 'f', 0)
        .arg(s.periodP99Ms, 0, 'f', 2)
        .arg(m_snapshot.deviceForce.norm(), 0, 'f', 2);
}

}  // namespace softtouch::ui

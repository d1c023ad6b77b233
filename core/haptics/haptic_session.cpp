#include "core/haptics/haptic_session.h"

#include "core/body/lattice_body.h"

#include <string>

namespace softtouch {

Result<std::unique_ptr<HapticLoop>> createHapticSession(const Scene& scene, std::size_t object,
                                                         std::unique_ptr<InputDevice> device,
                                                         const HapticSessionOptions& options) {
    if (object >= scene.objects.size())
        return Status::error("no object " + std::to_string(object) + " to drive (the scene has " +
                             std::to_string(scene.objects.size()) + ")");
    if (!device)
        return Status::error("no device to drive object '" + scene.objects[object].name + "' with");
    if (!(options.workspaceScale > 0.0 && options.workspaceScale <= 1e6))
        return Status::error("workspace scale must be in (0, 1e6], got " + std::to_string(options.workspaceScale));
    const SceneObject& o = scene.objects[object];
    auto model = buildLatticeBody(o.lattice, o.material);
    if (!model)
        return Status::error("object '" + o.name + "': " + model.message());

    HapticSettings settings;
    if (options.fitWorkspace) {
        const Bounds rest = boundsOf(o.lattice.restNodes());
        settings.calibration = DeviceCalibration::fit(device->info(), rest.min, rest.max);
        settings.calibration.scale *= options.workspaceScale;
    }
    settings.recordCapacity = options.recordCapacity;
    ExternalForces world;
    world.gravity = scene.world.gravity;
    world.planes = scene.world.planes;
    return HapticLoop::create(model.value(), scene.world.simulation, world, std::move(device), settings);
}

}  // namespace softtouch

#pragma once
/// A haptic session on one object of a scene: the one set-up the editor's device tool and
/// `softtouch-cli haptic` share, so both feel the same body under the same world. The loop gets its own
/// body built from the object's lattice and material, the scene's gravity, ground planes and simulation
/// settings, and the device's workspace fitted onto the object's lattice.

#include "core/haptics/haptic_loop.h"
#include "core/scene/scene.h"

#include <memory>

namespace softtouch {

/// How a session maps and records the device.
struct HapticSessionOptions {
    /// Fit the device's workspace box onto the lattice's rest nodes (centres matched, uniform scale);
    /// false keeps device metres as scene metres (identity calibration).
    bool fitWorkspace = true;
    /// Multiplies the fitted scale (the editor's workspace slider), (0, 1e6].
    double workspaceScale = 1.0;
    /// Ticks to record for a trajectory file; 0 records nothing.
    std::size_t recordCapacity = 0;
};

/// Creates the loop driving `scene.objects[object]` with `device` (not started). Errors name the object
/// (a bad material) or the setting.
Result<std::unique_ptr<HapticLoop>> createHapticSession(const Scene& scene, std::size_t object,
                                                         std::unique_ptr<InputDevice> device,
                                                         const HapticSessionOptions& options = {});

}  // namespace softtouch

#pragma once
/// Trajectory files (`*.sttraj`, JSON): what a scripted device replays and what a recorded session's
/// device samples are saved as. Layout and an example: docs/formats.md ("Trajectory").

#include "core/base/result.h"
#include "core/haptics/input_device.h"

#include <filesystem>
#include <vector>

namespace softtouch::io {

/// A trajectory: the device it claims to be and its samples in increasing time.
struct Trajectory {
    DeviceInfo device = scriptedDeviceInfo();  ///< From the optional "device" object; defaults otherwise.
    std::vector<DeviceSample> samples;         ///< At least one; times strictly increasing.
};

/// Reads a trajectory. Samples without velocities get them from the positions (central differences,
/// one-sided at the ends). Errors name the file, the JSON pointer and what was expected
/// ("walk.sttraj: /samples/3: expected a time after 0.25 s, got 0.2").
Result<Trajectory> loadTrajectory(const std::filesystem::path& path);

/// Writes a trajectory atomically (every sample with velocity, buttons, pressure and tilt; doubles
/// written with 17 significant digits, so a recording read back replays bit for bit).
Status saveTrajectory(const std::filesystem::path& path, const Trajectory& trajectory);

}  // namespace softtouch::io

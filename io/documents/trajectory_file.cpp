#include "io/documents/trajectory_file.h"

#include "io/files/atomic_file.h"
#include "io/files/json_reader.h"

#include <cmath>
#include <sstream>

namespace softtouch::io {

namespace {

constexpr const char* kFormat = "softtouch-trajectory";
constexpr int kTrajectoryVersion = 1;

/// Metres: a device's workspace box lies within this of its origin.
constexpr double kMaxWorkspace = 1000.0;

void readDevice(const JsonValue& v, DeviceInfo& info) {
    if (!v.expectObject()) return;
    v.checkKeys({"name", "degreesOfFreedom", "workspace", "maxForce", "stableStiffness", "buttons", "forceFeedback"});
    if (auto x = v["name"].string()) info.name = *x;
    if (auto x = v["degreesOfFreedom"].integer(0, 6)) info.degreesOfFreedom = *x;
    if (const JsonValue ws = v["workspace"]; ws.expectObject()) {
        ws.checkKeys({"min", "max"});
        const auto lo = ws["min"].vec3(true);
        const auto hi = ws["max"].vec3(true);
        if (lo && hi) {
            // A real device reaches metres at most; the coupling divides by the workspace's size, which
            // ±1e300 overflows (a bake of such a recording failed where validate passed it).
            if (lo->cwiseAbs().maxCoeff() > kMaxWorkspace || hi->cwiseAbs().maxCoeff() > kMaxWorkspace)
                ws.problem("expected a workspace within " + std::to_string(int(kMaxWorkspace)) + " m of the origin");
            else if (((*hi - *lo).array() < 0.0).any())
                ws["max"].problem("expected every component of max to be at least that of min");
            info.workspaceMin = *lo;
            info.workspaceMax = *hi;
        }
    }
    if (auto x = v["maxForce"].number(0.0, 1e4, "N")) info.maxForceN = *x;
    if (auto x = v["stableStiffness"].number(0.0, 1e6, "N/m")) info.stableStiffnessNPerM = *x;
    if (auto x = v["buttons"].integer(0, 32)) info.buttons = *x;
    if (auto x = v["forceFeedback"].boolean()) info.forceFeedback = *x;
}

/// Bound on every time, position and velocity in a trajectory, given or derived: what a recording of a
/// loaded trajectory writes stays inside it, so every recording reloads.
constexpr double kMaxMagnitude = 1e12;

std::optional<double> finiteAt(const JsonValue& sample, std::size_t i, const char* what) {
    const JsonValue v = sample.at(i);
    if (!v.isNumber()) {
        v.problem(std::string("expected a number (") + what + ")");
        return std::nullopt;
    }
    return v.number(-kMaxMagnitude, kMaxMagnitude, what);
}

}  // namespace

Result<Trajectory> loadTrajectory(const std::filesystem::path& path) {
    JsonIssues issues(path.string());
    const auto doc = parseJsonFile(path.string(), issues);
    if (!doc) return Status::error(issues.summary());
    const JsonValue root(&*doc, "", &issues);
    if (!root.expectObject(true)) return Status::error(issues.summary());
    root.checkKeys({"format", "version", "device", "samples"});
    const auto format = root["format"].string(true);
    if (format && *format != kFormat) root["format"].problem(std::string("expected \"") + kFormat + "\", got \"" + *format + "\"");
    if (const auto version = root["version"].integer(1, 1000000, true); version && *version > kTrajectoryVersion)
        root["version"].problem("version " + std::to_string(*version) + " was written by a newer SoftTouch; this build reads up to " +
                                std::to_string(kTrajectoryVersion));
    if (!issues.empty()) return Status::error(issues.summary());

    Trajectory trajectory;
    readDevice(root["device"], trajectory.device);
    const JsonValue samples = root["samples"];
    if (!samples.isArray() || samples.size() == 0) samples.problem("expected a non-empty array of samples");
    bool allVelocities = true;
    for (std::size_t i = 0; i < samples.size(); ++i) {
        const JsonValue s = samples.at(i);
        // [t, x, y, z] or [t, x, y, z, vx, vy, vz] or [t, x, y, z, vx, vy, vz, buttons, pressure, tiltX, tiltY]
        if (!s.isArray() || (s.size() != 4 && s.size() != 7 && s.size() != 11)) {
            s.problem("expected [t, x, y, z], [t, x, y, z, vx, vy, vz] or [t, x, y, z, vx, vy, vz, buttons, pressure, "
                      "tiltX, tiltY]");
            continue;
        }
        DeviceSample d;
        const auto t = finiteAt(s, 0, "time, s");
        if (!t) continue;
        if (!trajectory.samples.empty() && *t <= trajectory.samples.back().time) {
            std::ostringstream msg;
            msg.precision(17);
            msg << "expected a time after " << trajectory.samples.back().time << " s, got " << *t;
            s.at(0).problem(msg.str());
            continue;
        }
        d.time = *t;
        bool ok = true;
        for (int a = 0; a < 3; ++a) {
            const auto x = finiteAt(s, std::size_t(1 + a), "position, m");
            ok = ok && x.has_value();
            if (x) d.position[a] = *x;
        }
        if (s.size() >= 7) {
            for (int a = 0; a < 3; ++a) {
                const auto x = finiteAt(s, std::size_t(4 + a), "velocity, m/s");
                ok = ok && x.has_value();
                if (x) d.velocity[a] = *x;
            }
        } else {
            allVelocities = false;
        }
        if (s.size() == 11) {
            if (auto b = s.at(7).integer(0, 2147483647)) d.buttons = std::uint32_t(*b); else ok = false;
            if (auto p = s.at(8).number(0.0, 1.0, "pressure")) d.pressure = *p; else ok = false;
            if (auto x = s.at(9).number(-2.0, 2.0, "tilt, rad")) d.tiltX = *x; else ok = false;
            if (auto x = s.at(10).number(-2.0, 2.0, "tilt, rad")) d.tiltY = *x; else ok = false;
        }
        if (ok) trajectory.samples.push_back(d);
    }
    if (!issues.empty()) return Status::error(issues.summary());
    if (!allVelocities) {
        // Velocities from positions: central differences inside, one-sided at the ends.
        auto& s = trajectory.samples;
        const std::size_t n = s.size();
        for (std::size_t i = 0; i < n && n > 1; ++i) {
            const std::size_t a = i == 0 ? 0 : i - 1;
            const std::size_t b = i + 1 == n ? n - 1 : i + 1;
            s[i].velocity = (s[b].position - s[a].position) / (s[b].time - s[a].time);
            // A velocity the file could not hold would make a recording of this trajectory unreadable.
            if (!s[i].velocity.allFinite() || s[i].velocity.cwiseAbs().maxCoeff() > kMaxMagnitude) {
                std::ostringstream msg;
                msg.precision(3);
                msg << "moves " << (s[b].position - s[a].position).norm() << " m in " << (s[b].time - s[a].time)
                    << " s between samples " << a << " and " << b << ": faster than " << kMaxMagnitude
                    << " m/s on an axis, the most a trajectory can hold";
                samples.at(i).problem(msg.str());
                return Status::error(issues.summary());
            }
        }
    }
    return trajectory;
}

Status saveTrajectory(const std::filesystem::path& path, const Trajectory& trajectory) {
    nlohmann::json doc;
    doc["format"] = kFormat;
    doc["version"] = kTrajectoryVersion;
    const DeviceInfo& d = trajectory.device;
    doc["device"] = {{"name", d.name},
                     {"degreesOfFreedom", d.degreesOfFreedom},
                     {"workspace",
                      {{"min", {d.workspaceMin.x(), d.workspaceMin.y(), d.workspaceMin.z()}},
                       {"max", {d.workspaceMax.x(), d.workspaceMax.y(), d.workspaceMax.z()}}}},
                     {"maxForce", d.maxForceN},
                     {"stableStiffness", d.stableStiffnessNPerM},
                     {"buttons", d.buttons},
                     {"forceFeedback", d.forceFeedback}};
    // One sample per line: recordings stay diffable without the size of full indentation.
    std::string text = doc.dump();
    text.pop_back();  // the closing brace
    text += ",\"samples\":[";
    for (std::size_t i = 0; i < trajectory.samples.size(); ++i) {
        const DeviceSample& s = trajectory.samples[i];
        for (double x : {s.time, s.position.x(), s.position.y(), s.position.z(), s.velocity.x(), s.velocity.y(),
                         s.velocity.z(), s.pressure, s.tiltX, s.tiltY})
            if (!std::isfinite(x))
                return Status::error(path.string() + ": /samples/" + std::to_string(i) +
                                     ": holds a non-finite value; nothing was written");
        const nlohmann::json row = {s.time, s.position.x(), s.position.y(), s.position.z(), s.velocity.x(),
                                    s.velocity.y(), s.velocity.z(), s.buttons, s.pressure, s.tiltX, s.tiltY};
        text += (i == 0 ? "\n" : ",\n") + row.dump();
    }
    text += "\n]}\n";
    return writeFileAtomically(path, text);
}

}  // namespace softtouch::io

#pragma once
/// The haptic loop's achieved rate and period jitter on a real scene and on a ~1,000,000-triangle
/// one, while another thread deforms the mesh from the loop's snapshots at 60 Hz as the editor would.
/// The loop steps only the lattice, so its rate must not fall with the mesh size.

#include "core/scene/scene.h"

#include <nlohmann/json.hpp>

#include <ostream>
#include <string>

namespace softtouch::bench {

/// One scene to run the loop on.
struct HapticBenchScene {
    std::string name;      ///< Shown in the report.
    const Scene* scene;    ///< Object 0 is grabbed; its world gives gravity, planes and the integrator.
    Vec3 grabPoint;        ///< Material point grabbed, lattice parameters in [0,1]^3.
};

/// Runs the loop for `seconds` on each scene (plus the generated million-triangle ellipsoid) and
/// returns the "haptic" rows, each scene first with the loop alone, then with a 60 Hz mesh consumer:
/// [{scene, triangles, mesh_consumer, rate_hz, p50_period_ms, p99_period_ms, max_period_ms,
/// tick_p99_us, missed_deadlines, realtime, ticks, mesh_evaluations}].
/// `priority` is the SCHED_FIFO priority asked for (0: normal scheduling).
nlohmann::json hapticBench(const std::vector<HapticBenchScene>& scenes, double seconds, int priority, std::ostream& out);

}  // namespace softtouch::bench

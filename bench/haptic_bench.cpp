#include "bench/haptic_bench.h"

#include "core/body/lattice_body.h"
#include "core/geometry/binding.h"
#include "core/geometry/oriented_box.h"
#include "core/geometry/primitives.h"
#include "core/haptics/haptic_loop.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>

namespace softtouch::bench {
namespace {

using nlohmann::json;

/// A sphere of about a million triangles in a 4x4x4 lattice with the star's material, its bottom
/// layer heavy-anchored: 2·1000·(501 − 1) = 1,000,000 triangles.
Scene millionTriangleScene() {
    Scene scene;
    SceneObject object;
    object.name = "ellipsoid-1M";
    object.mesh = makeUvEllipsoid(501, 1000, Vec3(0.5, 0.4, 0.3));
    object.lattice = Lattice::create(LatticeShape{}, fitBox(object.mesh->positions).value()).value();
    object.material = uniformMaterial(object.lattice, 0.0002, 80.0, 0.3);
    object.material.nodeDamping.assign(object.material.mass.size(), 0.004);
    for (int k = 0; k < 4; ++k)
        for (int i = 0; i < 4; ++i) object.material.anchor[std::size_t(object.lattice.index(i, 0, k))] = AnchorMode::Heavy;
    scene.objects.push_back(std::move(object));
    scene.world.simulation.integrator = IntegratorKind::ImplicitEuler;
    return scene;
}

json runOne(const std::string& name, const Scene& scene, const Vec3& grabUvw, double seconds, bool deformMesh,
            int priority, std::ostream& out) {
    const SceneObject& object = scene.objects.front();
    auto model = buildLatticeBody(object.lattice, object.material);
    if (!model) {
        out << "  " << name << ": " << model.message() << "\n";
        return json{{"scene", name}, {"error", model.message()}};
    }
    // A scripted hand circling 5 cm around the grabbed point at 1 Hz, in scene coordinates.
    const Vec3 grab = object.lattice.evaluate(grabUvw, object.lattice.restNodes());
    std::vector<DeviceSample> samples;
    const int n = int(std::ceil((seconds + 1.0) * 1000.0));
    for (int i = 0; i <= n; ++i) {
        const double t = i * 1e-3, w = 2.0 * 3.141592653589793;
        DeviceSample s;
        s.time = t;
        s.position = grab + 0.05 * Vec3(std::sin(w * t), 1.0 - std::cos(w * t), 0.0);
        s.velocity = 0.05 * w * Vec3(std::cos(w * t), std::sin(w * t), 0.0);
        samples.push_back(s);
    }
    DeviceInfo info = scriptedDeviceInfo();
    HapticSettings settings;
    settings.statsWindow = int(seconds * 1000.0) + 1000;  // the whole run
    settings.coupling.stiffness = 20.0;
    settings.coupling.damping = 0.05;
    settings.realtimePriority = priority;  // granted only with CAP_SYS_NICE / an rtprio limit; reported either way
    ExternalForces world;
    world.gravity = scene.world.gravity;
    world.planes = scene.world.planes;
    SimulationSettings simulation = scene.world.simulation;
    simulation.sleep = false;
    auto loop = HapticLoop::create(model.value(), simulation, world,
                                   std::make_unique<TrajectoryDevice>(std::move(samples), info), settings);
    if (!loop) {
        out << "  " << name << ": " << loop.message() << "\n";
        return json{{"scene", name}, {"error", loop.message()}};
    }
    // The editor's side: bind the mesh, then deform it from the newest snapshot at 60 Hz on this
    // thread (one worker thread, so the loop keeps the machine's other core) while the loop runs.
    const Binding binding = Binding::create(object.lattice, object.mesh->positions, object.mesh->normals);
    std::vector<Vec3f> positions(binding.vertexCount()), normals(binding.vertexCount());
    HapticSnapshot snapshot;
    long long evaluations = 0;
    HapticLoop& l = *loop.value();
    l.post(HapticCommand::grab(object.lattice.weights(grabUvw)));
    l.start();
    const auto start = std::chrono::steady_clock::now();
    auto frame = start;
    while (std::chrono::steady_clock::now() - start < std::chrono::duration<double>(seconds)) {
        frame += std::chrono::microseconds(16667);
        if (l.readSnapshot(snapshot) && deformMesh) {
            binding.evaluate(snapshot.positions, positions, normals, 1);
            ++evaluations;
        }
        std::this_thread::sleep_until(frame);
    }
    l.stop();
    const HapticStats& s = l.stats();
    const std::size_t triangles = object.mesh->triangles.size();
    char line[300];
    std::snprintf(line, sizeof line,
                  "  %-14s %9zu triangles, %-12s %7.1f Hz  period p50 %.3f  p99 %.3f  max %.3f ms  tick p99 %.0f us  "
                  "missed %lld  mesh frames %lld%s\n",
                  name.c_str(), triangles, deformMesh ? "mesh 60 Hz:" : "loop alone:", s.rateHz, s.periodP50Ms, s.periodP99Ms, s.periodMaxMs, s.tickP99Us,
                  s.missedDeadlines, evaluations, s.realtime ? "  (SCHED_FIFO)" : "");
    out << line << std::flush;
    return json{{"scene", name},
                {"triangles", triangles},
                {"mesh_consumer", deformMesh},
                {"rate_hz", s.rateHz},
                {"p50_period_ms", s.periodP50Ms},
                {"p99_period_ms", s.periodP99Ms},
                {"max_period_ms", s.periodMaxMs},
                {"tick_p99_us", s.tickP99Us},
                {"missed_deadlines", s.missedDeadlines},
                {"realtime", s.realtime},
                {"ticks", s.ticks},
                {"mesh_evaluations", evaluations}};
}

}  // namespace

json hapticBench(const std::vector<HapticBenchScene>& scenes, double seconds, int priority, std::ostream& out) {
    out << "\nHaptic loop at 1 kHz (own thread; the mesh is deformed from its snapshots at 60 Hz on another), "
        << seconds << " s each\n";
    json rows = json::array();
    const Scene million = millionTriangleScene();
    std::vector<HapticBenchScene> all = scenes;
    all.push_back({"ellipsoid-1M", &million, Vec3(0.5, 1.0, 0.5)});
    // Each scene twice: the loop alone, then with the editor's side deforming the mesh at 60 Hz on
    // another thread (which competes for the cores, not for anything the loop touches).
    for (bool deform : {false, true})
        for (const HapticBenchScene& s : all) rows.push_back(runOne(s.name, *s.scene, s.grabPoint, seconds, deform, priority, out));
    return rows;
}

}  // namespace softtouch::bench

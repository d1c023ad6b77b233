// A simulation step allocates nothing once warmed up: the haptic loop steps the body at 1 kHz on a
// real-time thread, where a call into the allocator can block for longer than the period.
// Counts calls to malloc by interposing it (glibc); under AddressSanitizer, whose runtime owns
// malloc, the count is not available and the test says so.
#include "core/body/lattice_body.h"
#include "core/solver/simulator.h"

#include <QtTest>
#include <atomic>
#include <cmath>

// GCC says so with __SANITIZE_ADDRESS__, clang with __has_feature.
#if defined(__SANITIZE_ADDRESS__)
#define SOFTTOUCH_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SOFTTOUCH_UNDER_ASAN 1
#endif
#endif

#if defined(SOFTTOUCH_UNDER_ASAN)
#define SOFTTOUCH_COUNTS_MALLOC 0
#else
#define SOFTTOUCH_COUNTS_MALLOC 1
static std::atomic<long> g_mallocs{0};
extern "C" void* __libc_malloc(std::size_t size);
extern "C" void* malloc(std::size_t size) {
    g_mallocs.fetch_add(1, std::memory_order_relaxed);
    return __libc_malloc(size);
}
#endif

using namespace softtouch;

class TestAllocations : public QObject {
    Q_OBJECT
private slots:
    void stepAllocatesNothing_data();
    void stepAllocatesNothing();
};

void TestAllocations::stepAllocatesNothing_data() {
    QTest::addColumn<int>("integrator");
    QTest::addColumn<bool>("solidElement");
    for (IntegratorKind k : {IntegratorKind::SymplecticEuler, IntegratorKind::Verlet, IntegratorKind::ImplicitEuler,
                             IntegratorKind::Xpbd})
        QTest::newRow(std::string(integratorName(k)).c_str()) << int(k) << false;
    for (IntegratorKind k : {IntegratorKind::SymplecticEuler, IntegratorKind::Verlet, IntegratorKind::ImplicitEuler})
        QTest::newRow((std::string(integratorName(k)) + " (solid element)").c_str()) << int(k) << true;
}

void TestAllocations::stepAllocatesNothing() {
#if !SOFTTOUCH_COUNTS_MALLOC
    QSKIP("AddressSanitizer owns malloc: allocations cannot be counted in this build");
#else
    QFETCH(int, integrator);
    QFETCH(bool, solidElement);
    const Lattice lattice = Lattice::create({LatticeKind::Bezier, {4, 4, 4}}, OrientedBox{}).value();
    LatticeMaterial material = uniformMaterial(lattice, 0.02, 80.0, 0.9);
    if (solidElement) {  // a continuum material (the element's own scratch is the thread's, warmed up below)
        material = continuumMaterial(lattice, 1000.0, 5000.0, 20.0);
        material.nodeDamping.assign(material.mass.size(), 0.5);
        material.element = BodyElement::Solid;
    }
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 4; ++j)
            material.anchor[std::size_t(lattice.index(0, j, k))] = AnchorMode::Pinned;
    SimulationSettings settings;
    settings.integrator = IntegratorKind(integrator);
    Simulator sim(buildLatticeBody(lattice, material).value(), settings);
    // Everything a scene can ask for: gravity, a ground plane the body reaches, two hands.
    ExternalForces forces;
    forces.gravity = Vec3(0.0, -9.81, 0.0);
    CollisionPlane ground;
    ground.point = Vec3(0.0, -0.05, 0.0);
    forces.planes.push_back(ground);
    for (double w : {0.3, 0.8}) {
        DragSpring drag;
        drag.support = lattice.weights(Vec3(1.0, 0.5, w));
        drag.stiffness = 100.0;
        forces.drags.push_back(drag);
    }
    auto move = [&](int step) {
        for (std::size_t d = 0; d < forces.drags.size(); ++d)
            forces.drags[d].target = Vec3(1.1, 0.5 + 0.3 * std::sin(0.05 * step + double(d)), 0.4 * double(d + 1));
    };
    for (int step = 0; step < 20; ++step) {  // warm-up: work arrays take their sizes
        move(step);
        QVERIFY(sim.step(forces).problem.empty());
    }
    const long before = g_mallocs.load();
    int substeps = 0;
    for (int step = 20; step < 260; ++step) {
        move(step);
        substeps += sim.step(forces).substeps;
    }
    const long calls = g_mallocs.load() - before;
    QVERIFY(substeps >= 240);  // the body really stepped (never asleep, never refused)
    QVERIFY2(calls == 0, qPrintable(QString("%1 calls to malloc in 240 steps").arg(calls)));
#endif
}

QTEST_APPLESS_MAIN(TestAllocations)
#include "test_allocations.moc"

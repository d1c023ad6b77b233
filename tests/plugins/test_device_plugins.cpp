// The device plugins as the editor loads them: QPluginLoader over the build's plugin folder, found
// by interface; the null device when nothing is connected; the scripted device driving the loop.
#include "core/body/lattice_body.h"
#include "core/haptics/haptic_loop.h"
#include "io/documents/trajectory_file.h"
#include "plugins/device_registry.h"

#include <QTemporaryDir>
#include <QtTest/QtTest>

#include <fstream>

using namespace softtouch;

class TestDevicePlugins : public QObject {
    Q_OBJECT
private slots:
    void pluginsLoadByInterface();
    void nullDeviceWhenNothingIsConnected();
    void scriptedDeviceReplaysItsFile();
    void scriptedDeviceErrorsNameTheFile();
    void sdl2LoadsWithoutAPad();
    void notAPluginIsReported();
};

void TestDevicePlugins::pluginsLoadByInterface() {
    DeviceRegistry registry(SOFTTOUCH_DEVICE_PLUGIN_DIR);
    QStringList names;
    for (InputDevicePlugin* p : registry.plugins()) {
        QVERIFY(!p->name().isEmpty());
        QVERIFY(!p->description().isEmpty());
        QVERIFY2(!names.contains(p->name()), qPrintable("two plugins named " + p->name()));
        names << p->name();
    }
    QVERIFY2(registry.problems().isEmpty(), qPrintable(registry.problems().join("\n")));
    QVERIFY(names.contains("null"));
    QVERIFY(names.contains("scripted"));
    if (SOFTTOUCH_HAVE_SDL2_PLUGIN) QVERIFY(names.contains("sdl2"));
    QVERIFY(registry.plugin("null")->capabilities() & unsigned(DeviceCapability::Virtual));
    const unsigned scripted = registry.plugin("scripted")->capabilities();
    QVERIFY((scripted & unsigned(DeviceCapability::Virtual)) && (scripted & unsigned(DeviceCapability::NeedsArgument)));
    QCOMPARE(registry.plugin("nonexistent"), nullptr);
}

void TestDevicePlugins::nullDeviceWhenNothingIsConnected() {
    DeviceRegistry registry(SOFTTOUCH_DEVICE_PLUGIN_DIR);
    for (InputDevicePlugin* p : registry.plugins())
        if (!(p->capabilities() & unsigned(DeviceCapability::Virtual)) && p->deviceCount() > 0)
            QSKIP(qPrintable(QString("a %1 device is connected here").arg(p->name())));
    QString chosen;
    auto device = registry.open({}, 0, {}, &chosen);
    QVERIFY(device);
    QCOMPARE(chosen, QString("null"));
    QVERIFY(!device->info().forceFeedback);
    QCOMPARE(device->read(1.0).position, Vec3::Zero());
    // With no plugins at all the registry still gives core's null device.
    QTemporaryDir empty;
    DeviceRegistry none(empty.path());
    QVERIFY(none.plugins().isEmpty());
    auto fallback = none.open({}, 0, {}, &chosen);
    QVERIFY(fallback);
    QCOMPARE(chosen, QString("null"));
    // A named plugin that is not there is an error, not a silent null device.
    QString error;
    QVERIFY(!none.open("sdl2", 0, {}, &chosen, &error));
    QVERIFY2(error.contains("sdl2"), qPrintable(error));
}

void TestDevicePlugins::scriptedDeviceReplaysItsFile() {
    QTemporaryDir dir;
    io::Trajectory t;
    t.device.maxForceN = 2.0;
    for (int i = 0; i <= 200; ++i) {
        DeviceSample s;
        s.time = i * 0.001;
        s.position = Vec3(0.0, 0.03 * s.time / 0.2, 0.0);
        s.velocity = Vec3(0.0, 0.15, 0.0);
        t.samples.push_back(s);
    }
    const QString path = dir.filePath("lift.sttraj");
    QVERIFY(io::saveTrajectory(path.toStdString(), t).ok());
    DeviceRegistry registry(SOFTTOUCH_DEVICE_PLUGIN_DIR);
    QString error;
    auto device = registry.open("scripted", 0, path, nullptr, &error);
    QVERIFY2(device, qPrintable(error));
    QCOMPARE(device->info().maxForceN, 2.0);
    QCOMPARE(device->read(0.1).position, t.samples[100].position);

    // Through the loop: a body grabbed at the origin and lifted 3 cm pushes the hand back down.
    OrientedBox box;
    box.origin = Vec3(-0.05, -0.1, -0.05);
    box.size = Vec3::Constant(0.1);
    const Lattice lattice = Lattice::create(LatticeShape{}, box).value();
    LatticeMaterial material = uniformMaterial(lattice, 0.002, 80.0, 0.3);
    for (int k = 0; k < 4; ++k)
        for (int i = 0; i < 4; ++i) material.anchor[std::size_t(lattice.index(i, 0, k))] = AnchorMode::Pinned;
    auto loop = HapticLoop::create(buildLatticeBody(lattice, material).value(), SimulationSettings{}, ExternalForces{},
                                   std::move(device), HapticSettings{});
    QVERIFY2(loop.ok(), loop.message().c_str());
    loop.value()->post(HapticCommand::grab(lattice.weights(Vec3(0.5, 1.0, 0.5))));
    loop.value()->tickFor(200);
    HapticSnapshot snap;
    QVERIFY(loop.value()->readSnapshot(snap));
    QVERIFY2(snap.deviceForce.y() < -0.05, qPrintable(QString("force %1 N").arg(snap.deviceForce.y())));
    QVERIFY(snap.deviceForce.norm() <= 2.0 + 1e-12);
}

void TestDevicePlugins::scriptedDeviceErrorsNameTheFile() {
    DeviceRegistry registry(SOFTTOUCH_DEVICE_PLUGIN_DIR);
    QString error;
    QVERIFY(!registry.open("scripted", 0, {}, nullptr, &error));
    QVERIFY2(error.contains("trajectory file"), qPrintable(error));
    QTemporaryDir dir;
    const QString path = dir.filePath("broken.sttraj");
    std::ofstream(path.toStdString()) << R"({"format": "softtouch-trajectory", "version": 1, "samples": [[0, 1, 2]]})";
    QVERIFY(!registry.open("scripted", 0, path, nullptr, &error));
    QVERIFY2(error.contains("broken.sttraj") && error.contains("/samples/0"), qPrintable(error));
}

void TestDevicePlugins::sdl2LoadsWithoutAPad() {
    if (!SOFTTOUCH_HAVE_SDL2_PLUGIN) QSKIP("SDL2 was not found at configure time");
    DeviceRegistry registry(SOFTTOUCH_DEVICE_PLUGIN_DIR);
    InputDevicePlugin* sdl = registry.plugin("sdl2");
    QVERIFY(sdl);
    QVERIFY(sdl->capabilities() & unsigned(DeviceCapability::ForceFeedback));
    const int count = sdl->deviceCount();
    QVERIFY(count >= 0);
    QVERIFY(!sdl->createDevice(count, {}));  // one past the last
    QVERIFY2(sdl->errorString().contains("no joystick or gamepad"), qPrintable(sdl->errorString()));
}

void TestDevicePlugins::notAPluginIsReported() {
    QTemporaryDir dir;
    std::ofstream(dir.filePath("libfake.so").toStdString()) << "not a shared object";
    DeviceRegistry registry(dir.path());
    QVERIFY(registry.plugins().isEmpty());
    QCOMPARE(registry.problems().size(), 1);
    QVERIFY2(registry.problems().front().contains("libfake.so"), qPrintable(registry.problems().front()));
}

QTEST_GUILESS_MAIN(TestDevicePlugins)
#include "test_device_plugins.moc"

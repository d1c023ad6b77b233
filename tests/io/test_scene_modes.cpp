// The bundled anchored angelfish: the modes `softtouch-cli modes` and the editor show against its
// baked free vibration, with every integrator at a fine step.
#include "helpers/mode_measure.h"
#include "core/modes/modes.h"
#include "io/documents/project_file.h"

#include <QtTest>

#include <filesystem>

using namespace softtouch;

namespace {
const std::filesystem::path kScene = std::filesystem::path(SOFTTOUCH_SOURCE_DIR) / "presets/scenes/angelfish-swim.softtouch";
}

class TestSceneModes : public QObject {
    Q_OBJECT
private slots:
    void anchoredFishModesMatchBakedVibration_data() {
        QTest::addColumn<int>("integrator");
        for (IntegratorKind k : {IntegratorKind::SymplecticEuler, IntegratorKind::Verlet, IntegratorKind::ImplicitEuler,
                                 IntegratorKind::Xpbd})
            QTest::newRow(std::string(integratorName(k)).c_str()) << int(k);
    }
    void anchoredFishModesMatchBakedVibration() {
        QFETCH(int, integrator);
        auto project = io::loadProject(kScene);
        QVERIFY2(project.ok(), project.message().c_str());
        const SceneObject& fish = project->scene.objects.front();
        auto body = buildLatticeBody(fish.lattice, fish.material);
        QVERIFY2(body.ok(), body.message().c_str());
        const auto modes = analyseModes(*body.value(), 1);
        QVERIFY2(modes.ok(), modes.message().c_str());
        QCOMPARE(modes->rigidModes, 0);  // pinned at its tail end
        const VibrationMode& mode = modes->modes.front();
        SimulationSettings settings = project->scene.world.simulation;
        settings.integrator = IntegratorKind(integrator);
        settings.dt = 1.0 / (mode.frequencyHz * 2000.0);
        settings.xpbdSubsteps = 4;
        const int sampleEvery = 50;
        const FittedOscillation measured =
            test::measureMode(body.value(), settings, mode, 1e-3, 4.0 / mode.frequencyHz, sampleEvery);
        qInfo("%s: displayed %.4f Hz zeta %.4f; measured %.4f Hz zeta %.4f", QTest::currentDataTag(), mode.frequencyHz,
              mode.dampingRatio, measured.frequencyHz, measured.dampingRatio);
        QVERIFY(measured.oscillates);
        QVERIFY(std::abs(measured.frequencyHz / mode.dampedFrequencyHz() - 1.0) < 0.03);
        QVERIFY(std::abs(measured.dampingRatio / mode.dampingRatio - 1.0) < 0.10);
    }
};

QTEST_APPLESS_MAIN(TestSceneModes)
#include "test_scene_modes.moc"

// Setup presets: export an object's setup, apply it to the same mesh (identical scene) and to another
// fish on another lattice (remapped, valid, simulates); bad presets name the problem.
#include "core/modes/modes.h"
#include "io/documents/preset_file.h"
#include "io/documents/project_file.h"
#include "io/pipeline/bake.h"

#include <QTemporaryDir>
#include <QtTest>
#include <filesystem>
#include <fstream>

using namespace softtouch;
using namespace softtouch::io;

namespace {

const std::filesystem::path kPresets = std::filesystem::path(SOFTTOUCH_SOURCE_DIR) / "presets";

std::string readText(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), {});
}

std::filesystem::path inDir(const QTemporaryDir& dir, const std::string& name) {
    return std::filesystem::path(dir.path().toStdString()) / name;
}

/// The angelfish with painted maps: stiffness rising from tail to head, heavier belly nodes, node
/// damping (the rate, 1/s) strongest at the tail.
Project paintedAngelfish() {
    auto project = loadProject(kPresets / "scenes/angelfish-swim.softtouch");
    if (!project)
        qFatal("%s", project.message().c_str());
    SceneObject& o = project->scene.objects[0];
    for (int n = 0; n < o.lattice.nodeCount(); ++n) {
        const Vec3 uvw = o.lattice.restNodeParameters(n);
        o.material.stiffness[std::size_t(n)] = 30.0 + 60.0 * uvw.x();
        o.material.mass[std::size_t(n)] = uvw.y() < 0.5 ? 0.03 : 0.01;
        o.material.nodeDamping[std::size_t(n)] = 0.5 + 2.0 * (1.0 - uvw.x());
    }
    return project.value();
}

}  // namespace

class TestPresets : public QObject {
    Q_OBJECT
private slots:
    void exportThenApplyOnTheSameMeshIsIdentical();
    void applyOntoAnotherFishRemapsAndSimulates();
    void shippedSetupAppliesToEveryFish();
    void everyMaterialPresetWobblesAlikeOn4And8_data();
    void everyMaterialPresetWobblesAlikeOn4And8();
    void badPresetsNameTheProblem_data();
    void badPresetsNameTheProblem();
    void validateListsEveryProblemOfAPreset();
};

void TestPresets::exportThenApplyOnTheSameMeshIsIdentical() {
    QTemporaryDir dir;
    const Project source = paintedAngelfish();
    auto setup = setupFromProject(source, 0);
    QVERIFY2(setup.ok(), setup.message().c_str());
    QCOMPARE(setup->clips.size(), std::size_t(1));
    QVERIFY(saveSetupPreset(setup.value(), inDir(dir, "fish.stpreset")).ok());
    QVERIFY(validateFile(inDir(dir, "fish.stpreset")).empty());
    auto loaded = loadSetupPreset(inDir(dir, "fish.stpreset"));
    QVERIFY2(loaded.ok(), loaded.message().c_str());
    QCOMPARE(loaded->material.stiffness, source.scene.objects[0].material.stiffness);
    QCOMPARE(loaded->material.nodeDamping, source.scene.objects[0].material.nodeDamping);

    // Onto the plain angelfish scene (uniform material, its own drivers): the painted scene again.
    auto plain = loadProject(kPresets / "scenes/angelfish-swim.softtouch");
    QVERIFY(plain.ok());
    QVERIFY(plain->scene.objects[0].material.stiffness != source.scene.objects[0].material.stiffness);
    auto applied = applySetupPreset(loaded.value(), plain.value(), 0);
    QVERIFY2(applied.ok(), applied.message().c_str());
    QVERIFY(saveProject(source, inDir(dir, "source.softtouch")).ok());
    QVERIFY(saveProject(applied.value(), inDir(dir, "applied.softtouch")).ok());
    const std::string a = readText(inDir(dir, "source.softtouch")), b = readText(inDir(dir, "applied.softtouch"));
    QVERIFY(a.size() > 1000);
    QCOMPARE(b, a);
}

void TestPresets::applyOntoAnotherFishRemapsAndSimulates() {
    QTemporaryDir dir;
    auto setup = setupFromProject(paintedAngelfish(), 0);
    QVERIFY(setup.ok());
    // The guppy on a finer B-spline lattice along its body: 6x4x4 nodes instead of the preset's 4x4x4.
    auto guppy = loadProject(kPresets / "scenes/guppy-swim.softtouch");
    QVERIFY(guppy.ok());
    SceneObject& o = guppy->scene.objects[0];
    o.lattice = Lattice::create({LatticeKind::BSpline, {6, 4, 4}}, o.lattice.box()).value();
    o.material = uniformMaterial(o.lattice, 0.02, 80.0, 0.9);
    auto applied = applySetupPreset(setup.value(), guppy.value(), 0);
    QVERIFY2(applied.ok(), applied.message().c_str());
    const SceneObject& g = applied->scene.objects[0];
    QCOMPARE(g.material.stiffness.size(), std::size_t(96));
    // Anchors keep their extent in the material: the preset pins its head face (u = 1), so the guppy's
    // head face is pinned and nothing behind it, though its next layer (u = 8/9) is nearest to a preset
    // head node.
    int pinned = 0;
    for (int n = 0; n < 96; ++n) {
        const bool head = g.lattice.restNodeParameters(n).x() == 1.0;
        QCOMPARE(g.material.anchor[std::size_t(n)] == AnchorMode::Pinned, head);
        pinned += head;
    }
    QCOMPARE(pinned, 16);
    // The stiffness gradient survives the remap: the head side is stiffer than the tail side.
    QVERIFY(g.material.stiffness[std::size_t(g.lattice.index(5, 1, 1))] >
            g.material.stiffness[std::size_t(g.lattice.index(0, 1, 1))]);
    QVERIFY(g.material.nodeDamping[std::size_t(g.lattice.index(5, 1, 1))] <
            g.material.nodeDamping[std::size_t(g.lattice.index(0, 1, 1))]);
    QCOMPARE(g.drivers.size(), std::size_t(1));

    // It saves, reloads and bakes its swim cycle: finite, moving, seamless.
    QVERIFY(saveProject(applied.value(), inDir(dir, "guppy.softtouch")).ok());
    auto reloaded = loadProject(inDir(dir, "guppy.softtouch"));
    QVERIFY2(reloaded.ok(), reloaded.message().c_str());
    QCOMPARE(reloaded->scene.objects[0].lattice.nodeCount(), 96);
    auto frames = evaluateClip(reloaded->scene, reloaded->clips, *reloaded->clips.findClip("swim"));
    QVERIFY2(frames.ok(), frames.message().c_str());
    const SeamMeasure seam = measureSeam(frames.value());
    QVERIFY2(seam.medianStep > 1e-3, qPrintable(QString("median step %1 m").arg(seam.medianStep)));
    QVERIFY2(seam.localRatio < 1.5, qPrintable(QString("seam %1 x the steps beside it").arg(seam.localRatio)));
}

void TestPresets::shippedSetupAppliesToEveryFish() {
    auto setup = loadSetupPreset(kPresets / "setups/fish-swim.stpreset");
    QVERIFY2(setup.ok(), setup.message().c_str());
    QVERIFY(!setup->name.empty() && !setup->description.empty());
    // Read without saying which kind, each shipped preset comes back as the kind it is.
    const auto asAny = loadPreset(kPresets / "setups/fish-swim.stpreset");
    QVERIFY2(asAny.ok(), asAny.message().c_str());
    QVERIFY(std::holds_alternative<SetupPreset>(asAny.value()));
    QCOMPARE(std::get<SetupPreset>(asAny.value()).name, setup->name);
    const auto material = loadPreset(kPresets / "materials/jelly.stpreset");
    QVERIFY2(material.ok(), material.message().c_str());
    QVERIFY(std::holds_alternative<MaterialPreset>(material.value()));
    for (const char* scene : {"angelfish-swim", "demekin-swim", "guppy-swim"}) {
        auto project = loadProject(kPresets / "scenes" / (std::string(scene) + ".softtouch"));
        QVERIFY(project.ok());
        auto applied = applySetupPreset(setup.value(), project.value(), 0);
        QVERIFY2(applied.ok(), applied.message().c_str());
        auto sim = SceneSimulation::create(applied->scene);
        QVERIFY(sim.ok());
        sim->advanceTo(0.5);
        QVERIFY(sim->simulator(0).state().isFinite());
    }
}

void TestPresets::everyMaterialPresetWobblesAlikeOn4And8_data() {
    QTest::addColumn<QString>("preset");
    for (const auto& entry : std::filesystem::directory_iterator(kPresets / "materials"))
        if (entry.path().extension() == ".stpreset")
            QTest::newRow(entry.path().stem().string().c_str()) << QString::fromStdString(entry.path().string());
}

// A material preset means the same body on a coarse and a fine lattice: applied to the angelfish's box
// (head pinned, u >= 0.9) on Bezier 4x4x4 and 8x8x8, the lowest mode moves by at most 5%.
void TestPresets::everyMaterialPresetWobblesAlikeOn4And8() {
    QFETCH(QString, preset);
    auto loaded = loadMaterialPreset(preset.toStdString());
    QVERIFY2(loaded.ok(), loaded.message().c_str());
    auto project = loadProject(kPresets / "scenes/angelfish-swim.softtouch");
    QVERIFY2(project.ok(), project.message().c_str());
    const OrientedBox box = project->scene.objects[0].lattice.box();
    std::array<double, 2> hz{};
    for (int n : {4, 8}) {
        const Lattice lattice = Lattice::create({LatticeKind::Bezier, {n, n, n}}, box).value();
        LatticeMaterial m = defaultMaterial(lattice);
        for (int node = 0; node < lattice.nodeCount(); ++node)
            if (lattice.restNodeParameters(node).x() >= 0.9)
                m.anchor[std::size_t(node)] = AnchorMode::Pinned;
        const Status applied = applyMaterialPreset(loaded.value(), lattice, m);
        QVERIFY2(applied.ok(), applied.message().c_str());
        auto body = buildLatticeBody(lattice, m);
        QVERIFY2(body.ok(), body.message().c_str());
        auto modes = analyseModes(*body.value(), 1);
        QVERIFY2(modes.ok(), modes.message().c_str());
        hz[n == 4 ? 0 : 1] = modes->modes.front().frequencyHz;
    }
    qInfo("lowest mode: %.4f Hz on 4x4x4, %.4f Hz on 8x8x8", hz[0], hz[1]);
    QVERIFY2(std::abs(hz[1] / hz[0] - 1.0) <= 0.05, qPrintable(QString("%1 vs %2 Hz").arg(hz[0]).arg(hz[1])));
}

void TestPresets::badPresetsNameTheProblem_data() {
    QTest::addColumn<QString>("text");
    QTest::addColumn<QString>("expected");
    const QString head = R"({"format": "softtouch-preset", "version": 1, "kind": "setup", "name": "x", )";
    QTest::newRow("material kind") << R"({"format": "softtouch-preset", "version": 1, "kind": "material", "name": "x", "material": {}})"
                                   << "/kind: expected \"setup\"";
    QTest::newRow("no lattice") << head + R"("material": {}})" << "/lattice";
    QTest::newRow("map of the wrong size") << head + R"("lattice": {"nodes": [2, 2, 2]}, "material": {"stiffness": [1, 2, 3]}})"
                                           << "/material/stiffness: expected one value per lattice node (8), got 3";
    QTest::newRow("node damping map of the wrong size")
        << head + R"("lattice": {"nodes": [2, 2, 2]}, "material": {"airDamping": [0.1, 0.2]}})"
        << "/material/airDamping: expected one value per lattice node (8), got 2";
    QTest::newRow("negative node damping on a node")
        << head + R"("lattice": {"nodes": [2, 2, 2]}, "material": {"airDamping": [0, 0, 0, 0, 0, 0, 0, -1]}})"
        << "/material/airDamping/7: expected a number in [0, 1e+06] (N·s/m), got -1";
    QTest::newRow("node out of range") << head + R"("lattice": {"nodes": [2, 2, 2]}, "anchors": [{"nodes": [[2, 0, 0]]}]})"
                                       << "/anchors/0/nodes/0: node index out of range";
    QTest::newRow("session clip") << head + R"("lattice": {"nodes": [2, 2, 2]}, "clips": [{"name": "a", "source": "session", "of": "s"}]})"
                                  << "/clips/0/source: a setup preset carries drivers clips only";
    QTest::newRow("typo") << head + R"("lattice": {"nodes": [2, 2, 2]}, "driver": []})" << "driver";
    QTest::newRow("all void") << head + R"("lattice": {"nodes": [2, 2, 2]}, "voids": {"region": {"min": [0,0,0], "max": [1,1,1]}}})"
                              << "void";
}

void TestPresets::badPresetsNameTheProblem() {
    QFETCH(QString, text);
    QFETCH(QString, expected);
    QTemporaryDir dir;
    const auto path = inDir(dir, "bad.stpreset");
    std::ofstream(path, std::ios::binary) << text.toStdString();
    auto preset = loadSetupPreset(path);
    QVERIFY(!preset.ok());
    QVERIFY2(preset.message().find("bad.stpreset") != std::string::npos, preset.message().c_str());
    QVERIFY2(preset.message().find(expected.toStdString()) != std::string::npos, preset.message().c_str());
    // validateFile judges a file by its own kind: a valid material preset is fine as such.
    if (!text.contains(R"("kind": "material")"))
        QVERIFY(!validateFile(path).empty());
    // loadPreset goes by the kind the file declares: a setup's problems are the setup loader's own.
    const auto any = loadPreset(path);
    if (text.contains(R"("kind": "setup")")) {
        QVERIFY(!any.ok());
        QCOMPARE(any.message(), preset.message());
    }
}

// validateFile lists every problem of a preset of either kind, each with its own pointer (it used to give
// the loader's one-line summary: the first problem and how many more).
void TestPresets::validateListsEveryProblemOfAPreset() {
    QTemporaryDir dir;
    const auto setup = inDir(dir, "setup.stpreset");
    std::ofstream(setup, std::ios::binary)
        << R"({"format": "softtouch-preset", "version": 3, "kind": "setup", "name": "x", "lattice": {"nodes": [2, 2, 2]},
              "material": {"airDamping": -1}, "anchors": [{"nodes": [[2, 0, 0]]}], "driver": []})";
    const auto setupProblems = validateFile(setup);
    QVERIFY2(setupProblems.size() == 3, std::to_string(setupProblems.size()).c_str());
    for (const char* pointer : {"/material/airDamping", "/anchors/0/nodes/0", "driver"})
        QVERIFY2(std::any_of(setupProblems.begin(), setupProblems.end(),
                             [&](const std::string& p) { return p.find(pointer) != std::string::npos && p.find("setup.stpreset") != std::string::npos; }),
                 pointer);
    const auto material = inDir(dir, "material.stpreset");
    std::ofstream(material, std::ios::binary)
        << R"({"format": "softtouch-preset", "version": 3, "name": "m", "material": {"stiffness": [1, 2], "damping": -1}})";
    const auto materialProblems = validateFile(material);
    for (const char* pointer : {"/kind", "/material/stiffness", "/material/damping"})
        QVERIFY2(std::any_of(materialProblems.begin(), materialProblems.end(),
                             [&](const std::string& p) { return p.find(pointer) != std::string::npos; }),
                 pointer);
    QVERIFY(!loadMaterialPreset(material).ok());
}

QTEST_GUILESS_MAIN(TestPresets)
#include "test_presets.moc"

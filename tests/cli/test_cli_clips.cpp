// End to end: `bake --clip` and `preset export|apply` on the bundled fish.
#include "core/authoring/clip.h"
#include "io/documents/preset_file.h"
#include "io/documents/project_file.h"
#include "io/export/vertex_cache.h"

#include "helpers/cli_run.h"
#include "helpers/gltf_read.h"

#include <QDir>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QFile>
#include <QProcess>
#include <QTemporaryDir>
#include <QtTest>

using namespace softtouch;

namespace {

using test::Run;
using test::runCli;
const QString kPresets = QStringLiteral(SOFTTOUCH_SOURCE_DIR "/presets/");


}  // namespace

class TestCliClips : public QObject {
    Q_OBJECT
private slots:
    void bakeSwimClipOfEveryFish_data();
    void bakeSwimClipOfEveryFish();
    void unknownClipFails();
    void firstFramesOfALongClipAreTheClipsFirstFrames();
    void presetExportApplyBake();
    void materialPresetAppliesAsTheEditorAppliesIt();
    void badPresetWritesNothing();
    void gltfReadsUseTinygltfsOwnLibrary();
    void skinOnTheSourceRigKeepsTheSkeleton();
    void skinRigChoiceIsRefusedWhereItCannotHold();
};

void TestCliClips::bakeSwimClipOfEveryFish_data() {
    QTest::addColumn<QString>("scene");
    QTest::newRow("angelfish") << "angelfish-swim";
    QTest::newRow("demekin") << "demekin-swim";
    QTest::newRow("guppy") << "guppy-swim";
}

void TestCliClips::bakeSwimClipOfEveryFish() {
    QFETCH(QString, scene);
    QTemporaryDir dir;
    const QString out = dir.filePath("swim.pc2");
    const Run r = runCli({"bake", kPresets + "scenes/" + scene + ".softtouch", "--clip", "swim", "--out", out, "--quiet"});
    QVERIFY2(r.exitCode == 0, qPrintable(r.err));
    QVERIFY(r.out.contains("clip swim"));
    QVERIFY(r.out.contains("loop seam"));
    auto cache = io::readPc2(out.toStdString());
    QVERIFY2(cache.ok(), cache.message().c_str());
    QCOMPARE(cache->frames.size(), std::size_t(24));
    // The seam on the mesh the file holds.
    std::vector<std::vector<Vec3>> frames;
    for (const auto& f : cache->frames) {
        std::vector<Vec3> points;
        for (const Vec3f& p : f)
            points.push_back(p.cast<double>());
        frames.push_back(std::move(points));
    }
    const SeamMeasure seam = measureSeam(frames);
    QVERIFY2(seam.ratio <= 1.5, qPrintable(QString("seam %1 x median").arg(seam.ratio)));
    // --frames 48 on a loop clip plays the cycle twice.
    const QString twice = dir.filePath("twice.pc2");
    QCOMPARE(runCli({"bake", kPresets + "scenes/" + scene + ".softtouch", "--clip", "swim", "--out", twice, "--frames", "48",
                     "--quiet"}).exitCode, 0);
    auto cycled = io::readPc2(twice.toStdString());
    QVERIFY(cycled.ok());
    QCOMPARE(cycled->frames.size(), std::size_t(48));
    QVERIFY(cycled->frames[30] == cache->frames[6]);
}

// `bake --frames 12` of a 100,000-frame clip evaluates 12 frames, not the clip (it took 40 s and 511 MB),
// and they are exactly the first 12 frames of the clip baked whole.
void TestCliClips::firstFramesOfALongClipAreTheClipsFirstFrames() {
    QTemporaryDir dir;
    QVERIFY(QDir(dir.path()).mkdir("scenes"));
    for (const char* folder : {"meshes", "materials"})
        QVERIFY(QFile::link(kPresets + folder, dir.filePath(folder)));
    QFile source(kPresets + "scenes/angelfish-swim.softtouch");
    QVERIFY(source.open(QIODevice::ReadOnly));
    QString text = QString::fromUtf8(source.readAll());
    const QString swim = R"({"name": "swim",)";
    QVERIFY(text.contains(swim));
    text.replace(swim, R"({"name": "long", "source": "drivers", "frames": 100000, "fps": 24},
                         {"name": "short", "source": "drivers", "frames": 30, "fps": 24}, )" + swim);
    QFile scene(dir.filePath("scenes/fish.softtouch"));
    QVERIFY(scene.open(QIODevice::WriteOnly) && scene.write(text.toUtf8()) > 0);
    scene.close();

    const Run whole = runCli({"bake", scene.fileName(), "--clip", "short", "--out", dir.filePath("short.pc2"), "--quiet"});
    QVERIFY2(whole.exitCode == 0, qPrintable(whole.err));
    const Run first = runCli({"bake", scene.fileName(), "--clip", "long", "--frames", "12", "--out", dir.filePath("long.pc2"), "--quiet"});
    QVERIFY2(first.exitCode == 0, qPrintable(first.err));
    auto all = io::readPc2(dir.filePath("short.pc2").toStdString());
    auto twelve = io::readPc2(dir.filePath("long.pc2").toStdString());
    QVERIFY(all.ok() && twelve.ok());
    QCOMPARE(twelve->frames.size(), std::size_t(12));
    for (std::size_t f = 0; f < 12; ++f)
        QVERIFY2(twelve->frames[f] == all->frames[f], qPrintable(QString("frame %1 differs").arg(f)));
}

void TestCliClips::unknownClipFails() {
    QTemporaryDir dir;
    const QString out = dir.filePath("x.pc2");
    const Run r = runCli({"bake", kPresets + "scenes/guppy-swim.softtouch", "--clip", "walk", "--out", out, "--quiet"});
    QCOMPARE(r.exitCode, 1);
    QVERIFY2(r.err.contains("no clip named 'walk' (the scene has: swim)"), qPrintable(r.err));
    QVERIFY(!QFile::exists(out));
    const Run fps = runCli({"bake", kPresets + "scenes/guppy-swim.softtouch", "--clip", "swim", "--fps", "30", "--out", out});
    QCOMPARE(fps.exitCode, 1);
    QVERIFY2(fps.err.contains("plays at 24"), qPrintable(fps.err));
}

void TestCliClips::presetExportApplyBake() {
    QTemporaryDir dir;
    const QString preset = dir.filePath("angelfish.stpreset");
    const Run exported = runCli({"preset", "export", kPresets + "scenes/angelfish-swim.softtouch", "--out", preset,
                                 "--name", "Angelfish swim"});
    QVERIFY2(exported.exitCode == 0, qPrintable(exported.err));
    QVERIFY(runCli({"validate", preset}).exitCode == 0);
    // Onto the same scene: the same project as saving it directly would give.
    const QString same = dir.filePath("same.softtouch");
    QCOMPARE(runCli({"preset", "apply", preset, kPresets + "scenes/angelfish-swim.softtouch", "--out", same}).exitCode, 0);
    auto original = io::loadProject((kPresets + "scenes/angelfish-swim.softtouch").toStdString());
    QVERIFY(original.ok());
    const QString direct = dir.filePath("direct.softtouch");
    QVERIFY(io::saveProject(original.value(), direct.toStdString()).ok());
    QFile a(same), b(direct);
    QVERIFY(a.open(QIODevice::ReadOnly) && b.open(QIODevice::ReadOnly));
    QCOMPARE(a.readAll(), b.readAll());
    // Onto the demekin: a valid project that bakes.
    const QString demekin = dir.filePath("demekin.softtouch");
    const Run applied = runCli({"preset", "apply", preset, kPresets + "scenes/demekin-swim.softtouch", "--out", demekin});
    QVERIFY2(applied.exitCode == 0, qPrintable(applied.err));
    QVERIFY(runCli({"validate", demekin}).exitCode == 0);
    const Run baked = runCli({"bake", demekin, "--clip", "swim", "--out", dir.filePath("d.pc2"), "--quiet"});
    QVERIFY2(baked.exitCode == 0, qPrintable(baked.err));
}

// A material preset (presets/materials) applies from the command line too, the same as the editor's Presets dock
// applies it (io::applyMaterialPreset on every node): it was refused as "not a setup".
void TestCliClips::materialPresetAppliesAsTheEditorAppliesIt() {
    QTemporaryDir dir;
    const QString scene = kPresets + "scenes/guppy-swim.softtouch", preset = kPresets + "materials/jelly.stpreset";
    const QString out = dir.filePath("jelly.softtouch");
    const Run applied = runCli({"preset", "apply", preset, scene, "--out", out});
    QVERIFY2(applied.exitCode == 0, qPrintable(applied.err));
    QVERIFY2(applied.out.contains("material 'Jelly' on 'guppy'"), qPrintable(applied.out));
    auto written = io::loadProject(out.toStdString());
    auto original = io::loadProject(scene.toStdString());
    auto jelly = io::loadMaterialPreset(preset.toStdString());
    QVERIFY(written.ok() && original.ok() && jelly.ok());
    SceneObject& o = original->scene.objects[0];
    QVERIFY(io::applyMaterialPreset(jelly.value(), o.lattice, o.material).ok());
    QVERIFY(written->scene.objects[0].material == o.material);
    QVERIFY(!(written->scene.objects[0].material == io::loadProject(scene.toStdString())->scene.objects[0].material));
    QVERIFY(runCli({"bake", out, "--clip", "swim", "--frames", "4", "--out", dir.filePath("j.pc2"), "--quiet"}).exitCode == 0);
}

void TestCliClips::badPresetWritesNothing() {
    QTemporaryDir dir;
    const QString bad = dir.filePath("bad.stpreset");
    QFile f(bad);
    QVERIFY(f.open(QIODevice::WriteOnly));
    f.write(R"({"format": "softtouch-preset", "version": 1, "kind": "setup", "name": "x", "lattice": {"nodes": [4, 4, 4]},
               "material": {"stiffness": -5}})");
    f.close();
    const QString out = dir.filePath("new.softtouch");
    const Run r = runCli({"preset", "apply", bad, kPresets + "scenes/guppy-swim.softtouch", "--out", out});
    QCOMPARE(r.exitCode, 1);
    QVERIFY2(r.err.contains("bad.stpreset") && r.err.contains("/material/stiffness"), qPrintable(r.err));
    QVERIFY(!QFile::exists(out));
    QCOMPARE(runCli({"preset", "explode"}).exitCode, 2);
    QCOMPARE(runCli({"preset", "export", kPresets + "scenes/guppy-swim.softtouch"}).exitCode, 2);
    const Run noObject = runCli({"preset", "export", kPresets + "scenes/guppy-swim.softtouch", "--object", "shark", "--out",
                                 dir.filePath("p.stpreset")});
    QCOMPARE(noObject.exitCode, 1);
    QVERIFY2(noObject.err.contains("no object named 'shark'"), qPrintable(noObject.err));
}


// libdraco (which assimp links) exports a tinygltf of its own, built with other options: its TinyGLTF has
// another layout. softtouch-cli once bound its glTF reads to it (libdraco came first among the libraries it
// loads), which worked by luck; a test program that did the same crashed. The dynamic linker's own report
// (LD_DEBUG=bindings) of `preview` reading a GLB says where every tinygltf call of the program goes.
void TestCliClips::gltfReadsUseTinygltfsOwnLibrary() {
    QTemporaryDir dir;
    const QString glb = dir.filePath("swim.glb");
    QCOMPARE(runCli({"bake", kPresets + "scenes/guppy-swim.softtouch", "--clip", "swim", "--frames", "4", "--format", "skin",
                     "--out", glb, "--quiet"}).exitCode, 0);
    QProcess preview;
    QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
    env.insert("LD_DEBUG", "bindings");
    env.insert("LD_DEBUG_OUTPUT", dir.filePath("bindings"));
    preview.setProcessEnvironment(env);
    preview.start(test::kCli, {"preview", glb, "--out", dir.filePath("page")});
    QVERIFY(preview.waitForFinished(120000));
    QVERIFY2(preview.exitCode() == 0, preview.readAllStandardError().constData());
    int toTinygltf = 0;
    QStringList elsewhere;
    for (const QString& name : QDir(dir.path()).entryList({"bindings.*"}, QDir::Files)) {
        QFile log(dir.filePath(name));
        QVERIFY(log.open(QIODevice::ReadOnly));
        for (const QByteArray& line : log.readAll().split('\n')) {
            // "binding file PROGRAM [0] to LIBRARY [0]: normal symbol `_ZN8tinygltf..."
            if (!line.contains("softtouch-cli [0] to ") || !line.contains("`_ZN8tinygltf"))
                continue;
            if (line.contains("libtinygltf.so"))
                ++toTinygltf;
            else
                elsewhere << QString::fromUtf8(line.trimmed());
        }
    }
    QVERIFY2(elsewhere.isEmpty(), qPrintable(elsewhere.join('\n')));
    QVERIFY2(toTinygltf > 0, "the dynamic linker reported no tinygltf binding of softtouch-cli");
}

namespace {

/// The node of `model` named `name`; -1 when none is.
int nodeNamed(const tinygltf::Model& model, const std::string& name) {
    for (std::size_t n = 0; n < model.nodes.size(); ++n)
        if (model.nodes[n].name == name)
            return int(n);
    return -1;
}

/// The parent of node `child`; -1 for a top-level node.
int parentOf(const tinygltf::Model& model, int child) {
    for (std::size_t n = 0; n < model.nodes.size(); ++n)
        for (int c : model.nodes[n].children)
            if (c == child)
                return int(n);
    return -1;
}

/// A node's translation, rotation and scale as ten numbers (the identity's where the file leaves one out).
std::vector<double> restOf(const tinygltf::Node& node) {
    std::vector<double> t = node.translation.empty() ? std::vector<double>{0, 0, 0} : node.translation;
    const std::vector<double> r = node.rotation.empty() ? std::vector<double>{0, 0, 0, 1} : node.rotation;
    const std::vector<double> s = node.scale.empty() ? std::vector<double>{1, 1, 1} : node.scale;
    t.insert(t.end(), r.begin(), r.end());
    t.insert(t.end(), s.begin(), s.end());
    return t;
}

double largestDifference(const std::vector<double>& a, const std::vector<double>& b) {
    double d = a.size() == b.size() ? 0.0 : 1e30;
    for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
        d = std::max(d, std::abs(a[i] - b[i]));
    return d;
}

}  // namespace

// A skinned export of the rigged guppy keeps the skeleton it was imported with: every joint by name, under the
// same parent, with its rest transform and inverse bind matrix, the file's bind mesh, and at most 16 helper bones
// hung under source joints. With goal weight 1 everywhere the clip is the rig's own motion, and no helper is added.
void TestCliClips::skinOnTheSourceRigKeepsTheSkeleton() {
    QTemporaryDir dir;
    const Run baked = runCli({"bake", kPresets + "scenes/guppy-rigged.softtouch", "--clip", "swim", "--format", "skin",
                              "--out", dir.filePath("g.glb"), "--quiet"});
    QVERIFY2(baked.exitCode == 0, qPrintable(baked.err));
    QVERIFY2(baked.out.contains("skinned onto the source rig: its 6 joints kept"), qPrintable(baked.out));
    const tinygltf::Model ours = test::loadGlb(dir.filePath("g.glb").toStdString());
    const tinygltf::Model theirs = test::loadGlb((kPresets + "meshes/guppy-rigged.glb").toStdString());
    QCOMPARE(ours.skins.size(), std::size_t(1));
    const tinygltf::Skin& skin = ours.skins.front();
    const tinygltf::Skin& source = theirs.skins.front();
    const std::vector<float> ourBinds = test::accessorFloats(ours, skin.inverseBindMatrices);
    const std::vector<float> theirBinds = test::accessorFloats(theirs, source.inverseBindMatrices);
    for (std::size_t j = 0; j < source.joints.size(); ++j) {
        const tinygltf::Node& joint = theirs.nodes[std::size_t(source.joints[j])];
        const int mine = skin.joints.at(j);
        QCOMPARE(ours.nodes[std::size_t(mine)].name, joint.name);
        const int theirParent = parentOf(theirs, source.joints[j]);
        const int ourParent = parentOf(ours, mine);
        QCOMPARE(ourParent < 0 ? std::string() : ours.nodes[std::size_t(ourParent)].name,
                 theirParent < 0 ? std::string() : theirs.nodes[std::size_t(theirParent)].name);
        QVERIFY2(largestDifference(restOf(ours.nodes[std::size_t(mine)]), restOf(joint)) < 1e-6, joint.name.c_str());
        for (std::size_t e = 0; e < 16; ++e)
            QVERIFY(std::abs(ourBinds[16 * j + e] - theirBinds[16 * j + e]) < 1e-6f);
    }
    const std::size_t helpers = skin.joints.size() - source.joints.size();
    QVERIFY2(helpers <= 16, qPrintable(QString::number(helpers)));
    for (std::size_t h = source.joints.size(); h < skin.joints.size(); ++h) {
        const int parent = parentOf(ours, skin.joints[h]);
        QVERIFY(parent >= 0);
        QVERIFY2(nodeNamed(theirs, ours.nodes[std::size_t(parent)].name) >= 0, "a helper hangs under a source joint");
    }
    // The bind mesh is the file's, vertex for vertex.
    const auto position = [](const tinygltf::Model& m) {
        return test::accessorFloats(m, m.meshes.front().primitives.front().attributes.at("POSITION"));
    };
    const std::vector<float> ourBind = position(ours), theirBind = position(theirs);
    QCOMPARE(ourBind.size(), theirBind.size());
    for (std::size_t e = 0; e < ourBind.size(); ++e)
        QVERIFY(std::abs(ourBind[e] - theirBind[e]) < 1e-6f);

    // Goal weight 1 everywhere: the clip is the rig's motion itself.
    QFile file(kPresets + "scenes/guppy-rigged.softtouch");
    QVERIFY(file.open(QIODevice::ReadOnly));
    QJsonObject project = QJsonDocument::fromJson(file.readAll()).object();
    QJsonArray objects = project["objects"].toArray();
    QJsonObject fish = objects[0].toObject();
    fish["mesh"] = kPresets + "meshes/guppy-rigged.glb";
    QJsonObject material = fish["material"].toObject();
    material["preset"] = kPresets + "materials/fish-body.stpreset";
    QJsonArray ones;
    for (qsizetype i = 0; i < material["goalWeight"].toArray().size(); ++i)
        ones.append(1.0);
    material["goalWeight"] = ones;
    fish["material"] = material;
    objects[0] = fish;
    project["objects"] = objects;
    QFile pinned(dir.filePath("pinned.softtouch"));
    QVERIFY(pinned.open(QIODevice::WriteOnly));
    pinned.write(QJsonDocument(project).toJson());
    pinned.close();
    const Run still = runCli({"bake", pinned.fileName(), "--clip", "swim", "--format", "skin", "--out", dir.filePath("p.glb"),
                              "--quiet"});
    QVERIFY2(still.exitCode == 0, qPrintable(still.err));
    QVERIFY2(still.out.contains("its 6 joints kept (names, hierarchy, bind pose, animation) and 0 helper bones"),
             qPrintable(still.out));
    QCOMPARE(test::loadGlb(dir.filePath("p.glb").toStdString()).skins.front().joints.size(), source.joints.size());
}

// --rig source says why where there is no rig to keep; --rig fitted fits free bones; --rig is for skin only.
void TestCliClips::skinRigChoiceIsRefusedWhereItCannotHold() {
    QTemporaryDir dir;
    const Run noRig = runCli({"bake", kPresets + "scenes/angelfish-swim.softtouch", "--clip", "swim", "--format", "skin",
                              "--rig", "source", "--out", dir.filePath("a.glb"), "--quiet"});
    QVERIFY(noRig.exitCode != 0);
    QVERIFY2(noRig.err.contains("--rig source: object 'angelfish' has no base animation"), qPrintable(noRig.err));
    QVERIFY(!QFile::exists(dir.filePath("a.glb")));
    const Run fitted = runCli({"bake", kPresets + "scenes/guppy-rigged.softtouch", "--clip", "swim", "--format", "skin",
                               "--rig", "fitted", "--out", dir.filePath("f.glb"), "--quiet"});
    QVERIFY2(fitted.exitCode == 0, qPrintable(fitted.err));
    QVERIFY2(fitted.out.contains("skinned: ") && fitted.out.contains("rigid bones"), qPrintable(fitted.out));
    const Run wrongFormat = runCli({"bake", kPresets + "scenes/guppy-rigged.softtouch", "--rig", "source", "--out",
                                    dir.filePath("g.pc2"), "--quiet"});
    QCOMPARE(wrongFormat.exitCode, 2);
    QVERIFY2(wrongFormat.err.contains("--rig"), qPrintable(wrongFormat.err));
    const Run badName = runCli({"bake", kPresets + "scenes/guppy-rigged.softtouch", "--format", "skin", "--rig", "bones",
                                "--out", dir.filePath("g.glb"), "--quiet"});
    QCOMPARE(badName.exitCode, 2);
    QVERIFY2(badName.err.contains("expects auto, source or fitted"), qPrintable(badName.err));
}

QTEST_GUILESS_MAIN(TestCliClips)
#include "test_cli_clips.moc"

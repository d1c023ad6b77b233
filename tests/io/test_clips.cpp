// The clip library in project files (version 2) and the fish swim cycles: seamless loops, sessions
// and keyframes that survive a save, clear errors on bad clips.
#include "core/authoring/session.h"
#include "io/documents/project_file.h"
#include "io/pipeline/bake.h"

#include <QTemporaryDir>
#include <QtTest>
#include <fstream>

using namespace softtouch;
using namespace softtouch::io;

namespace {

const std::filesystem::path kPresets = std::filesystem::path(SOFTTOUCH_SOURCE_DIR) / "presets";

std::filesystem::path writeFile(const QTemporaryDir& dir, const std::string& name, const std::string& text) {
    const std::filesystem::path path = std::filesystem::path(dir.path().toStdString()) / name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

std::string readText(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), {});
}

/// A guppy project with `rootExtra` added at the top level, at `version`.
std::string projectText(int version, const std::string& rootExtra) {
    return R"({"format": "softtouch-project", "version": )" + std::to_string(version) + R"(,
      "objects": [{"name": "fish", "mesh": ")" + (kPresets / "meshes/guppy.obj").string() + R"(",
                   "lattice": {"nodes": [4, 4, 4]},
                   "drivers": [{"type": "swim", "point": [0, 0.5, 0.5], "frequency": 1, "amplitude": 0.1}]}])" +
           rootExtra + "}";
}

/// Bakes a clip to PC2 and reads the mesh frames back.
std::vector<std::vector<Vec3>> bakeMeshFrames(const Project& project, const std::string& clip, const QTemporaryDir& dir) {
    BakeOptions options;
    options.output = std::filesystem::path(dir.path().toStdString()) / (clip + ".pc2");
    options.clips = &project.clips;
    options.clip = clip;
    auto result = bake(project.scene, options);
    if (!result)
        qFatal("%s", result.message().c_str());
    auto cache = readPc2(options.output);
    if (!cache)
        qFatal("%s", cache.message().c_str());
    std::vector<std::vector<Vec3>> frames;
    for (const auto& f : cache->frames) {
        std::vector<Vec3> points;
        for (const Vec3f& p : f)
            points.push_back(p.cast<double>());
        frames.push_back(std::move(points));
    }
    return frames;
}

}  // namespace

class TestClips : public QObject {
    Q_OBJECT
private slots:
    void fishSwimCyclesAreSeamless_data();
    void fishSwimCyclesAreSeamless();
    void loopClosureRemovesThePop();
    void libraryRoundTripsAndSessionsReplayExactly();
    void versionOneStillReads();
    void badClipsNameTheProblem_data();
    void badClipsNameTheProblem();
};

void TestClips::fishSwimCyclesAreSeamless_data() {
    QTest::addColumn<QString>("scene");
    QTest::newRow("angelfish") << "angelfish-swim";
    QTest::newRow("demekin") << "demekin-swim";
    QTest::newRow("guppy") << "guppy-swim";
}

void TestClips::fishSwimCyclesAreSeamless() {
    QFETCH(QString, scene);
    auto project = loadProject(kPresets / "scenes" / (scene.toStdString() + ".softtouch"));
    QVERIFY2(project.ok(), project.message().c_str());
    const Clip* swim = project->clips.findClip("swim");
    QVERIFY(swim);
    QVERIFY(swim->loop);
    QCOMPARE(swim->seconds(), 1.0);
    QTemporaryDir dir;
    // Measured on the baked mesh, as a game engine plays it: frame 23 -> frame 0.
    const auto frames = bakeMeshFrames(project.value(), "swim", dir);
    QCOMPARE(frames.size(), std::size_t(24));
    const SeamMeasure seam = measureSeam(frames);
    qInfo("%s swim: seam jump %.5f m, median step %.5f m, ratio %.3f, beside-seam ratio %.3f", qPrintable(scene), seam.jump,
          seam.medianStep, seam.ratio, seam.localRatio);
    QVERIFY2(seam.medianStep > 1e-3, "the fish hardly moves");
    QVERIFY2(seam.ratio <= 1.5, qPrintable(QString("seam %1 x the median step").arg(seam.ratio)));
    QVERIFY2(seam.localRatio <= 1.5, qPrintable(QString("seam %1 x the steps beside it").arg(seam.localRatio)));
}

void TestClips::loopClosureRemovesThePop() {
    // A cycle cut while the swim is still fading in does not repeat: without closure the seam pops.
    auto project = loadProject(kPresets / "scenes/angelfish-swim.softtouch");
    QVERIFY(project.ok());
    Clip clip = *project->clips.findClip("swim");
    clip.startSeconds = 0.25;
    clip.blendFrames = 0;
    auto open = evaluateClip(project->scene, project->clips, clip);
    QVERIFY2(open.ok(), open.message().c_str());
    clip.blendFrames = 6;
    auto closed = evaluateClip(project->scene, project->clips, clip);
    QVERIFY(closed.ok());
    const SeamMeasure before = measureSeam(open.value()), after = measureSeam(closed.value());
    qInfo("unclosed ratio %.3f, closed %.3f", before.ratio, after.ratio);
    QVERIFY2(before.ratio > 2.0, qPrintable(QString("unclosed seam only %1 x").arg(before.ratio)));
    QVERIFY2(after.ratio < 1.0 && after.localRatio < 1.5, qPrintable(QString("closed seam %1 x").arg(after.ratio)));
    // Only the blend window changed: the first frames are untouched.
    for (std::size_t f = 0; f < 24 - 6; ++f)
        QVERIFY(open->nodes[f][0] == closed->nodes[f][0]);
    QVERIFY(open->nodes[20][0] != closed->nodes[20][0]);
}

void TestClips::libraryRoundTripsAndSessionsReplayExactly() {
    QTemporaryDir dir;
    auto loaded = loadProject(kPresets / "scenes/guppy-swim.softtouch");
    QVERIFY2(loaded.ok(), loaded.message().c_str());
    Project project = loaded.value();

    // Record a session with a mouse pulling the head sideways on top of the swim.
    auto created = SceneSimulation::create(project.scene);
    QVERIFY(created.ok());
    SceneSimulation& sim = created.value();
    const Lattice& lattice = sim.object(0).lattice;
    sim.advanceTo(0.2);
    SessionRecorder recorder;
    recorder.begin(sim);
    for (int f = 1; f <= 24; ++f) {
        if (f >= 4 && f < 14) {
            DragSpring drag;
            drag.support = lattice.weights(Vec3(0.8, 0.5, 0.5));
            drag.target = lattice.evaluate(Vec3(0.8, 0.5, 0.5), lattice.restNodes()) + Vec3(0, 0, 0.01 * f);
            drag.targetVelocity = Vec3(0, 0, 0.24);
            drag.stiffness = 30.0;
            sim.setInteractiveDrags(0, {drag});
        } else if (f == 14) {
            sim.setInteractiveDrags(0, {});
        }
        recorder.recordStep(sim);
        sim.advanceTo(0.2 + f / 24.0);
    }
    const BodyState live = sim.simulator(0).state();
    project.clips.sessions.push_back({"take 1", recorder.finish(sim)});

    // Keys: the tail node layer up, then back.
    KeyframeAnimation keys(std::size_t(lattice.nodeCount()));
    const std::vector<Vec3> rest = lattice.restNodes();
    std::vector<Vec3> up = rest;
    for (Vec3& p : up)
        p.y() += 0.05;
    QVERIFY(keys.setKey(0.0, rest, rest, {0, 4, 8, 12}).ok());
    QVERIFY(keys.setKey(0.5, rest, up, {0, 4, 8, 12}).ok());
    QVERIFY(keys.setInterpolation(0, KeyInterpolation::Constant).ok());
    project.clips.keyframes.push_back({"flick", {keys}});
    project.clips.clips.push_back(Clip{"take", ClipSource::Session, "take 1", 0.0, 24, 24.0, false, 0, std::nullopt});
    project.clips.clips.push_back(Clip{"flick", ClipSource::Keyframes, "flick", 0.0, 12, 24.0, false, 0, GoalSettings{}});
    project.clips.defaultClip = "take";
    QVERIFY2(project.clips.validate(project.scene).ok(), project.clips.validate(project.scene).message().c_str());

    const auto saved = std::filesystem::path(dir.path().toStdString()) / "guppy.softtouch";
    QVERIFY(saveProject(project, saved).ok());
    QVERIFY(readText(saved).find("\"version\": " + std::to_string(kProjectVersion)) != std::string::npos);
    auto reloaded = loadProject(saved);
    QVERIFY2(reloaded.ok(), reloaded.message().c_str());
    const ClipLibrary& lib = reloaded->clips;
    QCOMPARE(lib.clips.size(), std::size_t(3));
    QCOMPARE(lib.defaultClip, std::string("take"));
    QVERIFY(lib.findClip("flick")->goals.has_value());
    QCOMPARE(lib.findKeyframes("flick")->objects[0].keys().size(), std::size_t(2));
    QCOMPARE(lib.findKeyframes("flick")->objects[0].keys()[1].nodes, (std::vector<std::uint32_t>{0, 4, 8, 12}));
    QCOMPARE(lib.findKeyframes("flick")->objects[0].keys()[0].interpolation, KeyInterpolation::Constant);
    QCOMPARE(lib.findKeyframes("flick")->objects[0].keys()[1].interpolation, KeyInterpolation::Smooth);

    // The saved session replays bit for bit: 17 significant digits survive the JSON.
    const Session& session = lib.findSession("take 1")->session;
    QCOMPARE(session.events.size(), project.clips.sessions[0].session.events.size());
    auto replay = SceneSimulation::create(reloaded->scene);
    QVERIFY(replay.ok());
    QVERIFY(replaySession(replay.value(), session, {}).ok());
    QVERIFY(replay->simulator(0).state().position == live.position);
    QVERIFY(replay->simulator(0).state().velocity == live.velocity);
    // The session clip's last frame is the live state one frame before the end.
    auto take = evaluateClip(reloaded->scene, lib, *lib.findClip("take"));
    QVERIFY2(take.ok(), take.message().c_str());
    QCOMPARE(take->nodes.size(), std::size_t(24));
    // Saving again gives the same bytes.
    const auto again = std::filesystem::path(dir.path().toStdString()) / "again.softtouch";
    QVERIFY(saveProject(reloaded.value(), again).ok());
    QCOMPARE(readText(again), readText(saved));
    // Baking without --clip takes the default clip.
    BakeOptions options;
    options.output = std::filesystem::path(dir.path().toStdString()) / "default.pc2";
    options.clips = &reloaded->clips;
    auto baked = bake(reloaded->scene, options);
    QVERIFY2(baked.ok(), baked.message().c_str());
    QCOMPARE(baked->clip, std::string("take"));
    QCOMPARE(baked->frames, 24);
}

void TestClips::versionOneStillReads() {
    auto star = loadProject(kPresets / "scenes/star-drag.softtouch");  // written as version 1
    QVERIFY2(star.ok(), star.message().c_str());
    QVERIFY(star->clips.clips.empty());
    QTemporaryDir dir;
    const auto v1 = writeFile(dir, "v1.softtouch", projectText(1, ""));
    QVERIFY(loadProject(v1).ok());
    const auto v1clips = writeFile(dir, "v1clips.softtouch", projectText(1, R"(, "clips": {"library": []})"));
    auto refused = loadProject(v1clips);
    QVERIFY(!refused.ok());
    QVERIFY2(refused.message().find("/clips") != std::string::npos &&
                 refused.message().find("version 2") != std::string::npos,
             refused.message().c_str());
    const auto newer = writeFile(dir, "newer.softtouch", projectText(kProjectVersion + 1, ""));
    QVERIFY(loadProject(newer).message().find("newer") != std::string::npos);
}

void TestClips::badClipsNameTheProblem_data() {
    QTest::addColumn<QString>("extra");
    QTest::addColumn<QString>("expected");
    QTest::newRow("unknown source") << R"(, "clips": {"library": [{"name": "a", "source": "dance"}]})"
                                    << "/clips/library/0/source: expected \"drivers\"";
    QTest::newRow("missing session") << R"(, "clips": {"library": [{"name": "a", "source": "session", "of": "x"}]})"
                                     << "no session named 'x'";
    QTest::newRow("duplicate clip") << R"(, "clips": {"library": [{"name": "a"}, {"name": "a"}]})"
                                    << "two clips are named 'a'";
    QTest::newRow("blend too long") << R"(, "clips": {"library": [{"name": "a", "frames": 4, "loop": true, "blend": 9}]})"
                                    << "blend window must be in [0, frames]";
    QTest::newRow("bad default") << R"(, "clips": {"default": "b", "library": [{"name": "a"}]})"
                                 << "default clip 'b'";
    QTest::newRow("typo") << R"(, "clips": {"library": [{"name": "a", "fsp": 30}]})" << "/clips/library/0";
    QTest::newRow("key node out of range")
        << R"(, "keyframes": [{"name": "k", "objects": [{"keys": [{"time": 0, "nodes": [64], "displacement": [[0,0,0]]}]}]}])"
        << "/keyframes/0/objects/0/keys/0/nodes/0: expected an integer in [0, 63]";
    QTest::newRow("unknown key interpolation")
        << R"(, "keyframes": [{"name": "k", "objects": [{"keys": [{"time": 0, "nodes": [0], "displacement": [[0,0,0]], "interpolation": "bezier"}]}]}])"
        << "/keyframes/0/objects/0/keys/0/interpolation: expected";
    QTest::newRow("session of another lattice")
        << R"(, "sessions": [{"name": "s", "dt": 0.004166666666666667, "start": {"step": 0, "bodies": [{"position": [0, 0, 0], "velocity": [0, 0, 0]}]}, "end": 10}])"
        << "/sessions/0/start/bodies/0/position: expected 192 numbers";
}

void TestClips::badClipsNameTheProblem() {
    QFETCH(QString, extra);
    QFETCH(QString, expected);
    QTemporaryDir dir;
    const auto path = writeFile(dir, "bad.softtouch", projectText(2, extra.toStdString()));
    auto project = loadProject(path);
    QVERIFY(!project.ok());
    QVERIFY2(project.message().find("bad.softtouch") != std::string::npos, project.message().c_str());
    QVERIFY2(project.message().find(expected.toStdString()) != std::string::npos, project.message().c_str());
    // An unknown clip at bake time lists the known ones.
    auto good = loadProject(kPresets / "scenes/guppy-swim.softtouch");
    BakeOptions options;
    options.output = std::filesystem::path(dir.path().toStdString()) / "x.pc2";
    options.clips = &good->clips;
    options.clip = "walk";
    auto baked = bake(good->scene, options);
    QVERIFY(!baked.ok());
    QVERIFY2(baked.message().find("no clip named 'walk' (the scene has: swim)") != std::string::npos, baked.message().c_str());
    QVERIFY(!std::filesystem::exists(options.output));
}

QTEST_GUILESS_MAIN(TestClips)
#include "test_clips.moc"

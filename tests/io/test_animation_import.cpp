// Animated imports (io/import/animation_import.h) and bakes on a base animation (core/animation/base_motion.h): keyed
// transforms, a skinned bar and a blend shape, written as GLB by the test with a known motion, import to
// that motion; with goal weight 1 everywhere a PC2 bake is the base animation itself; bad requests fail
// naming the file and what is wrong.

#include "helpers/collada_box.h"
#include "helpers/rigged_gltf.h"

#include "io/documents/project_file.h"
#include "io/export/vertex_cache.h"
#include "io/import/animation_import.h"
#include "io/import/isolated_import.h"
#include "io/pipeline/bake.h"
#include "io/pipeline/frame_source.h"

#include <QProcess>
#include <QTemporaryDir>
#include <QtTest>

#include <chrono>
#include <fstream>
#include <limits>
#include <new>
#include <set>
#include <stdexcept>
#include <thread>

#include <unistd.h>

using namespace softtouch;
using namespace softtouch::io;
using namespace softtouch::test;

namespace {

const std::filesystem::path kPresets = SOFTTOUCH_SOURCE_DIR "/presets";

/// For each imported vertex, the written vertex at the same place (assimp joins the duplicates of the
/// written faces' shared edges, which move alike).
std::vector<std::size_t> matchVertices(const std::vector<Vec3f>& imported, const std::vector<Vec3f>& written) {
    std::vector<std::size_t> match(imported.size());
    for (std::size_t v = 0; v < imported.size(); ++v) {
        double best = 1e30;
        for (std::size_t w = 0; w < written.size(); ++w) {
            const double d = (imported[v] - written[w]).squaredNorm();
            if (d < best)
                best = d, match[v] = w;
        }
    }
    return match;
}

double diagonalOf(const std::vector<Vec3f>& p) {
    Vec3f lo = p.front(), hi = p.front();
    for (const Vec3f& x : p)
        lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
    return double((hi - lo).norm());
}

void addRigRows() {
    QTest::addColumn<int>("kind");
    QTest::newRow("keyed transforms") << int(RigKind::Keyed);
    QTest::newRow("skinned") << int(RigKind::Skinned);
    QTest::newRow("morph targets") << int(RigKind::Morph);
}

/// `json` written as NAME in `dir`; its path.
std::filesystem::path writeProject(const QTemporaryDir& dir, const char* name, const nlohmann::json& json) {
    const std::filesystem::path path = dir.filePath(name).toStdString();
    std::ofstream(path) << json.dump();
    return path;
}

std::string projectFor(const std::string& glb, const std::string& extra = "") {
    return R"({"format": "softtouch-project", "version": 4,
      "objects": [{"name": "rig", "mesh": ")" + glb + R"(",
                   "animation": {"take": "take", "loop": false, "sampleRate": 120},
                   "lattice": {"nodes": [4, 4, 4]},
                   "material": {"goalWeight": 1)" + extra + R"(}}],
      "simulation": {"integrator": "verlet"},
      "clip": {"frames": 24, "fps": 24}})";
}

/// Writes `to`: the GLB `from` with every key time of its takes multiplied by `factor` (a float in the file, as
/// glTF stores times: 3e38 s and beyond become infinite there). The accessors' min and max follow, as doubles.
bool writeStretched(const std::string& from, const std::string& to, double factor) {
    tinygltf::TinyGLTF io;
    tinygltf::Model model;
    std::string error, warning;
    if (!io.LoadBinaryFromFile(&model, &error, &warning, from) || model.animations.empty())
        return false;
    std::set<int> done;
    for (const tinygltf::Animation& animation : model.animations)
        for (const tinygltf::AnimationSampler& sampler : animation.samplers) {
            if (!done.insert(sampler.input).second)
                continue;
            tinygltf::Accessor& input = model.accessors.at(std::size_t(sampler.input));
            const tinygltf::BufferView& view = model.bufferViews.at(std::size_t(input.bufferView));
            auto* times = reinterpret_cast<float*>(model.buffers.at(std::size_t(view.buffer)).data.data() + view.byteOffset +
                                                   input.byteOffset);
            for (std::size_t k = 0; k < input.count; ++k)
                times[k] = float(double(times[k]) * factor);
            for (double& x : input.minValues)
                x *= factor;
            for (double& x : input.maxValues)
                x *= factor;
        }
    return io.WriteGltfSceneToFile(&model, to, false, true, false, true);
}

/// Writes `to`: the GLB `from` with `extra` empty nodes under its first node (a rig of that many more nodes).
bool writeWithExtraNodes(const std::string& from, const std::string& to, std::size_t extra) {
    tinygltf::TinyGLTF io;
    tinygltf::Model model;
    std::string error, warning;
    if (!io.LoadBinaryFromFile(&model, &error, &warning, from))
        return false;
    for (std::size_t i = 0; i < extra; ++i) {
        model.nodes.front().children.push_back(int(model.nodes.size()));
        model.nodes.emplace_back().name = "joint" + std::to_string(i);
    }
    return io.WriteGltfSceneToFile(&model, to, false, true, false, true);
}

/// Writes `to`: the GLB `from` with `targets` blend shapes on its first mesh, each weighed 0.5 by default, all
/// of them one small bulge (the same accessor, so the file stays small while every sample applies each).
bool writeWithBlendShapes(const std::string& from, const std::string& to, std::size_t targets) {
    tinygltf::TinyGLTF io;
    tinygltf::Model model;
    std::string error, warning;
    if (!io.LoadBinaryFromFile(&model, &error, &warning, from))
        return false;
    tinygltf::Mesh& mesh = model.meshes.front();
    const auto vertices = model.accessors.at(std::size_t(mesh.primitives.front().attributes.at("POSITION"))).count;
    const std::vector<Vec3f> delta(vertices, Vec3f(0.0f, 0.001f, 0.0f));
    const int bulge = rigged_detail::addVec3(model, delta, true);
    for (std::size_t t = 0; t < targets; ++t)
        mesh.primitives.front().targets.push_back({{"POSITION", bulge}});
    mesh.weights.assign(targets, 0.5);
    return io.WriteGltfSceneToFile(&model, to, false, true, false, true);
}

/// The keyed COLLADA box of colladaKeyedTranslationImports, its last key at `lastKey` (text, seconds).
void writeColladaBoxEndingAt(const std::string& path, const std::string& lastKey) {
    writeKeyedColladaBox(path, "-10 -5 -2 10 -5 -2 -10 5 -2 10 5 -2 -10 -5 2 10 -5 2 -10 5 2 10 5 2",
                         "0 0.25 0.5 0.75 " + lastKey, "0 0 0 10 0 0 20 0 0 10 0 0 0 0 0");
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

class TestAnimationImport : public QObject {
    Q_OBJECT

private slots:
    void importsTheRigsMotion_data() { addRigRows(); }

    // Every sample on a key is where the rig puts the vertex (assimp's reading, SoftTouch's evaluation of
    // the hierarchy, skin and blend shapes), to float precision.
    void importsTheRigsMotion() {
        QFETCH(int, kind);
        QTemporaryDir dir;
        const std::string path = dir.filePath("rig.glb").toStdString();
        const RiggedFile rig = writeRiggedGlb(RigKind(kind), path);
        AnimationRequest request;
        request.loop = false;
        auto imported = importAnimatedMesh(path, request);
        QVERIFY2(imported.ok(), imported.message().c_str());
        QCOMPARE(imported->takes.size(), std::size_t(1));
        QCOMPARE(QString::fromStdString(imported->takes[0].first), QString("take"));
        QVERIFY(std::abs(imported->takes[0].second - 1.0) < 1e-6);
        QCOMPARE(QString::fromStdString(imported->unit), QString("metres (glTF)"));
        const BaseAnimation& a = imported->animation;
        QCOMPARE(a.samples.size(), std::size_t(121));
        const auto match = matchVertices(imported->mesh.positions, rig.rest);
        const double diagonal = diagonalOf(rig.rest);
        double worst = 0.0;
        for (int k = 0; k <= 24; ++k)
            for (std::size_t v = 0; v < match.size(); ++v)
                worst = std::max(worst, double((a.samples[std::size_t(5 * k)][v] - rig.expected[std::size_t(k)][match[v]]).norm()));
        qInfo("%s: %zu vertices (%zu written), worst sample %.3g of the diagonal from the rig's motion",
              QTest::currentDataTag(), imported->mesh.positions.size(), rig.rest.size(), worst / diagonal);
        QVERIFY(worst <= 1e-6 * diagonal);
        // It moves: the motion is not the rest pose.
        double moved = 0.0;
        for (std::size_t v = 0; v < match.size(); ++v)
            moved = std::max(moved, double((a.samples[30][v] - a.samples[0][v]).norm()));
        QVERIFY(moved > 0.02 * diagonal);
    }

    void weightOneBakesTheBase_data() { addRigRows(); }

    // The must-show: goal weight 1 everywhere, the bake (a PC2 through the whole project path) equals the
    // base animation within 1e-6 of the diagonal.
    void weightOneBakesTheBase() {
        QFETCH(int, kind);
        QTemporaryDir dir;
        const std::string glb = dir.filePath("rig.glb").toStdString();
        const RiggedFile rig = writeRiggedGlb(RigKind(kind), glb);
        const std::filesystem::path projectPath = dir.filePath("rig.softtouch").toStdString();
        std::ofstream(projectPath) << projectFor(glb);
        auto project = loadProject(projectPath);
        QVERIFY2(project.ok(), project.message().c_str());
        QCOMPARE(project->importNotes.size(), std::size_t(1));
        qInfo("%s", project->importNotes[0].c_str());
        BakeOptions options;
        options.output = dir.filePath("rig.pc2").toStdString();
        auto baked = bake(project->scene, options);
        QVERIFY2(baked.ok(), baked.message().c_str());
        auto cache = readPc2(options.output);
        QVERIFY2(cache.ok(), cache.message().c_str());
        QCOMPARE(cache->frames.size(), std::size_t(24));
        const auto match = matchVertices(project->scene.objects[0].mesh->positions, rig.rest);
        const double diagonal = diagonalOf(rig.rest);
        double worst = 0.0;
        for (std::size_t f = 0; f < 24; ++f)
            for (std::size_t v = 0; v < match.size(); ++v)
                worst = std::max(worst, double((cache->frames[f][v] - rig.expected[f][match[v]]).norm()));
        qInfo("%s: worst baked vertex %.3g of the diagonal from the base animation", QTest::currentDataTag(), worst / diagonal);
        QVERIFY(worst <= 1e-6 * diagonal);
        // An MDD of the same bake holds the same frames.
        options.output = dir.filePath("rig.mdd").toStdString();
        options.format = findExportFormat("mdd");
        QVERIFY(bake(project->scene, options).ok());
        auto mdd = readMdd(options.output);
        QVERIFY2(mdd.ok(), mdd.message().c_str());
        QCOMPARE(mdd->frames, cache->frames);
        // Saved and read back, the project keeps its animation and goal weights.
        const std::filesystem::path saved = dir.filePath("saved.softtouch").toStdString();
        QVERIFY(saveProject(project.value(), saved).ok());
        auto again = loadProject(saved);
        QVERIFY2(again.ok(), again.message().c_str());
        QVERIFY(again->scene.objects[0].baseAnimation);
        QCOMPARE(again->scene.objects[0].baseAnimation->samples.size(), std::size_t(121));
        QCOMPARE(again->scene.objects[0].material.goalWeight, project->scene.objects[0].material.goalWeight);
    }

    // The sample: presets/scenes/guppy-rigged.softtouch, the rigged guppy's one-second swim with its spine
    // following (goal weight 1) and belly, flanks and tail fin on looser goals. Its swim clip loops (the mesh's
    // seam is no larger than its median frame step) and the wobble shows (free nodes leave their goal by at
    // least 2% of the mesh's diagonal at peak).
    void riggedGuppyLoopsAndWobbles() {
        auto project = loadProject(kPresets / "scenes/guppy-rigged.softtouch");
        QVERIFY2(project.ok(), project.message().c_str());
        const SceneObject& guppy = project->scene.objects[0];
        QVERIFY(guppy.baseAnimation && guppy.baseAnimation->loop);
        QCOMPARE(QString::fromStdString(guppy.baseAnimation->take), QString("swim"));
        FrameRequest request;
        request.clips = &project->clips;
        request.clip = "swim";
        auto source = FrameSource::create(project->scene, request);
        QVERIFY2(source.ok(), source.message().c_str());
        const std::size_t n = guppy.mesh->positions.size();
        std::vector<std::vector<Vec3f>> frames;
        double wobble = 0.0;
        const std::vector<Vec3>& rest = guppy.lattice.restNodes();
        for (int f = 0; f < source->frameCount(); ++f) {
            source->seek(f);
            frames.emplace_back(n);
            source->evaluate(0, frames.back(), {});
            const auto nodes = source->nodes(0);
            for (std::size_t i = 0; i < rest.size(); ++i)
                if (guppy.material.goalWeight[i] < 1.0)
                    wobble = std::max(wobble, (nodes[i] - rest[i]).norm());
        }
        auto rms = [&](const std::vector<Vec3f>& a, const std::vector<Vec3f>& b) {
            double sum = 0.0;
            for (std::size_t v = 0; v < n; ++v)
                sum += (a[v] - b[v]).squaredNorm();
            return std::sqrt(sum / double(n));
        };
        std::vector<double> steps;
        for (std::size_t f = 0; f + 1 < frames.size(); ++f)
            steps.push_back(rms(frames[f], frames[f + 1]));
        std::sort(steps.begin(), steps.end());
        const double median = steps[steps.size() / 2], seam = rms(frames.back(), frames.front());
        const double diagonal = guppy.mesh->bounds().diagonal();
        qInfo("guppy swim clip, %zu frames: seam %.4f m against a median frame step of %.4f m (%.2fx); free nodes "
              "leave their goal by up to %.4f m, %.1f%% of the diagonal",
              frames.size(), seam, median, seam / median, wobble, 100.0 * wobble / diagonal);
        QCOMPARE(int(frames.size()), 24);
        QVERIFY(seam <= median);
        QVERIFY(wobble >= 0.02 * diagonal);
    }

    // Goal weights at points (a vertex group from another tool, "goalWeightPoints") are fitted to the nodes on load.
    // At 1 on every vertex, every node is exactly 1 and the bake is the base animation itself; a map painted on
    // the tail's half frees the tail's nodes and keeps the head's; a save writes the nodes' weights, which read
    // back the same. A file that gives the weights twice, on an object with no animation, or out of range is
    // refused at the field.
    void goalWeightPointsAreFittedToTheNodes() {
        QTemporaryDir dir;
        std::ifstream in(kPresets / "scenes/guppy-rigged.softtouch");
        nlohmann::json json = nlohmann::json::parse(in);
        nlohmann::json& object = json["objects"][0];
        object["mesh"] = (kPresets / "meshes/guppy-rigged.glb").string();
        object["material"]["preset"] = (kPresets / "materials/fish-body.stpreset").string();
        object["material"].erase("goalWeight");
        auto plain = loadProject(writeProject(dir, "plain.softtouch", json));
        QVERIFY2(plain.ok(), plain.message().c_str());
        const std::vector<Vec3f>& rest = plain->scene.objects[0].mesh->positions;
        const auto withWeights = [&](auto weightAt) {
            nlohmann::json points = nlohmann::json::array();
            for (const Vec3f& p : rest)
                points.push_back({p.x(), p.y(), p.z(), weightAt(p)});
            nlohmann::json text = json;
            text["objects"][0]["goalWeightPoints"] = points;
            return text;
        };

        auto pinned = loadProject(writeProject(dir, "pinned.softtouch", withWeights([](const Vec3f&) { return 1.0; })));
        QVERIFY2(pinned.ok(), pinned.message().c_str());
        for (double w : pinned->scene.objects[0].material.goalWeight)
            QCOMPARE(w, 1.0);
        BakeOptions options;
        options.output = dir.filePath("pinned.pc2").toStdString();
        QVERIFY(bake(pinned->scene, options).ok());
        auto cache = readPc2(options.output);
        QVERIFY2(cache.ok(), cache.message().c_str());
        const BaseAnimation& base = *pinned->scene.objects[0].baseAnimation;
        const double diagonal = pinned->scene.objects[0].mesh->bounds().diagonal();
        std::vector<Vec3f> expected(rest.size());
        double worst = 0.0;
        for (std::size_t f = 0; f < cache->frames.size(); ++f) {
            base.positionsAt(double(f) / 24.0, expected);
            for (std::size_t v = 0; v < rest.size(); ++v)
                worst = std::max(worst, double((cache->frames[f][v] - expected[v]).norm()));
        }
        QVERIFY2(worst <= 1e-6 * diagonal, qPrintable(QString("worst %1 of the diagonal").arg(worst / diagonal)));

        // The guppy swims along x, its head at +x: a map of 1 on the head's half and 0 on the tail's.
        const Eigen::AlignedBox3f bounds = [&] {
            Eigen::AlignedBox3f b;
            for (const Vec3f& p : rest)
                b.extend(p);
            return b;
        }();
        const float middle = bounds.center().x();
        auto painted = loadProject(writeProject(dir, "painted.softtouch", withWeights([&](const Vec3f& p) { return p.x() > middle ? 1.0 : 0.0; })));
        QVERIFY2(painted.ok(), painted.message().c_str());
        const SceneObject& guppy = painted->scene.objects[0];
        const std::vector<double>& goal = guppy.material.goalWeight;
        // Every row along the fish rises from tail to head; the end columns lean to the map's values (a Bezier
        // node weighs every vertex, so a corner the mesh does not reach mixes in the far half).
        double tails = 0.0, heads = 0.0;
        const int rows = guppy.lattice.count(1) * guppy.lattice.count(2), last = guppy.lattice.count(0) - 1;
        for (int k = 0; k < guppy.lattice.count(2); ++k)
            for (int j = 0; j < guppy.lattice.count(1); ++j) {
                for (int i = 1; i <= last; ++i)
                    QVERIFY(goal[std::size_t(guppy.lattice.index(i, j, k))] > goal[std::size_t(guppy.lattice.index(i - 1, j, k))]);
                tails += goal[std::size_t(guppy.lattice.index(0, j, k))] / rows;
                heads += goal[std::size_t(guppy.lattice.index(last, j, k))] / rows;
            }
        QVERIFY2(tails < 0.2 && heads > 0.8, qPrintable(QString("tail column %1, head column %2").arg(tails).arg(heads)));
        const std::filesystem::path saved = dir.filePath("saved.softtouch").toStdString();
        QVERIFY(saveProject(painted.value(), saved).ok());
        QVERIFY(!nlohmann::json::parse(std::ifstream(saved))["objects"][0].contains("goalWeightPoints"));
        auto again = loadProject(saved);
        QVERIFY2(again.ok(), again.message().c_str());
        QCOMPARE(again->scene.objects[0].material.goalWeight, goal);

        const auto refused = [&](const nlohmann::json& text, const std::string& where, const std::string& what) {
            auto project = loadProject(writeProject(dir, "refused.softtouch", text));
            QVERIFY(!project.ok());
            QVERIFY2(project.message().find(where) != std::string::npos && project.message().find(what) != std::string::npos,
                     project.message().c_str());
        };
        nlohmann::json twice = withWeights([](const Vec3f&) { return 0.5; });
        twice["objects"][0]["material"]["goalWeight"] = 0.5;
        refused(twice, "/objects/0/goalWeightPoints", "not both");
        nlohmann::json still = withWeights([](const Vec3f&) { return 0.5; });
        still["objects"][0].erase("animation");
        still["objects"][0]["mesh"] = (kPresets / "meshes/guppy.obj").string();
        refused(still, "/objects/0/goalWeightPoints", "animation");
        refused(withWeights([](const Vec3f&) { return 1.5; }), "/objects/0/goalWeightPoints/0/3", "1");
        nlohmann::json shortItem = withWeights([](const Vec3f&) { return 0.5; });
        shortItem["objects"][0]["goalWeightPoints"][7] = {0.0, 0.0, 0.0};
        refused(shortItem, "/objects/0/goalWeightPoints/7", "[x, y, z, weight]");
    }

    // COLLADA, written here by hand (assimp's own COLLADA export of an animation is not read back by its
    // importer): a box whose node's translation is keyed, in centimetres (<unit meter="0.01">), imports to that
    // motion in metres.
    void colladaKeyedTranslationImports() {
        QTemporaryDir dir;
        const std::string path = dir.filePath("box.dae").toStdString();
        const std::vector<Vec3f> corners = {{-10, -5, -2}, {10, -5, -2}, {-10, 5, -2}, {10, 5, -2},
                                            {-10, -5, 2},  {10, -5, 2},  {-10, 5, 2},  {10, 5, 2}};
        std::string positions, keys, values;
        for (const Vec3f& c : corners)
            positions += std::to_string(c.x()) + " " + std::to_string(c.y()) + " " + std::to_string(c.z()) + " ";
        std::vector<double> shift;  // centimetres along x at t = 0, 0.25, ..., 1 s
        for (int k = 0; k <= 4; ++k) {
            shift.push_back(30.0 * std::sin(0.5 * M_PI * k));
            keys += std::to_string(0.25 * k) + " ";
            values += std::to_string(shift.back()) + " 0 0 ";
        }
        writeKeyedColladaBox(path, positions, keys, values);
        AnimationRequest request;
        request.loop = false;
        request.rate = 4.0;  // a sample on every key
        auto imported = importAnimatedMesh(path, request);
        QVERIFY2(imported.ok(), imported.message().c_str());
        qInfo("%zu vertices, %zu samples, take \"%s\" of %.3f s, %s", imported->mesh.positions.size(),
              imported->animation.samples.size(), imported->animation.take.c_str(), imported->takes.front().second,
              imported->unit.c_str());
        QCOMPARE(imported->animation.samples.size(), std::size_t(5));
        QCOMPARE(QString::fromStdString(imported->unit), QString("metres (COLLADA's <unit>, applied by assimp)"));
        double worst = 0.0;
        for (std::size_t k = 0; k < 5; ++k)
            for (std::size_t v = 0; v < imported->mesh.positions.size(); ++v) {
                // Where the vertex was at rest, in metres, moved by the key's shift.
                const Vec3f rest = imported->animation.samples[0][v];
                const Vec3f expected = rest + Vec3f(float(0.01 * shift[k]), 0.0f, 0.0f);
                worst = std::max(worst, double((imported->animation.samples[k][v] - expected).norm()));
            }
        const Bounds b = imported->mesh.bounds();
        qInfo("box %.3f x %.3f x %.3f m; worst sample %.3g m from the keyed translation", b.max.x() - b.min.x(),
              b.max.y() - b.min.y(), b.max.z() - b.min.z(), worst);
        QVERIFY(std::abs((b.max.x() - b.min.x()) - 0.2) < 1e-5);  // 20 cm, in metres
        QVERIFY(worst < 1e-6);
    }

    // With weight 0 and nothing pinned the body lags its base: the bake leaves the base animation.
    void freeBodyLagsItsBase() {
        QTemporaryDir dir;
        const std::string glb = dir.filePath("rig.glb").toStdString();
        const RiggedFile rig = writeRiggedGlb(RigKind::Keyed, glb);
        const std::filesystem::path projectPath = dir.filePath("rig.softtouch").toStdString();
        std::ofstream(projectPath) << projectFor(glb).replace(projectFor(glb).find("\"goalWeight\": 1"), 15, "\"goalWeight\": 0.3");
        auto project = loadProject(projectPath);
        QVERIFY2(project.ok(), project.message().c_str());
        BakeOptions options;
        options.output = dir.filePath("rig.pc2").toStdString();
        QVERIFY(bake(project->scene, options).ok());
        auto cache = readPc2(options.output);
        QVERIFY(cache.ok());
        const auto match = matchVertices(project->scene.objects[0].mesh->positions, rig.rest);
        double worst = 0.0;
        for (std::size_t f = 0; f < 24; ++f)
            for (std::size_t v = 0; v < match.size(); ++v)
                worst = std::max(worst, double((cache->frames[f][v] - rig.expected[f][match[v]]).norm()));
        qInfo("goal weight 0.3: the body leaves its base by up to %.3g m", worst);
        QVERIFY(worst > 0.01 * diagonalOf(rig.rest));
    }

    // What cannot be done says so: a still mesh has no animation, a take that is not there lists those that
    // are, a range outside the take, and the lattice cache, which cannot carry a rig's motion.
    // A rig with two takes (its first, and a copy that plays twice as fast): both are listed without sampling
    // either, and the second imports as its own motion, a sample at t where the first's key at 2t is.
    void listsTakesAndImportsTheOneAskedFor() {
        QTemporaryDir dir;
        const std::string one = dir.filePath("rig.glb").toStdString(), two = dir.filePath("two-takes.glb").toStdString();
        const RiggedFile rig = writeRiggedGlb(RigKind::Keyed, one);
        QVERIFY(writeWithSecondTake(one, two, "dash", 2.0));
        auto takes = animationTakes(two);
        QVERIFY2(takes.ok(), takes.message().c_str());
        QCOMPARE(takes->size(), std::size_t(2));
        QCOMPARE(QString::fromStdString(takes->at(0).first), QString("take"));
        QCOMPARE(QString::fromStdString(takes->at(1).first), QString("dash"));
        QVERIFY(std::abs(takes->at(0).second - 1.0) < 1e-6 && std::abs(takes->at(1).second - 0.5) < 1e-6);
        AnimationRequest request;
        request.take = "dash";
        request.rate = 48.0;
        request.loop = false;
        auto dash = importAnimatedMesh(two, request);
        QVERIFY2(dash.ok(), dash.message().c_str());
        QCOMPARE(QString::fromStdString(dash->animation.take), QString("dash"));
        QCOMPARE(dash->animation.samples.size(), std::size_t(25));
        const auto match = matchVertices(dash->mesh.positions, rig.rest);
        double worst = 0.0;
        for (int k = 0; k <= 24; ++k)
            for (std::size_t v = 0; v < match.size(); ++v)
                worst = std::max(worst, double((dash->animation.samples[std::size_t(k)][v] - rig.expected[std::size_t(k)][match[v]]).norm()));
        QVERIFY2(worst <= 1e-6 * diagonalOf(rig.rest), qPrintable(QString::number(worst)));
        auto still = animationTakes(kPresets / "meshes/guppy.obj");
        QVERIFY(!still.ok());
        QVERIFY2(still.message().find("guppy.obj' has no animation") != std::string::npos, still.message().c_str());
        auto missing = animationTakes(dir.filePath("missing.glb").toStdString());
        QVERIFY(!missing.ok());
        QVERIFY2(missing.message().find("missing.glb") != std::string::npos, missing.message().c_str());
    }

    void badRequestsFailClearly() {
        QTemporaryDir dir;
        const std::string glb = dir.filePath("rig.glb").toStdString();
        (void)writeRiggedGlb(RigKind::Skinned, glb);
        auto still = importAnimatedMesh(kPresets / "meshes/guppy.obj", {});
        QVERIFY(!still.ok());
        QVERIFY2(still.message().find("guppy.obj' has no animation") != std::string::npos, still.message().c_str());
        AnimationRequest request;
        request.take = "walk";
        auto missing = importAnimatedMesh(glb, request);
        QVERIFY(!missing.ok());
        QVERIFY2(missing.message().find("has no take \"walk\"; it has \"take\" (1 s)") != std::string::npos,
                 missing.message().c_str());
        request.take = "take";
        request.start = 0.5;
        request.end = 2.0;
        auto outside = importAnimatedMesh(glb, request);
        QVERIFY(!outside.ok());
        QVERIFY2(outside.message().find("0.5 to 2 s is not inside take \"take\" (0 to 1 s)") != std::string::npos,
                 outside.message().c_str());

        const std::filesystem::path projectPath = dir.filePath("rig.softtouch").toStdString();
        std::ofstream(projectPath) << projectFor(glb);
        auto project = loadProject(projectPath);
        QVERIFY2(project.ok(), project.message().c_str());
        BakeOptions options;
        options.output = dir.filePath("rig-lattice").toStdString();
        options.format = findExportFormat("lattice");
        auto refused = bake(project->scene, options);
        QVERIFY(!refused.ok());
        QVERIFY2(refused.message().find("object 'rig' moves with its own base animation") != std::string::npos,
                 refused.message().c_str());
        QVERIFY(!std::filesystem::exists(dir.filePath("rig-lattice.glb").toStdString()));
        // A goal weight outside [0, 1] names the key.
        std::ofstream(projectPath) << projectFor(glb).replace(projectFor(glb).find("\"goalWeight\": 1"), 15, "\"goalWeight\": 2");
        auto bad = loadProject(projectPath);
        QVERIFY(!bad.ok());
        QVERIFY2(bad.message().find("/objects/0/material/goalWeight") != std::string::npos, bad.message().c_str());
    }

    void nonsenseTakeLengthsAreRefused_data() {
        QTest::addColumn<QString>("format");
        QTest::addColumn<QString>("length");  // glTF: a factor on the rig's 1 s take; COLLADA: the last key, seconds
        QTest::addColumn<bool>("loop");
        QTest::addColumn<QString>("expected");
        const QString tooLong = "the range 0 to %1 s of take \"%2\" (%1 s) ends past 3600 s, the furthest into a "
                                "take SoftTouch samples: give it an end of at most 3600 s";
        const QString infinite = "take \"take\" is inf s long; its key times are not finite numbers";
        // Before: 2 samples and exit 0 when looping (the sample count overflowed); std::length_error in the
        // child ("the importer (assimp) crashed on it") when not.
        QTest::newRow("glTF, 1e30 s, looping") << "glb" << "1e30" << true << tooLong.arg("1e+30", "take");
        QTest::newRow("glTF, 1e30 s, once") << "glb" << "1e30" << false << tooLong.arg("1e+30", "take");
        // glTF holds times as floats: 1e39 s is infinite there.
        QTest::newRow("glTF, infinite, looping") << "glb" << "1e39" << true << infinite;
        QTest::newRow("glTF, infinite, once") << "glb" << "1e39" << false << infinite;
        // assimp's COLLADA reader drops a last key above ~1e19 s; 1e17 s at 120 samples/s overflowed the count too.
        QTest::newRow("COLLADA, 1e17 s, looping") << "dae" << "1e17" << true << tooLong.arg("1e+17", "animation");
        QTest::newRow("COLLADA, 1e17 s, once") << "dae" << "1e17" << false << tooLong.arg("1e+17", "animation");
    }

    // A take of 1e30 s or an infinite one is refused, naming the limit, before anything is sampled, whether it is
    // asked for directly or through a project; the first hour of a 1e30 s take is an ordinary request.
    void nonsenseTakeLengthsAreRefused() {
        QFETCH(QString, format);
        QFETCH(QString, length);
        QFETCH(bool, loop);
        QFETCH(QString, expected);
        QTemporaryDir dir;
        const std::string path = dir.filePath("long." + format).toStdString();
        if (format == "glb") {
            const std::string rig = dir.filePath("rig.glb").toStdString();
            (void)writeRiggedGlb(RigKind::Keyed, rig);
            QVERIFY(writeStretched(rig, path, length.toDouble()));
        } else {
            writeColladaBoxEndingAt(path, length.toStdString());
        }
        AnimationRequest request;
        request.loop = loop;
        const auto started = std::chrono::steady_clock::now();
        auto imported = importAnimatedMesh(path, request);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
        if (imported.ok())
            QFAIL(qPrintable(QString("imported %1 samples").arg(imported->animation.samples.size())));
        qInfo("%s (%.2f s)", imported.message().c_str(), seconds);
        QCOMPARE(QString::fromStdString(imported.message()),
                 QString("mesh file '%1': %2").arg(QString::fromStdString(path), expected));
        // The same through a project: the error is on the object's mesh.
        const std::filesystem::path projectPath = dir.filePath("long.softtouch").toStdString();
        std::ofstream(projectPath) << "{\"format\": \"softtouch-project\", \"version\": 4, \"objects\": [{\"name\": \"rig\", "
                                      "\"mesh\": \"" + path + "\", \"animation\": {\"loop\": " + (loop ? "true" : "false") +
                                      "}, \"lattice\": {\"nodes\": [3, 3, 3]}, \"material\": {\"goalWeight\": 1}}]}";
        auto project = loadProject(projectPath);
        QVERIFY(!project.ok());
        QVERIFY2(contains(project.message(), "/objects/0/mesh: " + imported.message()), project.message().c_str());
        if (length.startsWith("1e") && length != "1e39") {
            // The first second of it is an ordinary request.
            request.end = 1.0;
            request.rate = 24.0;
            auto first = importAnimatedMesh(path, request);
            QVERIFY2(first.ok(), first.message().c_str());
            QCOMPARE(first->animation.samples.size(), std::size_t(loop ? 24 : 25));
        }
    }

    // A range that is not finite is refused as such (an end of -inf used to mean the take's end, a NaN start was
    // "not inside the take").
    void rangesMustBeFinite() {
        QTemporaryDir dir;
        const std::string glb = dir.filePath("rig.glb").toStdString();
        (void)writeRiggedGlb(RigKind::Keyed, glb);
        const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
        struct Range {
            double start, end;
            const char* said;
        };
        for (const Range& range : {Range{nan, 1.0, "nan to 1"}, Range{0.0, inf, "0 to inf"}, Range{0.0, -inf, "0 to -inf"},
                                   Range{-inf, 1.0, "-inf to 1"}}) {
            AnimationRequest request;
            request.start = range.start;
            request.end = range.end;
            auto imported = importAnimatedMesh(glb, request);
            QVERIFY(!imported.ok());
            QCOMPARE(QString::fromStdString(imported.message()),
                     QString::fromStdString("mesh file '" + glb +
                                            "': the animation's range must be finite numbers of seconds, got " + range.said));
        }
    }

    // The rigged guppy's swim stretched to an hour, sampled once a second: 3,601 samples of 3,198 vertices, 11.5
    // million positions, within every limit. Under the sanitizers the import used to be stopped by the importer's
    // 10 s deadline; sampling now reports progress, and the deadline only stops an importer that shows none.
    // Sample k is the swim at k/3600 of its second.
    void aTakeOfAnHourIsSampledWhole() {
        QTemporaryDir dir;
        const std::string hour = dir.filePath("guppy-hour.glb").toStdString();
        const std::string guppy = (kPresets / "meshes/guppy-rigged.glb").string();
        QVERIFY(writeStretched(guppy, hour, 3600.0));
        AnimationRequest request;
        request.rate = 1.0;
        request.loop = false;
        const auto started = std::chrono::steady_clock::now();
        auto imported = importAnimatedMesh(hour, request);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
        QVERIFY2(imported.ok(), imported.message().c_str());
        QCOMPARE(imported->takes.front().second, 3600.0);
        QCOMPARE(imported->animation.samples.size(), std::size_t(3601));
        QCOMPARE(imported->mesh.positions.size(), std::size_t(3198));
        qInfo("3601 samples of %zu vertices in %.2f s", imported->mesh.positions.size(), seconds);
        request.rate = 4.0;
        auto swim = importAnimatedMesh(guppy, request);
        QVERIFY2(swim.ok(), swim.message().c_str());
        const double diagonal = swim->mesh.bounds().diagonal();
        double worst = 0.0;
        for (std::size_t k = 0; k <= 4; ++k)
            for (std::size_t v = 0; v < 3198; ++v)
                worst = std::max(worst,
                                 double((imported->animation.samples[900 * k][v] - swim->animation.samples[k][v]).norm()));
        QVERIFY2(worst < 1e-5 * diagonal, qPrintable(QString::number(worst / diagonal)));
    }

    // Each bound is refused with its limit named before anything is sampled: the positions the samples hold, the
    // rig's nodes, and the operations its samples take (a rig with many weighed blend shapes).
    void samplingIsBoundedBeforeItStarts() {
        QTemporaryDir dir;
        const std::string hour = dir.filePath("guppy-hour.glb").toStdString();
        QVERIFY(writeStretched((kPresets / "meshes/guppy-rigged.glb").string(), hour, 3600.0));
        AnimationRequest request;
        request.rate = 3.0;
        request.loop = false;
        auto positions = importAnimatedMesh(hour, request);
        QVERIFY(!positions.ok());
        QCOMPARE(QString::fromStdString(positions.message()),
                 QString::fromStdString("mesh file '" + hour + "': 10801 samples of 3198 vertices is 34541598 positions, "
                                        "more than SoftTouch keeps (32000000): sample a shorter range or at a lower rate"));

        const std::string rig = dir.filePath("rig.glb").toStdString(), crowded = dir.filePath("crowded.glb").toStdString();
        (void)writeRiggedGlb(RigKind::Keyed, rig);
        QVERIFY(writeWithExtraNodes(rig, crowded, kMaxRigNodes));
        auto nodes = importAnimatedMesh(crowded, {});
        QVERIFY(!nodes.ok());
        QCOMPARE(QString::fromStdString(nodes.message()),
                 QString::fromStdString("mesh file '" + crowded + "': its rig has more than 10000 nodes (joints and others), "
                                        "the most SoftTouch samples"));
        const std::string fewer = dir.filePath("fewer.glb").toStdString();
        QVERIFY(writeWithExtraNodes(rig, fewer, kMaxRigNodes - 10));
        request = {};
        request.rate = 2.0;
        auto enough = importAnimatedMesh(fewer, request);
        QVERIFY2(enough.ok(), enough.message().c_str());

        // 1,001 samples of the box's 98 vertices (once assimp joins the faces' shared corners), each sample
        // applying every blend shape to every vertex.
        const std::string shapes = dir.filePath("shapes.glb").toStdString();
        const auto targets = std::size_t(kMaxSampledOperations / (1001.0 * 98.0)) + 1;
        QVERIFY(writeWithBlendShapes(rig, shapes, targets));
        request = {};
        request.rate = 1000.0;
        request.loop = false;
        auto operations = importAnimatedMesh(shapes, request);
        QVERIFY(!operations.ok());
        qInfo("%zu blend shapes: %s", targets, operations.message().c_str());
        QVERIFY2(contains(operations.message(), "1001 samples of this rig is ") &&
                     contains(operations.message(), " rig operations (") &&
                     contains(operations.message(), "more than SoftTouch evaluates in one import (256000000): sample a "
                                                    "shorter range or at a lower rate"),
                 operations.message().c_str());
    }

    // An exception in the importer's child comes back as its cause, not as a crash (std::length_error from a
    // sample count that overflowed was "the importer (assimp) crashed on it (signal 6: terminate called …)").
    void importerExceptionsAreReportedWithTheirCause() {
        const std::filesystem::path file = kPresets / "meshes/guppy-rigged.glb";
        auto lengthError = runIsolated(file, "'x.glb'", []() -> std::string {
            throw std::length_error("cannot create std::vector larger than max_size()");
        });
        QVERIFY(!lengthError.ok());
        QCOMPARE(QString::fromStdString(lengthError.message()),
                 QString("cannot read mesh 'x.glb': the importer failed: cannot create std::vector larger than max_size()"));
        auto badAlloc = runIsolated(file, "'x.glb'", []() -> std::string {
            std::fputs("something the importer printed first\n", stderr);
            throw std::bad_alloc();
        });
        QCOMPARE(QString::fromStdString(badAlloc.message()),
                 QString("cannot read mesh 'x.glb': the importer failed: std::bad_alloc"));
        auto other = runIsolated(file, "'x.glb'", []() -> std::string { throw 42; });
        QCOMPARE(QString::fromStdString(other.message()),
                 QString("cannot read mesh 'x.glb': the importer failed: an exception that is not a std::exception"));
    }

    // The importer's deadline stops a child that shows no sign of life for its idle window (kImportIdleSeconds
    // in every import; 3 s here, so the test does not sleep 22 s in each suite), not one that is busy: a child
    // that reports progress runs past it and delivers; one that goes quiet is stopped that long after its last
    // sign (before, every child was stopped 10 s after it started, busy or not).
    void importDeadlineStopsOnlyAQuietChild() {
        const std::filesystem::path file = kPresets / "meshes/guppy-rigged.glb";  // under 1 MiB: no extra time
        using Clock = std::chrono::steady_clock;
        constexpr double kIdle = 3.0;
        const auto idle = std::chrono::duration<double>(kIdle);
        auto started = Clock::now();
        auto busy = runIsolated(file, "'busy.glb'", [&] {
            while (Clock::now() - started < idle + std::chrono::seconds(1)) {
                std::this_thread::sleep_for(std::chrono::milliseconds(50));
                reportImportProgress();
            }
            return std::string("delivered");
        }, kIdle);
        QVERIFY2(busy.ok(), busy.message().c_str());
        QCOMPARE(QString::fromStdString(busy.value()), QString("delivered"));
        started = Clock::now();
        auto quiet = runIsolated(file, "'quiet.glb'", [&] {
            while (Clock::now() - started < std::chrono::seconds(1)) {
                std::this_thread::sleep_for(std::chrono::milliseconds(50));
                reportImportProgress();
            }
            for (;;)
                ::pause();  // a hang: no more progress
            return std::string();
        }, kIdle);
        const double seconds = std::chrono::duration<double>(Clock::now() - started).count();
        QVERIFY(!quiet.ok());
        QCOMPARE(QString::fromStdString(quiet.message()),
                 QString("cannot read mesh 'quiet.glb': the importer (assimp) showed no progress for 3 s and was stopped"));
        qInfo("the quiet child was stopped after %.2f s", seconds);
        QVERIFY(seconds >= kIdle + 0.5 && seconds < kIdle + 3.0);
    }

    // Every import runs in the importer program, started beside this one with posix_spawn: a child with one
    // thread, where a fork() of a threaded process could inherit a lock another thread held (the sanitizers'
    // allocators hung such children now and then). Its answers are the forked child's, byte for byte.
    void importsRunInTheImporterProgram() {
        const std::filesystem::path program = importerProgram();
        QVERIFY2(!program.empty(), "softtouch-import is not built beside the tests");
        QCOMPARE(QString::fromStdString(program.filename().string()), QString(kImporterProgramName));
        const std::filesystem::path guppy = kPresets / "meshes/guppy-rigged.glb";
        std::vector<ImportRequest> requests(4);
        requests[0].kind = ImportRequest::Kind::Animated;
        requests[0].animation.rate = 24.0;
        requests[1].kind = ImportRequest::Kind::Takes;
        requests[2].kind = ImportRequest::Kind::SourceRig;
        requests[2].takeSeconds = {0.0, 0.25, 0.5};
        requests[3].kind = ImportRequest::Kind::CheckMeshes;
        for (ImportRequest& request : requests) {
            request.paths = {guppy};
            if (request.kind == ImportRequest::Kind::CheckMeshes)
                request.paths.push_back(kPresets / "meshes/guppy.obj");
            auto spawned = runImport(request, "'guppy-rigged.glb'");
            auto forked = runIsolated(guppy, "'guppy-rigged.glb'", [&] { return answerImportRequest(request); });
            QVERIFY2(spawned.ok() && forked.ok(), (spawned.ok() ? forked : spawned).message().c_str());
            QVERIFY(spawned.value().size() > 1);
            QVERIFY2(spawned.value() == forked.value(), qPrintable(QString("request kind %1").arg(int(request.kind))));
        }
    }

    // A request the program cannot read (another build's, or none) is refused with its own exit status and a
    // line saying so, which runImport() turns into a message.
    void theImporterProgramRefusesARequestItCannotRead() {
        const std::filesystem::path program = importerProgram();
        QVERIFY2(!program.empty(), "softtouch-import is not built beside the tests");
        QProcess child;
        child.start(QString::fromStdString(program.string()), {});
        QVERIFY(child.waitForStarted());
        child.write("not a request");
        child.closeWriteChannel();
        QVERIFY(child.waitForFinished(30000));
        QCOMPARE(child.exitCode(), 5);
        QVERIFY2(child.readAllStandardError().contains("did not decode"), "no reason given");
        QVERIFY(child.readAllStandardOutput().isEmpty());
    }
};

QTEST_GUILESS_MAIN(TestAnimationImport)
#include "test_animation_import.moc"

// Round trips of the clip exports (glTF/GLB morph animation, vertex animation textures, lattice
// cache) against the PC2 of the same bake, and their behaviour on bad input.

#include "io/bake.h"
#include "io/clip_writer.h"
#include "io/project_file.h"
#include "io/vertex_cache.h"

#include <assimp/Importer.hpp>
#include <assimp/anim.h>
#include <assimp/mesh.h>
#include <assimp/scene.h>

#include <QTemporaryDir>
#include <QtTest>

#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>

#include <sys/stat.h>

using namespace softtouch;
using namespace softtouch::io;
namespace fs = std::filesystem;

namespace {

const fs::path kSource = SOFTTOUCH_SOURCE_DIR;

/// Frames baked by the round trips: enough for real motion, few enough for ASan runs.
constexpr int kFrames = 6;

/// The formats written through ClipWriter only.
const char* const kClipFormats[] = {"gltf", "glb"};

std::string readText(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeText(const fs::path& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
}

/// Names of the entries of a folder, sorted.
QStringList folderEntries(const fs::path& dir) {
    QStringList names;
    for (const auto& entry : fs::directory_iterator(dir))
        names << QString::fromStdString(entry.path().filename().string());
    names.sort();
    return names;
}

/// Diagonal of the bounding box of every position of every frame.
double diagonalOf(const VertexCache& cache) {
    Vec3f lo = Vec3f::Constant(std::numeric_limits<float>::max());
    Vec3f hi = -lo;
    for (const auto& frame : cache.frames) {
        for (const Vec3f& p : frame) {
            lo = lo.cwiseMin(p);
            hi = hi.cwiseMax(p);
        }
    }
    return double((hi - lo).norm());
}

Scene loadScene(const fs::path& path) {
    Result<Project> project = loadProject(path);
    if (!project)
        qFatal("%s", project.message().c_str());
    return project.value().scene;
}

/// Bakes `scene` to `out` in `format` (kFrames frames) and returns the result; fails the test on error.
BakeResult bakeTo(const Scene& scene, CacheFormat format, const fs::path& out, ClipExportOptions exportOptions = {}) {
    BakeOptions options;
    options.output = out;
    options.format = format;
    options.frames = kFrames;
    options.threads = 1;
    options.exportOptions = exportOptions;
    Result<BakeResult> result = bake(scene, options);
    if (!result)
        qFatal("bake failed: %s", result.message().c_str());
    return result.value();
}

/// A small mesh on a small lattice: what the bad-input tests hand writers directly.
ClipSetup smallSetup() {
    ClipSetup setup;
    Mesh& mesh = setup.restMesh;
    mesh.positions = {Vec3f(0, 0, 0), Vec3f(1, 0, 0), Vec3f(0, 1, 0), Vec3f(1, 1, 0.5f)};
    mesh.triangles = {{0, 1, 2}, {1, 3, 2}};
    mesh.computeNormals();
    auto box = fitBox(mesh.positions);
    auto lattice = Lattice::create(LatticeShape{}, box.value());
    setup.objects.push_back(ClipObject{"small", 0, 4, 0, 2, lattice.value()});
    setup.info.pointCount = 4;
    setup.info.frameCount = 2;
    setup.info.fps = 24.0;
    return setup;
}

}  // namespace

class TestExports : public QObject {
    Q_OBJECT

private slots:
    void initTestCase();
    void formatNamesAndOutputs();
    void gltfRoundTrip_data();
    void gltfRoundTrip();
    void nonFiniteFrameLeavesOldFiles_data();
    void nonFiniteFrameLeavesOldFiles();
    void unwritablePathFailsEarly_data();
    void unwritablePathFailsEarly();

private:
    Scene m_fish;  ///< The angelfish swim scene (Bezier 4x4x4).
};

void TestExports::initTestCase() { m_fish = loadScene(kSource / "presets/scenes/angelfish-swim.softtouch"); }

void TestExports::formatNamesAndOutputs() {
    for (const char* name : kClipFormats) {
        const auto format = parseCacheFormat(name);
        QVERIFY(format);
        QCOMPARE(cacheFormatName(*format), std::string_view(name));
        QVERIFY(!isVertexCacheFormat(*format));
        QVERIFY(makeCacheWriter(*format, Mesh{}) == nullptr);
        QVERIFY(makeClipWriter(*format) != nullptr);
    }
    QCOMPARE(cacheFormatFromPath("a/b.GLB"), std::optional(CacheFormat::Glb));
    QCOMPARE(cacheFormatFromPath("a/b.gltf"), std::optional(CacheFormat::Gltf));
    QCOMPARE(exportOutputs(CacheFormat::Vat, "out/fish").back(), fs::path("out/fish.vat.json"));
    QCOMPARE(exportOutputs(CacheFormat::Lattice, "out/fish.v2").front(), fs::path("out/fish.v2.lattice.glb"));
    QCOMPARE(restMeshPath("out/fish.v2", CacheFormat::Lattice), fs::path("out/fish.v2.obj"));
}

void TestExports::gltfRoundTrip_data() {
    QTest::addColumn<QString>("name");
    QTest::addColumn<bool>("linear");
    QTest::addColumn<bool>("normals");
    QTest::newRow("glb linear with normals") << "clip.glb" << true << true;
    QTest::newRow("gltf step without normals") << "clip.gltf" << false << false;
}

void TestExports::gltfRoundTrip() {
    QFETCH(QString, name);
    QFETCH(bool, linear);
    QFETCH(bool, normals);
    QTemporaryDir dir;
    const fs::path out = fs::path(dir.path().toStdString()) / name.toStdString();
    const CacheFormat format = *cacheFormatFromPath(out);
    ClipExportOptions options;
    options.gltfLinear = linear;
    options.gltfNormals = normals;
    const BakeResult baked = bakeTo(m_fish, format, out, options);
    QCOMPARE(baked.files, std::vector<fs::path>{out});
    bakeTo(m_fish, CacheFormat::Pc2, out.parent_path() / "clip.pc2");
    const Result<VertexCache> pc2 = readPc2(out.parent_path() / "clip.pc2");
    QVERIFY2(pc2, pc2.message().c_str());
    const VertexCache& reference = pc2.value();
    const double tolerance = 1e-5 * diagonalOf(reference);

    // Re-import with assimp, no post-processing: vertices stay unjoined and in order.
    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile(out.string(), 0);
    QVERIFY2(scene != nullptr, importer.GetErrorString());
    QCOMPARE(scene->mNumMeshes, 1u);
    const aiMesh* mesh = scene->mMeshes[0];
    QCOMPARE(std::size_t(mesh->mNumVertices), reference.info.pointCount);
    QCOMPARE(int(mesh->mNumAnimMeshes), kFrames);
    QCOMPARE(mesh->mAnimMeshes[0]->HasNormals(), normals);
    double worst = 0.0;
    for (int f = 0; f < kFrames; ++f) {
        const aiAnimMesh* target = mesh->mAnimMeshes[f];
        QCOMPARE(target->mNumVertices, mesh->mNumVertices);
        for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
            // assimp stores a target as absolute positions (rest + delta).
            const aiVector3D& p = target->mVertices[v];
            const Vec3f& expected = reference.frames[std::size_t(f)][v];
            worst = std::max(worst, double((Vec3f(p.x, p.y, p.z) - expected).norm()));
        }
    }
    qInfo("worst glTF position error: %.3g of the diagonal", worst / diagonalOf(reference));
    QVERIFY2(worst <= tolerance, qPrintable(QString("error %1 > %2").arg(worst).arg(tolerance)));
    // The clip really moves: the comparison above is not between identical rest poses.
    QVERIFY((reference.frames.back()[0] - reference.frames.front()[0]).norm() > 0.0f ||
            (reference.frames.back()[100] - reference.frames.front()[100]).norm() > 0.0f);

    // The weights animation: key f at f / fps holds target f alone.
    QCOMPARE(scene->mNumAnimations, 1u);
    const aiAnimation* animation = scene->mAnimations[0];
    QCOMPARE(animation->mNumMorphMeshChannels, 1u);
    const aiMeshMorphAnim* channel = animation->mMorphMeshChannels[0];
    QCOMPARE(int(channel->mNumKeys), kFrames);
    const double ticksPerSecond = animation->mTicksPerSecond > 0 ? animation->mTicksPerSecond : 1.0;
    for (int f = 0; f < kFrames; ++f) {
        const aiMeshMorphKey& key = channel->mKeys[f];
        QVERIFY(std::abs(key.mTime / ticksPerSecond - f / m_fish.world.fps) < 1e-6);
        double sum = 0.0;
        bool found = false;
        for (unsigned k = 0; k < key.mNumValuesAndWeights; ++k) {
            sum += key.mWeights[k];
            if (key.mValues[k] == unsigned(f) && key.mWeights[k] == 1.0)
                found = true;
        }
        QVERIFY(found);
        QCOMPARE(sum, 1.0);
    }
}

void TestExports::nonFiniteFrameLeavesOldFiles_data() {
    QTest::addColumn<QString>("format");
    for (const char* name : kClipFormats)
        QTest::newRow(name) << name;
}

void TestExports::nonFiniteFrameLeavesOldFiles() {
    QFETCH(QString, format);
    const CacheFormat kind = *parseCacheFormat(format.toStdString());
    QTemporaryDir dir;
    const fs::path base = fs::path(dir.path().toStdString()) / ("clip." + format.toStdString());
    const std::vector<fs::path> outputs = exportOutputs(kind, base);
    for (const fs::path& path : outputs)
        writeText(path, "previous " + path.filename().string());
    const QStringList before = folderEntries(base.parent_path());

    const ClipSetup setup = smallSetup();
    auto writer = makeClipWriter(kind);
    QVERIFY(writer->begin(base, setup));
    std::vector<Vec3f> positions = setup.restMesh.positions;
    std::vector<Vec3f> normals = setup.restMesh.normals;
    std::vector<Vec3> nodes = setup.objects.front().lattice.restNodes();
    FrameData frame;
    frame.positions = positions;
    frame.normals = normals;
    frame.nodes = {nodes};
    QVERIFY(writer->writeFrame(frame));
    positions[2].y() = std::numeric_limits<float>::quiet_NaN();
    if (kind == CacheFormat::Lattice) {  // the lattice cache stores nodes: poison those
        positions[2].y() = 0.0f;
        nodes[5].x() = std::numeric_limits<double>::infinity();
    }
    const Status s = writer->writeFrame(frame);
    QVERIFY(!s);
    QVERIFY2(QString::fromStdString(s.message()).contains("not finite"), s.message().c_str());
    QVERIFY2(QString::fromStdString(s.message()).contains(QString::fromStdString(base.string())), s.message().c_str());
    QVERIFY(!writer->finish());
    for (const fs::path& path : outputs)
        QCOMPARE(readText(path), "previous " + path.filename().string());
    QCOMPARE(folderEntries(base.parent_path()), before);
}

void TestExports::unwritablePathFailsEarly_data() {
    QTest::addColumn<QString>("format");
    for (const char* name : kClipFormats)
        QTest::newRow(name) << name;
}

void TestExports::unwritablePathFailsEarly() {
    QFETCH(QString, format);
    const CacheFormat kind = *parseCacheFormat(format.toStdString());
    QTemporaryDir dir;
    const fs::path missing = fs::path(dir.path().toStdString()) / "no-such-folder" / "clip";
    auto writer = makeClipWriter(kind);
    const Status s = writer->begin(missing, smallSetup());
    QVERIFY(!s);
    QVERIFY2(QString::fromStdString(s.message()).contains("no-such-folder"), s.message().c_str());
    QVERIFY(!fs::exists(missing.parent_path()));
}

QTEST_GUILESS_MAIN(TestExports)
#include "test_exports.moc"

// Round trips of the clip exports (glTF/GLB morph animation, vertex animation textures, lattice
// cache) against the PC2 of the same bake, and their behaviour on bad input.

#include "helpers/gltf_read.h"
#include "io/documents/project_file.h"
#include "io/export/clip_writer.h"
#include "io/export/clip_writer_internal.h"
#include "io/export/export_formats.h"
#include "io/export/lattice_cache.h"
#include "io/export/vertex_cache.h"
#include "io/import/gltf_meshopt.h"
#include "io/pipeline/bake.h"

#include <assimp/Importer.hpp>
#include <assimp/anim.h>
#include <assimp/mesh.h>
#include <assimp/scene.h>

#include <ImfRgbaFile.h>
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include <QProcess>
#include "core/fitting/morph_basis.h"

#include <QStandardPaths>
#include <QTemporaryDir>
#include <QtTest>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <set>
#include <string>

#include <sys/stat.h>

using namespace softtouch;
using namespace softtouch::io;
using softtouch::test::accessorFloats;
using softtouch::test::loadGlb;
namespace fs = std::filesystem;

namespace {

const fs::path kSource = SOFTTOUCH_SOURCE_DIR;

/// Frames baked by the round trips: enough for real motion, few enough for ASan runs.
constexpr int kFrames = 6;

/// The formats written through ClipWriter only.
const char* const kClipFormats[] = {"gltf", "glb", "vat", "lattice"};

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
BakeResult bakeTo(const Scene& scene, std::string_view format, const fs::path& out, ClipExportOptions exportOptions = {}) {
    BakeOptions options;
    options.output = out;
    options.format = findExportFormat(format);
    if (!options.format)
        qFatal("no export is called %s", std::string(format).c_str());
    options.frames = kFrames;
    options.threads = 1;
    options.exportOptions = exportOptions;
    Result<BakeResult> result = bake(scene, options);
    if (!result)
        qFatal("bake failed: %s", result.message().c_str());
    return result.value();
}

/// One data row per export of the registry (io/export/export_formats.h), named after it: a new export gets
/// the failure tests below without a line here.
void exportRows() {
    QTest::addColumn<QString>("format");
    for (const ExportFormat& f : exportFormats())
        QTest::newRow(std::string(f.name).c_str()) << QString::fromUtf8(f.name.data(), qsizetype(f.name.size()));
}

/// Every B-spline basis function of one axis and its derivative at t, by the textbook Cox-de Boor
/// recursion over the header's knot vector (dense, 0/0 = 0): independent of core/geometry/axis_basis and of
/// the shaders' triangular form. Outside [0,1] the end spans extrapolate, as the engine does.
struct AxisValues {
    std::vector<double> value;  ///< N_i(t), i < count.
    std::vector<double> slope;  ///< dN_i/dt.
};

AxisValues bsplineBasis(const std::vector<double>& knots, int degree, int count, double t) {
    int span = degree;  // the last knot span whose start is <= t
    while (span < count - 1 && knots[std::size_t(span + 1)] <= t)
        ++span;
    const auto ratio = [](double a, double b) { return b == 0.0 ? 0.0 : a / b; };
    const auto U = [&](int i) { return knots[std::size_t(i)]; };
    std::vector<double> n(knots.size(), 0.0);  // degree q functions, N_{i,q} for i < knots - q - 1
    n[std::size_t(span)] = 1.0;
    std::vector<double> lower;
    for (int q = 1; q <= degree; ++q) {
        lower = n;
        for (int i = 0; i + q + 1 < int(knots.size()); ++i)
            n[std::size_t(i)] = ratio(t - U(i), U(i + q) - U(i)) * lower[std::size_t(i)] +
                                ratio(U(i + q + 1) - t, U(i + q + 1) - U(i + 1)) * lower[std::size_t(i + 1)];
    }
    AxisValues out;
    out.value.assign(n.begin(), n.begin() + count);
    out.slope.assign(std::size_t(count), 0.0);
    for (int i = 0; i < count; ++i)  // N'_{i,p} = p N_{i,p-1} / (U_{i+p} - U_i) - p N_{i+1,p-1} / (U_{i+p+1} - U_{i+1})
        out.slope[std::size_t(i)] = degree * (ratio(lower[std::size_t(i)], U(i + degree) - U(i)) -
                                              ratio(lower[std::size_t(i + 1)], U(i + degree + 1) - U(i + 1)));
    return out;
}

/// The three axes' basis of one object of a lattice cache at a vertex's parameters: a vertex's for every frame.
using LatticeBasis = std::array<AxisValues, 3>;
LatticeBasis latticeBasis(const LatticeCacheObject& object, const Vec3& uvw) {
    LatticeBasis axis;
    for (std::size_t a = 0; a < 3; ++a)
        axis[a] = bsplineBasis(object.knots[a], object.degrees[a], object.nodes[a], uvw[int(a)]);
    return axis;
}

/// x(u,v,w) = sum_ijk P_ijk N_i(u) N_j(v) N_k(w) for one object of a lattice cache, and the unit
/// normal from the Jacobian's cofactor (core/geometry/binding.h) applied to the rest normal.
std::pair<Vec3, Vec3> evaluateLattice(const LatticeCacheObject& object, const Vec3f* nodes, const LatticeBasis& axis,
                                      const Vec3& restNormal) {
    Vec3 x = Vec3::Zero();
    Vec3 xu = Vec3::Zero();
    Vec3 xv = Vec3::Zero();
    Vec3 xw = Vec3::Zero();
    for (int k = 0; k < object.nodes[2]; ++k)
        for (int j = 0; j < object.nodes[1]; ++j)
            for (int i = 0; i < object.nodes[0]; ++i) {
                const Vec3 p = nodes[i + object.nodes[0] * (j + object.nodes[1] * k)].cast<double>();
                const double nu = axis[0].value[std::size_t(i)], nv = axis[1].value[std::size_t(j)],
                             nw = axis[2].value[std::size_t(k)];
                x += nu * nv * nw * p;
                xu += axis[0].slope[std::size_t(i)] * nv * nw * p;
                xv += nu * axis[1].slope[std::size_t(j)] * nw * p;
                xw += nu * nv * axis[2].slope[std::size_t(k)] * p;
            }
    // cof(A) n_rest with A = d(u,v,w)/dx = diag(1/size) axes^T, up to a positive factor.
    const Vec3 m = (object.box.axes.transpose() * restNormal).cwiseProduct(object.box.size);
    const Vec3 normal = (xv.cross(xw) * m.x() + xw.cross(xu) * m.y() + xu.cross(xv) * m.z()).normalized();
    return {x, normal};
}

/// A project with two objects on different lattices (the star on a cubic B-spline 6x4x4 with its
/// drag, then the swimming angelfish on its Bezier 4x4x4), so that vertex, triangle and node offsets
/// of the second object matter.
void writeTwoObjectProject(const fs::path& path) {
    const fs::path scenes = kSource / "presets/scenes";
    nlohmann::json star = nlohmann::json::parse(readText(scenes / "star-drag.softtouch"));
    nlohmann::json fish = nlohmann::json::parse(readText(scenes / "angelfish-swim.softtouch"));
    nlohmann::json first = star["objects"][0];
    first["lattice"] = {{"kind", "bspline"}, {"nodes", {6, 4, 4}}, {"padding", 0.02}};
    first["mesh"] = (kSource / "presets/meshes/star.obj").string();
    nlohmann::json second = fish["objects"][0];
    second["mesh"] = (kSource / "presets/meshes/angelfish.obj").string();
    second["material"]["preset"] = (kSource / "presets/materials/fish-body.stpreset").string();
    fish["objects"] = nlohmann::json::array({first, second});
    writeText(path, fish.dump(2));
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
    void registryDescribesEveryExport();
    void registryChecksSettingsOnce_data();
    void registryChecksSettingsOnce();
    void gltfRoundTrip_data();
    void gltfRoundTrip();
    void gltfWarnsAboutTargetCount();
    void gltfRefusesClipsTooLongToHold();
    void gltfCompressedMorphsKeepTheErrorTarget_data();
    void gltfCompressedMorphsKeepTheErrorTarget();
    void gltfSkinnedExportReproducesTheClip_data();
    void gltfSkinnedExportReproducesTheClip();
    void compressedGlbDecodesToTheSameBytes();
    void compressedGlbRefusesCorruptInput();
    void indicesTakeSixteenBitsWhereTheyFit();
    void compressedGlbStoresNormalsAsUnitVectors();
    void vatRoundTrip_data();
    void vatRoundTrip();
    void latticeRoundTrip_data();
    void latticeRoundTrip();
    void latticeCacheRejectsBadFiles();
    void latticeShadersCompile_data();
    void latticeShadersCompile();
    void hlslShadersShareTheGlslInterface_data();
    void hlslShadersShareTheGlslInterface();
    void cancelledBakeLeavesOldFiles_data();
    void cancelledBakeLeavesOldFiles();
    void nonFiniteFrameLeavesOldFiles_data();
    void nonFiniteFrameLeavesOldFiles();
    void unchangedFramesAreNotDeformedAgain();
    void unwritablePathFailsEarly_data();
    void unwritablePathFailsEarly();

private:
    Scene m_fish;  ///< The angelfish swim scene (Bezier 4x4x4).
};

void TestExports::initTestCase() { m_fish = loadScene(kSource / "presets/scenes/angelfish-swim.softtouch"); }

void TestExports::formatNamesAndOutputs() {
    // The plain vertex caches keep their names; every export (these too) comes from the registry.
    for (const char* name : {"pc2", "mdd", "objseq"}) {
        const auto format = parseCacheFormat(name);
        QVERIFY(format);
        QCOMPARE(cacheFormatName(*format), std::string_view(name));
        QVERIFY(findExportFormat(name) != nullptr);
    }
    for (const char* name : kClipFormats)
        QVERIFY2(!parseCacheFormat(name), name);
    QCOMPARE(cacheFormatFromPath("a/b.OBJ"), std::optional(CacheFormat::ObjSequence));
    QCOMPARE(cacheFormatFromPath("a/b.glb"), std::nullopt);
    // Where each export's files and rest mesh go.
    QCOMPARE(exportFiles(*findExportFormat("vat"), "out/fish").back(), fs::path("out/fish.vat.json"));
    QCOMPARE(exportFiles(*findExportFormat("lattice"), "out/fish.v2").front(), fs::path("out/fish.v2.lattice.glb"));
    QCOMPARE(exportFiles(*findExportFormat("pc2"), "out/fish.pc2"), std::vector<fs::path>{"out/fish.pc2"});
    const std::vector<fs::path> frames = exportFiles(*findExportFormat("objseq"), "out/fish.obj", 3);
    QCOMPARE(frames, (std::vector<fs::path>{objSequenceFramePath("out/fish.obj", 0), objSequenceFramePath("out/fish.obj", 1),
                                            objSequenceFramePath("out/fish.obj", 2)}));
    QCOMPARE(restMeshPath("out/fish.v2", *findExportFormat("lattice")), fs::path("out/fish.v2.obj"));
    QCOMPARE(restMeshPath("out/fish.pc2", *findExportFormat("pc2")), fs::path("out/fish.obj"));
    QCOMPARE(restMeshPath("out/fish.obj", *findExportFormat("objseq")), fs::path("out/fish.obj"));
}

void TestExports::registryDescribesEveryExport() {
    QStringList names;
    for (const ExportFormat& f : exportFormats()) {
        const QString name = QString::fromUtf8(f.name.data(), qsizetype(f.name.size()));
        QVERIFY2(!names.contains(name), qPrintable(name));
        names << name;
        QCOMPARE(findExportFormat(f.name), &f);
        QCOMPARE(findExportFormat(name.toUpper().toStdString()), &f);
        QVERIFY2(!f.label.empty() && !f.help.empty(), qPrintable(name));
        // What the registry says an export needs is what its writer asks the bake for.
        const std::vector<std::string_view> extensions = extensionsOf(f);
        const fs::path path = fs::path("out/clip") += std::string(extensions.empty() ? std::string_view() : extensions.front());
        const Result<ClipExportOptions> options = exportOptions(f);
        QVERIFY2(options, options.message().c_str());
        const auto writer = f.makeWriter(path, options.value());
        QCOMPARE(writer->needsNormals(), f.needs == ExportNeeds::Normals);
        QCOMPARE(writer->needsNodes(), f.needs == ExportNeeds::LatticeNodes);
        // An export without an extension takes a base path: each file it writes adds a suffix to it.
        if (f.extensions.empty())
            for (const fs::path& out : exportFiles(f, path))
                QVERIFY2(out.string().starts_with(path.string() + "."), out.string().c_str());
        // Its extensions name it, or an export listed before it (.glb is glb, not pca).
        for (std::string_view one : extensionsOf(f)) {
            const ExportFormat* byPath = exportFormatForPath(fs::path("a/b") += std::string(one));
            QVERIFY2(byPath && byPath <= &f, std::string(one).c_str());
        }
    }
    QCOMPARE(QString::fromStdString(exportFormatNames("|", "|")), names.join("|"));
    QVERIFY(QString::fromStdString(exportFormatNames()).endsWith(" or " + names.back()));
    QCOMPARE(exportExtensions(), std::string(".pc2, .mdd, .obj, .gltf, .glb"));
    // The writer of a glTF export follows the path where the export allows both files.
    QCOMPARE(exportFormatForPath("a/b.GLB")->name, std::string_view("glb"));
    QCOMPARE(exportFormatForPath("a/b.obj")->name, std::string_view("objseq"));
    QVERIFY(!exportFormatForPath("a/b"));
    QVERIFY(!exportFormatForPath("a/b.fbx"));
    // pca and skin write what the path names (glTF JSON for .gltf, GLB otherwise); gltf and glb what
    // their names say, whatever the path: read back from the files each writes.
    QTemporaryDir dir;
    const auto written = [&](const char* name, const char* file) {
        const ExportFormat& f = *findExportFormat(name);
        const fs::path path = fs::path(dir.path().toStdString()) / file;
        ClipSetup setup = smallSetup();
        auto writer = f.makeWriter(path, exportOptions(f).value());
        if (!writer->begin(path, setup))
            return std::string("begin failed");
        std::vector<Vec3f> positions = setup.restMesh.positions;
        FrameData frame;
        frame.normals = setup.restMesh.normals;
        frame.nodes = {setup.objects.front().lattice.restNodes()};
        for (std::size_t k = 0; k < setup.info.frameCount; ++k) {
            positions[3].z() = 0.5f + 0.1f * float(k);
            frame.positions = positions;
            if (!writer->writeFrame(frame))
                return std::string("frame failed");
        }
        if (Status s = writer->finish(); !s)
            return s.message();
        return readText(path).substr(0, 4) == "glTF" ? std::string("glb") : std::string("gltf");
    };
    QCOMPARE(written("pca", "a.gltf"), std::string("gltf"));
    QCOMPARE(written("skin", "b.GLTF"), std::string("gltf"));
    QCOMPARE(written("skin", "c.glb"), std::string("glb"));
    QCOMPARE(written("pca", "d"), std::string("glb"));
    QCOMPARE(written("glb", "e.gltf"), std::string("glb"));  // named: the name wins
    QCOMPARE(written("gltf", "f.glb"), std::string("gltf"));
}

void TestExports::registryChecksSettingsOnce_data() {
    QTest::addColumn<QString>("format");
    QTest::addColumn<double>("error");    // < 0: unset
    QTest::addColumn<double>("targets");
    QTest::addColumn<double>("bones");
    QTest::addColumn<QString>("problem");
    QTest::newRow("error on pc2") << "pc2" << 0.01 << -1.0 << -1.0 << "--error: is for --format pca and --format skin";
    QTest::newRow("targets on glb") << "glb" << -1.0 << 8.0 << -1.0 << "--targets: is for --format pca";
    QTest::newRow("bones on pca") << "pca" << -1.0 << -1.0 << 16.0 << "--bones: is for --format skin";
    QTest::newRow("bones and error") << "skin" << 0.01 << -1.0 << 16.0 << "--bones: fixes the bone count, and --error chooses it: give one";
    QTest::newRow("error 0") << "pca" << 0.0 << -1.0 << -1.0 << "--error: must be a number in (0, 0.1] (a fraction of the diagonal), got 0";
    QTest::newRow("error 0.2") << "skin" << 0.2 << -1.0 << -1.0 << "--error: must be a number in (0, 0.1] (a fraction of the diagonal), got 0.2";
    QTest::newRow("one target") << "pca" << -1.0 << 1.0 << -1.0 << "--targets: must be a whole number in [2, 256]";
    QTest::newRow("half a target") << "pca" << -1.0 << 2.5 << -1.0 << "--targets: must be a whole number in [2, 256]";
    QTest::newRow("257 bones") << "skin" << -1.0 << -1.0 << 257.0 << "--bones: must be a whole number in [1, 256], got 257";
    QTest::newRow("pca, 8 targets") << "pca" << 0.01 << 8.0 << -1.0 << "";
    QTest::newRow("skin, 16 bones") << "skin" << -1.0 << -1.0 << 16.0 << "";
    QTest::newRow("skin, defaults") << "skin" << -1.0 << -1.0 << -1.0 << "";
    QTest::newRow("pc2, defaults") << "pc2" << -1.0 << -1.0 << -1.0 << "";
}

void TestExports::registryChecksSettingsOnce() {
    QFETCH(QString, format);
    QFETCH(double, error);
    QFETCH(double, targets);
    QFETCH(double, bones);
    QFETCH(QString, problem);
    const auto set = [](double v) { return v < 0 ? std::nullopt : std::optional(v); };
    const Result<ClipExportOptions> options =
        exportOptions(*findExportFormat(format.toStdString()), {set(error), set(targets), set(bones)});
    if (!problem.isEmpty()) {
        QVERIFY(!options);
        QVERIFY2(QString::fromStdString(options.message()).startsWith(problem), options.message().c_str());
        return;
    }
    QVERIFY2(options, options.message().c_str());
    const double target = error < 0 ? ClipExportOptions::kDefaultCompressionError : error;
    const bool pca = format == "pca", skin = format == "skin";
    QCOMPARE(options->gltfMorphError, pca ? target : 0.0);
    QCOMPARE(options->gltfMaxMorphs, pca && targets > 0 ? int(targets) - 1 : 32);
    QCOMPARE(options->skinBones, skin && bones > 0 ? int(bones) : 0);
    QCOMPARE(options->skinError, skin && bones < 0 ? target : 0.0);
}

void TestExports::gltfRoundTrip_data() {
    QTest::addColumn<QString>("name");
    QTest::addColumn<bool>("linear");
    QTest::addColumn<bool>("normals");
    QTest::addColumn<QString>("sceneFile");  // empty: the angelfish swim
    QTest::newRow("glb linear with normals") << "clip.glb" << true << true << "";
    QTest::newRow("gltf step without normals") << "clip.gltf" << false << false << "";
    // A body on a base animation (the rig moves the mesh, the lattice adds the wobble) exports the same way.
    QTest::newRow("glb of the rigged guppy") << "clip.glb" << true << true << "guppy-rigged.softtouch";
    // Two objects: one mesh and node per object, named after it, each with its own targets (#15 item 3).
    QTest::newRow("glb of the angelfish pair") << "clip.glb" << true << true << "angelfish-pair.softtouch";
}

void TestExports::gltfRoundTrip() {
    QFETCH(QString, name);
    QFETCH(bool, linear);
    QFETCH(bool, normals);
    QFETCH(QString, sceneFile);
    const Scene source = sceneFile.isEmpty() ? m_fish : loadScene(kSource / "presets/scenes" / sceneFile.toStdString());
    QTemporaryDir dir;
    const fs::path out = fs::path(dir.path().toStdString()) / name.toStdString();
    const ExportFormat& format = *exportFormatForPath(out);
    ClipExportOptions options;
    options.gltfLinear = linear;
    options.gltfNormals = normals;
    const BakeResult baked = bakeTo(source, format.name, out, options);
    QCOMPARE(baked.files, std::vector<fs::path>{out});
    bakeTo(source, "pc2", out.parent_path() / "clip.pc2");
    const Result<VertexCache> pc2 = readPc2(out.parent_path() / "clip.pc2");
    QVERIFY2(pc2, pc2.message().c_str());
    const VertexCache& reference = pc2.value();
    const double tolerance = 1e-5 * diagonalOf(reference);

    // Re-import with assimp, no post-processing: vertices stay unjoined and in order, one mesh per object
    // (named after it) in scene order, together the cache's vertices.
    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile(out.string(), 0);
    QVERIFY2(scene != nullptr, importer.GetErrorString());
    QCOMPARE(std::size_t(scene->mNumMeshes), source.objects.size());
    double worst = 0.0;
    std::size_t first = 0;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        const aiMesh* mesh = scene->mMeshes[m];
        if (source.objects.size() > 1)
            QCOMPARE(std::string(mesh->mName.C_Str()), source.objects[m].name);
        QCOMPARE(std::size_t(mesh->mNumVertices), source.objects[m].mesh->positions.size());
        QCOMPARE(int(mesh->mNumAnimMeshes), kFrames);
        QCOMPARE(mesh->mAnimMeshes[0]->HasNormals(), normals);
        for (int f = 0; f < kFrames; ++f) {
            const aiAnimMesh* target = mesh->mAnimMeshes[f];
            QCOMPARE(target->mNumVertices, mesh->mNumVertices);
            for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
                // assimp stores a target as absolute positions (rest + delta).
                const aiVector3D& p = target->mVertices[v];
                const Vec3f& expected = reference.frames[std::size_t(f)][first + v];
                worst = std::max(worst, double((Vec3f(p.x, p.y, p.z) - expected).norm()));
            }
        }
        first += mesh->mNumVertices;
    }
    QCOMPARE(first, reference.info.pointCount);
    qInfo("worst glTF position error: %.3g of the diagonal", worst / diagonalOf(reference));
    QVERIFY2(worst <= tolerance, qPrintable(QString("error %1 > %2").arg(worst).arg(tolerance)));
    // The clip really moves: the comparison above is not between identical rest poses.
    QVERIFY((reference.frames.back()[0] - reference.frames.front()[0]).norm() > 0.0f ||
            (reference.frames.back()[100] - reference.frames.front()[100]).norm() > 0.0f);

    // The weights animation: key f at f / fps holds target f alone.
    QCOMPARE(scene->mNumAnimations, 1u);
    const aiAnimation* animation = scene->mAnimations[0];
    QCOMPARE(std::size_t(animation->mNumMorphMeshChannels), source.objects.size());  // one per object's node
    const aiMeshMorphAnim* channel = animation->mMorphMeshChannels[0];
    QCOMPARE(int(channel->mNumKeys), kFrames);
    const double ticksPerSecond = animation->mTicksPerSecond > 0 ? animation->mTicksPerSecond : 1.0;
    for (int f = 0; f < kFrames; ++f) {
        const aiMeshMorphKey& key = channel->mKeys[f];
        QVERIFY(std::abs(key.mTime / ticksPerSecond - f / source.world.fps) < 1e-6);
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

void TestExports::gltfCompressedMorphsKeepTheErrorTarget_data() {
    QTest::addColumn<double>("target");  // RMS vertex error per frame, fraction of the rest mesh's diagonal
    QTest::newRow("0.3%") << 3e-3;
    QTest::newRow("0.1%") << 1e-3;
    QTest::newRow("0.03%") << 3e-4;
}

void TestExports::gltfCompressedMorphsKeepTheErrorTarget() {
    // The swim baked for a second, exported as compressed morphs, re-imported with assimp and played back
    // as an engine would (rest + Σ weight × (target − rest) at each key): every frame within the target of
    // the PC2 of the same bake, with the fewest components that can be, in fewer bytes than the PC2.
    QFETCH(double, target);
    QTemporaryDir dir;
    const fs::path out = fs::path(dir.path().toStdString()) / "swim.glb";
    constexpr int kSwimFrames = 24;
    BakeOptions options;
    options.output = out;
    options.format = findExportFormat("glb");
    options.frames = kSwimFrames;
    options.threads = 1;
    options.exportOptions.gltfMorphError = target;
    Result<BakeResult> baked = bake(m_fish, options);
    QVERIFY2(baked, baked.message().c_str());
    QVERIFY(!baked->notes.empty());
    options.output = out.parent_path() / "swim.pc2";
    options.format = findExportFormat("pc2");
    QVERIFY(bake(m_fish, options));
    const Result<VertexCache> pc2 = readPc2(out.parent_path() / "swim.pc2");
    QVERIFY2(pc2, pc2.message().c_str());

    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile(out.string(), 0);
    QVERIFY2(scene != nullptr, importer.GetErrorString());
    const aiMesh* mesh = scene->mMeshes[0];
    const std::size_t vertices = mesh->mNumVertices;
    QCOMPARE(vertices, pc2->info.pointCount);
    const std::size_t targets = mesh->mNumAnimMeshes;
    QVERIFY2(targets >= 2 && targets < std::size_t(kSwimFrames), qPrintable(QString::number(targets)));
    Vec3f lo = Vec3f::Constant(1e30f), hi = -lo;
    for (std::size_t v = 0; v < vertices; ++v) {
        const Vec3f p(mesh->mVertices[v].x, mesh->mVertices[v].y, mesh->mVertices[v].z);
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    const double diagonal = double((hi - lo).norm());
    const aiMeshMorphAnim* channel = scene->mAnimations[0]->mMorphMeshChannels[0];
    QCOMPARE(int(channel->mNumKeys), kSwimFrames);
    double worstRms = 0.0;
    std::vector<float> deltas;  // the PC2's frames as displacements from the rest mesh
    for (int f = 0; f < kSwimFrames; ++f) {
        const aiMeshMorphKey& key = channel->mKeys[f];
        double squared = 0.0;
        for (std::size_t v = 0; v < vertices; ++v) {
            const aiVector3D& rest = mesh->mVertices[v];
            aiVector3D p = rest;
            for (unsigned k = 0; k < key.mNumValuesAndWeights; ++k)
                p += float(key.mWeights[k]) * (mesh->mAnimMeshes[key.mValues[k]]->mVertices[v] - rest);
            const Vec3f& expected = pc2->frames[std::size_t(f)][v];
            squared += double((Vec3f(p.x, p.y, p.z) - expected).squaredNorm());
            const Vec3f d = expected - Vec3f(rest.x, rest.y, rest.z);
            deltas.insert(deltas.end(), d.data(), d.data() + 3);
        }
        worstRms = std::max(worstRms, std::sqrt(squared / double(vertices)));
    }
    qInfo("target %.2g: %zu targets (mean + components), worst frame RMS %.3g of the diagonal, %lld bytes against "
          "%lld for PC2", target, targets, worstRms / diagonal, (long long)fs::file_size(out),
          (long long)fs::file_size(out.parent_path() / "swim.pc2"));
    QVERIFY2(worstRms <= target * diagonal * (1.0 + 1e-3) + 1e-7,
             qPrintable(QString("worst frame RMS %1 above %2").arg(worstRms / diagonal).arg(target)));
    // The fewest: one component less misses the target.
    const MorphBasis fewer = fitMorphBasis(deltas, std::size_t(kSwimFrames), 3 * vertices, target * diagonal, targets - 2);
    QVERIFY2(fewer.worstFrameRms > target * diagonal,
             qPrintable(QString("%1 components already reach %2").arg(targets - 2).arg(fewer.worstFrameRms / diagonal)));
    QVERIFY(fs::file_size(out) < fs::file_size(out.parent_path() / "swim.pc2"));
}

void TestExports::gltfSkinnedExportReproducesTheClip_data() {
    QTest::addColumn<double>("error");  // RMS target, fraction of the rest mesh's diagonal (0: fixed bones)
    QTest::addColumn<int>("bones");
    QTest::addColumn<bool>("compressed");  // bake --compress: read back through expandGlb
    QTest::newRow("error 0.5%") << 5e-3 << 0 << false;
    QTest::newRow("16 bones") << 0.0 << 16 << false;
    QTest::newRow("error 0.5%, compressed") << 5e-3 << 0 << true;
}

void TestExports::gltfSkinnedExportReproducesTheClip() {
    // The swim as rigid bones: checked as a validator would (weights ≥ 0 summing to 1, at most 4 per
    // vertex, joints in range, identity inverse binds, one key per frame), then re-imported with assimp and
    // skinned as an engine does, frame by frame, against the PC2 of the same bake. Compressed, the file
    // is at most a tenth of the PC2 and stores 8-bit joints and weights; assimp reads it expanded.
    QFETCH(double, error);
    QFETCH(int, bones);
    QFETCH(bool, compressed);
    QTemporaryDir dir;
    const fs::path out = fs::path(dir.path().toStdString()) / "skin.glb";
    constexpr int kSwimFrames = 24;
    BakeOptions options;
    options.output = out;
    options.format = findExportFormat("glb");
    options.frames = kSwimFrames;
    options.threads = 1;
    options.exportOptions.skinError = error;
    options.exportOptions.skinBones = bones;
    options.exportOptions.gltfCompress = compressed;
    Result<BakeResult> baked = bake(m_fish, options);
    QVERIFY2(baked, baked.message().c_str());
    QVERIFY(!baked->notes.empty());
    const fs::path written = out;
    options.output = out.parent_path() / "skin.pc2";
    options.format = findExportFormat("pc2");
    QVERIFY(bake(m_fish, options));
    const Result<VertexCache> pc2 = readPc2(out.parent_path() / "skin.pc2");
    QVERIFY2(pc2, pc2.message().c_str());
    const std::size_t n = pc2->info.pointCount;
    const fs::path read = compressed ? out.parent_path() / "expanded.glb" : out;
    if (compressed) {
        const std::string packed = readText(out);
        QVERIFY(usesMeshoptCompression(packed));
        QVERIFY2(fs::file_size(out) * 10 <= fs::file_size(out.parent_path() / "skin.pc2"),
                 qPrintable(QString("%1 bytes against %2 for PC2").arg(fs::file_size(out)).arg(fs::file_size(out.parent_path() / "skin.pc2"))));
        Result<std::string> expanded = expandGlb(packed, out.string());
        QVERIFY2(expanded, expanded.message().c_str());
        QVERIFY(!usesMeshoptCompression(expanded.value()));
        writeText(read, expanded.value());
    }

    const tinygltf::Model model = loadGlb(read);
    QCOMPARE(model.skins.size(), std::size_t(1));
    const std::size_t joints = model.skins[0].joints.size();
    QVERIFY(joints >= 8 && joints <= 64);
    if (bones > 0)
        QCOMPARE(int(joints), bones);
    const tinygltf::Primitive& primitive = model.meshes.at(0).primitives.at(0);
    const tinygltf::Accessor& jointAccessor = model.accessors.at(std::size_t(primitive.attributes.at("JOINTS_0")));
    const tinygltf::Accessor& weightAccessor = model.accessors.at(std::size_t(primitive.attributes.at("WEIGHTS_0")));
    QCOMPARE(jointAccessor.componentType, compressed ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE : TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
    const tinygltf::BufferView& jointView = model.bufferViews.at(std::size_t(jointAccessor.bufferView));
    std::vector<std::uint16_t> jointIndices(4 * n);
    std::vector<float> weights(4 * n);
    if (compressed) {
        // The file's weights were normalized bytes (expanded to floats for assimp): whole 255ths, each vertex's
        // summing to exactly 255.
        QCOMPARE(weightAccessor.componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
        weights = accessorFloats(model, primitive.attributes.at("WEIGHTS_0"));
        const unsigned char* j8 = model.buffers[0].data.data() + jointView.byteOffset;
        for (std::size_t v = 0; v < n; ++v) {
            long sum = 0;
            for (std::size_t s = 0; s < 4; ++s) {
                jointIndices[4 * v + s] = j8[4 * v + s];
                const double steps = double(weights[4 * v + s]) * 255.0;
                QVERIFY2(std::abs(steps - std::round(steps)) < 1e-4, qPrintable(QString("vertex %1: weight %2").arg(v).arg(steps)));
                sum += std::lround(steps);
            }
            QVERIFY2(sum == 255, qPrintable(QString("vertex %1 weights sum to %2/255").arg(v).arg(sum)));
        }
    } else {
        weights = accessorFloats(model, primitive.attributes.at("WEIGHTS_0"));
        std::memcpy(jointIndices.data(), model.buffers[0].data.data() + jointView.byteOffset, jointIndices.size() * 2);
    }
    QCOMPARE(weights.size(), 4 * n);
    for (std::size_t v = 0; v < n; ++v) {
        float sum = 0.0f;
        for (std::size_t s = 0; s < 4; ++s) {
            QVERIFY(weights[4 * v + s] >= 0.0f);
            QVERIFY(jointIndices[4 * v + s] < joints);
            sum += weights[4 * v + s];
        }
        QVERIFY2(std::abs(sum - 1.0f) <= 2e-7f * 4, qPrintable(QString("vertex %1 weights sum to %2").arg(v).arg(double(sum))));
    }
    QVERIFY(!model.accessors.at(std::size_t(primitive.attributes.at("POSITION"))).minValues.empty());
    const std::vector<float> inverseBinds = accessorFloats(model, model.skins[0].inverseBindMatrices);
    QCOMPARE(inverseBinds.size(), 16 * joints);
    for (std::size_t i = 0; i < inverseBinds.size(); ++i)
        QCOMPARE(inverseBinds[i], (i % 16) % 5 == 0 ? 1.0f : 0.0f);

    // assimp's view: bones with offset matrices and weights, node animations with one key per frame.
    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile(read.string(), 0);
    QVERIFY2(scene != nullptr, importer.GetErrorString());
    const aiMesh* mesh = scene->mMeshes[0];
    QCOMPARE(std::size_t(mesh->mNumVertices), n);
    QVERIFY(mesh->mNumBones >= 1 && mesh->mNumBones <= joints);
    QCOMPARE(scene->mNumAnimations, 1u);
    const aiAnimation* animation = scene->mAnimations[0];
    std::map<std::string, const aiNodeAnim*> channels;
    for (unsigned c = 0; c < animation->mNumChannels; ++c)
        channels[animation->mChannels[c]->mNodeName.C_Str()] = animation->mChannels[c];
    Vec3f lo = Vec3f::Constant(1e30f), hi = -lo;
    for (std::size_t v = 0; v < n; ++v) {
        const Vec3f p(mesh->mVertices[v].x, mesh->mVertices[v].y, mesh->mVertices[v].z);
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    const double diagonal = double((hi - lo).norm());
    double sum2 = 0.0, worst = 0.0;
    std::vector<aiVector3D> skinned(n);
    for (int f = 0; f < kSwimFrames; ++f) {
        std::fill(skinned.begin(), skinned.end(), aiVector3D(0, 0, 0));
        for (unsigned b = 0; b < mesh->mNumBones; ++b) {
            const aiBone* bone = mesh->mBones[b];
            const aiNodeAnim* channel = channels.at(bone->mName.C_Str());
            QCOMPARE(int(channel->mNumPositionKeys), kSwimFrames);
            QCOMPARE(int(channel->mNumRotationKeys), kSwimFrames);
            aiMatrix4x4 m(aiVector3D(1, 1, 1), channel->mRotationKeys[f].mValue, channel->mPositionKeys[f].mValue);
            m = m * bone->mOffsetMatrix;
            for (unsigned w = 0; w < bone->mNumWeights; ++w) {
                const aiVertexWeight& vw = bone->mWeights[w];
                skinned[vw.mVertexId] += vw.mWeight * (m * mesh->mVertices[vw.mVertexId]);
            }
        }
        for (std::size_t v = 0; v < n; ++v) {
            const double e = double((Vec3f(skinned[v].x, skinned[v].y, skinned[v].z) - pc2->frames[std::size_t(f)][v]).norm());
            sum2 += e * e;
            worst = std::max(worst, e);
        }
    }
    const double rms = std::sqrt(sum2 / double(n * kSwimFrames));
    qInfo("%zu bones: RMS %.3g, worst %.3g of the diagonal; %lld bytes against %lld for PC2", joints, rms / diagonal,
          worst / diagonal, (long long)fs::file_size(written), (long long)fs::file_size(out.parent_path() / "skin.pc2"));
    QVERIFY2(rms <= 5e-3 * diagonal, qPrintable(QString("RMS %1 of the diagonal").arg(rms / diagonal)));
    if (error > 0.0)
        QVERIFY(rms <= error * diagonal * 1.001);
    QVERIFY(fs::file_size(out) < fs::file_size(out.parent_path() / "skin.pc2"));
}

namespace {

/// The bytes an accessor reads (count elements, the view's stride honoured), tightly packed.
std::string accessorBytes(const tinygltf::Model& model, int index) {
    const tinygltf::Accessor& accessor = model.accessors.at(std::size_t(index));
    const tinygltf::BufferView& view = model.bufferViews.at(std::size_t(accessor.bufferView));
    const std::size_t element = std::size_t(tinygltf::GetComponentSizeInBytes(std::uint32_t(accessor.componentType)) *
                                            tinygltf::GetNumComponentsInType(std::uint32_t(accessor.type)));
    const std::size_t stride = view.byteStride != 0 ? view.byteStride : element;
    const auto* data = reinterpret_cast<const char*>(model.buffers.at(std::size_t(view.buffer)).data.data()) + view.byteOffset +
                       accessor.byteOffset;
    std::string out;
    for (std::size_t i = 0; i < accessor.count; ++i)
        out.append(data + i * stride, element);
    return out;
}

/// A GLB's JSON and binary chunk, apart and back together (to corrupt one field of a real file).
std::pair<nlohmann::json, std::string> splitGlb(const std::string& glb) {
    std::uint32_t jsonLength = 0, binLength = 0;
    std::memcpy(&jsonLength, glb.data() + 12, 4);
    std::memcpy(&binLength, glb.data() + 20 + jsonLength, 4);
    return {nlohmann::json::parse(glb.substr(20, jsonLength)), glb.substr(28 + jsonLength, binLength)};
}

std::string joinGlb(const nlohmann::json& document, std::string bin) {
    std::string text = document.dump();
    while (text.size() % 4 != 0)
        text += ' ';
    const auto u32 = [](std::size_t v) {
        const auto x = std::uint32_t(v);
        return std::string(reinterpret_cast<const char*>(&x), 4);
    };
    return "glTF" + u32(2) + u32(28 + text.size() + bin.size()) + u32(text.size()) + "JSON" + text + u32(bin.size()) +
           std::string("BIN\0", 4) + bin;
}

}  // namespace

void TestExports::compressedGlbDecodesToTheSameBytes() {
    // Compressed morphs, packed and unpacked: every accessor decodes to the bytes the plain export holds
    // (positions, keys), except the normals, which come back as 16-bit octahedral vectors within 1e-4 rad,
    // the morph targets, each value within 2^-15 of itself (16-bit mantissas) and with bounds that are the
    // decoded values', and the triangles, which may start at another corner. Only a GLB takes --compress, and only the formats that write one.
    QTemporaryDir dir;
    const fs::path plainPath = fs::path(dir.path().toStdString()) / "plain.glb";
    const fs::path packedPath = plainPath.parent_path() / "packed.glb";
    ClipExportOptions options = exportOptions(*findExportFormat("pca")).value();
    bakeTo(m_fish, "pca", plainPath, options);
    options.gltfCompress = true;
    const BakeResult packedBake = bakeTo(m_fish, "pca", packedPath, options);
    QVERIFY(!packedBake.notes.empty());
    const std::string packed = readText(packedPath);
    QVERIFY(usesMeshoptCompression(packed));
    QVERIFY(packed.size() < fs::file_size(plainPath));
    const nlohmann::json document = splitGlb(packed).first;
    QVERIFY(document.at("extensionsRequired").dump().find("EXT_meshopt_compression") != std::string::npos);
    QVERIFY(document.at("extensionsRequired").dump().find("KHR_mesh_quantization") != std::string::npos);
    Result<std::string> expanded = expandGlb(packed, packedPath.string());
    QVERIFY2(expanded, expanded.message().c_str());
    writeText(plainPath.parent_path() / "expanded.glb", expanded.value());
    const tinygltf::Model plain = loadGlb(plainPath);
    const tinygltf::Model unpacked = loadGlb(plainPath.parent_path() / "expanded.glb");
    QCOMPARE(unpacked.accessors.size(), plain.accessors.size());
    QVERIFY(unpacked.extensionsRequired.empty());
    const int normals = plain.meshes.at(0).primitives.at(0).attributes.at("NORMAL");
    const int indices = plain.meshes.at(0).primitives.at(0).indices;
    std::set<int> targets;
    for (const auto& target : plain.meshes.at(0).primitives.at(0).targets)
        for (const auto& [semantic, accessor] : target)
            targets.insert(accessor);
    QVERIFY(targets.size() >= 2);  // at least the mean, positions and normals
    double worstAngle = 0.0, worstTarget = 0.0;
    for (int a = 0; a < int(plain.accessors.size()); ++a) {
        QCOMPARE(unpacked.accessors[std::size_t(a)].count, plain.accessors[std::size_t(a)].count);
        const std::string before = accessorBytes(plain, a), after = accessorBytes(unpacked, a);
        QCOMPARE(after.size(), before.size());
        if (a == indices) {
            // The triangle codec may start a triangle at another corner: the same triangles, order and winding.
            // The fish's 3,656 vertices take 16-bit indices.
            QCOMPARE(plain.accessors[std::size_t(a)].componentType, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
            const auto corners = [](const std::string& bytes, std::size_t t) {
                std::array<std::uint16_t, 3> c;
                std::memcpy(c.data(), bytes.data() + 6 * t, 6);
                return c;
            };
            for (std::size_t t = 0; t < before.size() / 6; ++t) {
                const std::array<std::uint16_t, 3> x = corners(before, t), y = corners(after, t);
                const bool same = y == x || y == std::array{x[1], x[2], x[0]} || y == std::array{x[2], x[0], x[1]};
                QVERIFY2(same, qPrintable(QString("triangle %1 is another triangle").arg(t)));
            }
            continue;
        }
        if (targets.count(a)) {
            const tinygltf::Accessor& unpackedAccessor = unpacked.accessors[std::size_t(a)];
            std::array<float, 3> lo{1e30f, 1e30f, 1e30f}, hi{-1e30f, -1e30f, -1e30f};
            for (std::size_t i = 0; i < before.size() / 12; ++i) {
                float x[3], y[3];
                std::memcpy(x, before.data() + 12 * i, 12);
                std::memcpy(y, after.data() + 12 * i, 12);
                for (int c = 0; c < 3; ++c) {
                    QVERIFY2(std::abs(y[c] - x[c]) <= std::abs(x[c]) * 0x1p-15f,
                             qPrintable(QString("accessor %1, vertex %2: %3 for %4").arg(a).arg(i).arg(double(y[c])).arg(double(x[c]))));
                    worstTarget = std::max(worstTarget, double(std::abs(y[c] - x[c])));
                    lo[std::size_t(c)] = std::min(lo[std::size_t(c)], y[c]);
                    hi[std::size_t(c)] = std::max(hi[std::size_t(c)], y[c]);
                }
            }
            if (!unpackedAccessor.minValues.empty())  // POSITION's bounds: the validator compares them with the data
                for (std::size_t c = 0; c < 3; ++c) {
                    QCOMPARE(unpackedAccessor.minValues[c], double(lo[c]));
                    QCOMPARE(unpackedAccessor.maxValues[c], double(hi[c]));
                }
            continue;
        }
        if (a != normals) {
            QVERIFY2(after == before, qPrintable(QString("accessor %1 decodes to other bytes").arg(a)));
            continue;
        }
        for (std::size_t i = 0; i < before.size() / 12; ++i) {
            Vec3f x, y;
            std::memcpy(x.data(), before.data() + 12 * i, 12);
            std::memcpy(y.data(), after.data() + 12 * i, 12);
            worstAngle = std::max(worstAngle, std::atan2(double(x.cross(y).norm()), double(x.dot(y))));
        }
    }
    qInfo("pca: %zu bytes packed against %lld plain; normals within %.2g rad, morph-target deltas within %.2g m", packed.size(),
          (long long)fs::file_size(plainPath), worstAngle, worstTarget);
    QVERIFY2(worstAngle > 0.0 && worstAngle <= 1e-4, qPrintable(QString::number(worstAngle)));
    // The bake says how far packing moved the targets: the largest change, as measured here.
    const auto said = std::find_if(packedBake.notes.begin(), packedBake.notes.end(),
                                   [](const std::string& note) { return note.find("packed: morph-target deltas within") != std::string::npos; });
    QVERIFY2(said != packedBake.notes.end(), packedBake.notes.front().c_str());
    char expected[32];
    std::snprintf(expected, sizeof expected, "within %.2g m", worstTarget);
    QVERIFY2(said->find(expected) != std::string::npos, qPrintable(QString::fromStdString(*said) + " / " + expected));
    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile((plainPath.parent_path() / "expanded.glb").string(), 0);
    QVERIFY2(scene != nullptr, importer.GetErrorString());
    QCOMPARE(std::size_t(scene->mMeshes[0]->mNumVertices), plain.accessors.at(std::size_t(plain.meshes[0].primitives[0].attributes.at("POSITION"))).count);

    // Where --compress does not apply.
    const auto onPc2 = exportOptions(*findExportFormat("pc2"), {std::nullopt, std::nullopt, std::nullopt, true});
    QVERIFY(!onPc2);
    QCOMPARE(QString::fromStdString(onPc2.message()), QString("--compress: is for --format glb and --format pca and --format skin"));
    QVERIFY(exportOptions(*findExportFormat("skin"), {std::nullopt, std::nullopt, std::nullopt, true})->gltfCompress);
    BakeOptions json;
    json.output = plainPath.parent_path() / "packed.gltf";
    json.format = findExportFormat("pca");
    json.frames = kFrames;
    json.exportOptions = options;
    const Result<BakeResult> refused = bake(m_fish, json);
    QVERIFY(!refused);
    QVERIFY2(refused.message().find("packed.gltf") != std::string::npos && refused.message().find(".glb") != std::string::npos,
             refused.message().c_str());
    QVERIFY(!fs::exists(json.output));
}

void TestExports::indicesTakeSixteenBitsWhereTheyFit() {
    // Every GLB export's triangles: 16-bit while each index (relative to its primitive's first vertex) is below
    // 65535, the value glTF reserves; 32-bit from there. The view after them starts on 4 bytes either way.
    for (const std::uint32_t largest : {65534u, 65535u}) {
        tinygltf::Model model;
        model.buffers.emplace_back();
        model.buffers.front().data.assign(4, 0);
        const std::uint32_t base = 10;
        const std::vector<std::array<std::uint32_t, 3>> triangles{{10, 11, 12}, {12, 11, base + largest}, {13, 14, 15}};
        const int a = detail::addIndexAccessor(model, triangles, base);
        const tinygltf::Accessor& accessor = model.accessors.at(std::size_t(a));
        const bool narrow = largest < 65535;
        QCOMPARE(accessor.componentType, narrow ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT : TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);
        QCOMPARE(accessor.count, std::size_t(9));
        const std::string bytes = accessorBytes(model, a);
        QCOMPARE(bytes.size(), std::size_t(narrow ? 18 : 36));
        for (std::size_t i = 0; i < 9; ++i) {
            std::uint32_t value = 0;
            std::memcpy(&value, bytes.data() + i * (narrow ? 2 : 4), narrow ? 2 : 4);
            QCOMPARE(value, triangles[i / 3][i % 3] - base);
        }
        QCOMPARE(model.buffers.front().data.size() % 4, std::size_t(0));
    }
}

void TestExports::compressedGlbRefusesCorruptInput() {
    // A compressed GLB with one thing wrong: every reading fails with the file, the view and the problem,
    // and nothing crashes (fuzz_glb explores the rest).
    QTemporaryDir dir;
    const fs::path path = fs::path(dir.path().toStdString()) / "packed.glb";
    ClipExportOptions options = exportOptions(*findExportFormat("pca")).value();
    options.gltfCompress = true;
    bakeTo(m_fish, "pca", path, options);
    const std::string packed = readText(path);
    QVERIFY(expandGlb(packed, "packed.glb"));
    const auto [document, bin] = splitGlb(packed);
    int view = -1;  // the first compressed view
    for (int v = 0; v < int(document["bufferViews"].size()) && view < 0; ++v)
        if (document["bufferViews"][std::size_t(v)].contains("extensions"))
            view = v;
    QVERIFY(view >= 0);
    const auto changed = [&, document = document, bin = bin](const char* field, const nlohmann::json& value) {
        nlohmann::json d = document;
        d["bufferViews"][std::size_t(view)]["extensions"]["EXT_meshopt_compression"][field] = value;
        return joinGlb(d, bin);
    };
    const std::string named = "packed.glb: buffer view " + std::to_string(view);
    const std::size_t length = document["bufferViews"][std::size_t(view)]["extensions"]["EXT_meshopt_compression"]["byteLength"];
    std::string scrambled = bin;
    const std::size_t at = document["bufferViews"][std::size_t(view)]["extensions"]["EXT_meshopt_compression"]["byteOffset"];
    for (std::size_t i = 1; i < 64 && i < length; ++i)  // the header byte and the first block's control bytes
        scrambled[at + i] = char(0xFF);
    scrambled[at] = char(0x00);
    for (const auto& [input, problem] : std::vector<std::pair<std::string, std::string>>{
             {packed.substr(0, packed.size() / 2), "packed.glb is truncated"},
             {"not a glb at all", "packed.glb is not a GLB file"},
             {changed("byteLength", bin.size() * 2), named + " has compressed data outside the binary chunk"},
             {changed("count", 7), named + " has a byteStride and count that do not give its byteLength"},
             {changed("mode", "SPIRAL"), named + " has an unknown compression mode \"SPIRAL\""},
             {changed("buffer", 1), named + " takes its compressed data from a buffer other than"},
             {changed("mode", 5), "packed.glb: the glTF JSON is not laid out as glTF 2.0 says"},
             {changed("byteStride", "eight"), named + " has a byteStride and count that do not give its byteLength"},
             {joinGlb(document, scrambled), named + " does not decode"}}) {
        const Result<std::string> read = expandGlb(input, "packed.glb");
        QVERIFY2(!read, problem.c_str());
        QVERIFY2(read.message().rfind(problem, 0) == 0, read.message().c_str());
    }
    const auto again = compressGlb(packed, "packed.glb");
    QVERIFY(!again);
    QVERIFY2(again.message().find("already compressed") != std::string::npos, again.message().c_str());
}

void TestExports::compressedGlbStoresNormalsAsUnitVectors() {
    // A triangle whose normals are unit, zero and NaN (glTF asks for unit ones; a degenerate mesh can have
    // others): packed and expanded, the unit one within 1e-4 rad, the others +z, never a division's garbage.
    const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float normals[9] = {0.6f, 0.0f, 0.8f, 0, 0, 0, nan, 0, 0};
    const std::uint32_t indices[3] = {0, 1, 2};
    std::string bin(reinterpret_cast<const char*>(positions), 36);
    bin.append(reinterpret_cast<const char*>(normals), 36);
    bin.append(reinterpret_cast<const char*>(indices), 12);
    const nlohmann::json document = {
        {"asset", {{"version", "2.0"}}},
        {"buffers", {{{"byteLength", 84}}}},
        {"bufferViews", {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 36}, {"target", 34962}},
                         {{"buffer", 0}, {"byteOffset", 36}, {"byteLength", 36}, {"target", 34962}},
                         {{"buffer", 0}, {"byteOffset", 72}, {"byteLength", 12}, {"target", 34963}}}},
        {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"},
                        {"min", {0, 0, 0}}, {"max", {1, 1, 0}}},
                       {{"bufferView", 1}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"}},
                       {{"bufferView", 2}, {"componentType", 5125}, {"count", 3}, {"type", "SCALAR"}}}},
        {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}, {"indices", 2}}}}}}},
        {"nodes", {{{"mesh", 0}}}},
        {"scenes", {{{"nodes", {0}}}}}};
    const auto packed = compressGlb(joinGlb(document, bin), "triangle.glb");
    QVERIFY2(packed, packed.message().c_str());
    QCOMPARE(packed->octahedralNormals, 1);
    const auto expanded = expandGlb(packed->glb, "triangle.glb");
    QVERIFY2(expanded, expanded.message().c_str());
    const auto [out, outBin] = splitGlb(expanded.value());
    const nlohmann::json& accessor = out["accessors"][1];
    QCOMPARE(accessor["componentType"].get<int>(), 5126);
    const std::size_t offset = out["bufferViews"][accessor["bufferView"].get<std::size_t>()]["byteOffset"];
    float values[9];
    std::memcpy(values, outBin.data() + offset, 36);
    const Vec3f n[3] = {Vec3f(values[0], values[1], values[2]), Vec3f(values[3], values[4], values[5]),
                        Vec3f(values[6], values[7], values[8])};
    QVERIFY2(std::acos(std::min(1.0f, n[0].dot(Vec3f(0.6f, 0.0f, 0.8f)))) < 1e-4f, qPrintable(QString::number(double(n[0].z()))));
    for (int i = 1; i < 3; ++i)
        QVERIFY2((n[i] - Vec3f(0, 0, 1)).norm() < 1e-4f, qPrintable(QString("normal %1: %2 %3 %4").arg(i).arg(double(n[i].x())).arg(double(n[i].y())).arg(double(n[i].z()))));
}

void TestExports::gltfRefusesClipsTooLongToHold() {
    // glTF cannot stream: a clip of a million frames would need terabytes for one target per frame (the
    // weight table alone is frames²) and for the PCA's Gram matrix. Refused at begin(), before any frame
    // is simulated, with the way out; a short clip is accepted.
    QTemporaryDir dir;
    const fs::path path = fs::path(dir.path().toStdString()) / "long.glb";
    ClipExportOptions pca;
    pca.gltfMorphError = 0.005;
    for (const ClipExportOptions& options : {ClipExportOptions{}, pca}) {
        ClipSetup setup = smallSetup();
        setup.info.frameCount = 1000000;
        auto writer = findExportFormat("glb")->makeWriter(path, options);
        const Status s = writer->begin(path, setup);
        QVERIFY(!s.ok());
        QVERIFY2(QString::fromStdString(s.message()).contains("holds the whole clip in memory") &&
                     QString::fromStdString(s.message()).contains("vat or lattice"),
                 s.message().c_str());
        setup.info.frameCount = 100;
        QVERIFY(writer->begin(path, setup).ok());
        writer->abort();
    }
    QVERIFY(!fs::exists(path));
}

void TestExports::gltfWarnsAboutTargetCount() {
    QTemporaryDir dir;
    const fs::path path = fs::path(dir.path().toStdString()) / "long.glb";
    for (const std::size_t frames : {std::size_t(64), std::size_t(65)}) {
        ClipSetup setup = smallSetup();
        setup.info.frameCount = frames;
        auto writer = findExportFormat("glb")->makeWriter(path, {});
        QVERIFY(writer->begin(path, setup));
        FrameData frame;
        frame.normals = setup.restMesh.normals;
        std::vector<Vec3f> positions = setup.restMesh.positions;
        frame.positions = positions;
        for (std::size_t f = 0; f < frames; ++f) {
            positions[3].z() = 0.5f + 0.01f * float(f);
            QVERIFY(writer->writeFrame(frame));
        }
        const Status s = writer->finish();
        QVERIFY2(s, s.message().c_str());
        if (frames == 64) {
            QVERIFY(writer->warnings().empty());
        } else {
            QCOMPARE(writer->warnings().size(), std::size_t(1));
            const QString warning = QString::fromStdString(writer->warnings().front());
            QVERIFY2(warning.contains("65 morph targets") && warning.contains("at most 2 are active") &&
                         warning.contains("long.glb"),
                     qPrintable(warning));
        }
    }
}

void TestExports::vatRoundTrip_data() {
    QTest::addColumn<int>("maxWidth");
    QTest::addColumn<QString>("scene");  // empty: the angelfish swim
    QTest::newRow("one row per frame") << 8192 << "";
    QTest::newRow("wrapped rows") << 1000 << "";  // 3,656 vertices: 4 rows per frame, the last one partial
    QTest::newRow("the rigged guppy on its base animation") << 8192 << "guppy-rigged.softtouch";
}

void TestExports::vatRoundTrip() {
    QFETCH(int, maxWidth);
    QFETCH(QString, scene);
    const Scene source = scene.isEmpty() ? m_fish : loadScene(kSource / "presets/scenes" / scene.toStdString());
    QTemporaryDir dir;
    const fs::path base = fs::path(dir.path().toStdString()) / "swim";
    ClipExportOptions options;
    options.vatMaxWidth = maxWidth;
    const BakeResult baked = bakeTo(source, "vat", base, options);
    QCOMPARE(baked.files, exportFiles(*findExportFormat("vat"), base));
    for (const fs::path& file : baked.files)
        QVERIFY2(fs::is_regular_file(file), file.c_str());
    bakeTo(source, "pc2", base.parent_path() / "swim.pc2");
    bakeTo(source, "glb", base.parent_path() / "normals.glb");  // the bake's normals, as morph targets
    const tinygltf::Model morphs = loadGlb(base.parent_path() / "normals.glb");
    const tinygltf::Primitive& morphed = morphs.meshes.at(0).primitives.at(0);
    const std::vector<float> morphRestNormals = accessorFloats(morphs, morphed.attributes.at("NORMAL"));
    const Result<VertexCache> pc2 = readPc2(base.parent_path() / "swim.pc2");
    QVERIFY2(pc2, pc2.message().c_str());
    const VertexCache& reference = pc2.value();
    const std::size_t vertices = reference.info.pointCount;

    // Everything below comes from the exported files alone: sidecar, mesh, textures.
    const nlohmann::json sidecar = nlohmann::json::parse(readText(base.string() + ".vat.json"));
    QCOMPARE(sidecar.at("frameCount").get<int>(), kFrames);
    QCOMPARE(sidecar.at("fps").get<double>(), source.world.fps);
    QCOMPARE(sidecar.at("vertexCount").get<std::size_t>(), vertices);
    const auto width = sidecar.at("textureWidth").get<std::size_t>();
    const auto height = sidecar.at("textureHeight").get<std::size_t>();
    const auto rows = sidecar.at("rowsPerFrame").get<std::size_t>();
    QCOMPARE(width, std::min<std::size_t>(vertices, std::size_t(maxWidth)));
    QCOMPARE(rows, (vertices + width - 1) / width);
    QCOMPARE(height, rows * std::size_t(kFrames));
    const double rowStep = sidecar.at("frameRowStep").get<double>();

    const tinygltf::Model mesh = loadGlb(base.string() + ".vat-mesh.glb");
    const tinygltf::Primitive& primitive = mesh.meshes.at(0).primitives.at(0);
    const std::vector<float> rest = accessorFloats(mesh, primitive.attributes.at("POSITION"));
    const std::vector<float> index = accessorFloats(mesh, primitive.attributes.at("TEXCOORD_0"));
    const std::vector<float> lookup = accessorFloats(mesh, primitive.attributes.at("TEXCOORD_1"));
    QCOMPARE(rest.size(), 3 * vertices);

    auto decode = [&](const std::string& name) {
        Imf::RgbaInputFile file(name.c_str());
        const Imath::Box2i window = file.dataWindow();
        if (std::size_t(window.max.x - window.min.x + 1) != width || std::size_t(window.max.y - window.min.y + 1) != height)
            qFatal("%s has the wrong size", name.c_str());
        std::vector<Imf::Rgba> pixels(width * height);
        file.setFrameBuffer(pixels.data(), 1, width);
        file.readPixels(window.min.y, window.max.y);
        return pixels;
    };
    const std::vector<Imf::Rgba> offsets = decode(base.string() + ".vat-position.exr");
    const std::vector<Imf::Rgba> normals = decode(base.string() + ".vat-normal.exr");

    const Vec3f lo(sidecar["bounds"]["min"][0], sidecar["bounds"]["min"][1], sidecar["bounds"]["min"][2]);
    const Vec3f hi(sidecar["bounds"]["max"][0], sidecar["bounds"]["max"][1], sidecar["bounds"]["max"][2]);
    double worstExcess = -1.0;  // largest (error - tolerance); must stay <= 0
    double worstRelative = 0.0;
    const double diagonal = diagonalOf(reference);
    double worstNormal = 0.0;
    for (int f = 0; f < kFrames; ++f) {
        const std::vector<float> normalDeltas = accessorFloats(morphs, morphed.targets.at(std::size_t(f)).at("NORMAL"));
        for (std::size_t v = 0; v < vertices; ++v) {
            QCOMPARE(std::size_t(index[2 * v]), v);
            // What a VAT shader does: the lookup UV of frame 0 plus f rows of frames, texel centres.
            const double u = lookup[2 * v];
            const double vv = lookup[2 * v + 1] + f * rowStep;
            const auto x = std::size_t(std::floor(u * double(width)));
            const auto y = std::size_t(std::floor(vv * double(height)));
            QVERIFY(x < width && y < height);
            const Imf::Rgba& o = offsets[y * width + x];
            const Imf::Rgba& n = normals[y * width + x];
            const Vec3f offset(o.r, o.g, o.b);
            QVERIFY((offset.array() >= lo.array() - 1e-3f * std::abs(lo.maxCoeff()) - 1e-6f).all());
            QVERIFY((offset.array() <= hi.array() + 1e-3f * std::abs(hi.maxCoeff()) + 1e-6f).all());
            const Vec3f decoded = Vec3f(rest[3 * v], rest[3 * v + 1], rest[3 * v + 2]) + offset;
            const Vec3f& expected = reference.frames[std::size_t(f)][v];
            const Vec3f restPosition(rest[3 * v], rest[3 * v + 1], rest[3 * v + 2]);
            for (int c = 0; c < 3; ++c) {
                // Half keeps 11 significant bits of the offset: relative 2^-11, absolute 2^-25 for
                // subnormals; the float sum adds one rounding of the position.
                const double trueOffset = double(expected[c]) - double(restPosition[c]);
                const double tolerance = std::abs(trueOffset) * std::ldexp(1.0, -11) + std::ldexp(1.0, -25) +
                                         2.0 * std::numeric_limits<float>::epsilon() * std::abs(expected[c]);
                const double error = std::abs(double(decoded[c]) - double(expected[c]));
                worstExcess = std::max(worstExcess, error - tolerance);
                worstRelative = std::max(worstRelative, error / diagonal);
            }
            // Normals: the bake's (rest + morph delta) rounded to half, 2^-11 relative per component.
            for (int c = 0; c < 3; ++c) {
                const float bakedNormal = morphRestNormals[3 * v + std::size_t(c)] + normalDeltas[3 * v + std::size_t(c)];
                const float decodedNormal = c == 0 ? float(n.r) : c == 1 ? float(n.g) : float(n.b);
                const double error = std::abs(double(decodedNormal) - double(bakedNormal));
                worstNormal = std::max(worstNormal, error);
                QVERIFY2(error <= std::abs(bakedNormal) * std::ldexp(1.0, -11) + std::ldexp(1.0, -24),
                         qPrintable(QString("frame %1 vertex %2 normal %3: %4 vs %5").arg(f).arg(v).arg(c)
                                        .arg(decodedNormal).arg(bakedNormal)));
            }
        }
    }
    qInfo("VAT: worst position error %.3g of the diagonal; worst excess over half precision %.3g m; worst normal "
          "component error %.3g", worstRelative, worstExcess, worstNormal);
    QVERIFY(worstExcess <= 0.0);
    QVERIFY((hi - lo).maxCoeff() > 0.0f);  // the clip moves
}

void TestExports::latticeRoundTrip_data() {
    QTest::addColumn<QString>("scene");
    QTest::addColumn<QString>("lattice");
    QTest::newRow("angelfish, Bezier 4x4x4") << "angelfish-swim" << "";
    QTest::newRow("star, cubic B-spline 6x4x4") << "star-drag" << R"("lattice": {"kind": "bspline", "nodes": [6, 4, 4], "padding": 0.02})";
    QTest::newRow("star, Bezier 8x3x4 (degree 7)") << "star-drag" << R"("lattice": {"kind": "bezier", "nodes": [8, 3, 4], "padding": 0.02})";
    QTest::newRow("two objects: B-spline star + Bezier angelfish") << "two-objects" << "";
}

void TestExports::latticeRoundTrip() {
    QFETCH(QString, scene);
    QFETCH(QString, lattice);
    QTemporaryDir dir;
    const fs::path folder = dir.path().toStdString();
    fs::path project = kSource / "presets/scenes" / (scene.toStdString() + ".softtouch");
    if (scene == "two-objects") {
        project = folder / "scene.softtouch";
        writeTwoObjectProject(project);
    } else if (!lattice.isEmpty()) {  // the same scene on another lattice
        std::string text = readText(project);
        const auto begin = text.find("\"lattice\"");
        const auto end = text.find('}', begin);
        text.replace(begin, end + 1 - begin, lattice.toStdString());
        const auto mesh = text.find("../meshes/");
        text.replace(mesh, 3, (kSource / "presets").string() + "/");
        project = folder / "scene.softtouch";
        writeText(project, text);
    }
    const Scene source = loadScene(project);
    const fs::path base = folder / "clip";
    const BakeResult baked = bakeTo(source, "lattice", base);
    QCOMPARE(baked.files, exportFiles(*findExportFormat("lattice"), base));
    bakeTo(source, "pc2", folder / "clip.pc2");
    bakeTo(source, "glb", folder / "normals.glb");  // the bake's normals, as morph targets (a mesh per object)
    const tinygltf::Model morphs = loadGlb(folder / "normals.glb");
    QCOMPARE(morphs.meshes.size(), source.objects.size());
    const Result<VertexCache> pc2 = readPc2(folder / "clip.pc2");
    QVERIFY2(pc2, pc2.message().c_str());
    const VertexCache& reference = pc2.value();

    // From the exported files alone: the header and nodes of the .bin, the parameters of the GLB.
    const Result<LatticeCache> read = readLatticeCache(base.string() + ".lattice.bin");
    QVERIFY2(read, read.message().c_str());
    const LatticeCache& cache = read.value();
    QCOMPARE(int(cache.frameCount), kFrames);
    QCOMPARE(cache.fps, source.world.fps);
    QCOMPARE(cache.objects.size(), source.objects.size());
    const tinygltf::Model mesh = loadGlb(folder / cache.mesh);
    QCOMPARE(mesh.meshes.at(0).primitives.size(), cache.objects.size());

    const double diagonal = diagonalOf(reference);
    double worst = 0.0;
    double worstNormal = 0.0;
    for (std::size_t o = 0; o < cache.objects.size(); ++o) {
        const LatticeCacheObject& object = cache.objects[o];
        QCOMPARE(object.kind, source.objects[o].lattice.shape().kind);
        const std::vector<float> uvw = accessorFloats(mesh, mesh.meshes[0].primitives[o].attributes.at("_LATTICE_UVW"));
        const std::vector<float> restNormals = accessorFloats(mesh, mesh.meshes[0].primitives[o].attributes.at("NORMAL"));
        QCOMPARE(uvw.size(), 3 * std::size_t(object.vertexCount));
        std::size_t firstNode = 0;
        for (std::size_t before = 0; before < o; ++before)
            firstNode += std::size_t(cache.objects[before].nodeCount());
        const tinygltf::Primitive& morphed = morphs.meshes.at(o).primitives.at(0);
        const std::vector<float> morphRestNormals = accessorFloats(morphs, morphed.attributes.at("NORMAL"));
        std::vector<LatticeBasis> basis(object.vertexCount);
        for (std::size_t v = 0; v < object.vertexCount; ++v)
            basis[v] = latticeBasis(object, Vec3(uvw[3 * v], uvw[3 * v + 1], uvw[3 * v + 2]));
        for (std::size_t f = 0; f < cache.frameCount; ++f) {
            const std::vector<float> normalDeltas = accessorFloats(morphs, morphed.targets.at(f).at("NORMAL"));
            for (std::size_t v = 0; v < object.vertexCount; ++v) {
                const Vec3 n(restNormals[3 * v], restNormals[3 * v + 1], restNormals[3 * v + 2]);
                const auto [x, normal] = evaluateLattice(object, cache.frames[f].data() + firstNode, basis[v], n);
                const Vec3f& expected = reference.frames[f][object.firstVertex + v];
                worst = std::max(worst, (x - expected.cast<double>()).norm());
                const std::size_t g = 3 * v;  // in the object's own glTF mesh
                const Vec3 bakedNormal(morphRestNormals[g] + normalDeltas[g], morphRestNormals[g + 1] + normalDeltas[g + 1],
                                       morphRestNormals[g + 2] + normalDeltas[g + 2]);
                worstNormal = std::max(worstNormal, (normal - bakedNormal).norm());
            }
        }
    }
    const auto size = [](const fs::path& p) { return double(fs::file_size(p)); };
    qInfo("lattice cache: worst error %.3g of the diagonal, normals %.3g; %.0f + %.0f bytes vs PC2 %.0f bytes",
          worst / diagonal, worstNormal,
          size(base.string() + ".lattice.bin"), size(base.string() + ".lattice.glb"), size(folder / "clip.pc2"));
    QVERIFY2(worst <= 1e-6 * diagonal, qPrintable(QString("error %1 of the diagonal").arg(worst / diagonal)));
    // Normals: the bake's are float32 (basis values too); the shaders' formula must agree with them.
    QVERIFY2(worstNormal <= 1e-5, qPrintable(QString("normal error %1").arg(worstNormal)));
    // The clip moves, so the comparison is not between rest poses.
    double motion = 0.0;
    for (std::size_t v = 0; v < reference.info.pointCount; ++v)
        motion = std::max(motion, double((reference.frames.back()[v] - reference.frames.front()[v]).norm()));
    QVERIFY(motion > 1e-3 * diagonal);
}

void TestExports::latticeCacheRejectsBadFiles() {
    QTemporaryDir dir;
    const fs::path base = fs::path(dir.path().toStdString()) / "clip";
    bakeTo(m_fish, "lattice", base);
    const fs::path bin = base.string() + ".lattice.bin";
    const std::string good = readText(bin);
    struct Case {
        std::string bytes;
        const char* expected;
    };
    std::string wrongKind = good;
    wrongKind.replace(wrongKind.find("\"bezier\""), 8, "\"bezjer\"");
    std::string wrongNodes = good;
    wrongNodes.replace(wrongNodes.find("\"nodes\":[4,4,4]"), 15, "\"nodes\":[4,4,1]");
    const Case cases[] = {
        {"POINTCACHE2", "is not a lattice cache"},
        {good.substr(0, good.size() - 5), "is truncated"},
        {good + "xyz", "extra bytes"},
        {wrongKind, "/objects/0/kind"},
        {wrongNodes, "/objects/0/nodes"},
    };
    for (const Case& c : cases) {
        writeText(bin, c.bytes);
        const Result<LatticeCache> read = readLatticeCache(bin);
        QVERIFY(!read);
        QVERIFY2(QString::fromStdString(read.message()).contains(c.expected), read.message().c_str());
        QVERIFY2(QString::fromStdString(read.message()).contains("clip.lattice.bin"), read.message().c_str());
    }
}

void TestExports::latticeShadersCompile_data() {
    QTest::addColumn<QString>("file");
    QTest::addColumn<QStringList>("arguments");
    QTest::newRow("GLSL 4.30 vertex") << "lattice_deform.glsl" << QStringList{"-S", "vert"};
    QTest::newRow("HLSL vertex to SPIR-V") << "lattice_deform.hlsl" << QStringList{"-D", "-S", "vert", "-e", "main", "-V"};
    QTest::newRow("VAT GLSL 4.30 vertex") << "vat_deform.glsl" << QStringList{"-S", "vert"};
    QTest::newRow("VAT HLSL vertex to SPIR-V") << "vat_deform.hlsl" << QStringList{"-D", "-S", "vert", "-e", "main", "-V"};
}

void TestExports::latticeShadersCompile() {
    // The shaders mirror evaluateLattice() above; this proves they build (glslang-tools, installed by
    // scripts/install-deps.sh, compiles both the GLSL and the HLSL).
    QFETCH(QString, file);
    QFETCH(QStringList, arguments);
    const QString validator = QStandardPaths::findExecutable("glslangValidator");
    QVERIFY2(!validator.isEmpty(), "glslangValidator not found: run scripts/install-deps.sh (glslang-tools)");
    QTemporaryDir dir;
    QProcess process;
    if (arguments.contains("-V"))  // SPIR-V output for the HLSL; the GLSL is checked as OpenGL GLSL
        arguments << "-o" << dir.filePath("out.spv");
    arguments << QString::fromStdString((kSource / "io/shaders").string()) + "/" + file;
    process.start(validator, arguments);
    QVERIFY(process.waitForFinished(60000));
    const QByteArray output = process.readAllStandardOutput() + process.readAllStandardError();
    QVERIFY2(process.exitStatus() == QProcess::NormalExit && process.exitCode() == 0, output.constData());
}

void TestExports::hlslShadersShareTheGlslInterface_data() {
    QTest::addColumn<QString>("shader");
    QTest::newRow("lattice") << "lattice_deform";
    QTest::newRow("vat") << "vat_deform";
}

void TestExports::hlslShadersShareTheGlslInterface() {
    // The HLSL versions run nowhere here (no D3D or Vulkan), so their interface is checked against the GLSL
    // ones, which do run: glslang's reflection of both lists the same parameters (names starting with u),
    // each of the same type (an engine sets them from the same files).
    QFETCH(QString, shader);
    const QString validator = QStandardPaths::findExecutable("glslangValidator");
    QVERIFY2(!validator.isEmpty(), "glslangValidator not found: run scripts/install-deps.sh (glslang-tools)");
    QTemporaryDir dir;
    const QString folder = QString::fromStdString((kSource / "io/shaders").string()) + "/";
    auto reflect = [&](const QStringList& arguments) {
        QProcess process;
        process.start(validator, arguments);
        process.waitForFinished(60000);
        std::map<std::string, std::string> parameters;  // name -> GL type code
        bool inUniforms = false;
        for (const QByteArray& line : process.readAllStandardOutput().split('\n')) {
            if (line.endsWith("reflection:")) {  // a section header: only "Uniform reflection:" is read
                inUniforms = line.startsWith("Uniform reflection:");
                continue;
            }
            if (!inUniforms || line.trimmed().isEmpty())
                continue;
            const QList<QByteArray> parts = line.split(':');
            const QByteArray name = parts.value(0).trimmed();
            const int at = line.indexOf("type ");
            const QByteArray type = at < 0 ? QByteArray() : line.mid(at + 5, line.indexOf(',', at) - at - 5);
            if (name.startsWith('u') && type != "0")  // HLSL's separate sampler state has no GLSL twin
                parameters[name.toStdString()] = type.toStdString();
        }
        return parameters;
    };
    const auto glsl = reflect({"-S", "vert", "-l", "-q", folder + shader + ".glsl"});
    const auto hlsl = reflect({"-D", "-S", "vert", "-e", "main", "-V", "-q", "-o", dir.filePath("out.spv"), folder + shader + ".hlsl"});
    QVERIFY(glsl.size() >= 8);
    QString differences;
    for (const auto& [name, type] : glsl)
        if (!hlsl.count(name) || hlsl.at(name) != type)
            differences += QString(" %1 (GLSL type %2, HLSL %3)").arg(QString::fromStdString(name), QString::fromStdString(type),
                                                                       hlsl.count(name) ? QString::fromStdString(hlsl.at(name)) : "missing");
    for (const auto& [name, type] : hlsl)
        if (!glsl.count(name))
            differences += QString(" %1 (only in HLSL)").arg(QString::fromStdString(name));
    QVERIFY2(differences.isEmpty(), qPrintable(shader + ":" + differences));
}

void TestExports::cancelledBakeLeavesOldFiles_data() {
    exportRows();
}

void TestExports::cancelledBakeLeavesOldFiles() {
    QFETCH(QString, format);
    const ExportFormat& registered = *findExportFormat(format.toStdString());
    QTemporaryDir dir;
    const fs::path base = fs::path(dir.path().toStdString()) / ("clip." + format.toStdString());
    std::vector<fs::path> outputs = exportFiles(registered, base, kFrames);  // an OBJ sequence: every frame's
    outputs.push_back(restMeshPath(base, registered));
    for (const fs::path& path : outputs)
        writeText(path, "previous " + path.filename().string());
    const QStringList before = folderEntries(base.parent_path());
    BakeOptions options;
    options.output = base;
    options.format = &registered;
    options.exportOptions = exportOptions(registered).value();
    options.frames = kFrames;
    options.threads = 1;
    options.progress = [](int done, int) { return done < 3; };
    const Result<BakeResult> result = bake(m_fish, options);
    QVERIFY(!result);
    QVERIFY2(QString::fromStdString(result.message()).contains("cancelled"), result.message().c_str());
    // Callers tell a cancel from a failure by its kind, not its words (the editor's check of the words
    // never matched, so a cancelled export showed "Export failed").
    QVERIFY(result.wasCancelled() && result.status().wasCancelled());
    QVERIFY(!Result<BakeResult>(Status::error("disk full")).wasCancelled());
    for (const fs::path& path : outputs)
        QCOMPARE(readText(path), "previous " + path.filename().string());
    QCOMPARE(folderEntries(base.parent_path()), before);
}

void TestExports::nonFiniteFrameLeavesOldFiles_data() {
    exportRows();
}

void TestExports::nonFiniteFrameLeavesOldFiles() {
    QFETCH(QString, format);
    const ExportFormat& registered = *findExportFormat(format.toStdString());
    QTemporaryDir dir;
    const fs::path base = fs::path(dir.path().toStdString()) / ("clip." + format.toStdString());
    const std::vector<fs::path> outputs = exportFiles(registered, base);
    for (const fs::path& path : outputs)
        writeText(path, "previous " + path.filename().string());
    const QStringList before = folderEntries(base.parent_path());

    const ClipSetup setup = smallSetup();
    auto writer = registered.makeWriter(base, exportOptions(registered).value());
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
    if (registered.needs == ExportNeeds::LatticeNodes) {  // the lattice cache stores nodes: poison those
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
    exportRows();
}

void TestExports::unwritablePathFailsEarly() {
    QFETCH(QString, format);
    const ExportFormat& registered = *findExportFormat(format.toStdString());
    QTemporaryDir dir;
    const fs::path missing = fs::path(dir.path().toStdString()) / "no-such-folder" / "clip";
    auto writer = registered.makeWriter(missing, exportOptions(registered).value());
    const Status s = writer->begin(missing, smallSetup());
    QVERIFY(!s);
    QVERIFY2(QString::fromStdString(s.message()).contains("no-such-folder"), s.message().c_str());
    QVERIFY(!fs::exists(missing.parent_path()));
}

QTEST_GUILESS_MAIN(TestExports)
#include "test_exports.moc"

void TestExports::unchangedFramesAreNotDeformedAgain() {
    QTemporaryDir dir;
    const fs::path root(dir.path().toStdString());
    // The swimming fish moves every frame: every frame is deformed.
    const BakeResult swimming = bakeTo(m_fish, "pc2", root / "swim.pc2");
    QCOMPARE(swimming.objects, 1);
    QCOMPARE(swimming.meshEvaluations, kFrames);

    // Without its drivers (and no gravity) nothing acts on it: its nodes never move, so only the
    // first frame is deformed, and every frame of the cache is still written and still the rest mesh.
    Scene still = m_fish;
    for (SceneObject& object : still.objects)
        object.drivers.clear();
    still.world.gravity = Vec3::Zero();
    const BakeResult resting = bakeTo(still, "pc2", root / "still.pc2");
    QCOMPARE(resting.meshEvaluations, 1);
    const Result<VertexCache> cache = readPc2(root / "still.pc2");
    QVERIFY2(cache.ok(), cache.message().c_str());
    QCOMPARE(int(cache.value().frames.size()), kFrames);
    const Mesh& rest = still.objects[0].mesh;
    for (const auto& frame : cache.value().frames) {
        QCOMPARE(frame.size(), rest.positions.size());
        for (std::size_t v = 0; v < frame.size(); ++v)
            QVERIFY((frame[v] - rest.positions[v]).norm() <= 1e-5f);
    }
}

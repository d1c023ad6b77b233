// Vertex-cache exporters: the exact bytes of each format, bit-exact round trips, and failures that
// report the file and the frame and never damage what was there before.
#include "io/export/vertex_cache.h"
#include "io/files/atomic_file.h"

#include <QTemporaryDir>
#include <QtTest>

#include <bit>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>

#include <sys/stat.h>

using namespace softtouch;
using namespace softtouch::io;
namespace fs = std::filesystem;

namespace {

using Bytes = std::vector<std::uint8_t>;

Bytes readBytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return Bytes(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void writeBytes(const fs::path& path, const Bytes& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// Byte order decoded by hand, independently of the implementation's helpers.
std::uint32_t le32(const Bytes& b, std::size_t at) {
    return std::uint32_t(b[at]) | std::uint32_t(b[at + 1]) << 8 | std::uint32_t(b[at + 2]) << 16 |
           std::uint32_t(b[at + 3]) << 24;
}
std::uint32_t be32(const Bytes& b, std::size_t at) {
    return std::uint32_t(b[at]) << 24 | std::uint32_t(b[at + 1]) << 16 | std::uint32_t(b[at + 2]) << 8 |
           std::uint32_t(b[at + 3]);
}
std::uint32_t bits(float f) { return std::bit_cast<std::uint32_t>(f); }

/// Deterministic positions that catch rounding and byte-order mistakes: fractions that are not
/// exact in binary, negatives, large and tiny magnitudes, a denormal, FLT_MAX and -0.
Vec3f samplePosition(std::size_t frame, std::size_t vertex) {
    const double f = double(frame);
    const double v = double(vertex);
    if (vertex == 0)
        return {0.1f + float(frame), std::numeric_limits<float>::denorm_min(), -0.0f};
    if (vertex == 1)
        return {std::numeric_limits<float>::max(), std::numeric_limits<float>::min(),
                -1e-30f * float(frame + 1)};
    return {float(std::sin(0.37 * v + 0.11 * f) * 3.7 + 0.1), float(-1234.5678 + v * 0.001 - f / 7.0),
            float(1.0 / (v + f + 3.0))};
}

std::vector<Vec3f> sampleFrame(std::size_t frame, std::size_t points) {
    std::vector<Vec3f> out(points);
    for (std::size_t v = 0; v < points; ++v)
        out[v] = samplePosition(frame, v);
    return out;
}

/// Empty when equal bit for bit, else where they first differ.
QString firstDifference(const std::vector<Vec3f>& actual, const std::vector<Vec3f>& expected) {
    if (actual.size() != expected.size())
        return QString("%1 vertices, expected %2").arg(actual.size()).arg(expected.size());
    for (std::size_t v = 0; v < actual.size(); ++v)
        for (int a = 0; a < 3; ++a)
            if (bits(actual[v][a]) != bits(expected[v][a]))
                return QString("vertex %1 axis %2: %3, expected %4")
                    .arg(v)
                    .arg(a)
                    .arg(double(actual[v][a]), 0, 'g', 9)
                    .arg(double(expected[v][a]), 0, 'g', 9);
    return {};
}

/// A grid of (columns x rows) vertices in the z = 0 plane, two triangles per cell.
Mesh gridMesh(std::uint32_t columns, std::uint32_t rows) {
    Mesh mesh;
    for (std::uint32_t r = 0; r < rows; ++r)
        for (std::uint32_t c = 0; c < columns; ++c)
            mesh.positions.push_back(Vec3f(0.1f * float(c), 0.3f * float(r), 0.0f));
    for (std::uint32_t r = 0; r + 1 < rows; ++r)
        for (std::uint32_t c = 0; c + 1 < columns; ++c) {
            const std::uint32_t i = r * columns + c;
            mesh.triangles.push_back({i, i + 1, i + columns});
            mesh.triangles.push_back({i + 1, i + columns + 1, i + columns});
        }
    return mesh;
}

CacheFormat formatNamed(const QString& name) {
    const auto format = parseCacheFormat(name.toStdString());
    if (!format)
        qFatal("unknown format %s", qPrintable(name));
    return *format;
}

fs::path cachePath(const fs::path& dir, CacheFormat format, const std::string& base = "cache") {
    switch (format) {
    case CacheFormat::Pc2:
        return dir / (base + ".pc2");
    case CacheFormat::Mdd:
        return dir / (base + ".mdd");
    case CacheFormat::ObjSequence:
        return dir / (base + ".obj");
    }
    return {};
}

/// The file a finished cache's first frame lands in.
fs::path firstOutputFile(const fs::path& path, CacheFormat format) {
    return format == CacheFormat::ObjSequence ? objSequenceFramePath(path, 0) : path;
}

/// Names of the entries of a directory, sorted.
QStringList entries(const fs::path& dir) {
    QStringList names;
    for (const auto& entry : fs::directory_iterator(dir))
        names << QString::fromStdString(entry.path().filename().string());
    names.sort();
    return names;
}

/// Writes `frames` sample frames (announcing info.frameCount), stopping at the first error.
Status writeSampleFrames(VertexCacheWriter& writer, std::size_t frames, const CacheInfo& info) {
    for (std::size_t f = 0; f < frames; ++f) {
        if (Status s = writer.writeFrame(sampleFrame(f, info.pointCount)); !s)
            return s;
    }
    return Status::success();
}

/// A path the way io/ messages name it.
QString quoted(const fs::path& path) { return QString("'%1'").arg(QString::fromStdString(path.string())); }

fs::path toPath(const QTemporaryDir& dir) { return fs::path(dir.path().toStdString()); }

/// An OBJ file as a test reads it back: a parser independent of the writer.
struct ObjData {
    std::string firstLine;
    std::vector<Vec3f> positions;
    std::vector<Vec3f> normals;
    std::vector<std::array<std::uint32_t, 3>> faces;  ///< 0-based vertex indices.
    int facesWithNormals = 0;                         ///< Faces written "a//a b//b c//c" with n == v.
    QStringList otherLines;                           ///< Anything but comments, v, vn, f.
    QString error;                                    ///< First parse error, empty when none.
};

bool parseFloat(const std::string& token, float& value) {
    const auto result = std::from_chars(token.data(), token.data() + token.size(), value);
    return result.ec == std::errc() && result.ptr == token.data() + token.size();
}

bool parseIndex(std::string_view token, std::uint32_t& value) {
    const auto result = std::from_chars(token.data(), token.data() + token.size(), value);
    return result.ec == std::errc() && result.ptr == token.data() + token.size() && value >= 1;
}

ObjData parseObj(const fs::path& path) {
    ObjData obj;
    std::ifstream in(path);
    if (!in) {
        obj.error = "cannot open";
        return obj;
    }
    std::string line;
    int lineNumber = 0;
    while (std::getline(in, line)) {
        ++lineNumber;
        if (lineNumber == 1)
            obj.firstLine = line;
        std::istringstream words(line);
        std::string kind;
        words >> kind;
        std::vector<std::string> tokens;
        for (std::string t; words >> t;)
            tokens.push_back(t);
        const QString where = QString("line %1: ").arg(lineNumber);
        if (kind.empty() || kind[0] == '#')
            continue;
        if (kind == "v" || kind == "vn") {
            Vec3f p;
            if (tokens.size() != 3 || !parseFloat(tokens[0], p.x()) || !parseFloat(tokens[1], p.y()) ||
                !parseFloat(tokens[2], p.z())) {
                obj.error = where + QString::fromStdString(line);
                return obj;
            }
            (kind == "v" ? obj.positions : obj.normals).push_back(p);
        } else if (kind == "f") {
            std::array<std::uint32_t, 3> face{};
            bool withNormals = true;
            bool good = tokens.size() == 3;
            for (std::size_t i = 0; good && i < 3; ++i) {
                const std::string_view token = tokens[i];
                const std::size_t slash = token.find("//");
                std::uint32_t v = 0;
                std::uint32_t n = 0;
                if (slash == std::string_view::npos) {
                    withNormals = false;
                    good = parseIndex(token, v);
                } else {
                    good = parseIndex(token.substr(0, slash), v) && parseIndex(token.substr(slash + 2), n) &&
                           n == v;
                }
                face[i] = v - 1;
            }
            if (!good) {
                obj.error = where + QString::fromStdString(line);
                return obj;
            }
            obj.faces.push_back(face);
            obj.facesWithNormals += withNormals ? 1 : 0;
        } else {
            obj.otherLines << QString::fromStdString(line);
        }
    }
    return obj;
}

}  // namespace

class TestCaches : public QObject {
    Q_OBJECT
private slots:
    void formatNames();
    void objSequenceFramePaths_data();
    void objSequenceFramePaths();
    void pc2HeaderBytes();
    void mddBigEndianBytesAndTimes();
    void roundTrip_data();
    void roundTrip();
    void objSequenceFilesParseBack();
    void writeObjRoundTrip_data();
    void writeObjRoundTrip();
    void writeObjRefusesBadMeshes_data();
    void writeObjRefusesBadMeshes();
    void nonFiniteFrameIsRefused_data();
    void nonFiniteFrameIsRefused();
    void failedWriteKeepsExistingFile_data();
    void failedWriteKeepsExistingFile();
    void wrongFrameCountIsRefused_data();
    void wrongFrameCountIsRefused();
    void invalidInfoIsRefused_data();
    void invalidInfoIsRefused();
    void badCacheFilesAreRejected_data();
    void badCacheFilesAreRejected();
    void unwritableTargetIsReported_data();
    void unwritableTargetIsReported();
    void atomicFileReplacesOnlyOnCommit();
};

void TestCaches::formatNames() {
    for (CacheFormat format : {CacheFormat::Pc2, CacheFormat::Mdd, CacheFormat::ObjSequence})
        QCOMPARE(parseCacheFormat(cacheFormatName(format)), std::optional(format));
    QCOMPARE(cacheFormatName(CacheFormat::Pc2), std::string_view("pc2"));
    QCOMPARE(cacheFormatName(CacheFormat::Mdd), std::string_view("mdd"));
    QCOMPARE(cacheFormatName(CacheFormat::ObjSequence), std::string_view("objseq"));
    QCOMPARE(parseCacheFormat("PC2"), std::optional(CacheFormat::Pc2));
    QVERIFY(!parseCacheFormat("abc"));
    QVERIFY(!parseCacheFormat(""));

    QCOMPARE(cacheFormatFromPath("/a/b.pc2"), std::optional(CacheFormat::Pc2));
    QCOMPARE(cacheFormatFromPath("/a/b.PC2"), std::optional(CacheFormat::Pc2));
    QCOMPARE(cacheFormatFromPath("b.Mdd"), std::optional(CacheFormat::Mdd));
    QCOMPARE(cacheFormatFromPath("dir.pc2/b.OBJ"), std::optional(CacheFormat::ObjSequence));
    QVERIFY(!cacheFormatFromPath("/a/b.abc"));
    QVERIFY(!cacheFormatFromPath("/a/pc2"));
}

void TestCaches::objSequenceFramePaths_data() {
    QTest::addColumn<QString>("path");
    QTest::addColumn<qulonglong>("frame");
    QTest::addColumn<QString>("expected");
    QTest::newRow("first") << "/out/body.obj" << 0ull << "/out/body_0000.obj";
    QTest::newRow("two digits") << "/out/body.obj" << 12ull << "/out/body_0012.obj";
    QTest::newRow("last of four") << "/out/body.obj" << 9999ull << "/out/body_9999.obj";
    QTest::newRow("five digits") << "/out/body.obj" << 10000ull << "/out/body_10000.obj";
    QTest::newRow("six digits") << "/out/body.obj" << 123456ull << "/out/body_123456.obj";
    QTest::newRow("relative") << "body.obj" << 7ull << "body_0007.obj";
    QTest::newRow("dots in name") << "/out/v1.2/body.final.obj" << 3ull << "/out/v1.2/body.final_0003.obj";
}

void TestCaches::objSequenceFramePaths() {
    QFETCH(QString, path);
    QFETCH(qulonglong, frame);
    QFETCH(QString, expected);
    QCOMPARE(QString::fromStdString(objSequenceFramePath(path.toStdString(), frame).string()), expected);
}

void TestCaches::pc2HeaderBytes() {
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const fs::path path = toPath(dir) / "body.pc2";
    const CacheInfo info{5, 3, 30.0, 7.0};
    auto writer = makeCacheWriter(CacheFormat::Pc2, Mesh{});
    QVERIFY(writer->begin(path, info).ok());
    QVERIFY(writeSampleFrames(*writer, 3, info).ok());
    QVERIFY2(!fs::exists(path), "nothing may be visible at the target before finish()");
    const Status finished = writer->finish();
    QVERIFY2(finished.ok(), finished.message().c_str());

    const Bytes b = readBytes(path);
    QCOMPARE(b.size(), std::size_t(32 + 3 * 5 * 12));
    const char signature[12] = {'P', 'O', 'I', 'N', 'T', 'C', 'A', 'C', 'H', 'E', '2', '\0'};
    QVERIFY(std::equal(signature, signature + 12, b.begin()));
    QCOMPARE(le32(b, 12), 1u);                     // version
    QCOMPARE(le32(b, 16), 5u);                     // numPoints
    QCOMPARE(le32(b, 20), bits(7.0f));             // startFrame
    QCOMPARE(le32(b, 24), bits(1.0f));             // sampleRate: a frame step, one sample per frame
    QCOMPARE(le32(b, 28), 3u);                     // numSamples
    // Samples follow the header, frame-major, x y z per point, little-endian.
    for (std::size_t f = 0; f < 3; ++f)
        for (std::size_t v = 0; v < 5; ++v)
            for (int a = 0; a < 3; ++a)
                QCOMPARE(le32(b, 32 + (f * 5 + v) * 12 + std::size_t(a) * 4), bits(samplePosition(f, v)[a]));
    QCOMPARE(entries(toPath(dir)), QStringList{"body.pc2"});
}

void TestCaches::mddBigEndianBytesAndTimes() {
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const fs::path path = toPath(dir) / "body.mdd";
    const CacheInfo info{6, 4, 25.0, 10.0};
    auto writer = makeCacheWriter(CacheFormat::Mdd, Mesh{});
    QVERIFY(writer->begin(path, info).ok());
    QVERIFY(writeSampleFrames(*writer, 4, info).ok());
    QVERIFY2(!fs::exists(path), "nothing may be visible at the target before finish()");
    QVERIFY(writer->finish().ok());

    const Bytes b = readBytes(path);
    QCOMPARE(b.size(), std::size_t(8 + 4 * 4 + 4 * 6 * 12));
    // Big-endian: the most significant byte comes first.
    QCOMPARE(b[0], std::uint8_t(0));
    QCOMPARE(b[3], std::uint8_t(4));
    QCOMPARE(be32(b, 0), 4u);  // numFrames
    QCOMPARE(be32(b, 4), 6u);  // numPoints
    // Times in seconds from the start frame: (10 + i) / 25.
    for (std::size_t i = 0; i < 4; ++i)
        QCOMPARE(be32(b, 8 + 4 * i), bits(float((10.0 + double(i)) / 25.0)));
    for (std::size_t f = 0; f < 4; ++f)
        for (std::size_t v = 0; v < 6; ++v)
            for (int a = 0; a < 3; ++a)
                QCOMPARE(be32(b, 24 + (f * 6 + v) * 12 + std::size_t(a) * 4), bits(samplePosition(f, v)[a]));
}

void TestCaches::roundTrip_data() {
    QTest::addColumn<QString>("format");
    QTest::addColumn<int>("points");
    QTest::addColumn<int>("frames");
    QTest::addColumn<double>("fps");
    QTest::addColumn<double>("startFrame");
    QTest::newRow("pc2 one point one frame") << "pc2" << 1 << 1 << 24.0 << 0.0;
    QTest::newRow("pc2 many") << "pc2" << 257 << 9 << 24.0 << 1001.0;
    QTest::newRow("pc2 negative fractional start") << "pc2" << 10 << 3 << 30.0 << -12.5;
    QTest::newRow("mdd one point one frame") << "mdd" << 1 << 1 << 24.0 << 0.0;
    QTest::newRow("mdd many") << "mdd" << 257 << 9 << 24.0 << 1001.0;
    QTest::newRow("mdd ntsc") << "mdd" << 10 << 48 << 24000.0 / 1001.0 << 1.0;
    QTest::newRow("mdd negative start") << "mdd" << 10 << 3 << 60.0 << -20.0;
    QTest::newRow("mdd fractional fps and start") << "mdd" << 3 << 100 << 12.5 << 3.25;
}

void TestCaches::roundTrip() {
    QFETCH(QString, format);
    QFETCH(int, points);
    QFETCH(int, frames);
    QFETCH(double, fps);
    QFETCH(double, startFrame);
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const CacheFormat kind = formatNamed(format);
    const fs::path path = cachePath(toPath(dir), kind);
    const CacheInfo info{std::size_t(points), std::size_t(frames), fps, startFrame};
    auto writer = makeCacheWriter(kind, Mesh{});
    QVERIFY(writer->begin(path, info).ok());
    QVERIFY(writeSampleFrames(*writer, info.frameCount, info).ok());
    QVERIFY(writer->finish().ok());

    const Result<VertexCache> cache = kind == CacheFormat::Pc2 ? readPc2(path) : readMdd(path);
    QVERIFY2(cache.ok(), cache.message().c_str());
    QCOMPARE(cache->info.pointCount, info.pointCount);
    QCOMPARE(cache->info.frameCount, info.frameCount);
    QCOMPARE(cache->frames.size(), info.frameCount);
    for (std::size_t f = 0; f < info.frameCount; ++f) {
        const QString difference = firstDifference(cache->frames[f], sampleFrame(f, info.pointCount));
        QVERIFY2(difference.isEmpty(), qPrintable(QString("frame %1: %2").arg(f).arg(difference)));
    }
    if (kind == CacheFormat::Pc2) {
        QVERIFY(cache->info.fps == 0.0);  // PC2 stores a frame step, not a frame rate: unknown
        QVERIFY(cache->info.startFrame == double(float(startFrame)));
    } else if (frames >= 2) {
        // Round rates and start frames come back exactly from the float32 times.
        QVERIFY2(cache->info.fps == fps, qPrintable(QString::number(cache->info.fps, 'g', 17)));
        QVERIFY2(cache->info.startFrame == startFrame,
                 qPrintable(QString::number(cache->info.startFrame, 'g', 17)));
    } else {
        QVERIFY(cache->info.fps == 0.0);  // one time says nothing about the rate: unknown
    }
}

void TestCaches::objSequenceFilesParseBack() {
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const Mesh rest = gridMesh(4, 3);  // 12 vertices, 12 triangles
    const fs::path path = toPath(dir) / "body.obj";
    const CacheInfo info{rest.positions.size(), 3, 24.0, 1.0};
    auto writer = makeCacheWriter(CacheFormat::ObjSequence, rest);
    QVERIFY(writer->begin(path, info).ok());
    QVERIFY(writeSampleFrames(*writer, 3, info).ok());
    for (std::size_t f = 0; f < 3; ++f)
        QVERIFY2(!fs::exists(objSequenceFramePath(path, f)), "no frame may be visible before finish()");
    const Status finished = writer->finish();
    QVERIFY2(finished.ok(), finished.message().c_str());

    QCOMPARE(entries(toPath(dir)), (QStringList{"body_0000.obj", "body_0001.obj", "body_0002.obj"}));
    for (std::size_t f = 0; f < 3; ++f) {
        const ObjData obj = parseObj(objSequenceFramePath(path, f));
        QVERIFY2(obj.error.isEmpty(), qPrintable(obj.error));
        const QString difference = firstDifference(obj.positions, sampleFrame(f, info.pointCount));
        QVERIFY2(difference.isEmpty(), qPrintable(QString("frame %1: %2").arg(f).arg(difference)));
        QVERIFY(obj.faces == rest.triangles);
        QCOMPARE(obj.facesWithNormals, 0);
        QVERIFY(obj.normals.empty());
        QVERIFY2(obj.otherLines.isEmpty(), qPrintable(obj.otherLines.join('\n')));
    }
}

void TestCaches::writeObjRoundTrip_data() {
    QTest::addColumn<bool>("withNormals");
    QTest::addColumn<bool>("overridePositions");
    QTest::newRow("rest positions with normals") << true << false;
    QTest::newRow("rest positions without normals") << false << false;
    QTest::newRow("given positions with normals") << true << true;
}

void TestCaches::writeObjRoundTrip() {
    QFETCH(bool, withNormals);
    QFETCH(bool, overridePositions);
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    Mesh mesh = gridMesh(5, 4);
    mesh.positions = sampleFrame(0, mesh.positions.size());  // awkward floats, same topology
    if (withNormals)
        mesh.computeNormals();
    const std::vector<Vec3f> given = sampleFrame(7, mesh.positions.size());
    const fs::path path = toPath(dir) / "rest.obj";
    const Status written =
        writeObj(path, mesh, overridePositions ? std::span<const Vec3f>(given) : std::span<const Vec3f>());
    QVERIFY2(written.ok(), written.message().c_str());

    const ObjData obj = parseObj(path);
    QVERIFY2(obj.error.isEmpty(), qPrintable(obj.error));
    QCOMPARE(obj.firstLine,
             std::string("# SoftTouch rest mesh: vertex order matches the vertex caches written beside it"));
    const QString difference = firstDifference(obj.positions, overridePositions ? given : mesh.positions);
    QVERIFY2(difference.isEmpty(), qPrintable(difference));
    if (withNormals) {
        const QString normalDifference = firstDifference(obj.normals, mesh.normals);
        QVERIFY2(normalDifference.isEmpty(), qPrintable(normalDifference));
    } else {
        QVERIFY(obj.normals.empty());
    }
    QVERIFY(obj.faces == mesh.triangles);
    QCOMPARE(obj.facesWithNormals, withNormals ? int(mesh.triangles.size()) : 0);
    // No o/g/s/usemtl lines: one object, in file order.
    QVERIFY2(obj.otherLines.isEmpty(), qPrintable(obj.otherLines.join('\n')));
    QCOMPARE(entries(toPath(dir)), QStringList{"rest.obj"});
}

void TestCaches::writeObjRefusesBadMeshes_data() {
    QTest::addColumn<QString>("defect");
    QTest::addColumn<QString>("message");
    QTest::newRow("non-finite vertex") << "nan vertex" << "vertex 4 is not finite";
    QTest::newRow("normal count") << "normals" << "5 normals for 12 vertices";
    QTest::newRow("index out of range") << "index" << "triangle 1 uses vertex 12 of 12";
    QTest::newRow("no vertices") << "empty" << "the mesh has no vertices";
}

void TestCaches::writeObjRefusesBadMeshes() {
    QFETCH(QString, defect);
    QFETCH(QString, message);
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    Mesh mesh = gridMesh(4, 3);
    if (defect == "nan vertex")
        mesh.positions[4].y() = std::numeric_limits<float>::quiet_NaN();
    else if (defect == "normals")
        mesh.normals.assign(5, Vec3f::UnitZ());
    else if (defect == "index")
        mesh.triangles[1][2] = 12;
    else if (defect == "empty")
        mesh = Mesh{};
    const fs::path path = toPath(dir) / "rest.obj";
    const Status written = writeObj(path, mesh);
    QVERIFY(!written.ok());
    QVERIFY2(QString::fromStdString(written.message()).contains(message), written.message().c_str());
    QVERIFY2(QString::fromStdString(written.message()).contains(quoted(path)),
             written.message().c_str());
    QVERIFY(entries(toPath(dir)).isEmpty());
}

void TestCaches::nonFiniteFrameIsRefused_data() {
    QTest::addColumn<QString>("format");
    QTest::addColumn<float>("value");
    QTest::addColumn<int>("axis");
    for (const char* format : {"pc2", "mdd", "objseq"}) {
        QTest::addRow("%s nan", format) << format << std::numeric_limits<float>::quiet_NaN() << 0;
        QTest::addRow("%s +inf", format) << format << std::numeric_limits<float>::infinity() << 1;
        QTest::addRow("%s -inf", format) << format << -std::numeric_limits<float>::infinity() << 2;
    }
}

void TestCaches::nonFiniteFrameIsRefused() {
    QFETCH(QString, format);
    QFETCH(float, value);
    QFETCH(int, axis);
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const CacheFormat kind = formatNamed(format);
    const Mesh rest = gridMesh(3, 2);  // 6 vertices
    const fs::path path = cachePath(toPath(dir), kind);
    const CacheInfo info{6, 5, 24.0, 0.0};
    auto writer = makeCacheWriter(kind, rest);
    QVERIFY(writer->begin(path, info).ok());
    QVERIFY(writeSampleFrames(*writer, 2, info).ok());
    std::vector<Vec3f> bad = sampleFrame(2, 6);
    bad[3][axis] = value;
    const Status refused = writer->writeFrame(bad);
    QVERIFY(!refused.ok());
    const QString message = QString::fromStdString(refused.message());
    QVERIFY2(message.contains("frame 2 vertex 3 is not finite"), qPrintable(message));
    QVERIFY2(message.contains("nothing was written to " + quoted(path)),
             qPrintable(message));
    // The writer aborted: no output, no temporaries, and it refuses to go on.
    QVERIFY2(entries(toPath(dir)).isEmpty(), qPrintable(entries(toPath(dir)).join(", ")));
    QVERIFY(!writer->writeFrame(sampleFrame(2, 6)).ok());
    QVERIFY(!writer->finish().ok());
    QVERIFY(entries(toPath(dir)).isEmpty());
    // ...but it can start over.
    QVERIFY(writer->begin(path, info).ok());
    QVERIFY(writeSampleFrames(*writer, 5, info).ok());
    QVERIFY(writer->finish().ok());
    QVERIFY(fs::exists(firstOutputFile(path, kind)));
}

void TestCaches::failedWriteKeepsExistingFile_data() {
    QTest::addColumn<QString>("format");
    QTest::addColumn<QString>("failure");
    QTest::addColumn<QString>("message");  // expected in the error; empty where none is returned
    for (const char* format : {"pc2", "mdd", "objseq"}) {
        QTest::addRow("%s abort", format) << format << "abort" << "";
        QTest::addRow("%s writer destroyed", format) << format << "destroy" << "";
        QTest::addRow("%s non-finite frame", format) << format << "nan" << "frame 1 vertex 0 is not finite";
        QTest::addRow("%s wrong point count", format)
            << format << "points" << "frame 1 has 5 vertices, the cache has 6 per frame";
        QTest::addRow("%s too few frames", format) << format << "finish" << "2 of the 3 announced frames";
    }
}

void TestCaches::failedWriteKeepsExistingFile() {
    QFETCH(QString, format);
    QFETCH(QString, failure);
    QFETCH(QString, message);
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const CacheFormat kind = formatNamed(format);
    const fs::path path = cachePath(toPath(dir), kind);
    const fs::path existing = firstOutputFile(path, kind);
    const Bytes previous = {'o', 'l', 'd', '\n', 0x00, 0xff, 0x10, 0x80};
    writeBytes(existing, previous);
    const QStringList before = entries(toPath(dir));

    auto writer = makeCacheWriter(kind, gridMesh(3, 2));
    const CacheInfo info{6, 3, 24.0, 0.0};
    QVERIFY(writer->begin(path, info).ok());
    QVERIFY(writer->writeFrame(sampleFrame(0, 6)).ok());
    Status result = Status::success();
    if (failure == "abort") {
        writer->abort();
    } else if (failure == "destroy") {
        writer.reset();
    } else if (failure == "nan") {
        std::vector<Vec3f> bad = sampleFrame(1, 6);
        bad[0].z() = std::numeric_limits<float>::quiet_NaN();
        result = writer->writeFrame(bad);
    } else if (failure == "points") {
        result = writer->writeFrame(sampleFrame(1, 5));
    } else if (failure == "finish") {
        QVERIFY(writer->writeFrame(sampleFrame(1, 6)).ok());
        result = writer->finish();
    }
    if (!message.isEmpty()) {
        QVERIFY(!result.ok());
        QVERIFY2(QString::fromStdString(result.message()).contains(message), result.message().c_str());
    }
    if (writer)
        QVERIFY(!writer->finish().ok());  // whatever failed cannot be published afterwards
    QVERIFY(readBytes(existing) == previous);
    QCOMPARE(entries(toPath(dir)), before);  // no temporaries left behind
}

void TestCaches::wrongFrameCountIsRefused_data() {
    QTest::addColumn<QString>("format");
    QTest::addColumn<int>("written");
    QTest::addColumn<QString>("message");
    for (const char* format : {"pc2", "mdd", "objseq"}) {
        QTest::addRow("%s none", format) << format << 0 << "0 of the 4 announced frames were written";
        QTest::addRow("%s fewer", format) << format << 3 << "3 of the 4 announced frames were written";
        QTest::addRow("%s more", format) << format << 5 << "frame 4 is one more than the 4 frames announced";
    }
}

void TestCaches::wrongFrameCountIsRefused() {
    QFETCH(QString, format);
    QFETCH(int, written);
    QFETCH(QString, message);
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const CacheFormat kind = formatNamed(format);
    const fs::path path = cachePath(toPath(dir), kind);
    const CacheInfo info{6, 4, 24.0, 0.0};
    auto writer = makeCacheWriter(kind, gridMesh(3, 2));
    QVERIFY(writer->begin(path, info).ok());
    Status failed = Status::success();
    for (int f = 0; f < written && failed.ok(); ++f)
        failed = writer->writeFrame(sampleFrame(std::size_t(f), 6));
    if (failed.ok())
        failed = writer->finish();
    QVERIFY(!failed.ok());
    QVERIFY2(QString::fromStdString(failed.message()).contains(message), failed.message().c_str());
    QVERIFY2(QString::fromStdString(failed.message()).contains(quoted(path)),
             failed.message().c_str());
    QVERIFY(!writer->finish().ok());
    QVERIFY2(entries(toPath(dir)).isEmpty(), qPrintable(entries(toPath(dir)).join(", ")));
}

void TestCaches::invalidInfoIsRefused_data() {
    QTest::addColumn<QString>("format");
    QTest::addColumn<qulonglong>("points");
    QTest::addColumn<qulonglong>("frames");
    QTest::addColumn<double>("fps");
    QTest::addColumn<double>("startFrame");
    QTest::addColumn<QString>("message");
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    for (const char* format : {"pc2", "mdd", "objseq"}) {
        QTest::addRow("%s no points", format)
            << format << 0ull << 3ull << 24.0 << 0.0 << "at least one vertex";
        QTest::addRow("%s no frames", format)
            << format << 6ull << 0ull << 24.0 << 0.0 << "at least one frame";
        QTest::addRow("%s zero fps", format) << format << 6ull << 3ull << 0.0 << 0.0 << "above 0 fps, got 0";
        QTest::addRow("%s negative fps", format)
            << format << 6ull << 3ull << -24.0 << 0.0 << "above 0 fps, got -24";
        QTest::addRow("%s nan fps", format) << format << 6ull << 3ull << nan << 0.0 << "above 0 fps, got nan";
        QTest::addRow("%s infinite fps", format)
            << format << 6ull << 3ull << inf << 0.0 << "above 0 fps, got inf";
        QTest::addRow("%s nan start", format)
            << format << 6ull << 3ull << 24.0 << nan << "start frame must be finite";
    }
}

void TestCaches::invalidInfoIsRefused() {
    QFETCH(QString, format);
    QFETCH(qulonglong, points);
    QFETCH(qulonglong, frames);
    QFETCH(double, fps);
    QFETCH(double, startFrame);
    QFETCH(QString, message);
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const CacheFormat kind = formatNamed(format);
    const fs::path path = cachePath(toPath(dir), kind);
    auto writer = makeCacheWriter(kind, Mesh{});
    const Status refused = writer->begin(path, CacheInfo{points, frames, fps, startFrame});
    QVERIFY(!refused.ok());
    const QString text = QString::fromStdString(refused.message());
    QVERIFY2(text.contains(message), qPrintable(text));
    QVERIFY2(text.contains("cannot write " + quoted(path)), qPrintable(text));
    QVERIFY(!writer->writeFrame(sampleFrame(0, 6)).ok());
    QVERIFY(entries(toPath(dir)).isEmpty());
}

void TestCaches::badCacheFilesAreRejected_data() {
    QTest::addColumn<QString>("format");
    QTest::addColumn<QString>("damage");
    QTest::addColumn<QString>("message");
    QTest::newRow("pc2 bad signature") << "pc2" << "signature" << "is not a PC2 file";
    QTest::newRow("pc2 empty file") << "pc2" << "empty" << "is not a PC2 file";
    QTest::newRow("pc2 header cut") << "pc2" << "cut header" << "is truncated: the PC2 header needs 32 bytes";
    QTest::newRow("pc2 last byte missing") << "pc2" << "cut 1" << "is truncated";
    QTest::newRow("pc2 extra bytes") << "pc2" << "extra 3" << "has 3 extra bytes";
    QTest::newRow("pc2 version 2") << "pc2" << "version" << "PC2 version 2";
    QTest::newRow("pc2 negative samples") << "pc2" << "negative" << "negative number of samples";
    QTest::newRow("pc2 absurd counts") << "pc2" << "huge" << "more than any file can hold";
    QTest::newRow("pc2 missing") << "pc2" << "missing" << "cannot read";
    QTest::newRow("mdd last byte missing") << "mdd" << "cut 1" << "is truncated";
    QTest::newRow("mdd extra bytes") << "mdd" << "extra 4" << "has 4 extra bytes";
    QTest::newRow("mdd counts cut") << "mdd" << "cut header" << "is truncated";
    QTest::newRow("mdd negative frames") << "mdd" << "negative" << "negative number of frames";
    QTest::newRow("mdd little-endian counts") << "mdd" << "swapped" << "is truncated";
    QTest::newRow("mdd missing") << "mdd" << "missing" << "cannot read";
}

void TestCaches::badCacheFilesAreRejected() {
    QFETCH(QString, format);
    QFETCH(QString, damage);
    QFETCH(QString, message);
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const CacheFormat kind = formatNamed(format);
    const fs::path path = cachePath(toPath(dir), kind);
    const CacheInfo info{4, 3, 24.0, 0.0};
    auto writer = makeCacheWriter(kind, Mesh{});
    QVERIFY(writer->begin(path, info).ok());
    QVERIFY(writeSampleFrames(*writer, 3, info).ok());
    QVERIFY(writer->finish().ok());

    Bytes b = readBytes(path);
    const bool pc2 = kind == CacheFormat::Pc2;
    if (damage == "signature")
        b[0] = 'Q';
    else if (damage == "empty")
        b.clear();
    else if (damage == "cut header")
        b.resize(pc2 ? 20 : 5);
    else if (damage == "cut 1")
        b.pop_back();
    else if (damage == "extra 3")
        b.insert(b.end(), 3, 0);
    else if (damage == "extra 4")
        b.insert(b.end(), 4, 0);
    else if (damage == "version")
        b[12] = 2;
    else if (damage == "negative")
        std::fill_n(b.begin() + (pc2 ? 28 : 0), 4, 0xff);  // -1 either way round
    else if (damage == "huge")
        for (std::size_t at : {16, 28})  // INT32_MAX points and samples: 2^62 · 12 bytes overflow 64 bits
            std::copy_n(Bytes{0xff, 0xff, 0xff, 0x7f}.begin(), 4, b.begin() + std::ptrdiff_t(at));
    else if (damage == "swapped")
        std::reverse(b.begin(), b.begin() + 4);  // 3 frames read as 0x03000000
    writeBytes(path, b);
    if (damage == "missing")
        fs::remove(path);

    const Result<VertexCache> cache = pc2 ? readPc2(path) : readMdd(path);
    QVERIFY(!cache.ok());
    const QString text = QString::fromStdString(cache.message());
    QVERIFY2(text.contains(quoted(path)), qPrintable(text));
    QVERIFY2(text.contains(message), qPrintable(text));
}

void TestCaches::unwritableTargetIsReported_data() {
    QTest::addColumn<QString>("format");  // "rest" for writeObj
    for (const char* format : {"pc2", "mdd", "objseq", "rest"})
        QTest::newRow(format) << format;
}

void TestCaches::unwritableTargetIsReported() {
    QFETCH(QString, format);
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    // A regular file where a directory should be: fails for root too, unlike permission bits.
    const fs::path notADirectory = toPath(dir) / "file";
    writeBytes(notADirectory, {'x'});
    Status failed = Status::success();
    if (format == "rest") {
        failed = writeObj(notADirectory / "rest.obj", gridMesh(3, 2));
    } else {
        const CacheFormat kind = formatNamed(format);
        auto writer = makeCacheWriter(kind, gridMesh(3, 2));
        failed = writer->begin(cachePath(notADirectory, kind), CacheInfo{6, 2, 24.0, 0.0});
    }
    QVERIFY(!failed.ok());
    const QString text = QString::fromStdString(failed.message());
    QVERIFY2(text.startsWith("cannot write '" + QString::fromStdString(notADirectory.string()) + "/"),
             qPrintable(text));
    QVERIFY2(!text.contains(".tmp-"), qPrintable(text));  // the file a person asked for, not our temporary
    QVERIFY2(text.contains("Not a directory"), qPrintable(text));
    QCOMPARE(entries(toPath(dir)), QStringList{"file"});
}

void TestCaches::atomicFileReplacesOnlyOnCommit() {
    QTemporaryDir dir;
    QVERIFY(dir.isValid());
    const fs::path target = toPath(dir) / "data.bin";
    writeBytes(target, {'o', 'l', 'd'});
    QCOMPARE(::chmod(target.c_str(), 0640), 0);

    {
        AtomicFile file(target);
        QVERIFY(file.open().ok());
        QVERIFY(file.write("new", 3).ok());
        QVERIFY((readBytes(target) == Bytes{'o', 'l', 'd'}));  // untouched while writing
        QCOMPARE(entries(toPath(dir)).size(), qsizetype(2));             // the temporary sits beside it
        QVERIFY(entries(toPath(dir))[1].startsWith("data.bin.tmp-"));
        QVERIFY(file.commit().ok());
    }
    QVERIFY((readBytes(target) == Bytes{'n', 'e', 'w'}));
    QCOMPARE(entries(toPath(dir)), QStringList{"data.bin"});
    QVERIFY(
        (fs::status(target).permissions() & fs::perms::all) ==
        (fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read)); // kept, as QSaveFile does

    {
        AtomicFile file(target);
        QVERIFY(file.open().ok());
        QVERIFY(file.write("abandoned", 9).ok());
        file.discard();
        QVERIFY(!file.write("x", 1).ok());
        QVERIFY(!file.commit().ok());
    }
    {
        AtomicFile file(target);
        QVERIFY(file.open().ok());
        QVERIFY(file.write("destroyed", 9).ok());
    }
    QVERIFY((readBytes(target) == Bytes{'n', 'e', 'w'}));
    QCOMPARE(entries(toPath(dir)), QStringList{"data.bin"});

    // A brand-new file appears only on commit.
    const fs::path fresh = toPath(dir) / "fresh.bin";
    AtomicFile file(fresh);
    QVERIFY(file.open().ok());
    QVERIFY(!fs::exists(fresh));
    QVERIFY(file.commit().ok());
    QVERIFY(fs::exists(fresh) && fs::file_size(fresh) == 0);
}

QTEST_GUILESS_MAIN(TestCaches)
#include "test_caches.moc"

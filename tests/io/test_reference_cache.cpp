// The study's reference cache (io/pipeline/reference_cache.h): what is stored is what is read back, a damaged or
// foreign file is never trusted, and the key changes with anything the reference depends on.
#include "io/pipeline/reference_cache.h"

#include <QTemporaryDir>
#include <QtTest>
#include <cstring>
#include <fstream>
#include <limits>

using namespace softtouch;

class TestReferenceCache : public QObject {
    Q_OBJECT
private slots:
    void initTestCase();
    void storedIsReadBackExactly();
    void damagedOrForeignFilesAreNotTrusted();
    void theKeyFollowsWhatTheReferenceDependsOn();

private:
    analysis::ConvergedReference sample() const;
    io::Project m_project;
    Clip m_clip;
};

void TestReferenceCache::initTestCase() {
    auto project = io::loadProject(SOFTTOUCH_SOURCE_DIR "/presets/scenes/demekin-swim.softtouch");
    QVERIFY2(project.ok(), project.message().c_str());
    m_project = project.value();
    auto clip = analysis::clipToPlay(m_project.scene, m_project.clips, "swim");
    QVERIFY2(clip.ok(), clip.message().c_str());
    m_clip = clip.value();
}

analysis::ConvergedReference TestReferenceCache::sample() const {
    analysis::ConvergedReference r;
    r.levels = {{"solid 3x3x3 bezier, verlet, dt 1/8000 s", std::numeric_limits<double>::quiet_NaN(), 0.5},
                {"solid 3x3x3 bezier, verlet, dt 1/4000 s", 2e-7, 0.25}};
    r.uncertainty = 3e-4;
    r.spaceUncertainty = 2.5e-4;
    r.timeUncertainty = 5e-5;
    r.spaceConverging = true;
    r.description = "solid element on 3x3x3 bezier, verlet, dt 1/4000 s";
    r.dt = 1.0 / 4000;
    r.frames.frames = 3;
    r.frames.positions = {std::vector<Vec3f>(6), std::vector<Vec3f>(9)};
    for (std::size_t o = 0; o < 2; ++o)
        for (std::size_t i = 0; i < r.frames.positions[o].size(); ++i)
            r.frames.positions[o][i] = Vec3f(float(i), -0.5f * float(o), 1e-7f * float(i * i));
    return r;
}

void TestReferenceCache::storedIsReadBackExactly() {
    QTemporaryDir dir;
    const std::filesystem::path folder = dir.filePath("references").toStdString();
    QVERIFY(io::readCachedReference(folder, "0123456789abcdef") == nullptr);  // nothing stored yet
    const analysis::ConvergedReference stored = sample();
    QVERIFY(io::writeCachedReference(folder, "0123456789abcdef", stored).ok());
    const auto read = io::readCachedReference(folder, "0123456789abcdef");
    QVERIFY(read != nullptr);
    QCOMPARE(read->levels.size(), stored.levels.size());
    for (std::size_t i = 0; i < stored.levels.size(); ++i) {
        QCOMPARE(read->levels[i].what, stored.levels[i].what);
        QCOMPARE(std::isnan(read->levels[i].change), std::isnan(stored.levels[i].change));
        QCOMPARE(read->levels[i].seconds, stored.levels[i].seconds);
    }
    QCOMPARE(read->levels[1].change, stored.levels[1].change);
    QCOMPARE(read->uncertainty, stored.uncertainty);
    QCOMPARE(read->spaceUncertainty, stored.spaceUncertainty);
    QCOMPARE(read->timeUncertainty, stored.timeUncertainty);
    QCOMPARE(read->spaceConverging, stored.spaceConverging);
    QCOMPARE(read->description, stored.description);
    QCOMPARE(read->dt, stored.dt);
    QCOMPARE(read->frames.frames, stored.frames.frames);
    QVERIFY(read->frames.positions == stored.frames.positions);  // bit for bit
}

void TestReferenceCache::damagedOrForeignFilesAreNotTrusted() {
    QTemporaryDir dir;
    const std::filesystem::path folder = dir.filePath("references").toStdString();
    QVERIFY(io::writeCachedReference(folder, "00000000000000aa", sample()).ok());
    const std::filesystem::path file = folder / "00000000000000aa.streference";
    std::ifstream in(file, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    in.close();
    auto storeAs = [&](const std::string& key, const std::string& content) {
        std::ofstream(folder / (key + ".streference"), std::ios::binary) << content;
    };
    // Stored under another key than the one inside: a file renamed or copied by hand.
    storeAs("00000000000000bb", bytes);
    QVERIFY(io::readCachedReference(folder, "00000000000000bb") == nullptr);
    // Cut anywhere, one byte more, or a point count beyond the file: refused, never read past the end.
    for (std::size_t cut : {std::size_t(0), std::size_t(10), bytes.size() / 2, bytes.size() - 1}) {
        storeAs("00000000000000cc", bytes.substr(0, cut));
        QVERIFY2(io::readCachedReference(folder, "00000000000000cc") == nullptr, qPrintable(QString("cut at %1").arg(cut)));
    }
    storeAs("00000000000000cc", bytes + "x");
    QVERIFY(io::readCachedReference(folder, "00000000000000cc") == nullptr);
    std::string lying = bytes;
    const std::size_t countAt = bytes.size() - 9 * sizeof(float) - sizeof(std::uint64_t);  // the last object's count
    const std::uint64_t huge = std::uint64_t(1) << 40;
    std::memcpy(lying.data() + countAt, &huge, sizeof huge);
    storeAs("00000000000000cc", lying);
    QVERIFY(io::readCachedReference(folder, "00000000000000cc") == nullptr);
    QVERIFY(io::readCachedReference(folder, "00000000000000aa") != nullptr);  // the good one still reads
}

void TestReferenceCache::theKeyFollowsWhatTheReferenceDependsOn() {
    analysis::ReferenceOptions options;
    const auto key = io::referenceKey(m_project, m_clip, options);
    QVERIFY2(key.ok(), key.message().c_str());
    QCOMPARE(int(key->size()), 16);
    QCOMPARE(io::referenceKey(m_project, m_clip, options).value(), key.value());  // the same inputs, the same key
    QVERIFY(io::referenceKey(io::loadProject(m_project.path).value(), m_clip, options).value() == key.value());

    auto differs = [&](const io::Project& project, const Clip& clip, const analysis::ReferenceOptions& o) {
        const auto other = io::referenceKey(project, clip, o);
        return other.ok() && other.value() != key.value();
    };
    io::Project stiffer = m_project;
    stiffer.scene.objects[0].material.stiffness[0] *= 1.01;  // one painted node
    QVERIFY(differs(stiffer, m_clip, options));
    io::Project moved = m_project;
    Mesh mesh = *m_project.scene.objects[0].mesh;
    mesh.positions[0].x() += 1e-4f;  // the mesh file changed
    moved.scene.objects[0].mesh = std::move(mesh);
    QVERIFY(differs(moved, m_clip, options));
    io::Project heavier = m_project;
    heavier.scene.world.gravity.y() -= 0.1;
    QVERIFY(differs(heavier, m_clip, options));
    Clip later = m_clip;
    later.startSeconds += 1.0 / 24;
    QVERIFY(differs(m_project, later, options));
    analysis::ReferenceOptions finer = options;
    finer.nodes = {4, 6};
    QVERIFY(differs(m_project, m_clip, finer));
}

QTEST_GUILESS_MAIN(TestReferenceCache)
#include "test_reference_cache.moc"

// The per-node material channels are declared once (core/body/material_channels.h), and everything that
// handles a channel iterates that table: these tests take every row through validation, resampling, the
// project file, material presets and the brush, so a new row is checked end to end; and they read
// LatticeMaterial's declaration, so a per-node member added without a row (or a row whose id the enum lacks)
// fails here.
#include "core/body/material_channels.h"
#include "io/documents/document_json.h"
#include "io/documents/preset_file.h"
#include "io/files/json_reader.h"
#include "ui/node_brush.h"

#include <QtTest>
#include <fstream>
#include <regex>
#include <sstream>

using namespace softtouch;

class TestMaterialChannels : public QObject {
    Q_OBJECT

  private slots:
    void everyPerNodeMemberHasARow();
    void everyChannelIsValidatedByName();
    void everyChannelResamplesAsItsScalingSays();
    void everyChannelRoundTripsThroughAProject();
    void presetsCarryTheirChannels();
    void theBrushPaintsEveryChannelAlone();
};

namespace {

const std::array<MaterialModel, 2> kModels{MaterialModel::LatticeSprings, MaterialModel::Continuum};

Lattice boxLattice(int n) {
    OrientedBox box;
    box.size = Vec3(0.3, 0.2, 0.1);
    return Lattice::create({LatticeKind::Bezier, {n, n, n}}, box).value();
}

/// A material whose every channel holds values that differ from node to node (within each range), and differ
/// from channel to channel: what a round trip must keep, value for value.
LatticeMaterial paintedMaterial(const Lattice& lattice, MaterialModel model) {
    LatticeMaterial m = defaultMaterial(lattice, model);
    int c = 0;
    for (const MaterialChannel& channel : materialChannels()) {
        std::vector<double>& values = channelValues(m, channel);
        const MaterialRange& range = channel.rangeFor(model);
        const double base =
            channel.scaling == ChannelScaling::Fraction ? 0.5 : std::max(channel.defaultFor(model), 1.0);
        for (std::size_t i = 0; i < values.size(); ++i)
            values[i] =
                std::clamp(base * (1.0 + 0.01 * double(c + 1) * double(i % 7) / 7.0), range.low, range.high);
        ++c;
    }
    return m;
}

/// The text between "struct NAME {" (or "enum class NAME ... {") and its closing brace in a header.
std::string declaration(const std::string& header, const std::string& opening) {
    std::ifstream in(std::string(SOFTTOUCH_SOURCE_DIR) + "/" + header);
    std::stringstream text;
    text << in.rdbuf();
    const std::string all = text.str();
    const std::size_t start = all.find(opening);
    if (start == std::string::npos)
        return {};
    return all.substr(start, all.find("\n};", start) - start);
}

} // namespace

void TestMaterialChannels::everyPerNodeMemberHasARow() {
    // Every std::vector<double> of LatticeMaterial is a per-node channel: each must be a row's values.
    const std::string material = declaration("core/body/lattice_body.h", "struct LatticeMaterial {");
    QVERIFY(!material.empty());
    const std::regex member(R"(std::vector<double>\s+(\w+)\s*;)");
    int members = 0;
    for (auto it = std::sregex_iterator(material.begin(), material.end(), member);
         it != std::sregex_iterator(); ++it) {
        ++members;
        const std::string name = (*it)[1];
        const auto rows =
            std::count_if(materialChannels().begin(), materialChannels().end(),
                          [&](const MaterialChannel& channel) { return name == channel.member; });
        QVERIFY2(rows == 1, ("LatticeMaterial::" + name +
                             " needs one row in materialChannels() (core/body/material_channels.cpp)")
                                .c_str());
    }
    QCOMPARE(members, int(materialChannels().size()));
    // One row per id of the enum, each found by its id.
    const std::string ids = declaration("core/body/material_channels.h", "enum class MaterialChannelId");
    const std::regex enumerator(R"(^\s+(\w+),)", std::regex::multiline);
    int enumerators = 0;
    for (auto it = std::sregex_iterator(ids.begin(), ids.end(), enumerator); it != std::sregex_iterator();
         ++it)
        ++enumerators;
    QCOMPARE(enumerators, int(materialChannels().size()));
    for (const MaterialChannel& channel : materialChannels()) {
        QCOMPARE(&materialChannel(channel.id), &channel);
        QCOMPARE(std::count_if(materialChannels().begin(), materialChannels().end(),
                               [&](const MaterialChannel& c) { return c.values == channel.values; }),
                 1);
        QVERIFY(channel.modelRange || channel.range);
    }
}

void TestMaterialChannels::everyChannelIsValidatedByName() {
    const Lattice lattice = boxLattice(3);
    const int node = lattice.index(1, 2, 0);
    for (const MaterialModel model : kModels) {
        for (const MaterialChannel& channel : materialChannels()) {
            const MaterialRange& range = channel.rangeFor(model);
            LatticeMaterial m = defaultMaterial(lattice, model);
            channelValues(m, channel)[std::size_t(node)] = range.high * 10.0 + 1.0;
            auto body = buildLatticeBody(lattice, m);
            QVERIFY2(!body, range.name);
            const std::string expected =
                std::string("node (1,2,0) ") + range.label +
                (std::string(range.label) == range.name ? "" : std::string(" (") + range.name + ")");
            QVERIFY2(body.message().find(expected) == 0, (expected + " / " + body.message()).c_str());
            // A map of the wrong length is refused naming the channel; an optional one may be empty.
            (m.*channel.values).assign(std::size_t(lattice.nodeCount() - 1), channel.defaultFor(model));
            body = buildLatticeBody(lattice, m);
            QVERIFY(!body);
            QVERIFY2(body.message().find(std::string(range.label) + " has " +
                                         std::to_string(lattice.nodeCount() - 1) + " values") !=
                         std::string::npos,
                     body.message().c_str());
            (m.*channel.values).clear();
            QCOMPARE(bool(buildLatticeBody(lattice, m)), channel.optional);
        }
    }
}

void TestMaterialChannels::everyChannelResamplesAsItsScalingSays() {
    const Lattice coarse = boxLattice(3), fine = boxLattice(5);
    const double volume = 27.0 / 125.0, spacing = 2.0 / 4.0; // one node's share of the box; node spacing
    for (const MaterialModel model : kModels) {
        LatticeMaterial m = defaultMaterial(coarse, model);
        for (const MaterialChannel& channel : materialChannels())
            channelValues(m, channel)
                .assign(m.mass.size(), channel.scaling == ChannelScaling::Fraction ? 0.25 : 2.0);
        const LatticeMaterial moved = resampleMaterial(coarse, m, fine, true);
        for (const MaterialChannel& channel : materialChannels()) {
            const std::vector<double>& values = moved.*channel.values;
            QCOMPARE(int(values.size()), fine.nodeCount());
            double expected = channel.scaling == ChannelScaling::Fraction ? 0.25 : 2.0;
            if (model == MaterialModel::LatticeSprings && channel.scaling == ChannelScaling::NodeVolume)
                expected *= volume;
            if (model == MaterialModel::LatticeSprings && channel.scaling == ChannelScaling::Spacing)
                expected *= spacing;
            for (double x : values)
                QVERIFY2(std::abs(x - expected) <= 1e-12 * expected, channel.member);
        }
    }
}

void TestMaterialChannels::everyChannelRoundTripsThroughAProject() {
    const Lattice lattice = boxLattice(3);
    for (const MaterialModel model : kModels) {
        const LatticeMaterial painted = paintedMaterial(lattice, model);
        nlohmann::json object;
        io::document::writeMaterial(lattice, painted, object);
        for (const MaterialChannel& channel : materialChannels())
            QVERIFY2(object["material"].contains(channel.rangeFor(model).name), channel.rangeFor(model).name);
        // Read onto a material of the other model: the file's "model" resets it, and every channel is the
        // file's.
        const MaterialModel other =
            model == MaterialModel::Continuum ? MaterialModel::LatticeSprings : MaterialModel::Continuum;
        LatticeMaterial read = defaultMaterial(lattice, other);
        io::JsonIssues issues("test");
        std::optional<double> total;
        io::document::readMaterial(io::JsonValue(&object["material"], "/material", &issues), read, total,
                                   false, {});
        QVERIFY2(issues.empty(), issues.summary().c_str());
        for (const MaterialChannel& channel : materialChannels())
            QVERIFY2(read.*channel.values == painted.*channel.values, channel.member);
        // An optional channel all 0 is left out of the file, and reads back as 0 everywhere.
        LatticeMaterial plain = painted;
        for (const MaterialChannel& channel : materialChannels())
            if (channel.optional)
                (plain.*channel.values).assign(plain.mass.size(), 0.0);
        nlohmann::json plainObject;
        io::document::writeMaterial(lattice, plain, plainObject);
        for (const MaterialChannel& channel : materialChannels())
            QCOMPARE(plainObject["material"].contains(channel.rangeFor(model).name), !channel.optional);
    }
}

void TestMaterialChannels::presetsCarryTheirChannels() {
    const Lattice lattice = boxLattice(3);
    QTemporaryDir dir;
    for (const MaterialModel model : kModels) {
        LatticeMaterial uniform = defaultMaterial(lattice, model);
        for (const MaterialChannel& channel : materialChannels())
            channelValues(uniform, channel)
                .assign(uniform.mass.size(), channel.scaling == ChannelScaling::Fraction
                                                 ? 0.375
                                                 : 3.0 * std::max(channel.defaultFor(model), 1.0));
        const std::string path = dir.filePath("p.stpreset").toStdString();
        QVERIFY(io::saveMaterialPreset("p", "", uniform, path));
        auto preset = io::loadMaterialPreset(path);
        QVERIFY2(preset.ok(), preset.message().c_str());
        LatticeMaterial onto = defaultMaterial(lattice, model);
        QVERIFY(io::applyMaterialPreset(preset.value(), lattice, onto, {lattice.index(1, 1, 1)}));
        for (const MaterialChannel& channel : materialChannels()) {
            const double given = (onto.*channel.values).empty()
                                     ? 0.0
                                     : (onto.*channel.values)[std::size_t(lattice.index(1, 1, 1))];
            const double expected = channel.inPresets ? (uniform.*channel.values)[0] : 0.0;
            QVERIFY2(std::abs(given - expected) <= 1e-12 * std::abs(expected), channel.member);
        }
    }
}

void TestMaterialChannels::theBrushPaintsEveryChannelAlone() {
    const Lattice lattice = boxLattice(3);
    for (const MaterialChannel& channel : materialChannels()) {
        LatticeMaterial m = defaultMaterial(lattice, MaterialModel::Continuum);
        const LatticeMaterial before = m;
        const auto [low, high] = ui::paintableRange(channel.id, m.model);
        const double value =
            channel.scaling == ChannelScaling::Fraction ? 0.75 : std::min(high, 7.0 * std::max(low, 1.0));
        const std::vector<int> nodes{0, 5};
        ui::fillNodes(m, channel.id, nodes, value);
        for (const MaterialChannel& other : materialChannels()) {
            const std::vector<double>& values = m.*other.values;
            for (int n = 0; n < lattice.nodeCount(); ++n) {
                const bool painted = other.id == channel.id && (n == 0 || n == 5);
                const double was =
                    (before.*other.values).empty() ? 0.0 : (before.*other.values)[std::size_t(n)];
                QCOMPARE(values[std::size_t(n)], painted ? value : was);
            }
        }
    }
}

QTEST_GUILESS_MAIN(TestMaterialChannels)
#include "test_material_channels.moc"

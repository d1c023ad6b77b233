// The pieces projects and presets share (io/documents/document_json.h), each reader beside its writer.
#include "io/documents/document_json.h"
#include "io/documents/preset_file.h"

#include "core/base/ranges.h"
#include "core/body/material_channels.h"

#include "io/files/file_text.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace softtouch::io::document {
namespace fs = std::filesystem;
using nlohmann::json;

// --- Header. ----------------------------------------------------------------------------------

/// A preset file's kind: a setup preset says "kind": "setup"; a material preset has no kind.
bool declaresSetup(const nlohmann::json& doc) {
    return doc.is_object() && doc.contains("kind") && doc["kind"] == "setup";
}

/// Checks "format" and "version" of a document.
bool readHeader(const JsonValue& root, const char* format, int maxVersion) {
    if (!root.expectObject(true))
        return false;
    const auto f = root["format"].string(true);
    if (f && *f != format) {
        root["format"].problem(std::string("expected \"") + format + "\", got \"" + *f + "\"");
        return false;
    }
    const auto v = root["version"].integer(1, 1000000, true);
    if (v && *v > maxVersion) {
        root["version"].problem("version " + std::to_string(*v) + " was written by a newer SoftTouch; this build reads up to " +
                                std::to_string(maxVersion));
        return false;
    }
    return f && v;
}

// --- Per-node maps and node selections. --------------------------------------------------------

namespace {

/// A per-node field: one number for every node, or an array of one number per node (i fastest).
void readPerNode(const JsonValue& v, std::vector<double>& out, double lo, double hi, const char* unit) {
    if (!v.exists())
        return;
    if (v.isArray()) {
        if (v.size() != out.size()) {
            v.problem("expected one value per lattice node (" + std::to_string(out.size()) + "), got " +
                      std::to_string(v.size()));
            return;
        }
        for (std::size_t i = 0; i < out.size(); ++i) {
            if (auto x = v.at(i).number(lo, hi, unit, true))
                out[i] = *x;
        }
        return;
    }
    if (auto x = v.number(lo, hi, unit))
        out.assign(out.size(), *x);
}

/// A per-node field as written: one number when every node has it, else the array.
json perNode(const std::vector<double>& values) {
    bool uniform = true;
    for (double v : values)
        uniform = uniform && v == values.front();
    if (uniform)
        return values.front();
    return values;
}

/// A node's [i, j, k], checked against the lattice.
std::optional<std::array<int, 3>> readNode(const JsonValue& v, const Lattice& lattice) {
    const auto c = v.int3(0, 1000000, true);
    if (!c)
        return std::nullopt;
    for (int a = 0; a < 3; ++a) {
        if ((*c)[std::size_t(a)] >= lattice.count(a)) {
            v.problem("node index out of range for a " + std::to_string(lattice.count(0)) + "x" +
                      std::to_string(lattice.count(1)) + "x" + std::to_string(lattice.count(2)) + " lattice");
            return std::nullopt;
        }
    }
    return c;
}

/// Nodes as a list of [i, j, k].
json nodeList(const Lattice& lattice, const std::vector<int>& nodes) {
    json list = json::array();
    for (int n : nodes) {
        const auto c = lattice.coords(n);
        list.push_back(json::array({c[0], c[1], c[2]}));
    }
    return list;
}

}  // namespace

/// Nodes selected by {"nodes": [[i,j,k],…]} or {"region": {"min": [u,v,w], "max": [u,v,w]}}.
std::vector<int> readNodeSelection(const JsonValue& v, const Lattice& lattice) {
    std::vector<int> nodes;
    if (const JsonValue list = v["nodes"]; list.exists()) {
        if (!list.isArray())
            list.problem("expected an array of [i,j,k] node indices");
        for (std::size_t i = 0; i < list.size(); ++i) {
            if (auto c = readNode(list.at(i), lattice))
                nodes.push_back(lattice.index((*c)[0], (*c)[1], (*c)[2]));
        }
    }
    if (const JsonValue region = v["region"]; region.expectObject()) {
        region.checkKeys({"min", "max"});
        const auto lo = region["min"].vec3(true);
        const auto hi = region["max"].vec3(true);
        if (lo && hi) {
            for (int n = 0; n < lattice.nodeCount(); ++n) {
                const Vec3 p = lattice.restNodeParameters(n);
                if ((p.array() >= lo->array() - 1e-9).all() && (p.array() <= hi->array() + 1e-9).all())
                    nodes.push_back(n);
            }
            if (nodes.empty())
                region.problem("the region selects no lattice node");
        }
    }
    if (!v["nodes"].exists() && !v["region"].exists())
        v.problem("expected \"nodes\" or \"region\"");
    return nodes;
}

/// An "anchors" array: groups of nodes (by list or region) with a mode, pinned or heavy.
void readAnchors(const JsonValue& anchors, const Lattice& lattice, std::vector<AnchorMode>& out) {
    if (!anchors.exists())
        return;
    if (!anchors.isArray())
        anchors.problem("expected an array of anchor groups");
    for (std::size_t i = 0; i < anchors.size(); ++i) {
        const JsonValue a = anchors.at(i);
        if (!a.expectObject(true))
            continue;
        a.checkKeys({"mode", "nodes", "region"});
        AnchorMode mode = AnchorMode::Pinned;
        if (auto m = a["mode"].string()) {
            if (*m == "heavy")
                mode = AnchorMode::Heavy;
            else if (*m != "pinned")
                a["mode"].problem("expected \"pinned\" or \"heavy\", got \"" + *m + "\"");
        }
        for (int node : readNodeSelection(a, lattice))
            out[std::size_t(node)] = mode;
    }
}

// --- Material. ---------------------------------------------------------------------------------

namespace {

void applyPreset(const JsonValue& v, LatticeMaterial& m, std::optional<double>& totalMass, const fs::path& baseDir) {
    const auto ref = v.string();
    if (!ref)
        return;
    const fs::path path = baseDir / *ref;
    auto preset = loadMaterialPreset(path);
    if (!preset) {
        v.problem("cannot use preset: " + preset.message());
        return;
    }
    JsonIssues presetIssues(path.string());
    readMaterial(JsonValue(&preset->material, "/material", &presetIssues), m, totalMass, false, baseDir);
    for (const std::string& message : presetIssues.messages())
        v.problem(message);
}

/// A material switched to another model by its file's "model" starts from that model's defaults.
void resetMaterialValues(LatticeMaterial& m, MaterialModel model) {
    m.model = model;
    for (const MaterialChannel& channel : materialChannels())
        if (channel.defaultValue)  // the model's own values; fractions mean the same under both
            (m.*channel.values).assign((m.*channel.values).size(), channel.defaultFor(model));
}

}  // namespace

void readMaterial(const JsonValue& v, LatticeMaterial& m, std::optional<double>& totalMass, bool allowPreset,
                  const fs::path& baseDir) {
    if (!v.expectObject())
        return;
    if (allowPreset)
        v.checkKeys({"preset", "model", "element", "mass", "totalMass", "massDistribution", "stiffness", "damping",
                     "airDamping", "density", "modulus", "viscosity", "dampingRate", "springKindScale", "anisotropy",
                     "heavyAnchorRatio", "stretchLimit", "squashLimit", "volumePreservation", "goalWeight"});
    else
        v.checkKeys({"model", "mass", "totalMass", "stiffness", "damping", "airDamping", "density", "modulus",
                     "viscosity", "dampingRate", "springKindScale", "anisotropy", "heavyAnchorRatio", "stretchLimit",
                     "squashLimit", "volumePreservation", "goalWeight"});
    if (allowPreset)
        applyPreset(v["preset"], m, totalMass, baseDir);
    // Each model has its own keys (materialRanges().name), so a file can never give kilograms where a
    // density is meant.
    const MaterialRanges& springs = materialRanges(MaterialModel::LatticeSprings);
    const MaterialRanges& continuum = materialRanges(MaterialModel::Continuum);
    if (const auto model = v["model"].string()) {
        const MaterialModel wanted = *model == continuum.model ? MaterialModel::Continuum : MaterialModel::LatticeSprings;
        if (*model != continuum.model && *model != springs.model)
            v["model"].problem(std::string("expected \"") + continuum.model + "\" or \"" + springs.model + "\", got \"" +
                               *model + "\"");
        else if (wanted != m.model)
            resetMaterialValues(m, wanted);
    }
    if (const auto element = v["element"].string()) {
        if (*element == bodyElementName(BodyElement::Solid))
            m.element = BodyElement::Solid;
        else if (*element == bodyElementName(BodyElement::Springs))
            m.element = BodyElement::Springs;
        else
            v["element"].problem(std::string("expected \"") + bodyElementName(BodyElement::Springs) + "\" or \"" +
                                 bodyElementName(BodyElement::Solid) + "\", got \"" + *element + "\"");
    }
    const MaterialRanges& range = materialRanges(m.model);
    const MaterialModel otherModel = m.model == MaterialModel::Continuum ? MaterialModel::LatticeSprings : MaterialModel::Continuum;
    for (const MaterialChannel& channel : materialChannels()) {
        const char* mine = channel.rangeFor(m.model).name;
        const char* theirs = channel.rangeFor(otherModel).name;
        if (mine != theirs && v[theirs].exists())
            v[theirs].problem(std::string("a ") + range.model + " material gives \"" + mine + "\", not \"" + theirs +
                              "\" (set \"model\" to change what the values mean)");
    }
    if (v[range.mass.name].exists() && v["totalMass"].exists())
        v["totalMass"].problem(std::string("give either ") + range.mass.name + " (per node) or totalMass, not both");
    if (v[range.mass.name].exists())
        totalMass.reset();
    if (auto t = v["totalMass"].number(1e-9, 1e15, "kg"))
        totalMass = *t;
    // Every channel is one number or a painted map (node damping was one number in every file before version 4, volume
    // preservation before it was painted); an optional channel a material has none of yet is 0 where not given.
    for (const MaterialChannel& channel : materialChannels()) {
        const MaterialRange& r = channel.rangeFor(m.model);
        std::vector<double>& values = channel.optional ? channelValues(m, channel) : m.*channel.values;
        readPerNode(v[r.name], values, r.low, r.high, r.unit);
    }
    if (const JsonValue k = v["springKindScale"]; k.expectObject()) {
        k.checkKeys({"edge", "face", "body"});
        const char* names[3] = {"edge", "face", "body"};
        for (std::size_t i = 0; i < 3; ++i) {
            if (auto x = k[names[i]].number(0.0, 1e3))
                m.kindScale[i] = *x;
        }
    }
    if (auto a = v["anisotropy"].vec3()) {
        if ((a->array() < 1e-6).any() || (a->array() > 1e6).any())
            v["anisotropy"].problem("each anisotropy factor must be in [1e-6, 1e6]");
        else
            m.anisotropy = *a;
    }
    if (auto x = v.field(kHeavyAnchorRatio))
        m.heavyAnchorRatio = *x;
    // Length / rest length of every spring: 0 (or absent) is no limit, otherwise within core's range.
    auto readLimit = [&](const char* key, double low, double high, double& into) {
        if (auto x = v[key].number(0.0, high)) {
            if (*x != 0.0 && *x < low)
                v[key].problem("expected 0 (off) or a limit in [" + detail::formatNumber(low) + ", " +
                               detail::formatNumber(high) + "] times the rest length");
            else
                into = *x;
        }
    };
    readLimit("stretchLimit", kMinStretchLimit, kMaxStretchLimit, m.strainLimits.stretch);
    readLimit("squashLimit", kMinSquashLimit, kMaxSquashLimit, m.strainLimits.squash);
}

/// A "totalMass" spread evenly over the non-void nodes (once voids are known): the same kg per node,
/// or for a Continuum material the same density over the nodes' share of the box.
void spreadTotalMass(const Lattice& lattice, LatticeMaterial& material, const std::optional<double>& totalMass) {
    if (!totalMass)
        return;
    const bool continuum = material.model == MaterialModel::Continuum;
    const std::vector<double> volume = nodeVolumes(lattice);
    double solid = 0.0;
    for (std::size_t n = 0; n < material.isVoid.size(); ++n)
        solid += material.isVoid[n] ? 0.0 : continuum ? volume[n] : 1.0;
    if (solid > 0.0)
        material.mass.assign(material.mass.size(), *totalMass / solid);
}

/// The material, anchors and voids of a lattice as a project object writes them.
void writeMaterial(const Lattice& lattice, const LatticeMaterial& m, json& object) {
    const MaterialRanges& key = materialRanges(m.model);
    object["material"] = {{"model", key.model},
                          {"springKindScale", {{"edge", m.kindScale[0]}, {"face", m.kindScale[1]}, {"body", m.kindScale[2]}}},
                          {"anisotropy", vec(m.anisotropy)},
                          {kHeavyAnchorRatio.name, m.heavyAnchorRatio}};
    // An optional channel only where some node has it: files stay as they were before it existed.
    for (const MaterialChannel& channel : materialChannels()) {
        const std::vector<double>& values = m.*channel.values;
        if (!channel.optional || std::any_of(values.begin(), values.end(), [](double x) { return x != 0.0; }))
            object["material"][channel.rangeFor(m.model).name] = perNode(values);
    }
    if (m.element != BodyElement::Springs)  // springs, the default, unwritten: older files stay as they were
        object["material"]["element"] = bodyElementName(m.element);
    if (m.strainLimits.stretch > 0.0)
        object["material"]["stretchLimit"] = m.strainLimits.stretch;
    if (m.strainLimits.squash > 0.0)
        object["material"]["squashLimit"] = m.strainLimits.squash;
    std::vector<int> pinned, heavy, voids;
    for (int n = 0; n < lattice.nodeCount(); ++n) {
        if (m.anchor[std::size_t(n)] == AnchorMode::Pinned) pinned.push_back(n);
        if (m.anchor[std::size_t(n)] == AnchorMode::Heavy) heavy.push_back(n);
        if (m.isVoid[std::size_t(n)]) voids.push_back(n);
    }
    json anchors = json::array();
    if (!pinned.empty()) anchors.push_back({{"mode", "pinned"}, {"nodes", nodeList(lattice, pinned)}});
    if (!heavy.empty()) anchors.push_back({{"mode", "heavy"}, {"nodes", nodeList(lattice, heavy)}});
    object["anchors"] = anchors;
    if (!voids.empty())
        object["voids"] = {{"nodes", nodeList(lattice, voids)}};
}

// --- Lattice. ----------------------------------------------------------------------------------

std::optional<Lattice> readLattice(const JsonValue& v, const Mesh& mesh) {
    LatticeShape shape;
    BoxFitSettings fit;
    if (v.expectObject()) {
        v.checkKeys({"kind", "nodes", "padding", "oriented", "minThickness", "box"});
        if (auto k = v["kind"].string()) {
            if (*k == "bezier")
                shape.kind = LatticeKind::Bezier;
            else if (*k == "bspline")
                shape.kind = LatticeKind::BSpline;
            else
                v["kind"].problem("expected \"bezier\" or \"bspline\", got \"" + *k + "\"");
        }
        if (auto n = v["nodes"].int3(2, 64))
            shape.nodes = *n;
        if (auto x = v["padding"].number(0.0, 1.0)) fit.padding = *x;
        if (auto x = v["minThickness"].number(1e-6, 1.0)) fit.minThickness = *x;
        if (auto x = v["oriented"].boolean()) fit.oriented = *x;
    }
    if (Status s = shape.validate(); !s) {
        v["nodes"].problem(s.message());
        return std::nullopt;
    }
    OrientedBox box;
    if (const JsonValue b = v["box"]; b.expectObject()) {
        b.checkKeys({"origin", "size", "axes"});
        const auto origin = b["origin"].vec3(true);
        const auto size = b["size"].vec3(true);
        const JsonValue axes = b["axes"];
        if (!origin || !size)
            return std::nullopt;
        box.origin = *origin;
        box.size = *size;
        if (axes.exists()) {
            if (axes.size() != 3) {
                axes.problem("expected three axis vectors [[ux,uy,uz],[vx,vy,vz],[wx,wy,wz]]");
                return std::nullopt;
            }
            for (std::size_t a = 0; a < 3; ++a) {
                auto axis = axes.at(a).vec3(true);
                if (!axis)
                    return std::nullopt;
                box.axes.col(Eigen::Index(a)) = *axis;
            }
        }
        if (Status s = box.validate(); !s) {
            b.problem(s.message());
            return std::nullopt;
        }
    } else {
        auto fitted = fitBox(mesh.positions, fit);
        if (!fitted) {
            v.problem(fitted.message());
            return std::nullopt;
        }
        box = fitted.value();
    }
    auto lattice = Lattice::create(shape, box);
    if (!lattice) {
        v.problem(lattice.message());
        return std::nullopt;
    }
    return lattice.value();
}

json vec(const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }

/// A lattice as written: kind, nodes per axis and its box.
json latticeJson(const LatticeShape& shape, const OrientedBox& box) {
    return {{"kind", shape.kind == LatticeKind::Bezier ? "bezier" : "bspline"},
            {"nodes", {shape.nodes[0], shape.nodes[1], shape.nodes[2]}},
            {"box",
             {{"origin", vec(box.origin)},
              {"size", vec(box.size)},
              {"axes", json::array({vec(box.axes.col(0)), vec(box.axes.col(1)), vec(box.axes.col(2))})}}}};
}

// --- Drivers. ----------------------------------------------------------------------------------

namespace {

/// One driver, validated (problems reported at its pointer).
std::optional<Driver> readDriver(const JsonValue& v) {
    if (!v.expectObject(true))
        return std::nullopt;
    const auto type = v["type"].string(true);
    if (!type)
        return std::nullopt;
    if (*type == "swim") {
        v.checkKeys({"type", "point", "direction", "frequency", "amplitude", "phase", "ramp", "stiffness", "damping", "radius"});
        SwimDriver s;
        if (auto p = v["point"].vec3()) s.point = *p;
        if (auto d = v["direction"].vec3()) s.direction = *d;
        if (auto x = v.field(kSwimFrequency)) s.frequencyHz = *x;
        if (auto x = v.field(kSwimAmplitude)) s.amplitude = *x;
        if (auto x = v.field(kSwimPhase)) s.phase = *x;
        if (auto x = v.field(kSwimRamp)) s.rampSeconds = *x;
        if (auto x = v.field(kDriverStiffness)) s.stiffness = *x;
        if (auto x = v.field(kDriverDamping)) s.damping = *x;
        if (auto x = v.field(kDriverRadius)) s.radius = *x;
        return s;
    }
    if (*type == "drag") {
        v.checkKeys({"type", "point", "keys", "stiffness", "damping", "release", "radius"});
        ScriptedDrag d;
        if (auto p = v["point"].vec3()) d.point = *p;
        const JsonValue keys = v["keys"];
        if (!keys.isArray() || keys.size() == 0)
            keys.problem("expected a non-empty array of {\"time\", \"offset\"} keys");
        for (std::size_t i = 0; i < keys.size(); ++i) {
            const JsonValue k = keys.at(i);
            if (!k.expectObject(true))
                continue;
            k.checkKeys({"time", "offset"});
            const auto t = k["time"].number(-1e9, 1e9, "s", true);
            const auto o = k["offset"].vec3(true);
            if (t && o)
                d.keys.push_back({*t, *o});
        }
        if (auto x = v.field(kDriverStiffness)) d.stiffness = *x;
        if (auto x = v.field(kDriverDamping)) d.damping = *x;
        if (auto x = v.field(kDragRelease)) d.releaseTime = *x;
        if (auto x = v.field(kDriverRadius)) d.radius = *x;
        return d;
    }
    v["type"].problem("expected \"swim\" or \"drag\", got \"" + *type + "\"");
    return std::nullopt;
}

}  // namespace

/// A "drivers" array, each driver validated (problems reported at its pointer).
void readDrivers(const JsonValue& drivers, std::vector<Driver>& out) {
    if (!drivers.exists())
        return;
    if (!drivers.isArray())
        drivers.problem("expected an array of drivers");
    for (std::size_t i = 0; i < drivers.size(); ++i) {
        if (auto d = readDriver(drivers.at(i))) {
            if (Status s = validateDriver(*d); !s)
                drivers.at(i).problem(s.message());
            else
                out.push_back(*d);
        }
    }
}

json driverJson(const Driver& driver) {
    json out;
    if (const auto* d = std::get_if<ScriptedDrag>(&driver)) {
        json keys = json::array();
        for (const PathKey& k : d->keys)
            keys.push_back({{"time", k.time}, {"offset", vec(k.offset)}});
        out = {{"type", "drag"}, {"point", vec(d->point)}, {"keys", keys}, {kDriverStiffness.name, d->stiffness},
               {kDriverDamping.name, d->damping}};
        if (d->releaseTime >= 0.0)
            out[kDragRelease.name] = d->releaseTime;
    } else {
        const auto& s = std::get<SwimDriver>(driver);
        out = {{"type", "swim"},
               {"point", vec(s.point)},
               {"direction", vec(s.direction)},
               {kSwimFrequency.name, s.frequencyHz},
               {kSwimAmplitude.name, s.amplitude},
               {kSwimPhase.name, s.phase},
               {kSwimRamp.name, s.rampSeconds},
               {kDriverStiffness.name, s.stiffness},
               {kDriverDamping.name, s.damping}};
    }
    if (const double radius = driverRadius(driver); radius > 0.0)  // written only where it holds more than the point
        out[kDriverRadius.name] = radius;
    return out;
}

}  // namespace softtouch::io::document

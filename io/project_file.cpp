#include "io/project_file.h"
#include "io/animation_import.h"

#include "core/mesh_surface.h"
#include "core/mesh_volume.h"
#include "core/ranges.h"
#include "core/integrator.h"
#include "core/simulator.h"

#include "io/atomic_file.h"
#include "io/mesh_import.h"
#include "io/trajectory_file.h"
#include "io/vertex_cache_internal.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace softtouch::io {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kProjectFormat = "softtouch-project";
constexpr const char* kPresetFormat = "softtouch-preset";
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

/// Applies a "material" object onto `m`. `totalMass` is returned for spreading once voids are known.
void readMaterial(const JsonValue& v, LatticeMaterial& m, std::optional<double>& totalMass, bool allowPreset,
                  const fs::path& baseDir);

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
    const DefaultMaterialValues& d = defaultMaterialValues(model);
    m.model = model;
    m.mass.assign(m.mass.size(), d.mass);
    m.stiffness.assign(m.stiffness.size(), d.stiffness);
    m.damping.assign(m.damping.size(), d.damping);
    m.nodeDamping.assign(m.nodeDamping.size(), d.nodeDamping);
}

void readMaterial(const JsonValue& v, LatticeMaterial& m, std::optional<double>& totalMass, bool allowPreset,
                  const fs::path& baseDir) {
    if (!v.expectObject())
        return;
    if (allowPreset)
        v.checkKeys({"preset", "model", "mass", "totalMass", "massDistribution", "stiffness", "damping", "airDamping",
                     "density", "modulus", "viscosity", "dampingRate", "springKindScale", "anisotropy", "heavyAnchorRatio",
                     "stretchLimit", "squashLimit", "volumePreservation", "goalWeight"});
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
    const MaterialRanges& range = materialRanges(m.model);
    const MaterialRanges& other = m.model == MaterialModel::Continuum ? springs : continuum;
    for (auto [mine, theirs] : {std::pair{range.mass.name, other.mass.name},
                                {range.stiffness.name, other.stiffness.name},
                                {range.damping.name, other.damping.name},
                                {range.nodeDamping.name, other.nodeDamping.name}}) {
        if (v[theirs].exists())
            v[theirs].problem(std::string("a ") + range.model + " material gives \"" + mine + "\", not \"" + theirs +
                              "\" (set \"model\" to change what the values mean)");
    }
    auto readField = [&](const MaterialRange& r, std::vector<double>& out) {
        readPerNode(v[r.name], out, r.low, r.high, r.unit);
    };
    if (v[range.mass.name].exists() && v["totalMass"].exists())
        v["totalMass"].problem(std::string("give either ") + range.mass.name + " (per node) or totalMass, not both");
    readField(range.mass, m.mass);
    if (v[range.mass.name].exists())
        totalMass.reset();
    if (auto t = v["totalMass"].number(1e-9, 1e15, "kg"))
        totalMass = *t;
    readField(range.stiffness, m.stiffness);
    readField(range.damping, m.damping);
    readField(range.nodeDamping, m.nodeDamping);  // one number (every file before version 4) or a painted map
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
    if (auto x = v["heavyAnchorRatio"].number(1.0, 1e9))
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
    // Fractions painted per node, one number or a map like the others (0 where a material has none yet):
    // how closely each node follows a base animation (core/base_motion.h), and volume preservation (one
    // number in every file before it was painted; all 0 is off).
    for (auto [fraction, values] : {std::pair{&kGoalWeightRange, &m.goalWeight},
                                    std::pair{&kVolumePreservationRange, &m.volumePreservation}}) {
        values->resize(m.mass.size(), 0.0);
        readField(*fraction, *values);
    }
}

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

std::optional<Driver> readDriver(const JsonValue& v) {
    if (!v.expectObject(true))
        return std::nullopt;
    const auto type = v["type"].string(true);
    if (!type)
        return std::nullopt;
    if (*type == "swim") {
        v.checkKeys({"type", "point", "direction", "frequency", "amplitude", "phase", "ramp", "stiffness", "damping"});
        SwimDriver s;
        if (auto p = v["point"].vec3()) s.point = *p;
        if (auto d = v["direction"].vec3()) s.direction = *d;
        if (auto x = v["frequency"].number(1e-9, 100.0, "Hz")) s.frequencyHz = *x;
        if (auto x = v["amplitude"].number(0.0, 1e3, "m")) s.amplitude = *x;
        if (auto x = v["phase"].number(-1e6, 1e6, "rad")) s.phase = *x;
        if (auto x = v["ramp"].number(0.0, 1e6, "s")) s.rampSeconds = *x;
        if (auto x = v["stiffness"].number(1e-12, 1e9, "N/m")) s.stiffness = *x;
        if (auto x = v["damping"].number(0.0, 1e6, "N·s/m")) s.damping = *x;
        return s;
    }
    if (*type == "drag") {
        v.checkKeys({"type", "point", "keys", "stiffness", "damping", "release"});
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
        if (auto x = v["stiffness"].number(1e-12, 1e9, "N/m")) d.stiffness = *x;
        if (auto x = v["damping"].number(0.0, 1e6, "N·s/m")) d.damping = *x;
        if (auto x = v["release"].number(0.0, 1e9, "s")) d.releaseTime = *x;
        return d;
    }
    v["type"].problem("expected \"swim\" or \"drag\", got \"" + *type + "\"");
    return std::nullopt;
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

/// An object's "totalMass" spread by its "massDistribution": "box" (the default, spreadTotalMass) or
/// "mesh", by each node's share of the mesh's volume (core/mesh_volume.h), written as kg per node or, for
/// a Continuum material, as the density map that gives those masses.
void spreadObjectMass(const JsonValue& v, const Lattice& lattice, const Mesh& mesh, LatticeMaterial& material,
                      const std::optional<double>& totalMass) {
    const JsonValue distribution = v["massDistribution"];
    const std::optional<std::string> by = distribution.string();
    if (by && *by != "box" && *by != "mesh") {
        distribution.problem("expected \"box\" or \"mesh\", got \"" + *by + "\"");
        return;
    }
    if (by && !totalMass) {
        distribution.problem("spreads a \"totalMass\", and this material gives none");
        return;
    }
    if (by != "mesh") {
        spreadTotalMass(lattice, material, totalMass);
        return;
    }
    auto shares = meshVolumeShares(lattice, mesh);
    if (!shares) {
        distribution.problem(shares.message());
        return;
    }
    const bool continuum = material.model == MaterialModel::Continuum;
    const std::vector<double> volume = nodeVolumes(lattice);
    const std::vector<double> kg = meshMassPerNode(shares.value(), material.isVoid, *totalMass);
    for (std::size_t n = 0; n < material.mass.size(); ++n)
        if (!material.isVoid[n])
            material.mass[n] = continuum ? kg[n] / volume[n] : kg[n];  // a density gives that mass
}

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

/// An object's "animation": which take of its mesh file, which part of it, how it is sampled, and how the
/// body follows it (its "goal" springs).
std::optional<AnimationRequest> readAnimationRequest(const JsonValue& a, FollowSettings& follow) {
    if (!a.expectObject())
        return std::nullopt;
    a.checkKeys({"take", "start", "end", "loop", "sampleRate", "goal"});
    AnimationRequest request;
    request.take = a["take"].string().value_or("");
    if (auto x = a["start"].number(0.0, ranges::kMaxClipStart, "s"))
        request.start = *x;
    if (auto x = a["end"].number(0.0, ranges::kMaxClipStart, "s")) {
        if (*x <= request.start)
            a["end"].problem("expected an end after \"start\" (" + detail::formatNumber(request.start) + " s)");
        request.end = *x;
    }
    request.loop = a["loop"].boolean().value_or(true);
    if (auto x = a["sampleRate"].number(1.0, 1000.0, "samples/s"))
        request.rate = *x;
    if (const JsonValue g = a["goal"]; g.expectObject()) {
        g.checkKeys({"frequency", "dampingRatio"});
        if (auto x = g["frequency"].number(1e-3, 1000.0, "Hz"))
            follow.frequency = *x;
        if (auto x = g["dampingRatio"].number(0.0, 100.0))
            follow.dampingRatio = *x;
    }
    return request;
}

/// An object's "restShape": the edits of its rest shape (core/rest_shape.h), each the lattice it was made on
/// (with its box) and the posed nodes, replayed in order over the mesh as read and placed. False, with the
/// problem recorded, when one is malformed or cannot apply.
bool readRestShape(const JsonValue& v, SceneObject& object, std::vector<RestShapeEdit>& edits) {
    if (!v.exists())
        return true;
    if (object.baseAnimation) {
        v.problem("an object on its own animation takes its rest shape from the animation; remove \"restShape\"");
        return false;
    }
    if (!v.isArray()) {
        v.problem("expected an array of edits [{\"lattice\": {\"kind\", \"nodes\", \"box\"}, \"nodes\": [[x, y, z], ...]}]");
        return false;
    }
    for (std::size_t e = 0; e < v.size(); ++e) {
        const JsonValue item = v.at(e);
        if (!item.expectObject(true))
            return false;
        item.checkKeys({"lattice", "nodes"});
        if (!item["lattice"]["box"].exists()) {
            item["lattice"].problem("expected the \"box\" the edit was made on");
            return false;
        }
        const auto lattice = readLattice(item["lattice"], object.mesh);
        if (!lattice)
            return false;
        RestShapeEdit edit;
        edit.shape = lattice->shape();
        edit.box = lattice->box();
        const JsonValue nodes = item["nodes"];
        if (nodes.size() != std::size_t(lattice->nodeCount())) {
            nodes.problem("expected " + std::to_string(lattice->nodeCount()) + " node positions [x, y, z], one per node of the lattice");
            return false;
        }
        for (std::size_t n = 0; n < nodes.size(); ++n) {
            const auto x = nodes.at(n).vec3(true);
            if (!x)
                return false;
            edit.nodes.push_back(*x);
        }
        if (Status s = applyRestShapeEdit(object.mesh, edit); !s) {
            item.problem(s.message());
            return false;
        }
        edits.push_back(std::move(edit));
    }
    return true;
}

void readObject(const JsonValue& v, const fs::path& baseDir, Project& project, JsonIssues& issues) {
    if (!v.expectObject(true))
        return;
    v.checkKeys({"name", "mesh", "animation", "position", "restShape", "lattice", "material", "anchors", "voids", "drivers"});
    SceneObject object;
    object.name = v["name"].string().value_or("object " + std::to_string(project.scene.objects.size()));
    const auto meshRef = v["mesh"].string(true);
    if (!meshRef)
        return;
    if (const JsonValue a = v["animation"]; a.exists()) {
        // The mesh's own animation: the mesh is its first sample (io/animation_import.h).
        auto request = readAnimationRequest(a, object.follow);
        if (!request)
            return;
        auto animated = importAnimatedMesh(baseDir / *meshRef, *request);
        if (!animated) {
            v["mesh"].problem(animated.message());
            return;
        }
        object.mesh = std::move(animated->mesh);
        object.baseAnimation = std::make_shared<BaseAnimation>(std::move(animated->animation));
        project.importNotes.push_back(object.name + ": take \"" + object.baseAnimation->take + "\" from " +
                                      detail::formatNumber(object.baseAnimation->start) + " s for " +
                                      detail::formatNumber(object.baseAnimation->duration()) + " s at " +
                                      detail::formatNumber(object.baseAnimation->rate) + " samples/s" +
                                      (object.baseAnimation->loop ? ", looping" : "") + "; " +
                                      std::to_string(object.mesh.positions.size()) + " vertices in " + animated->unit);
    } else {
        auto mesh = importMesh(baseDir / *meshRef);
        if (!mesh) {
            v["mesh"].problem(mesh.message());
            return;
        }
        object.mesh = std::move(mesh.value());
    }
    // Where the mesh goes in the scene: its file's coordinates moved by this (a lattice "box", like
    // everything else in the file, is in scene coordinates).
    Vec3 offset = Vec3::Zero();
    if (auto x = v["position"].vec3()) {
        if (x->norm() > ranges::kMaxMeshSize)
            v["position"].problem("expected at most 1e5 m from the origin");
        else
            offset = *x;
    }
    for (Vec3f& p : object.mesh.positions)
        p += offset.cast<float>();
    if (object.baseAnimation && !offset.isZero()) {
        auto moved = std::make_shared<BaseAnimation>(*object.baseAnimation);
        for (auto& sample : moved->samples)
            for (Vec3f& p : sample)
                p += offset.cast<float>();
        object.baseAnimation = std::move(moved);
    }
    std::vector<RestShapeEdit> restShape;
    if (!readRestShape(v["restShape"], object, restShape))
        return;
    auto lattice = readLattice(v["lattice"], object.mesh);
    if (!lattice)
        return;
    object.lattice = *lattice;
    object.material = uniformMaterial(object.lattice, 0.02, 80.0, 0.9);
    std::optional<double> totalMass;
    readMaterial(v["material"], object.material, totalMass, true, baseDir);

    readAnchors(v["anchors"], object.lattice, object.material.anchor);
    if (const JsonValue voids = v["voids"]; voids.expectObject()) {
        voids.checkKeys({"auto", "nodes", "region"});
        if (voids["auto"].boolean().value_or(false))
            object.material.isVoid = findEmptyNodes(object.lattice, object.mesh);
        if (voids["nodes"].exists() || voids["region"].exists()) {
            for (int node : readNodeSelection(voids, object.lattice))
                object.material.isVoid[std::size_t(node)] = 1;
        }
    }
    spreadObjectMass(v["material"], object.lattice, object.mesh, object.material, totalMass);
    readDrivers(v["drivers"], object.drivers);
    // The solver's limits, then the body itself, which validates combinations (every node void, …).
    if (issues.empty()) {
        if (Status s = checkObjectLimits(object, project.scene.world); !s) {
            v.problem(s.message());
        } else if (auto body = buildLatticeBody(object.lattice, object.material); !body) {
            v.problem(body.message());
        } else {
            // A step the explicit schemes would refuse at rest fails every bake: say so here, not there.
            const SimulationSettings& settings = project.scene.world.simulation;
            ExternalForces rest;
            rest.gravity = project.scene.world.gravity;
            const Simulator simulator(body.value(), settings);
            if (simulator.substepsFor(rest) > settings.maxSubsteps) {
                std::ostringstream msg;
                msg << "at dt = " << settings.dt << " s this body needs more than " << settings.maxSubsteps << " substeps of "
                    << integratorName(settings.integrator) << " a step (stable step " << simulator.stableStep(rest)
                    << " s): lower dt, soften the stiffest spring, raise the lightest mass, or use implicit-euler";
                v.problem(msg.str());
            }
        }
    }
    project.meshReferences.push_back(*meshRef);
    project.meshOffsets.resize(project.meshReferences.size() - 1, Vec3::Zero());
    project.meshOffsets.push_back(offset);
    project.restShapeEdits.resize(project.meshReferences.size() - 1);
    project.restShapeEdits.push_back(std::move(restShape));
    project.scene.objects.push_back(std::move(object));
}

void readWorld(const JsonValue& root, const fs::path& baseDir, WorldSettings& w) {
    if (const JsonValue world = root["world"]; world.expectObject()) {
        world.checkKeys({"gravity", "planes", "colliders", "bodyCollisions"});
        if (auto g = world["gravity"].vec3()) {
            if (g->norm() > ranges::kMaxGravity)
                world["gravity"].problem("expected at most 1e4 m/s² (a thousand g), got a magnitude of " + std::to_string(g->norm()));
            else
                w.gravity = *g;
        }
        const JsonValue planes = world["planes"];
        if (planes.exists() && !planes.isArray())
            planes.problem("expected an array of planes");
        for (std::size_t i = 0; i < planes.size(); ++i) {
            const JsonValue p = planes.at(i);
            if (!p.expectObject(true))
                continue;
            p.checkKeys({"point", "normal", "restitution", "friction"});
            CollisionPlane plane;
            if (auto x = p["point"].vec3()) plane.point = *x;
            if (auto n = p["normal"].vec3()) {
                if (n->norm() < 1e-9)
                    p["normal"].problem("the normal must not be zero");
                else
                    plane.normal = n->normalized();
            }
            if (auto x = p["restitution"].number(0.0, 1.0)) plane.restitution = *x;
            if (auto x = p["friction"].number(0.0, 10.0)) plane.friction = *x;
            w.planes.push_back(plane);
        }
        // Objects against each other (core/body_contacts.h): off unless the file turns them on.
        if (const JsonValue bodies = world["bodyCollisions"]; bodies.exists() && bodies.expectObject()) {
            bodies.checkKeys({"enabled", "restitution", "friction"});
            if (auto x = bodies["enabled"].boolean()) w.bodyCollisions.enabled = *x;
            if (auto x = bodies["restitution"].number(0.0, 1.0)) w.bodyCollisions.restitution = *x;
            if (auto x = bodies["friction"].number(0.0, 10.0)) w.bodyCollisions.friction = *x;
        }
        // Spheres, capsules, boxes and meshes (core/colliders.h); each shape has its own size keys.
        const JsonValue colliders = world["colliders"];
        if (colliders.exists() && !colliders.isArray())
            colliders.problem("expected an array of colliders");
        for (std::size_t i = 0; i < colliders.size(); ++i) {
            const JsonValue v = colliders.at(i);
            if (!v.expectObject(true))
                continue;
            Collider c;
            const auto shape = v["shape"].string();
            if (!shape || (*shape != "sphere" && *shape != "capsule" && *shape != "box" && *shape != "mesh")) {
                v["shape"].problem("expected \"sphere\", \"capsule\", \"box\" or \"mesh\"");
                continue;
            }
            c.shape = *shape == "sphere"    ? ColliderShape::Sphere
                      : *shape == "capsule" ? ColliderShape::Capsule
                      : *shape == "box"     ? ColliderShape::Box
                                            : ColliderShape::Mesh;
            if (c.shape == ColliderShape::Mesh) {
                v.checkKeys({"shape", "mesh", "centre", "axes", "scale", "restitution", "friction"});
                if (const auto ref = v["mesh"].string(true)) {
                    auto mesh = importMesh(baseDir / *ref);
                    auto surface = mesh ? MeshSurface::create(std::move(mesh.value()), *ref)
                                        : Result<std::shared_ptr<const MeshSurface>>(Status::error(mesh.message()));
                    if (surface)
                        c.surface = surface.value();
                    else
                        v["mesh"].problem(surface.message());
                }
                if (auto x = v["scale"].number(1e-6, 1e6)) c.scale = *x;
            } else if (c.shape == ColliderShape::Sphere)
                v.checkKeys({"shape", "centre", "radius", "restitution", "friction"});
            else if (c.shape == ColliderShape::Capsule)
                v.checkKeys({"shape", "centre", "radius", "axis", "halfLength", "restitution", "friction"});
            else
                v.checkKeys({"shape", "centre", "halfExtents", "axes", "restitution", "friction"});
            if (auto x = v["centre"].vec3(true)) c.centre = *x;
            if (c.shape == ColliderShape::Sphere || c.shape == ColliderShape::Capsule)
                if (auto x = v["radius"].number(1e-6, 1e6, "m", true)) c.radius = *x;
            if (c.shape == ColliderShape::Capsule) {
                if (auto x = v["halfLength"].number(0.0, 1e6, "m", true)) c.halfLength = *x;
                if (auto a = v["axis"].vec3(true)) {
                    if (a->norm() < 1e-9)
                        v["axis"].problem("the axis must not be zero");
                    else
                        c.axis = a->normalized();
                }
            }
            if (c.shape == ColliderShape::Box || c.shape == ColliderShape::Mesh) {
                if (c.shape == ColliderShape::Box)
                    if (auto h = v["halfExtents"].vec3(true)) {
                        if ((h->array() <= 0.0).any() || (h->array() > 1e6).any())
                            v["halfExtents"].problem("each half extent must be in (0, 1e6] m");
                        else
                            c.halfExtents = *h;
                    }
                const JsonValue axes = v["axes"];
                if (axes.exists()) {
                    if (!axes.isArray() || axes.size() != 3) {
                        axes.problem("expected three axis vectors [[x], [y], [z]]");
                    } else {
                        for (std::size_t k = 0; k < 3; ++k)
                            if (auto a = axes.at(k).vec3(true))
                                c.axes.col(Eigen::Index(k)) = *a;
                        if ((c.axes.transpose() * c.axes - Mat3::Identity()).cwiseAbs().maxCoeff() > 1e-6)
                            axes.problem("the axes must be unit and at right angles");
                    }
                }
            }
            if (auto x = v["restitution"].number(0.0, 1.0)) c.restitution = *x;
            if (auto x = v["friction"].number(0.0, 10.0)) c.friction = *x;
            if (c.shape == ColliderShape::Mesh && !c.surface)
                continue;  // its mesh's problem is reported
            w.colliders.push_back(c);
        }
    }
    if (const JsonValue sim = root["simulation"]; sim.expectObject()) {
        sim.checkKeys({"integrator", "dt", "xpbdSubsteps", "sleep"});
        if (auto name = sim["integrator"].string()) {
            if (auto kind = parseIntegratorKind(*name))
                w.simulation.integrator = *kind;
            else
                sim["integrator"].problem("expected \"symplectic-euler\", \"verlet\", \"implicit-euler\" or \"xpbd\", got \"" +
                                          *name + "\"");
        }
        if (auto x = sim["dt"].number(ranges::kMinDt, ranges::kMaxDt, "s")) w.simulation.dt = *x;
        if (auto x = sim["xpbdSubsteps"].integer(1, 10000)) w.simulation.xpbdSubsteps = *x;
        if (auto x = sim["sleep"].boolean()) w.simulation.sleep = *x;
    }
    if (const JsonValue clip = root["clip"]; clip.expectObject()) {
        clip.checkKeys({"frames", "fps"});
        if (auto x = clip["frames"].integer(1, ranges::kMaxFrames)) w.frames = *x;
        if (auto x = clip["fps"].number(ranges::kMinFps, ranges::kMaxFps, "frames per second")) w.fps = *x;
    }
    // What core checks beyond each field (a safety net: a rule added there is enforced here too).
    WorldSettings checked = w;
    if (Status s = checked.validate(); !s)
        root.problem(s.message());
}

// --- Version 2: the clip library. -------------------------------------------------------------

std::optional<DragSpring> readDrag(const JsonValue& v, std::size_t nodes) {
    if (!v.expectObject(true))
        return std::nullopt;
    v.checkKeys({"support", "target", "targetVelocity", "stiffness", "damping"});
    DragSpring d;
    const JsonValue support = v["support"];
    if (!support.isArray() || support.size() == 0) {
        support.problem("expected a non-empty array of [node, weight] pairs");
        return std::nullopt;
    }
    for (std::size_t i = 0; i < support.size(); ++i) {
        const JsonValue pair = support.at(i);
        if (pair.size() != 2) {
            pair.problem("expected [node, weight]");
            return std::nullopt;
        }
        const auto node = pair.at(0).integer(0, int(nodes) - 1, true);
        const auto weight = pair.at(1).number(-1e3, 1e3, "", true);
        if (!node || !weight)
            return std::nullopt;
        d.support.push_back(NodeWeight{std::uint32_t(*node), *weight});
    }
    const auto target = v["target"].vec3(true);
    if (!target)
        return std::nullopt;
    d.target = *target;
    if (auto x = v["targetVelocity"].vec3()) d.targetVelocity = *x;
    if (auto x = v["stiffness"].number(0.0, 1e9, "N/m")) d.stiffness = *x;
    if (auto x = v["damping"].number(0.0, 1e6, "N·s/m")) d.damping = *x;
    return d;
}

std::optional<std::vector<DragSpring>> readDrags(const JsonValue& v, std::size_t nodes) {
    if (!v.isArray()) {
        v.problem("expected an array of drag springs");
        return std::nullopt;
    }
    std::vector<DragSpring> drags;
    for (std::size_t i = 0; i < v.size(); ++i) {
        auto d = readDrag(v.at(i), nodes);
        if (!d)
            return std::nullopt;
        drags.push_back(std::move(*d));
    }
    return drags;
}

/// Flat [x,y,z, x,y,z, …] of `count` points.
bool readPoints(const JsonValue& v, std::size_t count, std::vector<Vec3>& out) {
    if (!v.isArray() || v.size() != 3 * count) {
        v.problem("expected " + std::to_string(3 * count) + " numbers (x, y, z of each of " + std::to_string(count) +
                  " lattice nodes)");
        return false;
    }
    out.assign(count, Vec3::Zero());
    for (std::size_t i = 0; i < 3 * count; ++i) {
        const auto x = v.at(i).number(-1e12, 1e12, "", true);
        if (!x)
            return false;
        out[i / 3][Eigen::Index(i % 3)] = *x;
    }
    return true;
}

std::optional<NamedSession> readSession(const JsonValue& v, const Scene& scene) {
    if (!v.expectObject(true))
        return std::nullopt;
    v.checkKeys({"name", "dt", "start", "end", "startDrags", "events"});
    NamedSession named;
    named.name = v["name"].string(true).value_or("");
    Session& s = named.session;
    const auto dt = v["dt"].number(ranges::kMinDt, ranges::kMaxDt, "s", true);
    if (!dt)
        return std::nullopt;
    s.dt = *dt;
    const JsonValue start = v["start"];
    if (!start.expectObject(true))
        return std::nullopt;
    start.checkKeys({"step", "bodies"});
    const auto step = start["step"].integer(0, 2000000000, true);
    const JsonValue bodies = start["bodies"];
    if (!step)
        return std::nullopt;
    s.start.step = *step;
    if (bodies.size() != scene.objects.size()) {
        bodies.problem("expected one body state per object (" + std::to_string(scene.objects.size()) + ")");
        return std::nullopt;
    }
    std::vector<std::size_t> nodes;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        const JsonValue b = bodies.at(i);
        if (!b.expectObject(true))
            return std::nullopt;
        b.checkKeys({"position", "velocity"});
        nodes.push_back(std::size_t(scene.objects[i].lattice.nodeCount()));
        BodyState state;
        if (!readPoints(b["position"], nodes.back(), state.position) ||
            !readPoints(b["velocity"], nodes.back(), state.velocity))
            return std::nullopt;
        s.start.bodies.push_back(std::move(state));
    }
    const auto end = v["end"].integer(0, 2000000000, true);
    if (!end)
        return std::nullopt;
    s.endStep = *end;
    if (const JsonValue drags = v["startDrags"]; drags.exists()) {
        if (drags.size() != nodes.size()) {
            drags.problem("expected one list of drags per object (" + std::to_string(nodes.size()) + ")");
            return std::nullopt;
        }
        for (std::size_t i = 0; i < nodes.size(); ++i) {
            auto d = readDrags(drags.at(i), nodes[i]);
            if (!d)
                return std::nullopt;
            s.startDrags.push_back(std::move(*d));
        }
    }
    const JsonValue events = v["events"];
    if (events.exists() && !events.isArray())
        events.problem("expected an array of events");
    for (std::size_t e = 0; e < events.size(); ++e) {
        const JsonValue ev = events.at(e);
        if (!ev.expectObject(true))
            return std::nullopt;
        ev.checkKeys({"step", "object", "drags"});
        const auto at = ev["step"].integer(0, 2000000000, true);
        const auto object = ev["object"].integer(0, int(nodes.size()) - 1, true);
        if (!at || !object)
            return std::nullopt;
        auto d = readDrags(ev["drags"], nodes[std::size_t(*object)]);
        if (!d)
            return std::nullopt;
        s.events.push_back(DragEvent{*at, std::uint32_t(*object), std::move(*d)});
    }
    // Order and ranges: the same checks a replay makes.
    long long last = s.start.step;
    for (std::size_t e = 0; e < s.events.size(); ++e) {
        if (s.events[e].step < last || s.events[e].step > s.endStep) {
            events.at(e)["step"].problem("event steps must not decrease and must lie in [start.step, end]");
            return std::nullopt;
        }
        last = s.events[e].step;
    }
    if (s.endStep < s.start.step)
        v["end"].problem("the session ends before it starts (start.step " + std::to_string(s.start.step) + ")");
    return named;
}

std::optional<NamedKeyframes> readKeyframes(const JsonValue& v, const Scene& scene) {
    if (!v.expectObject(true))
        return std::nullopt;
    v.checkKeys({"name", "objects"});
    NamedKeyframes named;
    named.name = v["name"].string(true).value_or("");
    const JsonValue objects = v["objects"];
    if (objects.size() != scene.objects.size()) {
        objects.problem("expected one entry per object (" + std::to_string(scene.objects.size()) + ")");
        return std::nullopt;
    }
    for (std::size_t i = 0; i < objects.size(); ++i) {
        const JsonValue o = objects.at(i);
        if (!o.expectObject(true))
            return std::nullopt;
        o.checkKeys({"keys"});
        const int nodes = scene.objects[i].lattice.nodeCount();
        KeyframeAnimation anim{std::size_t(nodes)};
        const JsonValue keys = o["keys"];
        if (keys.exists() && !keys.isArray())
            keys.problem("expected an array of keys");
        for (std::size_t k = 0; k < keys.size(); ++k) {
            const JsonValue key = keys.at(k);
            if (!key.expectObject(true))
                return std::nullopt;
            key.checkKeys({"time", "nodes", "displacement"});
            LatticeKey lk;
            const auto t = key["time"].number(-1e6, 1e6, "s", true);
            if (!t)
                return std::nullopt;
            lk.seconds = *t;
            const JsonValue ns = key["nodes"], ds = key["displacement"];
            if (!ns.isArray() || !ds.isArray() || ns.size() != ds.size()) {
                key.problem("expected \"nodes\" (node indices, i fastest) and \"displacement\" ([x,y,z] per node) of equal length");
                return std::nullopt;
            }
            for (std::size_t n = 0; n < ns.size(); ++n) {
                const auto node = ns.at(n).integer(0, nodes - 1, true);
                const auto d = ds.at(n).vec3(true);
                if (!node || !d)
                    return std::nullopt;
                lk.nodes.push_back(std::uint32_t(*node));
                lk.displacement.push_back(*d);
            }
            if (anim.keyAt(lk.seconds) >= 0) {
                key["time"].problem("two keys at the same time");
                return std::nullopt;
            }
            if (auto r = anim.insertKey(std::move(lk)); !r) {
                key.problem(r.message());
                return std::nullopt;
            }
        }
        named.objects.push_back(std::move(anim));
    }
    return named;
}

std::optional<Clip> readClip(const JsonValue& v) {
    if (!v.expectObject(true))
        return std::nullopt;
    v.checkKeys({"name", "source", "of", "start", "frames", "fps", "loop", "blend", "goals"});
    Clip c;
    c.name = v["name"].string(true).value_or("");
    if (auto src = v["source"].string()) {
        if (auto parsed = parseClipSource(*src))
            c.source = *parsed;
        else
            v["source"].problem("expected \"drivers\", \"session\" or \"keyframes\", got \"" + *src + "\"");
    }
    if (auto x = v["of"].string()) c.sourceName = *x;
    if (auto x = v["start"].number(0.0, ranges::kMaxClipStart, "s")) c.startSeconds = *x;
    if (auto x = v["frames"].integer(1, ranges::kMaxFrames)) c.frames = *x;
    if (auto x = v["fps"].number(ranges::kMinFps, ranges::kMaxFps, "frames per second")) c.fps = *x;
    if (auto x = v["loop"].boolean()) c.loop = *x;
    if (auto x = v["blend"].integer(0, 1000000)) c.blendFrames = *x;
    if (const JsonValue g = v["goals"]; g.expectObject()) {
        g.checkKeys({"stiffness", "damping", "weight"});
        GoalSettings goals;
        if (auto x = g["stiffness"].number(0.0, 1e9, "N/m")) goals.stiffness = *x;
        if (auto x = g["damping"].number(0.0, 1e6, "N·s/m")) goals.damping = *x;
        if (auto x = g["weight"].number(0.0, 1e3)) goals.weight = *x;
        c.goals = goals;
    }
    if (Status s = c.validate(); !s) {
        v.problem(s.message());
        return std::nullopt;
    }
    return c;
}

void readClipLibrary(const JsonValue& root, int version, Project& project) {
    if (version < 2) {
        for (const char* key : {"clips", "sessions", "keyframes"}) {
            if (root[key].exists())
                root[key].problem("clips, sessions and keyframes need project version 2");
        }
        return;
    }
    ClipLibrary& lib = project.clips;
    if (const JsonValue sessions = root["sessions"]; sessions.exists()) {
        if (!sessions.isArray())
            sessions.problem("expected an array of sessions");
        for (std::size_t i = 0; i < sessions.size(); ++i) {
            if (auto s = readSession(sessions.at(i), project.scene))
                lib.sessions.push_back(std::move(*s));
        }
    }
    if (const JsonValue keyframes = root["keyframes"]; keyframes.exists()) {
        if (!keyframes.isArray())
            keyframes.problem("expected an array of keyframe sets");
        for (std::size_t i = 0; i < keyframes.size(); ++i) {
            if (auto k = readKeyframes(keyframes.at(i), project.scene))
                lib.keyframes.push_back(std::move(*k));
        }
    }
    if (const JsonValue clips = root["clips"]; clips.expectObject()) {
        clips.checkKeys({"default", "library"});
        const JsonValue list = clips["library"];
        if (list.exists() && !list.isArray())
            list.problem("expected an array of clips");
        for (std::size_t i = 0; i < list.size(); ++i) {
            if (auto c = readClip(list.at(i)))
                lib.clips.push_back(std::move(*c));
        }
        if (auto d = clips["default"].string()) lib.defaultClip = *d;
    }
    if (Status s = lib.validate(project.scene); !s)
        root["clips"].problem(s.message());
}

/// Reads a whole project, collecting every problem.
std::optional<Project> readProject(const fs::path& path, JsonIssues& issues) {
    const auto doc = parseJsonFile(path.string(), issues);
    if (!doc)
        return std::nullopt;
    const JsonValue root(&*doc, "", &issues);
    if (!readHeader(root, kProjectFormat, kProjectVersion))
        return std::nullopt;
    root.checkKeys({"format", "version", "objects", "world", "simulation", "clip", "clips", "sessions", "keyframes"});
    Project project;
    project.path = path;
    const fs::path baseDir = path.parent_path();
    const JsonValue objects = root["objects"];
    if (!objects.isArray() || objects.size() == 0)
        objects.problem("expected a non-empty array of objects");
    // The world first: an object's body is built (and checked) only where the solver can run it.
    readWorld(root, baseDir, project.scene.world);
    for (std::size_t i = 0; i < objects.size(); ++i)
        readObject(objects.at(i), baseDir, project, issues);
    // The library refers to the objects' lattices: read it only onto a valid scene.
    if (!issues.empty())
        return std::nullopt;
    readClipLibrary(root, root["version"].integer(1, 1000000).value_or(1), project);
    if (!issues.empty())
        return std::nullopt;
    return project;
}

}  // namespace

Result<MaterialPreset> loadMaterialPreset(const fs::path& path) {
    JsonIssues issues(path.string());
    const auto doc = parseJsonFile(path.string(), issues);
    if (doc) {
        const JsonValue root(&*doc, "", &issues);
        if (readHeader(root, kPresetFormat, kPresetVersion)) {
            root.checkKeys({"format", "version", "kind", "name", "description", "material"});
            const auto kind = root["kind"].string(true);
            if (kind && *kind != "material")
                root["kind"].problem("expected \"material\", got \"" + *kind + "\" (a setup preset is loaded as a setup)");
            MaterialPreset preset;
            preset.name = root["name"].string(true).value_or("");
            preset.description = root["description"].string().value_or("");
            if (root["material"].expectObject(true)) {
                preset.material = (*doc)["material"];
                // Validate against a one-node lattice: per-node arrays make no sense in a preset.
                const Lattice probe = Lattice::create({LatticeKind::Bezier, {2, 2, 2}}, OrientedBox{}).value();
                LatticeMaterial m = uniformMaterial(probe, 1.0, 1.0, 0.0);
                std::optional<double> total;
                const JsonValue material = root["material"];
                for (const char* field :
                     {"mass", "stiffness", "damping", "airDamping", "density", "modulus", "viscosity", "dampingRate",
                      kVolumePreservationRange.name}) {
                    if (material[field].isArray())
                        material[field].problem("a preset holds one value for every node, not an array");
                }
                readMaterial(material, m, total, false, path.parent_path());
            }
            if (issues.empty())
                return preset;
        }
    }
    return Status::error(issues.summary());
}

Result<Project> loadProject(const fs::path& path) {
    JsonIssues issues(path.string());
    auto project = readProject(path, issues);
    if (!project)
        return Status::error(issues.summary());
    return std::move(*project);
}

std::vector<std::string> validateFile(const fs::path& path) {
    JsonIssues issues(path.string());
    const auto doc = parseJsonFile(path.string(), issues);
    if (!doc)
        return issues.messages();
    const std::string format = doc->is_object() && doc->contains("format") && (*doc)["format"].is_string()
                                   ? (*doc)["format"].get<std::string>()
                                   : std::string();
    if (format == "softtouch-trajectory") {  // a device recording, or a script for the scripted device
        auto trajectory = loadTrajectory(path);
        if (trajectory)
            return {};
        JsonIssues all(path.string());
        all.addGeneral(trajectory.message());
        return all.messages();
    }
    if (format == kPresetFormat && declaresSetup(*doc)) {
        auto setup = loadSetupPreset(path);
        if (setup)
            return {};
        JsonIssues all(path.string());
        all.addGeneral(setup.message());
        return all.messages();
    }
    if (format == kPresetFormat) {
        auto preset = loadMaterialPreset(path);
        if (preset)
            return {};
        // loadMaterialPreset summarises; re-read for the full list.
        JsonIssues all(path.string());
        all.addGeneral(preset.message());
        return all.messages();
    }
    readProject(path, issues);
    return issues.messages();
}

namespace {

json perNode(const std::vector<double>& values) {
    bool uniform = true;
    for (double v : values)
        uniform = uniform && v == values.front();
    if (uniform)
        return values.front();
    return values;
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


json nodeList(const Lattice& lattice, const std::vector<int>& nodes) {
    json list = json::array();
    for (int n : nodes) {
        const auto c = lattice.coords(n);
        list.push_back(json::array({c[0], c[1], c[2]}));
    }
    return list;
}

json driverJson(const Driver& driver) {
    if (const auto* d = std::get_if<ScriptedDrag>(&driver)) {
        json keys = json::array();
        for (const PathKey& k : d->keys)
            keys.push_back({{"time", k.time}, {"offset", vec(k.offset)}});
        json out = {{"type", "drag"}, {"point", vec(d->point)}, {"keys", keys}, {"stiffness", d->stiffness},
                    {"damping", d->damping}};
        if (d->releaseTime >= 0.0)
            out["release"] = d->releaseTime;
        return out;
    }
    const auto& s = std::get<SwimDriver>(driver);
    return {{"type", "swim"},           {"point", vec(s.point)},   {"direction", vec(s.direction)},
            {"frequency", s.frequencyHz}, {"amplitude", s.amplitude}, {"phase", s.phase},
            {"ramp", s.rampSeconds},     {"stiffness", s.stiffness}, {"damping", s.damping}};
}

json clipJson(const Clip& c) {
    json out = {{"name", c.name}, {"source", clipSourceName(c.source)}, {"start", c.startSeconds},
                {"frames", c.frames}, {"fps", c.fps}, {"loop", c.loop}, {"blend", c.blendFrames}};
    if (!c.sourceName.empty())
        out["of"] = c.sourceName;
    if (c.goals)
        out["goals"] = {{"stiffness", c.goals->stiffness}, {"damping", c.goals->damping}, {"weight", c.goals->weight}};
    return out;
}

json dragJson(const DragSpring& d) {
    json support = json::array();
    for (const NodeWeight& w : d.support)
        support.push_back(json::array({w.node, w.weight}));
    return {{"support", support}, {"target", vec(d.target)}, {"targetVelocity", vec(d.targetVelocity)},
            {"stiffness", d.stiffness}, {"damping", d.damping}};
}

json dragsJson(const std::vector<DragSpring>& drags) {
    json out = json::array();
    for (const DragSpring& d : drags)
        out.push_back(dragJson(d));
    return out;
}

json pointsJson(const std::vector<Vec3>& points) {
    json out = json::array();
    for (const Vec3& p : points) {
        out.push_back(p.x());
        out.push_back(p.y());
        out.push_back(p.z());
    }
    return out;
}

/// The clip library as its three top-level members (nlohmann writes doubles with 17 significant
/// digits, so session states read back bit for bit and replays stay exact).
void writeClipLibrary(const ClipLibrary& lib, json& doc) {
    if (!lib.sessions.empty()) {
        json sessions = json::array();
        for (const NamedSession& named : lib.sessions) {
            const Session& s = named.session;
            json bodies = json::array();
            for (const BodyState& b : s.start.bodies)
                bodies.push_back({{"position", pointsJson(b.position)}, {"velocity", pointsJson(b.velocity)}});
            json startDrags = json::array();
            for (const auto& drags : s.startDrags)
                startDrags.push_back(dragsJson(drags));
            json events = json::array();
            for (const DragEvent& e : s.events)
                events.push_back({{"step", e.step}, {"object", e.object}, {"drags", dragsJson(e.drags)}});
            json out = {{"name", named.name}, {"dt", s.dt}, {"start", {{"step", s.start.step}, {"bodies", bodies}}},
                        {"end", s.endStep}, {"events", events}};
            if (!s.startDrags.empty())
                out["startDrags"] = startDrags;
            sessions.push_back(out);
        }
        doc["sessions"] = sessions;
    }
    if (!lib.keyframes.empty()) {
        json sets = json::array();
        for (const NamedKeyframes& named : lib.keyframes) {
            json objects = json::array();
            for (const KeyframeAnimation& anim : named.objects) {
                json keys = json::array();
                for (const LatticeKey& k : anim.keys()) {
                    json displacement = json::array();
                    for (const Vec3& d : k.displacement)
                        displacement.push_back(vec(d));
                    keys.push_back({{"time", k.seconds}, {"nodes", k.nodes}, {"displacement", displacement}});
                }
                objects.push_back({{"keys", keys}});
            }
            sets.push_back({{"name", named.name}, {"objects", objects}});
        }
        doc["keyframes"] = sets;
    }
    if (!lib.clips.empty() || !lib.defaultClip.empty()) {
        json list = json::array();
        for (const Clip& c : lib.clips)
            list.push_back(clipJson(c));
        json clips = {{"library", list}};
        if (!lib.defaultClip.empty())
            clips["default"] = lib.defaultClip;
        doc["clips"] = clips;
    }
}

/// The material, anchors and voids of a lattice as a project object writes them.
void writeMaterial(const Lattice& lattice, const LatticeMaterial& m, json& object) {
    const MaterialRanges& key = materialRanges(m.model);
    object["material"] = {{"model", key.model},
                          {key.mass.name, perNode(m.mass)},
                          {key.stiffness.name, perNode(m.stiffness)},
                          {key.damping.name, perNode(m.damping)},
                          {"springKindScale", {{"edge", m.kindScale[0]}, {"face", m.kindScale[1]}, {"body", m.kindScale[2]}}},
                          {"anisotropy", vec(m.anisotropy)},
                          {"heavyAnchorRatio", m.heavyAnchorRatio},
                          {key.nodeDamping.name, perNode(m.nodeDamping)}};
    if (m.strainLimits.stretch > 0.0)
        object["material"]["stretchLimit"] = m.strainLimits.stretch;
    if (m.strainLimits.squash > 0.0)
        object["material"]["squashLimit"] = m.strainLimits.squash;
    if (largestVolumePreservation(m) > 0.0)
        object["material"][kVolumePreservationRange.name] = perNode(m.volumePreservation);
    if (std::any_of(m.goalWeight.begin(), m.goalWeight.end(), [](double w) { return w > 0.0; }))
        object["material"][kGoalWeightRange.name] = perNode(m.goalWeight);
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


}  // namespace

Status saveProject(const Project& project, const fs::path& path) {
    // Mesh references are relative to the project file: rebase them when saving somewhere else.
    // A project not yet saved (an imported mesh) has no path: its references are kept as they are
    // (fs::absolute of an empty path throws).
    const fs::path from = project.path.empty() ? fs::path() : fs::absolute(project.path).parent_path();
    const fs::path to = fs::absolute(path).parent_path();
    auto rebased = [&](const std::string& ref) {
        if (ref.empty() || fs::path(ref).is_absolute() || project.path.empty())
            return ref;
        return (from / ref).lexically_normal().lexically_relative(to.lexically_normal()).generic_string();
    };
    json objects = json::array();
    for (std::size_t i = 0; i < project.scene.objects.size(); ++i) {
        const SceneObject& o = project.scene.objects[i];
        const json lattice = latticeJson(o.lattice.shape(), o.lattice.box());
        json drivers = json::array();
        for (const Driver& d : o.drivers)
            drivers.push_back(driverJson(d));
        json object = {{"name", o.name},
                       {"mesh", rebased(i < project.meshReferences.size() ? project.meshReferences[i] : std::string())},
                       {"lattice", lattice},
                       {"drivers", drivers}};
        if (i < project.meshOffsets.size() && !project.meshOffsets[i].isZero())
            object["position"] = vec(project.meshOffsets[i]);
        if (i < project.restShapeEdits.size() && !project.restShapeEdits[i].empty()) {
            json edits = json::array();
            for (const RestShapeEdit& e : project.restShapeEdits[i]) {
                json nodes = json::array();
                for (const Vec3& x : e.nodes)
                    nodes.push_back(vec(x));
                edits.push_back({{"lattice", latticeJson(e.shape, e.box)}, {"nodes", nodes}});
            }
            object["restShape"] = edits;
        }
        if (const auto& a = o.baseAnimation)
            object["animation"] = {{"take", a->take},
                                   {"start", a->start},
                                   {"end", a->start + a->duration()},
                                   {"loop", a->loop},
                                   {"sampleRate", a->rate},
                                   {"goal", {{"frequency", o.follow.frequency}, {"dampingRatio", o.follow.dampingRatio}}}};
        writeMaterial(o.lattice, o.material, object);
        objects.push_back(object);
    }
    const WorldSettings& w = project.scene.world;
    json planes = json::array();
    for (const CollisionPlane& p : w.planes)
        planes.push_back({{"point", vec(p.point)}, {"normal", vec(p.normal)}, {"restitution", p.restitution},
                          {"friction", p.friction}});
    json colliders = json::array();
    for (const Collider& c : w.colliders) {
        json entry = {{"shape", colliderShapeName(c.shape)}, {"centre", vec(c.centre)}};
        if (c.shape == ColliderShape::Sphere || c.shape == ColliderShape::Capsule)
            entry["radius"] = c.radius;
        if (c.shape == ColliderShape::Capsule) {
            entry["axis"] = vec(c.axis);
            entry["halfLength"] = c.halfLength;
        }
        if (c.shape == ColliderShape::Box)
            entry["halfExtents"] = vec(c.halfExtents);
        if (c.shape == ColliderShape::Mesh) {
            entry["mesh"] = rebased(c.surface->source());
            entry["scale"] = c.scale;
        }
        if (c.shape == ColliderShape::Box || c.shape == ColliderShape::Mesh)
            entry["axes"] = {vec(c.axes.col(0)), vec(c.axes.col(1)), vec(c.axes.col(2))};
        entry["restitution"] = c.restitution;
        entry["friction"] = c.friction;
        colliders.push_back(entry);
    }
    json world = {{"gravity", vec(w.gravity)}, {"planes", planes}};
    if (!colliders.empty())
        world["colliders"] = colliders;
    if (w.bodyCollisions.enabled)
        world["bodyCollisions"] = {{"enabled", true},
                                   {"restitution", w.bodyCollisions.restitution},
                                   {"friction", w.bodyCollisions.friction}};
    json doc = {{"format", kProjectFormat},
                      {"version", kProjectVersion},
                      {"objects", objects},
                      {"world", world},
                      {"simulation",
                       {{"integrator", std::string(integratorName(w.simulation.integrator))},
                        {"dt", w.simulation.dt},
                        {"xpbdSubsteps", w.simulation.xpbdSubsteps},
                        {"sleep", w.simulation.sleep}}},
                      {"clip", {{"frames", w.frames}, {"fps", w.fps}}}};
    writeClipLibrary(project.clips, doc);
    return writeFileAtomically(path, doc.dump(2) + "\n");
}

Status applyMaterialPreset(const MaterialPreset& preset, const Lattice& lattice, LatticeMaterial& material,
                           const std::vector<int>& nodes) {
    JsonIssues issues("preset '" + preset.name + "'");
    LatticeMaterial m = material;
    std::optional<double> total;
    readMaterial(JsonValue(&preset.material, "/material", &issues), m, total, false, fs::path());
    if (!issues.empty())
        return Status::error(issues.summary());
    spreadTotalMass(lattice, m, total);
    if (nodes.empty() || m.model != material.model) {
        // A preset of another model replaces every value: half of a map in kg and half in kg/m³ means nothing.
        material = m;
        return Status::success();
    }
    for (int n : nodes) {
        if (n < 0 || n >= lattice.nodeCount())
            return Status::error("node " + std::to_string(n) + " is not in the lattice");
        material.mass[std::size_t(n)] = m.mass[std::size_t(n)];
        material.stiffness[std::size_t(n)] = m.stiffness[std::size_t(n)];
        material.damping[std::size_t(n)] = m.damping[std::size_t(n)];
        material.nodeDamping[std::size_t(n)] = m.nodeDamping[std::size_t(n)];
        if (!m.volumePreservation.empty() || !material.volumePreservation.empty()) {
            material.volumePreservation.resize(material.mass.size(), 0.0);
            material.volumePreservation[std::size_t(n)] = m.volumePreservation.empty() ? 0.0 : m.volumePreservation[std::size_t(n)];
        }
    }
    return Status::success();
}

Status saveMaterialPreset(const std::string& name, const std::string& description, const LatticeMaterial& material,
                          const fs::path& path) {
    double total = 0.0, stiffness = 0.0, damping = 0.0, nodeDamping = 0.0;
    int count = 0;
    std::optional<double> sameNodeDamping;  // every solid node's, when uniform: written exactly, not as a mean
    bool uniformNodeDamping = true;
    for (std::size_t n = 0; n < material.mass.size(); ++n) {
        if (material.isVoid[n])
            continue;
        total += material.mass[n];
        stiffness += material.stiffness[n];
        damping += material.damping[n];
        nodeDamping += material.nodeDamping[n];
        uniformNodeDamping = uniformNodeDamping && (!sameNodeDamping || *sameNodeDamping == material.nodeDamping[n]);
        sameNodeDamping = material.nodeDamping[n];
        ++count;
    }
    if (count == 0)
        return Status::error(path.string() + ": the material has no simulated node to take values from");
    const bool continuum = material.model == MaterialModel::Continuum;
    const MaterialRanges& key = materialRanges(material.model);
    json values = {{"model", key.model},
                   {key.stiffness.name, stiffness / count},
                   {key.damping.name, damping / count},
                   {"springKindScale",
                    {{"edge", material.kindScale[0]}, {"face", material.kindScale[1]}, {"body", material.kindScale[2]}}},
                   {"anisotropy", vec(material.anisotropy)},
                   {"heavyAnchorRatio", material.heavyAnchorRatio},
                   {key.nodeDamping.name, uniformNodeDamping ? *sameNodeDamping : nodeDamping / count}};
    // A lattice-springs preset keeps the body's total mass; a continuum one its (mean) density, which
    // means the same on every object.
    if (continuum)
        values[key.mass.name] = total / count;
    else
        values["totalMass"] = total;
    if (material.strainLimits.stretch > 0.0)
        values["stretchLimit"] = material.strainLimits.stretch;
    if (material.strainLimits.squash > 0.0)
        values["squashLimit"] = material.strainLimits.squash;
    // A preset holds one value: a painted map's mean over the solid nodes.
    if (largestVolumePreservation(material) > 0.0)
        values[kVolumePreservationRange.name] = solidMean(material.volumePreservation, material);
    const json doc = {{"format", kPresetFormat},
                      {"version", kPresetVersion},
                      {"kind", "material"},
                      {"name", name},
                      {"description", description},
                      {"material", values}};
    return writeFileAtomically(path, doc.dump(2) + "\n");
}

// --- Setup presets. ---------------------------------------------------------------------------

Result<SetupPreset> setupFromProject(const Project& project, std::size_t object) {
    if (object >= project.scene.objects.size())
        return Status::error("the project has no object " + std::to_string(object));
    const SceneObject& o = project.scene.objects[object];
    SetupPreset preset;
    preset.name = o.name;
    preset.shape = o.lattice.shape();
    preset.material = o.material;
    preset.drivers = o.drivers;
    for (const Clip& c : project.clips.clips) {
        if (c.source == ClipSource::Drivers)
            preset.clips.push_back(c);
    }
    return preset;
}

Status saveSetupPreset(const SetupPreset& preset, const fs::path& path) {
    auto lattice = Lattice::create(preset.shape, OrientedBox{});
    if (!lattice)
        return Status::error(path.string() + ": " + lattice.message());
    if (preset.material.mass.size() != std::size_t(lattice->nodeCount()))
        return Status::error(path.string() + ": the material has " + std::to_string(preset.material.mass.size()) +
                             " nodes, the lattice " + std::to_string(lattice->nodeCount()));
    json body = {{"format", kPresetFormat},
                 {"version", kPresetVersion},
                 {"kind", "setup"},
                 {"name", preset.name},
                 {"description", preset.description},
                 {"lattice",
                  {{"kind", preset.shape.kind == LatticeKind::Bezier ? "bezier" : "bspline"},
                   {"nodes", {preset.shape.nodes[0], preset.shape.nodes[1], preset.shape.nodes[2]}}}}};
    writeMaterial(lattice.value(), preset.material, body);
    json drivers = json::array();
    for (const Driver& d : preset.drivers)
        drivers.push_back(driverJson(d));
    body["drivers"] = drivers;
    json clips = json::array();
    for (const Clip& c : preset.clips)
        clips.push_back(clipJson(c));
    body["clips"] = clips;
    return writeFileAtomically(path, body.dump(2) + "\n");
}

Result<AnyPreset> loadPreset(const fs::path& path) {
    JsonIssues issues(path.string());
    const auto doc = parseJsonFile(path.string(), issues);
    if (!doc)
        return Status::error(issues.summary());
    if (declaresSetup(*doc)) {
        auto setup = loadSetupPreset(path);
        if (!setup)
            return setup.status();
        return AnyPreset(std::move(setup.value()));
    }
    auto material = loadMaterialPreset(path);
    if (!material)
        return material.status();
    return AnyPreset(std::move(material.value()));
}

Result<SetupPreset> loadSetupPreset(const fs::path& path) {
    JsonIssues issues(path.string());
    const auto doc = parseJsonFile(path.string(), issues);
    if (!doc)
        return Status::error(issues.summary());
    const JsonValue root(&*doc, "", &issues);
    if (!readHeader(root, kPresetFormat, kPresetVersion))
        return Status::error(issues.summary());
    root.checkKeys({"format", "version", "kind", "name", "description", "lattice", "material", "anchors", "voids",
                    "drivers", "clips"});
    const auto kind = root["kind"].string(true);
    if (kind && *kind != "setup") {
        root["kind"].problem("expected \"setup\", got \"" + *kind + "\" (a material preset is applied through a project's material.preset)");
        return Status::error(issues.summary());
    }
    SetupPreset preset;
    preset.name = root["name"].string(true).value_or("");
    preset.description = root["description"].string().value_or("");
    const JsonValue lat = root["lattice"];
    if (lat.expectObject(true)) {
        lat.checkKeys({"kind", "nodes"});
        if (auto k = lat["kind"].string()) {
            if (*k == "bspline")
                preset.shape.kind = LatticeKind::BSpline;
            else if (*k != "bezier")
                lat["kind"].problem("expected \"bezier\" or \"bspline\", got \"" + *k + "\"");
        }
        if (auto n = lat["nodes"].int3(2, 64, true))
            preset.shape.nodes = *n;
        if (Status st = preset.shape.validate(); !st)
            lat["nodes"].problem(st.message());
    }
    if (!issues.empty())
        return Status::error(issues.summary());
    // Painted maps are per node of the preset's own lattice; the box does not matter (parameters).
    const Lattice lattice = Lattice::create(preset.shape, OrientedBox{}).value();
    preset.material = uniformMaterial(lattice, 0.02, 80.0, 0.9);
    std::optional<double> totalMass;
    readMaterial(root["material"], preset.material, totalMass, false, path.parent_path());
    readAnchors(root["anchors"], lattice, preset.material.anchor);
    if (const JsonValue voids = root["voids"]; voids.expectObject()) {
        voids.checkKeys({"nodes", "region"});
        for (int node : readNodeSelection(voids, lattice))
            preset.material.isVoid[std::size_t(node)] = 1;
    }
    spreadTotalMass(lattice, preset.material, totalMass);
    readDrivers(root["drivers"], preset.drivers);
    if (const JsonValue clips = root["clips"]; clips.exists()) {
        if (!clips.isArray())
            clips.problem("expected an array of clips");
        for (std::size_t i = 0; i < clips.size(); ++i) {
            auto c = readClip(clips.at(i));
            if (!c)
                continue;
            if (c->source != ClipSource::Drivers)
                clips.at(i)["source"].problem("a setup preset carries drivers clips only (sessions and keys belong to one scene)");
            else
                preset.clips.push_back(*c);
        }
    }
    if (issues.empty()) {
        if (auto body = buildLatticeBody(lattice, preset.material); !body)
            root["material"].problem(body.message());
    }
    if (!issues.empty())
        return Status::error(issues.summary());
    return preset;
}

Result<Project> applySetupPreset(const SetupPreset& preset, Project project, std::size_t object) {
    if (object >= project.scene.objects.size())
        return Status::error("the project has no object " + std::to_string(object));
    SceneObject& o = project.scene.objects[object];
    const LatticeShape& target = o.lattice.shape();
    const bool sameShape = target == preset.shape;
    if (sameShape) {
        o.material = preset.material;
    } else {
        // The painted maps live on the preset's lattice; place it over this object's box and carry
        // every value to the nearest node in lattice parameters, rescaled so the body stays the same
        // material at the new spacing.
        auto from = Lattice::create(preset.shape, o.lattice.box());
        if (!from)
            return Status::error("preset '" + preset.name + "': " + from.message());
        o.material = resampleMaterial(from.value(), preset.material, o.lattice, true);
    }
    o.drivers = preset.drivers;
    for (const Clip& c : preset.clips) {
        auto& clips = project.clips.clips;
        auto it = std::find_if(clips.begin(), clips.end(), [&](const Clip& x) { return x.name == c.name; });
        if (it != clips.end())
            *it = c;
        else
            clips.push_back(c);
    }
    if (auto body = buildLatticeBody(o.lattice, o.material); !body)
        return Status::error("preset '" + preset.name + "' on object '" + o.name + "': " + body.message());
    if (auto sim = SceneSimulation::create(project.scene); !sim)
        return Status::error("preset '" + preset.name + "': " + sim.message());
    if (Status st = project.clips.validate(project.scene); !st)
        return Status::error("preset '" + preset.name + "': " + st.message());
    return project;
}

}  // namespace softtouch::io

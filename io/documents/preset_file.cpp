// Material and setup presets (*.stpreset): io/documents/preset_file.h.
#include "io/documents/clip_library_json.h"
#include "io/documents/document_json.h"
#include "io/documents/preset_file.h"

#include "core/base/ranges.h"
#include "core/body/material_channels.h"
#include "core/solver/simulator.h"

#include "io/files/atomic_file.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace softtouch::io {
namespace fs = std::filesystem;
using nlohmann::json;
using namespace document;

// --- Material presets. -------------------------------------------------------------------------

std::optional<MaterialPreset> readMaterialPreset(const json& doc, const fs::path& path, JsonIssues& issues) {
    const JsonValue root(&doc, "", &issues);
    if (!readHeader(root, kPresetFormat, kPresetVersion))
        return std::nullopt;
    root.checkKeys({"format", "version", "kind", "name", "description", "material"});
    const auto kind = root["kind"].string(true);
    if (kind && *kind != "material")
        root["kind"].problem("expected \"material\", got \"" + *kind + "\" (a setup preset is loaded as a setup)");
    MaterialPreset preset;
    preset.name = root["name"].string(true).value_or("");
    preset.description = root["description"].string().value_or("");
    if (root["material"].expectObject(true)) {
        preset.material = doc["material"];
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
    if (!issues.empty())
        return std::nullopt;
    return preset;
}

Result<MaterialPreset> loadMaterialPreset(const fs::path& path) { return loadDocument<MaterialPreset>(path, readMaterialPreset); }

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
        for (const MaterialChannel& channel : materialChannels()) {
            const std::vector<double>& given = m.*channel.values;
            if (channel.inPresets && (!given.empty() || !(material.*channel.values).empty()))
                channelValues(material, channel)[std::size_t(n)] = given.empty() ? 0.0 : given[std::size_t(n)];
        }
    }
    return Status::success();
}

Status saveMaterialPreset(const std::string& name, const std::string& description, const LatticeMaterial& material,
                          const fs::path& path) {
    int count = 0;
    for (std::size_t n = 0; n < material.mass.size(); ++n)
        count += material.isVoid[n] ? 0 : 1;
    if (count == 0)
        return Status::error(path.string() + ": the material has no simulated node to take values from");
    const bool continuum = material.model == MaterialModel::Continuum;
    const MaterialRanges& key = materialRanges(material.model);
    json values = {{"model", key.model},
                   {"springKindScale",
                    {{"edge", material.kindScale[0]}, {"face", material.kindScale[1]}, {"body", material.kindScale[2]}}},
                   {"anisotropy", vec(material.anisotropy)},
                   {"heavyAnchorRatio", material.heavyAnchorRatio}};
    // A preset holds one value a channel: every solid node's when they agree (written exactly), else their mean.
    for (const MaterialChannel& channel : materialChannels()) {
        const std::vector<double>& map = material.*channel.values;
        if (!channel.inPresets || map.empty())
            continue;
        double sum = 0.0;
        std::optional<double> same;
        bool uniform = true;
        for (std::size_t n = 0; n < map.size(); ++n) {
            if (material.isVoid[n])
                continue;
            sum += map[n];
            uniform = uniform && (!same || *same == map[n]);
            same = map[n];
        }
        if (channel.optional && !(std::abs(sum) > 0.0))
            continue;  // a channel the material does not use (all 0): presets stay as they were before it existed
        // A lattice-springs preset keeps the body's total mass; a continuum one its density, which means the same
        // on every object.
        if (channel.id == MaterialChannelId::Mass && !continuum)
            values["totalMass"] = sum;
        else
            values[channel.rangeFor(material.model).name] = uniform ? *same : sum / count;
    }
    if (material.strainLimits.stretch > 0.0)
        values["stretchLimit"] = material.strainLimits.stretch;
    if (material.strainLimits.squash > 0.0)
        values["squashLimit"] = material.strainLimits.squash;
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
    return loadDocument<AnyPreset>(path, [](const json& doc, const fs::path& at, JsonIssues& issues) -> std::optional<AnyPreset> {
        if (declaresSetup(doc))
            return readSetupPreset(doc, at, issues);
        return readMaterialPreset(doc, at, issues);
    });
}

std::optional<SetupPreset> readSetupPreset(const json& doc, const fs::path& path, JsonIssues& issues) {
    const JsonValue root(&doc, "", &issues);
    if (!readHeader(root, kPresetFormat, kPresetVersion))
        return std::nullopt;
    root.checkKeys({"format", "version", "kind", "name", "description", "lattice", "material", "anchors", "voids",
                    "drivers", "clips"});
    const auto kind = root["kind"].string(true);
    if (kind && *kind != "setup") {
        root["kind"].problem("expected \"setup\", got \"" + *kind + "\" (a material preset is applied through a project's material.preset)");
        return std::nullopt;
    }
    SetupPreset preset;
    preset.name = root["name"].string(true).value_or("");
    preset.description = root["description"].string().value_or("");
    const JsonValue lat = root["lattice"];
    const std::size_t before = issues.messages().size();
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
    if (issues.messages().size() > before)  // the maps are per node of this lattice: nothing to read them on
        return std::nullopt;
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
        return std::nullopt;
    return preset;
}

Result<SetupPreset> loadSetupPreset(const fs::path& path) { return loadDocument<SetupPreset>(path, readSetupPreset); }

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

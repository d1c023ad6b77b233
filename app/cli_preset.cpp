// `softtouch-cli preset export|apply`: share an object's setup (lattice, painted maps, drivers, clips).
#include "app/cli_commands.h"
#include "app/cli_options.h"
#include "app/cli_support.h"

#include "io/documents/preset_file.h"
#include "io/documents/project_file.h"

#include <cstdio>
#include <variant>

namespace softtouch::cli {
namespace {

constexpr const char* kPresetAbout = R"(The two forms:
  softtouch-cli preset export SCENE --out P.stpreset [--object NAME] [--name TEXT] [--description TEXT]
  softtouch-cli preset apply P.stpreset SCENE --out NEW.softtouch [--object NAME]

export  Writes the setup of one object of SCENE (default: the first): lattice kind and resolution, the
        painted per-node mass, stiffness and damping, anchors, voids, the drivers and the scene's drivers
        clips, as a preset of kind "setup".
apply   Puts a preset onto one object of SCENE and writes the result as a new project. A setup preset:
        the object keeps its mesh and lattice box; when the lattice resolutions differ the painted maps are
        remapped to the nearest node in lattice parameters (and rescaled so the body stays the same
        material). A material preset (presets/materials): its values on every node, anchors and voids
        kept, as the editor's Presets dock applies it. The result is validated before anything is written.
)";

/// Index of the object named `name` (empty: the first).
Result<std::size_t> findObject(const io::Project& project, const std::string& name) {
    if (name.empty())
        return std::size_t(0);
    std::string known;
    for (std::size_t i = 0; i < project.scene.objects.size(); ++i) {
        if (project.scene.objects[i].name == name)
            return i;
        known += (known.empty() ? "" : ", ") + project.scene.objects[i].name;
    }
    return Status::error(project.path.string() + ": no object named '" + name + "' (it has: " + known + ")");
}

}  // namespace

int runPreset(const std::vector<std::string>& args) {
    std::string action;
    std::vector<std::string> positional;
    std::string out, objectName;
    std::optional<std::string> name, description;
    CommandLine line("preset", kPresetAbout);
    line.positional("ACTION", action, {"export|apply", "", true});
    line.positionals("FILE", positional, "export: SCENE; apply: P.stpreset SCENE.");
    line.text("--out", out, {"FILE", "The preset (export) or the new project (apply).", true});
    line.text("--object", objectName, {"NAME", "The object (default: the first)."});
    line.text("--name", name, {"TEXT", "export: the preset's name (default: the object's)."});
    line.text("--description", description, {"TEXT", "export: the preset's description."});
    if (const auto exit = line.parse(args))
        return *exit;
    if (action != "export" && action != "apply")
        return line.usage("unknown preset action '" + action + "' (expected export or apply)");

    if (action == "export") {
        if (positional.size() != 1)
            return line.usage("preset export needs exactly one SCENE");
        auto project = io::loadProject(positional[0]);
        if (!project)
            return fail(project.message());
        auto object = findObject(project.value(), objectName);
        if (!object)
            return fail(object.message());
        auto preset = io::setupFromProject(project.value(), object.value());
        if (!preset)
            return fail(preset.message());
        if (name) preset->name = *name;
        if (description) preset->description = *description;
        if (Status s = io::saveSetupPreset(preset.value(), out); !s)
            return fail(s.message());
        std::printf("wrote %s (setup of '%s': %dx%dx%d lattice, %zu drivers, %zu clips)\n", out.c_str(),
                    project->scene.objects[object.value()].name.c_str(), preset->shape.nodes[0], preset->shape.nodes[1],
                    preset->shape.nodes[2], preset->drivers.size(), preset->clips.size());
        return 0;
    }
    if (positional.size() != 2)
        return line.usage("preset apply needs a PRESET and a SCENE");
    auto any = io::loadPreset(positional[0]);
    if (!any)
        return fail(any.message());
    auto project = io::loadProject(positional[1]);
    if (!project)
        return fail(project.message());
    auto object = findObject(project.value(), objectName);
    if (!object)
        return fail(object.message());
    if (const auto* material = std::get_if<io::MaterialPreset>(&any.value())) {
        // A material preset: its values on every node of the object (anchors and voids kept), as the editor's
        // Presets dock applies it.
        SceneObject& o = project->scene.objects[object.value()];
        LatticeMaterial after = o.material;
        if (Status s = io::applyMaterialPreset(*material, o.lattice, after); !s)
            return fail(positional[0] + " on " + positional[1] + ": " + s.message());
        if (auto body = buildLatticeBody(o.lattice, after); !body)
            return fail(positional[0] + " on " + positional[1] + ": object '" + o.name + "': " + body.message());
        o.material = std::move(after);
        if (Status s = io::saveProject(project.value(), out); !s)
            return fail(s.message());
        std::printf("wrote %s (material '%s' on '%s')\n", out.c_str(), material->name.c_str(), o.name.c_str());
        return 0;
    }
    const io::SetupPreset& setup = std::get<io::SetupPreset>(any.value());
    const LatticeShape before = project->scene.objects[object.value()].lattice.shape();
    auto applied = io::applySetupPreset(setup, project.value(), object.value());
    if (!applied)
        return fail(positional[0] + " on " + positional[1] + ": " + applied.message());
    if (Status s = io::saveProject(applied.value(), out); !s)
        return fail(s.message());
    const bool remapped = before.kind != setup.shape.kind || before.nodes != setup.shape.nodes;
    std::printf("wrote %s (preset '%s' on '%s'%s)\n", out.c_str(), setup.name.c_str(),
                applied->scene.objects[object.value()].name.c_str(),
                remapped ? ", painted maps remapped to the object's lattice" : "");
    return 0;
}

}  // namespace softtouch::cli

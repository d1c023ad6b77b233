// `softtouch-cli preset export|apply`: share an object's setup (lattice, painted maps, drivers, clips).
#include "app/cli_commands.h"
#include "app/cli_support.h"

#include "io/project_file.h"

#include <cstdio>

namespace softtouch::cli {
namespace {

constexpr const char* kPresetUsage = R"(Usage:
  softtouch-cli preset export SCENE --out P.stpreset [--object NAME] [--name TEXT] [--description TEXT]
  softtouch-cli preset apply P.stpreset SCENE --out NEW.softtouch [--object NAME]

export  Writes the setup of one object of SCENE (default: the first): lattice kind and resolution, the
        painted per-node mass, stiffness and damping, anchors, voids, the drivers and the scene's drivers
        clips, as a preset of kind "setup".
apply   Puts a setup preset onto one object of SCENE and writes the result as a new project. The object
        keeps its mesh and lattice box; when the lattice resolutions differ the painted maps are remapped
        to the nearest node in lattice parameters (and rescaled so the body stays the same material).
        The result is validated before anything is written.
)";

int presetUsage(const std::string& message) { return usageError(message, "preset"); }

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
    if (args.empty())
        return presetUsage("preset needs 'export' or 'apply'");
    if (args.front() == "--help" || args.front() == "-h") {
        std::fputs(kPresetUsage, stdout);
        return 0;
    }
    const std::string action = args.front();
    if (action != "export" && action != "apply")
        return presetUsage("unknown preset action '" + action + "' (expected export or apply)");
    std::vector<std::string> positional;
    std::string out, objectName, name, description;
    bool named = false, described = false;
    for (std::size_t i = 1; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a == "--help" || a == "-h") {
            std::fputs(kPresetUsage, stdout);
            return 0;
        }
        if (a == "--out" || a == "--object" || a == "--name" || a == "--description") {
            if (i + 1 >= args.size())
                return presetUsage(a + " needs a value");
            const std::string& v = args[++i];
            if (a == "--out") out = v;
            else if (a == "--object") objectName = v;
            else if (a == "--name") { name = v; named = true; }
            else { description = v; described = true; }
        } else if (!a.empty() && a[0] == '-') {
            return presetUsage("unknown option '" + a + "'");
        } else {
            positional.push_back(a);
        }
    }
    if (out.empty())
        return presetUsage("preset " + action + " needs --out FILE");

    if (action == "export") {
        if (positional.size() != 1)
            return presetUsage("preset export needs exactly one SCENE");
        auto project = io::loadProject(positional[0]);
        if (!project)
            return fail(project.message());
        auto object = findObject(project.value(), objectName);
        if (!object)
            return fail(object.message());
        auto preset = io::setupFromProject(project.value(), object.value());
        if (!preset)
            return fail(preset.message());
        if (named) preset->name = name;
        if (described) preset->description = description;
        if (Status s = io::saveSetupPreset(preset.value(), out); !s)
            return fail(s.message());
        std::printf("wrote %s (setup of '%s': %dx%dx%d lattice, %zu drivers, %zu clips)\n", out.c_str(),
                    project->scene.objects[object.value()].name.c_str(), preset->shape.nodes[0], preset->shape.nodes[1],
                    preset->shape.nodes[2], preset->drivers.size(), preset->clips.size());
        return 0;
    }
    if (positional.size() != 2)
        return presetUsage("preset apply needs a PRESET and a SCENE");
    auto preset = io::loadSetupPreset(positional[0]);
    if (!preset)
        return fail(preset.message());
    auto project = io::loadProject(positional[1]);
    if (!project)
        return fail(project.message());
    auto object = findObject(project.value(), objectName);
    if (!object)
        return fail(object.message());
    const LatticeShape before = project->scene.objects[object.value()].lattice.shape();
    auto applied = io::applySetupPreset(preset.value(), project.value(), object.value());
    if (!applied)
        return fail(positional[0] + " on " + positional[1] + ": " + applied.message());
    if (Status s = io::saveProject(applied.value(), out); !s)
        return fail(s.message());
    const bool remapped = before.kind != preset->shape.kind || before.nodes != preset->shape.nodes;
    std::printf("wrote %s (preset '%s' on '%s'%s)\n", out.c_str(), preset->name.c_str(),
                applied->scene.objects[object.value()].name.c_str(),
                remapped ? ", painted maps remapped to the object's lattice" : "");
    return 0;
}

}  // namespace softtouch::cli

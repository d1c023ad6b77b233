#pragma once
/// Presets (*.stpreset): a material preset (scalar values that apply to any lattice) and a setup preset
/// (an object's lattice, painted maps, drivers and drivers clips). Versioned JSON read through JsonValue,
/// written atomically. Schema: docs/project-format.md, "Preset, version 3".

#include "io/documents/project_file.h"

#include <filesystem>
#include <string>
#include <variant>
#include <vector>

namespace softtouch::io {

/// A shareable material: scalar values that apply to any lattice.
struct MaterialPreset {
    std::string name;                ///< Shown in preset lists.
    std::string description;         ///< One line for the user.
    nlohmann::json material;         ///< The "material" object, validated (same keys as a project's).
};

/// A shareable object setup (preset kind "setup"): lattice resolution, painted per-node material
/// with anchors and voids, drivers and the clips that play them. Material points of drivers are
/// lattice parameters, so a setup applies to any mesh.
struct SetupPreset {
    std::string name;                ///< Shown in preset lists.
    std::string description;         ///< One line for the user.
    LatticeShape shape;              ///< Lattice kind and resolution the maps were painted on.
    LatticeMaterial material;        ///< Per node of `shape` (i fastest), with anchors and voids.
    std::vector<Driver> drivers;     ///< Headless motion.
    std::vector<Clip> clips;         ///< Drivers clips only (sessions and keys belong to one scene).
};

/// Loads a material preset.
Result<MaterialPreset> loadMaterialPreset(const std::filesystem::path& path);
/// Applies a preset onto `material` (of `lattice`): to the listed nodes' mass, stiffness, spring and
/// node damping, or, when `nodes` is empty, to every node and to the global fields (kind scales,
/// anisotropy, heavy anchor ratio) too. A preset's totalMass becomes the same per-node mass it would
/// give spread over the whole lattice's non-void nodes. Anchors and voids are kept.
Status applyMaterialPreset(const MaterialPreset& preset, const Lattice& lattice, LatticeMaterial& material,
                           const std::vector<int>& nodes = {});
/// Writes `material` as a shareable preset (single values: means over non-void nodes, total mass),
/// atomically.
Status saveMaterialPreset(const std::string& name, const std::string& description, const LatticeMaterial& material,
                          const std::filesystem::path& path);

/// The setup of object `object` of a project (its lattice shape, material, drivers and the
/// project's drivers clips).
Result<SetupPreset> setupFromProject(const Project& project, std::size_t object);
/// Writes a setup preset atomically.
Status saveSetupPreset(const SetupPreset& preset, const std::filesystem::path& path);
/// Loads and validates a setup preset; errors name the file, the JSON pointer and the problem.
Result<SetupPreset> loadSetupPreset(const std::filesystem::path& path);
/// A preset file of either kind: a setup preset says "kind": "setup", a material preset has no kind.
using AnyPreset = std::variant<MaterialPreset, SetupPreset>;
/// Loads a preset of whichever kind the file declares; errors are that kind's loader's.
Result<AnyPreset> loadPreset(const std::filesystem::path& path);
/// The readers behind the loaders, on a parsed document, each problem added to `issues` (nothing when there
/// are any): validateFile lists them all, loadPreset parses a file once.
std::optional<MaterialPreset> readMaterialPreset(const nlohmann::json& doc, const std::filesystem::path& path,
                                                 JsonIssues& issues);
std::optional<SetupPreset> readSetupPreset(const nlohmann::json& doc, const std::filesystem::path& path, JsonIssues& issues);
/// Applies a setup to object `object` of `project`: the object keeps its mesh and lattice box; the
/// material (with anchors and voids) is carried over node for node when the lattice shapes match and
/// remapped with resampleMaterial (continuum scaling) when they differ; the drivers are replaced; the
/// preset's clips are added (replacing clips of the same name). The result is validated (it builds
/// and its clip library fits).
Result<Project> applySetupPreset(const SetupPreset& preset, Project project, std::size_t object);

}  // namespace softtouch::io

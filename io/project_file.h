#pragma once
/// Project files (*.softtouch) and material presets (*.stpreset): versioned JSON read through
/// JsonValue (errors name the file, the JSON pointer and what was expected) and written atomically.
/// Schema: docs/project-format.md.

#include "core/clip.h"
#include "core/rest_shape.h"
#include "core/scene.h"
#include "io/json_reader.h"

#include <filesystem>
#include <string>
#include <variant>
#include <vector>

namespace softtouch::io {

/// Version written by this build; older versions are read, newer ones refused. Version 2 adds the
/// clip library (clips, sessions, keyframes); version 1 files read as projects without clips. Version 3
/// adds the material model. Version 4 (preset 3) lets node damping be painted: "airDamping" /
/// "dampingRate" may be one value per node; the single number of older files is a uniform map.
constexpr int kProjectVersion = 4;
constexpr int kPresetVersion = 3;

/// A loaded project: the scene plus what is needed to write it back.
struct Project {
    std::filesystem::path path;              ///< The file it was loaded from.
    Scene scene;                             ///< Everything the engine needs.
    std::vector<std::string> meshReferences; ///< Per object, the mesh path as written (relative to the project).
    std::vector<Vec3> meshOffsets;           ///< Per object, the "position" its mesh was moved by on load (two fish
                                             ///< from one file); missing entries are zero.
    /// Per object, the edits of its rest shape replayed over the mesh file on load (core/rest_shape.h), in
    /// order; missing entries are none. The scene's meshes already have them applied.
    std::vector<std::vector<RestShapeEdit>> restShapeEdits;
    ClipLibrary clips;                       ///< Clips, sessions and keyframe sets (version 2); validated on load.
    std::vector<std::string> importNotes;    ///< Per animated object, what its import found ("guppy: take 'swim'
                                             ///< 0-1 s at 120 samples/s, metres (glTF)"), for the CLI and editor.
};

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

/// Loads a project and its meshes and builds the scene. On failure the message is the first
/// problem (and how many more there are).
Result<Project> loadProject(const std::filesystem::path& path);
/// Every problem in a project, preset or trajectory file (decided by its "format"); empty when valid.
std::vector<std::string> validateFile(const std::filesystem::path& path);
/// Writes a project atomically (explicit box, per-node values, anchors and voids as node lists).
Status saveProject(const Project& project, const std::filesystem::path& path);
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
/// Applies a setup to object `object` of `project`: the object keeps its mesh and lattice box; the
/// material (with anchors and voids) is carried over node for node when the lattice shapes match and
/// remapped with resampleMaterial (continuum scaling) when they differ; the drivers are replaced; the
/// preset's clips are added (replacing clips of the same name). The result is validated (it builds
/// and its clip library fits).
Result<Project> applySetupPreset(const SetupPreset& preset, Project project, std::size_t object);

}  // namespace softtouch::io

#pragma once
/// Project files (*.softtouch) and material presets (*.stpreset): versioned JSON read through
/// JsonValue (errors name the file, the JSON pointer and what was expected) and written atomically.
/// Schema: docs/project-format.md.

#include "core/clip.h"
#include "core/scene.h"
#include "io/json_reader.h"

#include <filesystem>
#include <string>
#include <vector>

namespace softtouch::io {

/// Version written by this build; older versions are read, newer ones refused. Version 2 adds the
/// clip library (clips, sessions, keyframes); version 1 files read as projects without clips.
constexpr int kProjectVersion = 2;
constexpr int kPresetVersion = 1;

/// A loaded project: the scene plus what is needed to write it back.
struct Project {
    std::filesystem::path path;              ///< The file it was loaded from.
    Scene scene;                             ///< Everything the engine needs.
    std::vector<std::string> meshReferences; ///< Per object, the mesh path as written (relative to the project).
    ClipLibrary clips;                       ///< Clips, sessions and keyframe sets (version 2); validated on load.
};

/// A shareable material: scalar values that apply to any lattice.
struct MaterialPreset {
    std::string name;                ///< Shown in preset lists.
    std::string description;         ///< One line for the user.
    nlohmann::json material;         ///< The "material" object, validated (same keys as a project's).
};

/// Loads a project and its meshes and builds the scene. On failure the message is the first
/// problem (and how many more there are).
Result<Project> loadProject(const std::filesystem::path& path);
/// Every problem in a project or preset file (decided by its "format"); empty when valid.
std::vector<std::string> validateFile(const std::filesystem::path& path);
/// Writes a project atomically (explicit box, per-node values, anchors and voids as node lists).
Status saveProject(const Project& project, const std::filesystem::path& path);
/// Loads a material preset.
Result<MaterialPreset> loadMaterialPreset(const std::filesystem::path& path);

}  // namespace softtouch::io

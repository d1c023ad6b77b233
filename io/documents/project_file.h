#pragma once
/// Project files (*.softtouch): versioned JSON read through JsonValue (errors name the file, the JSON
/// pointer and what was expected) and written atomically. Schema: docs/project-format.md. Split by
/// concern: this file's project and world (project_file.cpp), the clip library (clip_library_json.h),
/// the lattice, material and drivers a preset shares (document_json.h), presets (preset_file.h).

#include "core/authoring/clip.h"
#include "core/scene/rest_shape.h"
#include "core/scene/scene.h"
#include "io/files/json_reader.h"

#include <filesystem>
#include <string>
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
    /// Per object, the edits of its rest shape replayed over the mesh file on load (core/scene/rest_shape.h), in
    /// order; missing entries are none. The scene's meshes already have them applied.
    std::vector<std::vector<RestShapeEdit>> restShapeEdits;
    ClipLibrary clips;                       ///< Clips, sessions and keyframe sets (version 2); validated on load.
    std::vector<std::string> importNotes;    ///< Per animated object, what its import found ("guppy: take 'swim'
                                             ///< 0-1 s at 120 samples/s, metres (glTF)"), for the CLI and editor.
};

/// Loads a project and its meshes and builds the scene. On failure the message is the first
/// problem (and how many more there are).
Result<Project> loadProject(const std::filesystem::path& path);

/// loadProject() for a command that simulates it (bake, render, modes, ...): a project with no objects (an empty
/// scene, as the editor's File ▸ New saves it) is refused, naming the file.
Result<Project> loadProjectToRun(const std::filesystem::path& path);

/// Every problem in a project, preset or trajectory file (decided by its "format"); empty when valid.
std::vector<std::string> validateFile(const std::filesystem::path& path);
/// Writes a project atomically (explicit box, per-node values, anchors and voids as node lists).
Status saveProject(const Project& project, const std::filesystem::path& path);

}  // namespace softtouch::io

#pragma once
/// The length unit of a file read through assimp. SoftTouch works in metres; glTF is in metres by its
/// specification; FBX says its unit in GlobalSettings' UnitScaleFactor (centimetres per file unit: 1 is a
/// centimetre file, 100 a metre file). Blender's default FBX export writes a centimetre file whose root
/// carries a ×100 scale, so without this the mesh arrives 100 times too large. COLLADA's <unit> is applied
/// by assimp itself. Other formats say nothing and are taken as metres.

#include <string>

struct aiScene;

namespace softtouch::io {

struct SceneUnit {
    double metresPerUnit = 1.0; ///< Multiply file coordinates by this.
    std::string description;    ///< What was used and why, for the import report ("centimetres (FBX UnitScaleFactor 1)").
};

/// The unit of `scene`, read from `fileName`'s extension and the scene's metadata.
SceneUnit sceneUnit(const aiScene& scene, const std::string& fileName);

}  // namespace softtouch::io

#include "io/import/scene_units.h"

#include <assimp/scene.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace softtouch::io {

SceneUnit sceneUnit(const aiScene& scene, const std::string& fileName) {
    std::string extension = std::filesystem::path(fileName).extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    SceneUnit unit;
    if (extension == ".gltf" || extension == ".glb") {
        unit.description = "metres (glTF)";
        return unit;
    }
    if (extension == ".fbx") {
        double centimetres = 1.0;  // FBX's own default: a file that says nothing is in centimetres
        bool said = false;
        if (scene.mMetaData) {
            double d = 0.0;
            float f = 0.0f;
            if (scene.mMetaData->Get("UnitScaleFactor", d))
                said = true, centimetres = d;
            else if (scene.mMetaData->Get("UnitScaleFactor", f))
                said = true, centimetres = double(f);
        }
        if (!(std::isfinite(centimetres) && centimetres > 0.0))
            centimetres = 1.0, said = false;
        unit.metresPerUnit = centimetres / 100.0;
        char text[64];
        std::snprintf(text, sizeof text, "%g cm per unit (FBX UnitScaleFactor %g)", centimetres, centimetres);
        unit.description = !said                 ? std::string("centimetres (FBX UnitScaleFactor absent: FBX's default)")
                           : centimetres == 1.0   ? std::string("centimetres (FBX UnitScaleFactor 1)")
                           : centimetres == 100.0 ? std::string("metres (FBX UnitScaleFactor 100)")
                                                  : std::string(text);
        return unit;
    }
    if (extension == ".dae") {
        unit.description = "metres (COLLADA's <unit>, applied by assimp)";
        return unit;
    }
    unit.description = "metres (the file names no unit)";
    return unit;
}

}  // namespace softtouch::io

#pragma once
/// Where the editor finds its bundled files: next to the build tree's source (development) or in
/// <prefix>/share/softtouch (installed).

#include "app/bundled_paths.h"

#include <QString>

namespace softtouch::app {

/// The presets/ folder.
inline QString presetRoot() { return QString::fromStdString(bundledFolder("presets", "presets").string()); }

/// The bundled default scene: the angelfish swim.
inline QString defaultScenePath() { return presetRoot() + "/scenes/angelfish-swim.softtouch"; }

/// The shipped material presets.
inline QString presetFolder() { return presetRoot() + "/materials"; }

}  // namespace softtouch::app

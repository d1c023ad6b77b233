#pragma once
/// Where the editor finds its bundled files: next to the build tree's source (development) or in
/// <prefix>/share/softtouch (installed).

#include <QCoreApplication>
#include <QDir>
#include <QFileInfo>

namespace softtouch::app {

/// The presets/ folder.
inline QString presetRoot() {
    const QString installed = QCoreApplication::applicationDirPath() + "/../share/softtouch/presets";
    if (QFileInfo::exists(installed))
        return QDir(installed).absolutePath();
    return QStringLiteral(SOFTTOUCH_SOURCE_DIR "/presets");
}

/// The bundled default scene: the angelfish swim.
inline QString defaultScenePath() { return presetRoot() + "/scenes/angelfish-swim.softtouch"; }

/// The shipped material presets.
inline QString presetFolder() { return presetRoot() + "/materials"; }

}  // namespace softtouch::app

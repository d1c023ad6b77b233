#pragma once
/// The Qt application the picture-writing commands need (`study --out`'s plot, `modes --pictures`):
/// Qt draws text only with a QGuiApplication, and its offscreen platform gives one without any display.

#include <QGuiApplication>

#include <cstdlib>
#include <memory>

namespace softtouch::cli {

/// A QGuiApplication on the offscreen platform, kept alive by the caller while it draws; nullptr when
/// one exists already.
inline std::unique_ptr<QGuiApplication> offscreenGuiApplication() {
    if (QGuiApplication::instance())
        return nullptr;
    qputenv("QT_QPA_PLATFORM", "offscreen");
    static int argc = 1;
    static char name[] = "softtouch-cli";
    static char* argv[] = {name, nullptr};
    return std::make_unique<QGuiApplication>(argc, argv);
}

}  // namespace softtouch::cli

#pragma once
/// The Qt application the picture-writing commands of softtouch-bench need (`study --out`'s chart,
/// `modes --pictures`): Qt draws text only with an application object, Qt Charts only with a
/// QApplication, and the offscreen platform gives one without any display.

#include <QApplication>

#include <cstdlib>
#include <memory>

namespace softtouch::cli {

/// A QApplication on the offscreen platform, kept alive by the caller while it draws; nullptr when an
/// application object exists already.
inline std::unique_ptr<QApplication> offscreenApplication() {
    if (QCoreApplication::instance())
        return nullptr;
    qputenv("QT_QPA_PLATFORM", "offscreen");
    static int argc = 1;
    static char name[] = "softtouch-bench";
    static char* argv[] = {name, nullptr};
    return std::make_unique<QApplication>(argc, argv);
}

}  // namespace softtouch::cli

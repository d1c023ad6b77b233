#pragma once
/// Pictures of a body's vibration modes, drawn headless (render::EglContext, no X server): for each
/// mode the mesh deformed by +A·φ (the lattice nodes displaced along the mode shape, the mesh following
/// through the usual lattice map), the rest pose as a translucent ghost, the lattice overlay (springs
/// coloured by strain, anchors black) and a caption with the frequency and damping ratio. Each mode is
/// seen with the spine (the lattice's u axis) horizontal, from halfway between straight across the
/// mode's main motion and the usual 3/4 view: a fish's sideways tail swing shows its outline and its
/// motion at cos 45° each (modeCamera()).
///
/// `softtouch-cli modes SCENE --pictures PREFIX` writes them (docs/design/lattice.md, "Modes"). Text needs Qt's
/// raster painter, hence Qt Gui here and not in softtouch::render.

#include "core/base/result.h"
#include "core/modes/modes.h"
#include "core/scene/scene.h"
#include "render/camera.h"

#include <QImage>

#include <string>
#include <vector>

namespace softtouch::render {

/// How the pictures are drawn.
struct ModePictureOptions {
    int width = 640;                                ///< Pixels per mode picture, [16, 8192].
    int height = 400;                               ///< Pixels per mode picture, [16, 8192].
    double amplitudeFraction = kModeDisplayFraction;///< Largest node displacement / the box's largest side, [0, 1].
    bool caption = true;                            ///< Mode number, frequency and ζ in the top-left corner.
};

/// One mode's picture and the camera it was drawn with (to find a node's pixel in it).
struct ModePicture {
    QImage image;          ///< width x height, RGB.
    Camera camera;         ///< World to clip of the picture.
    double amplitude = 0.0;///< A, metres: the largest node displacement drawn.
};

/// The camera a mode is drawn with (see above), framing the lattice at rest and displaced by the
/// amplitude (at least the default one, so pictures at amplitude 0 and at the default share the camera).
Camera modeCamera(const SceneObject& object, const VibrationMode& mode, double amplitude, int width, int height);

/// Draws each mode of `object` (modes from analyseModes() on its body). Needs a QGuiApplication for the
/// captions (see writeModePictures()). `context` receives the OpenGL implementation used, if given.
Result<std::vector<ModePicture>> renderModePictures(const SceneObject& object, const std::vector<VibrationMode>& modes,
                                                    const ModePictureOptions& options, std::string* context = nullptr);

/// What writeModePictures() wrote.
struct ModePicturesWritten {
    std::vector<std::string> files;  ///< PREFIX-1.png ... PREFIX-N.png, then PREFIX-modes.png (all side by side).
    std::string context;             ///< The OpenGL implementation that drew them.
};

/// Renders the modes and writes PREFIX-1.png ... PREFIX-N.png and the strip PREFIX-modes.png, each
/// atomically, none unless every picture was drawn. Needs a QGuiApplication (headless: app/cli_offscreen_gui.h).
Result<ModePicturesWritten> writeModePictures(const SceneObject& object, const std::vector<VibrationMode>& modes,
                                              const ModePictureOptions& options, const std::string& prefix);

}  // namespace softtouch::render

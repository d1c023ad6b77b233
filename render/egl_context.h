#pragma once
/// A headless OpenGL 3.3 core context through EGL, with no X server and no window: Mesa's surfaceless
/// platform (EGL_PLATFORM_SURFACELESS_MESA, software llvmpipe or a GPU render node), else the first EGL
/// device (EGL_EXT_platform_device, e.g. NVIDIA's driver). It renders into its own framebuffer object
/// (RGBA8 colour + 24-bit depth, multisampled and resolved on read).

#include "core/base/result.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace softtouch::render {

/// Headless OpenGL context plus an offscreen framebuffer of a fixed size.
class EglContext {
public:
    /// Whether an EGL display can be initialised at all (a driver exists). Tests skip on failure only;
    /// once this succeeds, a failure of create() is a real error.
    static Status probeDriver();

    /// Creates the context, makes it current on this thread and binds a framebuffer of width x height
    /// pixels (1..16384 each) with up to `samples` MSAA samples (0 or 1: none). Errors say which EGL or
    /// GL step failed.
    static Result<std::unique_ptr<EglContext>> create(int width, int height, int samples = 4);

    ~EglContext();
    EglContext(const EglContext&) = delete;
    EglContext& operator=(const EglContext&) = delete;

    /// Makes the context current on the calling thread and binds its framebuffer for drawing.
    Status makeCurrent();
    /// Reallocates the framebuffer (context current).
    Status resize(int width, int height);
    /// Framebuffer width, pixels.
    int width() const;
    /// Framebuffer height, pixels.
    int height() const;
    /// MSAA samples actually used (0: none).
    int samples() const;
    /// Binds the drawing framebuffer (what MeshRenderer::draw() draws into).
    void bindFramebuffer();
    /// Resolves the framebuffer and reads it as RGBA8, rows top-down, width*height*4 bytes.
    Status readPixels(std::vector<std::uint8_t>& rgba);
    /// GL_RENDERER and GL_VERSION of the context, for logs ("llvmpipe ... / 4.5 (Core Profile) Mesa").
    std::string description() const;

private:
    struct Impl;
    explicit EglContext(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> m_impl;
};

}  // namespace softtouch::render

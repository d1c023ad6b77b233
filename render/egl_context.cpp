#include "render/egl_context.h"

#include "render/gl.h"

// Keep X11 out: EGL's platform header includes Xlib unless told not to.
#ifndef EGL_NO_X11
#define EGL_NO_X11 1
#endif
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <algorithm>
#include <cstring>
#include <mutex>
#include <string>

namespace softtouch::render {
namespace {

bool hasExtension(const char* list, const char* name) {
    if (list == nullptr)
        return false;
    const std::size_t length = std::strlen(name);
    for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += length)
        if ((p == list || p[-1] == ' ') && (p[length] == ' ' || p[length] == '\0'))
            return true;
    return false;
}

std::string eglErrorName(EGLint error) {
    switch (error) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
    default: return "EGL error " + std::to_string(error);
    }
}

/// The display stays initialised for the life of the process: EGL displays are not reference counted
/// (eglTerminate() would end every other context on it), initialising it again is a no-op, and
/// terminating unloads Mesa's driver with allocations LeakSanitizer then reports as ours.
std::mutex g_displayMutex;

struct OpenedDisplay {
    EGLDisplay display = EGL_NO_DISPLAY;
    std::string platform;  ///< "surfaceless" or "device".
};

Result<OpenedDisplay> openDisplay() {
    const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (clientExtensions == nullptr)
        return Status::error("EGL: no client extensions (is libEGL with a vendor library installed? libegl-mesa0)");
    auto getPlatformDisplay =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (getPlatformDisplay == nullptr)
        return Status::error("EGL: eglGetPlatformDisplayEXT is missing (EGL_EXT_platform_base)");
    std::string tried;
    if (hasExtension(clientExtensions, "EGL_MESA_platform_surfaceless")) {
        EGLDisplay display = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        if (display != EGL_NO_DISPLAY && eglInitialize(display, nullptr, nullptr) == EGL_TRUE)
            return OpenedDisplay{display, "surfaceless"};
        tried += "surfaceless platform: " + eglErrorName(eglGetError()) + "; ";
    } else {
        tried += "no EGL_MESA_platform_surfaceless; ";
    }
    auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    if (hasExtension(clientExtensions, "EGL_EXT_platform_device") && queryDevices != nullptr) {
        EGLDeviceEXT devices[16];
        EGLint count = 0;
        if (queryDevices(16, devices, &count) == EGL_TRUE) {
            for (EGLint d = 0; d < count; ++d) {
                EGLDisplay display = getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[d], nullptr);
                if (display != EGL_NO_DISPLAY && eglInitialize(display, nullptr, nullptr) == EGL_TRUE)
                    return OpenedDisplay{display, "device"};
            }
        }
        tried += "device platform: " + std::to_string(count) + " devices, none initialises";
    } else {
        tried += "no EGL_EXT_platform_device";
    }
    return Status::error("EGL: no headless display (" + tried + ")");
}

}  // namespace

struct EglContext::Impl {
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;
    std::string platform;
    int width = 0;
    int height = 0;
    int samples = 0;
    GLuint drawFramebuffer = 0;
    GLuint resolveFramebuffer = 0;  ///< Only with MSAA.
    GLuint colour = 0, depth = 0, resolveColour = 0;

    void freeFramebuffer() {
        const GLuint framebuffers[] = {drawFramebuffer, resolveFramebuffer};
        glDeleteFramebuffers(2, framebuffers);
        const GLuint renderbuffers[] = {colour, depth, resolveColour};
        glDeleteRenderbuffers(3, renderbuffers);
        drawFramebuffer = resolveFramebuffer = colour = depth = resolveColour = 0;
    }

    Status allocate(int w, int h) {
        if (w < 1 || h < 1 || w > 16384 || h > 16384)
            return Status::error("framebuffer size " + std::to_string(w) + "x" + std::to_string(h) +
                                 " is outside 1..16384 per side");
        GLint maxRenderbuffer = 0;
        glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxRenderbuffer);
        if (w > maxRenderbuffer || h > maxRenderbuffer)
            return Status::error("framebuffer size " + std::to_string(w) + "x" + std::to_string(h) +
                                 " exceeds this OpenGL's limit of " + std::to_string(maxRenderbuffer));
        freeFramebuffer();
        width = w;
        height = h;
        auto storage = [&](GLuint& rb, GLenum format, int s) {
            glGenRenderbuffers(1, &rb);
            glBindRenderbuffer(GL_RENDERBUFFER, rb);
            if (s > 1)
                glRenderbufferStorageMultisample(GL_RENDERBUFFER, s, format, w, h);
            else
                glRenderbufferStorage(GL_RENDERBUFFER, format, w, h);
        };
        storage(colour, GL_RGBA8, samples);
        storage(depth, GL_DEPTH_COMPONENT24, samples);
        glGenFramebuffers(1, &drawFramebuffer);
        glBindFramebuffer(GL_FRAMEBUFFER, drawFramebuffer);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            return Status::error("OpenGL: the offscreen framebuffer is incomplete");
        if (samples > 1) {
            storage(resolveColour, GL_RGBA8, 0);
            glGenFramebuffers(1, &resolveFramebuffer);
            glBindFramebuffer(GL_FRAMEBUFFER, resolveFramebuffer);
            glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, resolveColour);
            if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
                return Status::error("OpenGL: the resolve framebuffer is incomplete");
        }
        glBindRenderbuffer(GL_RENDERBUFFER, 0);
        glBindFramebuffer(GL_FRAMEBUFFER, drawFramebuffer);
        glViewport(0, 0, w, h);
        if (const GLenum error = glGetError(); error != GL_NO_ERROR)
            return Status::error("OpenGL error " + std::to_string(error) + " while creating the framebuffer");
        return Status::success();
    }

    void destroy() {
        if (context != EGL_NO_CONTEXT) {
            if (eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context) == EGL_TRUE)
                freeFramebuffer();
            eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
            eglDestroyContext(display, context);
            context = EGL_NO_CONTEXT;
        }
        display = EGL_NO_DISPLAY;
    }
};

EglContext::EglContext(std::unique_ptr<Impl> impl) : m_impl(std::move(impl)) {}

EglContext::~EglContext() {
    if (m_impl)
        m_impl->destroy();
}

Status EglContext::probeDriver() {
    std::lock_guard lock(g_displayMutex);
    auto opened = openDisplay();
    if (!opened)
        return Status::error(opened.message());
    return Status::success();
}

Result<std::unique_ptr<EglContext>> EglContext::create(int width, int height, int samples) {
    auto impl = std::make_unique<Impl>();
    {
        std::lock_guard lock(g_displayMutex);
        auto opened = openDisplay();
        if (!opened)
            return Status::error(opened.message());
        impl->display = opened->display;
        impl->platform = opened->platform;
    }
    auto fail = [&](const std::string& what) {
        const std::string message = "EGL (" + impl->platform + "): " + what + ": " + eglErrorName(eglGetError());
        impl->destroy();
        return Status::error(message);
    };
    if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE)
        return fail("eglBindAPI(EGL_OPENGL_API) failed, desktop OpenGL is not available");
    const EGLint configAttributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8,
                                       EGL_BLUE_SIZE, 8, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint configCount = 0;
    if (eglChooseConfig(impl->display, configAttributes, &config, 1, &configCount) != EGL_TRUE || configCount < 1) {
        if (!hasExtension(eglQueryString(impl->display, EGL_EXTENSIONS), "EGL_KHR_no_config_context"))
            return fail("no EGL config renders desktop OpenGL");
        config = EGL_NO_CONFIG_KHR;
    }
    const EGLint contextAttributes[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                                        EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                        EGL_NONE};
    impl->context = eglCreateContext(impl->display, config, EGL_NO_CONTEXT, contextAttributes);
    if (impl->context == EGL_NO_CONTEXT)
        return fail("cannot create an OpenGL 3.3 core context");
    if (eglMakeCurrent(impl->display, EGL_NO_SURFACE, EGL_NO_SURFACE, impl->context) != EGL_TRUE)
        return fail("cannot make the context current without a surface (EGL_KHR_surfaceless_context)");
    GLint maxSamples = 0;
    glGetIntegerv(GL_MAX_SAMPLES, &maxSamples);
    impl->samples = samples > 1 ? std::min(samples, int(maxSamples)) : 0;
    if (Status made = impl->allocate(width, height); !made) {
        impl->destroy();
        return made;
    }
    return std::unique_ptr<EglContext>(new EglContext(std::move(impl)));
}

Status EglContext::makeCurrent() {
    if (eglMakeCurrent(m_impl->display, EGL_NO_SURFACE, EGL_NO_SURFACE, m_impl->context) != EGL_TRUE)
        return Status::error("EGL: eglMakeCurrent failed: " + eglErrorName(eglGetError()));
    bindFramebuffer();
    return Status::success();
}

Status EglContext::resize(int width, int height) { return m_impl->allocate(width, height); }

int EglContext::width() const { return m_impl->width; }
int EglContext::height() const { return m_impl->height; }
int EglContext::samples() const { return m_impl->samples; }

void EglContext::bindFramebuffer() {
    glBindFramebuffer(GL_FRAMEBUFFER, m_impl->drawFramebuffer);
    glViewport(0, 0, m_impl->width, m_impl->height);
}

Status EglContext::readPixels(std::vector<std::uint8_t>& rgba) {
    const int w = m_impl->width, h = m_impl->height;
    if (m_impl->samples > 1) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, m_impl->drawFramebuffer);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m_impl->resolveFramebuffer);
        glBlitFramebuffer(0, 0, w, h, 0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, m_impl->resolveFramebuffer);
    } else {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, m_impl->drawFramebuffer);
    }
    const std::size_t row = std::size_t(w) * 4;
    std::vector<std::uint8_t> bottomUp(row * std::size_t(h));
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, bottomUp.data());
    bindFramebuffer();
    if (const GLenum error = glGetError(); error != GL_NO_ERROR)
        return Status::error("OpenGL error " + std::to_string(error) + " while reading the framebuffer");
    rgba.resize(bottomUp.size());
    for (int y = 0; y < h; ++y)  // OpenGL's rows run bottom-up
        std::memcpy(rgba.data() + std::size_t(y) * row, bottomUp.data() + std::size_t(h - 1 - y) * row, row);
    return Status::success();
}

std::string EglContext::description() const {
    const char* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const char* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    return std::string(renderer ? renderer : "?") + " / OpenGL " + (version ? version : "?") + " (EGL " +
           m_impl->platform + ")";
}

}  // namespace softtouch::render

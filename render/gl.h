#pragma once
/// The OpenGL 3.3 core API as the render module uses it: prototypes from the Khronos header, resolved by
/// glvnd's libOpenGL against whatever context is current (GLX under Qt, EGL headless). Private to render/.

#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/glcorearb.h>

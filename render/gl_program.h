#pragma once
/// Compiling and linking GLSL programs with errors that carry the driver's log. Private to render/.

#include "core/base/result.h"
#include "render/gl.h"

#include <string>
#include <vector>

namespace softtouch::render {

/// A linked program and the name it was built under (for error messages).
struct GlProgram {
    GLuint id = 0;     ///< Program object; 0 until linked.
    std::string name;  ///< For messages, e.g. "mesh".
    /// Location of a uniform (-1 when the linker removed it).
    GLint uniform(const char* uniformName) const { return glGetUniformLocation(id, uniformName); }
    /// Deletes the program (context current); safe on an empty one.
    void release();
};

/// Compiles a vertex and a fragment shader and links them. `feedbackVaryings`, when not empty, are
/// captured interleaved by transform feedback. Errors name the program, the stage and quote the log.
Result<GlProgram> buildProgram(const std::string& name, const std::string& vertexSource,
                               const std::string& fragmentSource,
                               const std::vector<const char*>& feedbackVaryings = {});

}  // namespace softtouch::render

#include "render/gl_program.h"

#include <algorithm>

namespace softtouch::render {
namespace {

Result<GLuint> compile(const std::string& name, GLenum stage, const std::string& source) {
    const GLuint shader = glCreateShader(stage);
    const char* text = source.c_str();
    glShaderSource(shader, 1, &text, nullptr);
    glCompileShader(shader);
    GLint ok = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (ok == GL_TRUE)
        return shader;
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(std::size_t(std::max(length, 1)), '\0');
    glGetShaderInfoLog(shader, length, nullptr, log.data());
    glDeleteShader(shader);
    return Status::error("OpenGL: the " + name + (stage == GL_VERTEX_SHADER ? " vertex" : " fragment") +
                         " shader does not compile: " + log.c_str());
}

}  // namespace

void GlProgram::release() {
    if (id != 0)
        glDeleteProgram(id);
    id = 0;
}

Result<GlProgram> buildProgram(const std::string& name, const std::string& vertexSource,
                               const std::string& fragmentSource,
                               const std::vector<const char*>& feedbackVaryings) {
    auto vertex = compile(name, GL_VERTEX_SHADER, vertexSource);
    if (!vertex)
        return Status::error(vertex.message());
    auto fragment = compile(name, GL_FRAGMENT_SHADER, fragmentSource);
    if (!fragment) {
        glDeleteShader(vertex.value());
        return Status::error(fragment.message());
    }
    GlProgram program;
    program.name = name;
    program.id = glCreateProgram();
    glAttachShader(program.id, vertex.value());
    glAttachShader(program.id, fragment.value());
    if (!feedbackVaryings.empty())
        glTransformFeedbackVaryings(program.id, GLsizei(feedbackVaryings.size()), feedbackVaryings.data(),
                                    GL_INTERLEAVED_ATTRIBS);
    glLinkProgram(program.id);
    glDetachShader(program.id, vertex.value());
    glDetachShader(program.id, fragment.value());
    glDeleteShader(vertex.value());
    glDeleteShader(fragment.value());
    GLint ok = GL_FALSE;
    glGetProgramiv(program.id, GL_LINK_STATUS, &ok);
    if (ok == GL_TRUE)
        return program;
    GLint length = 0;
    glGetProgramiv(program.id, GL_INFO_LOG_LENGTH, &length);
    std::string log(std::size_t(std::max(length, 1)), '\0');
    glGetProgramInfoLog(program.id, length, nullptr, log.data());
    program.release();
    return Status::error("OpenGL: the " + name + " program does not link: " + log.c_str());
}

}  // namespace softtouch::render

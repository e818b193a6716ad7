#include "shader.hpp"

#include <vector>

#include "frnn/error.hpp"

namespace frnn::view {
namespace {

GLuint compile(const char* name, GLenum type, const char* source) {
    const GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &source, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        GLint length = 0;
        glGetShaderiv(s, GL_INFO_LOG_LENGTH, &length);
        std::vector<char> log(std::size_t(length) + 1);
        glGetShaderInfoLog(s, length, nullptr, log.data());
        glDeleteShader(s);
        std::string text(log.data());
        for (char& c : text)
            if (c == '\n') c = ' ';  // one line
        throw error(std::string("shader '") + name + "' (" + (type == GL_VERTEX_SHADER ? "vertex" : "fragment") +
                    ") does not compile: " + text);
    }
    return s;
}

}  // namespace

shader_program::shader_program(const char* name, const char* vertex_source, const char* fragment_source) {
    const GLuint vs = compile(name, GL_VERTEX_SHADER, vertex_source);
    GLuint fs = 0;
    try {
        fs = compile(name, GL_FRAGMENT_SHADER, fragment_source);
    } catch (...) {
        glDeleteShader(vs);
        throw;
    }
    id_ = glCreateProgram();
    glAttachShader(id_, vs);
    glAttachShader(id_, fs);
    glLinkProgram(id_);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(id_, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[1024] = {};
        glGetProgramInfoLog(id_, sizeof log, nullptr, log);
        glDeleteProgram(id_);
        throw error(std::string("shader '") + name + "' does not link: " + log);
    }
}

shader_program::~shader_program() { glDeleteProgram(id_); }

}  // namespace frnn::view

// A linked GLSL program from vertex and fragment source; compile and link errors throw
// frnn::error with the driver's log. Needs a current OpenGL context.
#pragma once
#include <string>

#include "gl.hpp"

namespace frnn::view {

class shader_program {
public:
    shader_program(const char* name, const char* vertex_source, const char* fragment_source);
    ~shader_program();
    shader_program(const shader_program&) = delete;
    shader_program& operator=(const shader_program&) = delete;
    GLuint id() const { return id_; }
    GLint uniform(const char* name) const { return glGetUniformLocation(id_, name); }

private:
    GLuint id_ = 0;
};

}  // namespace frnn::view

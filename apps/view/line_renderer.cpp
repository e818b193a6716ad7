#include "line_renderer.hpp"

#include <cstddef>

namespace frnn::view {
namespace {
const char* vertex_source = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 rgb;
uniform mat4 view_projection;
out vec3 tint;
void main() {
    tint = rgb;
    gl_Position = view_projection * vec4(position, 1.0);
}
)";
const char* fragment_source = R"(#version 330 core
in vec3 tint;
out vec4 color;
void main() { color = vec4(tint, 1.0); }
)";
}  // namespace

line_renderer::line_renderer() : program_("lines", vertex_source, fragment_source) {
    glGenVertexArrays(1, &vao_);
    glGenBuffers(1, &vbo_);
    glBindVertexArray(vao_);
    glBindBuffer(GL_ARRAY_BUFFER, vbo_);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(line_vertex), nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(line_vertex), reinterpret_cast<void*>(offsetof(line_vertex, r)));
    glBindVertexArray(0);
}

line_renderer::~line_renderer() {
    glDeleteBuffers(1, &vbo_);
    glDeleteVertexArrays(1, &vao_);
}

void line_renderer::upload(const std::vector<line_vertex>& lines) {
    n_ = GLsizei(lines.size());
    glBindBuffer(GL_ARRAY_BUFFER, vbo_);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(lines.size() * sizeof(line_vertex)), lines.data(), GL_STREAM_DRAW);
}

void line_renderer::draw(const mat4& view_projection) const {
    glUseProgram(program_.id());
    glUniformMatrix4fv(program_.uniform("view_projection"), 1, GL_FALSE, view_projection.data());
    glBindVertexArray(vao_);
    glDrawArrays(GL_LINES, 0, n_);
    glBindVertexArray(0);
}

}  // namespace frnn::view

// Colored line segments (the domain and the colliders), drawn with depth test so particles
// hide what is behind them.
#pragma once
#include <vector>

#include "gl.hpp"
#include "linear_algebra.hpp"
#include "scene_lines.hpp"
#include "shader.hpp"

namespace frnn::view {

class line_renderer {
public:
    line_renderer();
    ~line_renderer();
    line_renderer(const line_renderer&) = delete;
    line_renderer& operator=(const line_renderer&) = delete;
    void upload(const std::vector<line_vertex>& lines);
    void draw(const mat4& view_projection) const;

private:
    shader_program program_;
    GLuint vao_ = 0, vbo_ = 0;
    GLsizei n_ = 0;
};

}  // namespace frnn::view

// Particles as shaded spheres: one camera-facing quad per particle (instanced, one draw call)
// whose fragments outside the disc are dropped and whose depth is that of the sphere's surface,
// so spheres intersect correctly. Each particle carries its position and the value of the
// field it is colored by; the color map and its range are uniforms.
// One buffer upload per frame (upload()); draw() may run any number of times.
#pragma once
#include <cstddef>
#include <vector>

#include "gl.hpp"
#include "linear_algebra.hpp"
#include "shader.hpp"

namespace frnn::view {

class particle_renderer {
public:
    particle_renderer();
    ~particle_renderer();
    particle_renderer(const particle_renderer&) = delete;
    particle_renderer& operator=(const particle_renderer&) = delete;

    /// x: n * 3 positions; value: n field values. One glBufferData of n * 4 floats.
    void upload(const std::vector<float>& x, const std::vector<float>& value);
    void draw(const mat4& view, const mat4& projection, float radius, float range_min, float range_max) const;
    std::size_t count() const { return n_; }

private:
    shader_program program_;
    GLuint vao_ = 0, vbo_ = 0;
    std::size_t n_ = 0;
    std::vector<float> packed_;  // x, y, z, value per particle
};

}  // namespace frnn::view

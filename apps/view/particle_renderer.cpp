#include "particle_renderer.hpp"

#include <string>

#include "colormap.hpp"

namespace frnn::view {
namespace {

const char* vertex_source = R"(#version 330 core
layout(location = 0) in vec4 particle;  // position, field value
uniform mat4 view, projection;
uniform float radius;
out vec2 corner;
out vec3 center;  // view space
out float value;
void main() {
    // Triangle strip over the quad's corners (-1,-1) (1,-1) (-1,1) (1,1).
    corner = vec2(float(gl_VertexID & 1) * 2.0 - 1.0, float(gl_VertexID >> 1) * 2.0 - 1.0);
    center = (view * vec4(particle.xyz, 1.0)).xyz;
    value = particle.w;
    gl_Position = projection * vec4(center + vec3(corner * radius, 0.0), 1.0);
}
)";

std::string fragment_source() {
    std::string s = R"(#version 330 core
in vec2 corner;
in vec3 center;
in float value;
uniform mat4 projection;
uniform float radius, range_min, range_max;
out vec4 color;
const int stops = )" + std::to_string(colormap_stops.size()) + R"(;
const vec3 map[stops] = vec3[stops](
)";
    for (std::size_t k = 0; k < colormap_stops.size(); ++k) {
        const auto& c = colormap_stops[k];
        s += "    vec3(" + std::to_string(c[0]) + ", " + std::to_string(c[1]) + ", " + std::to_string(c[2]) + ")" +
             (k + 1 < colormap_stops.size() ? ",\n" : "\n");
    }
    s += R"();
vec3 colormap(float t) {
    float u = clamp(t, 0.0, 1.0) * float(stops - 1);
    int k = min(int(u), stops - 2);
    return mix(map[k], map[k + 1], u - float(k));
}
void main() {
    float r2 = dot(corner, corner);
    if (r2 > 1.0) discard;
    vec3 normal = vec3(corner, sqrt(1.0 - r2));
    vec4 clip = projection * vec4(center + normal * radius, 1.0);
    gl_FragDepth = clip.z / clip.w * 0.5 + 0.5;
    float span = range_max - range_min;
    float t = span > 0.0 ? (value - range_min) / span : 0.5;
    // A head light: the sphere's center facing the camera shows the map's color exactly.
    color = vec4(colormap(t) * (0.35 + 0.65 * normal.z), 1.0);
}
)";
    return s;
}

}  // namespace

particle_renderer::particle_renderer() : program_("particles", vertex_source, fragment_source().c_str()) {
    glGenVertexArrays(1, &vao_);
    glGenBuffers(1, &vbo_);
    glBindVertexArray(vao_);
    glBindBuffer(GL_ARRAY_BUFFER, vbo_);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, 4 * sizeof(float), nullptr);
    glVertexAttribDivisor(0, 1);  // one particle per instance
    glBindVertexArray(0);
}

particle_renderer::~particle_renderer() {
    glDeleteBuffers(1, &vbo_);
    glDeleteVertexArrays(1, &vao_);
}

void particle_renderer::upload(const std::vector<float>& x, const std::vector<float>& value) {
    n_ = value.size();
    packed_.resize(n_ * 4);
    for (std::size_t i = 0; i < n_; ++i) {
        packed_[i * 4] = x[i * 3];
        packed_[i * 4 + 1] = x[i * 3 + 1];
        packed_[i * 4 + 2] = x[i * 3 + 2];
        packed_[i * 4 + 3] = value[i];
    }
    glBindBuffer(GL_ARRAY_BUFFER, vbo_);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(packed_.size() * sizeof(float)), packed_.data(), GL_STREAM_DRAW);
}

void particle_renderer::draw(const mat4& view, const mat4& projection, float radius, float range_min, float range_max) const {
    if (n_ == 0) return;
    glUseProgram(program_.id());
    glUniformMatrix4fv(program_.uniform("view"), 1, GL_FALSE, view.data());
    glUniformMatrix4fv(program_.uniform("projection"), 1, GL_FALSE, projection.data());
    glUniform1f(program_.uniform("radius"), radius);
    glUniform1f(program_.uniform("range_min"), range_min);
    glUniform1f(program_.uniform("range_max"), range_max);
    glBindVertexArray(vao_);
    glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, GLsizei(n_));
    glBindVertexArray(0);
}

}  // namespace frnn::view

// Writers of the simulation's output: VTK XML PolyData frames (.vtp, base64 binary), the
// ParaView time series (.pvd) and PNG pictures from a small software renderer. Files are
// written atomically (frnn/io/atomic_file.hpp): a reader never sees half a file.
// Complexity O(N) per frame. Thread safety: free functions, reentrant.
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "frnn/sim/ranks.hpp"
#include "frnn/sim/scene.hpp"
#include "frnn/sim/solver.hpp"

namespace frnn::sim {

/// One frame: positions, velocity, speed, density, pressure and id, in particle-id order.
void write_vtp(const std::string& path, const particle_view& p);
/// The same frame written by every rank, a collective call: rank r of P gives the particles
/// with ids [N r / P, N (r + 1) / P) of the frame's N, in any order (solver::id_share), and
/// writes them into the file at their place. Rank 0 makes the temporary file and renames it
/// when every rank has written: the bytes of write_vtp. A failure on any rank throws
/// ranks_agree_error on every rank and leaves no file.
void write_vtp(const std::string& path, const particle_view& p, rank_comm& ranks);
/// The .pvd collection listing (time, file) pairs.
void write_pvd(const std::string& path, const std::vector<std::pair<double, std::string>>& frames);

/// An RGB image, row-major from the top-left.
struct image {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgb;
};
/// Renders the particles as shaded splats colored by speed (blue slow, to white fast) from a
/// fixed camera framing the scene's domain: an oblique perspective view in 3D, the xy plane in
/// 2D. `max_speed` sets the color scale (0: from the frame).
/// Sphere colliders are drawn as grey balls and box colliders by their edges, posed at time t.
image render(const particle_view& p, const scene& s, double particle_radius, int width = 960, int height = 540,
             double max_speed = 0, double t = 0);
/// PNG encoding: 8-bit RGB, the image data compressed by zlib.
std::string encode_png(const image& img);
/// Decodes 8-bit RGB PNGs without row filters (those encode_png writes), for tests.
image decode_png(const std::string& data);

}  // namespace frnn::sim

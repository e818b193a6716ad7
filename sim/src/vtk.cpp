// VTK XML output: PolyData frames and the .pvd series.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include "frnn/io/atomic_file.hpp"
#include "frnn/error.hpp"
#include "frnn/sim/output.hpp"

namespace frnn::sim {

namespace {

/// VTK's "binary" inline format: base64 of a UInt32 byte count followed by the raw bytes.
void append_base64_block(std::string& out, const void* data, std::uint32_t bytes) {
    static const char* tbl = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string raw(sizeof bytes + bytes, '\0');
    std::memcpy(raw.data(), &bytes, sizeof bytes);
    std::memcpy(raw.data() + sizeof bytes, data, bytes);
    out.reserve(out.size() + raw.size() * 4 / 3 + 4);
    std::size_t i = 0;
    for (; i + 2 < raw.size(); i += 3) {
        const std::uint32_t v = std::uint32_t(std::uint8_t(raw[i])) << 16 | std::uint32_t(std::uint8_t(raw[i + 1])) << 8 | std::uint8_t(raw[i + 2]);
        out += tbl[v >> 18 & 63];
        out += tbl[v >> 12 & 63];
        out += tbl[v >> 6 & 63];
        out += tbl[v & 63];
    }
    if (i < raw.size()) {
        std::uint32_t v = std::uint32_t(std::uint8_t(raw[i])) << 16;
        if (i + 1 < raw.size()) v |= std::uint32_t(std::uint8_t(raw[i + 1])) << 8;
        out += tbl[v >> 18 & 63];
        out += tbl[v >> 12 & 63];
        out += i + 1 < raw.size() ? tbl[v >> 6 & 63] : '=';
        out += '=';
    }
}

template <class U>
void data_array(std::string& out, const char* type, const char* name, int comps, const std::vector<U>& v) {
    out += std::string("        <DataArray type=\"") + type + "\" Name=\"" + name + "\" NumberOfComponents=\"" +
           std::to_string(comps) + "\" format=\"binary\">\n          ";
    append_base64_block(out, v.data(), std::uint32_t(v.size() * sizeof(U)));
    out += "\n        </DataArray>\n";
}

}  // namespace

void write_vtp(const std::string& path, const particle_view& p) {
    const std::size_t n = p.n;
    std::vector<float> pos(n * 3, 0.f), vel(n * 3, 0.f), speed(n), rho(n), pr(n);
    std::vector<std::uint32_t> ids(n);
    std::vector<std::int32_t> conn(n), offs(n);
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t k = p.id[i];
        if (k >= n) throw error("write_vtp: particle id " + std::to_string(k) + " out of range");
        double s2 = 0;
        for (int a = 0; a < p.dim; ++a) {
            pos[k * 3 + a] = p.x[i * std::size_t(p.dim) + a];
            vel[k * 3 + a] = p.v[i * std::size_t(p.dim) + a];
            s2 += double(vel[k * 3 + a]) * vel[k * 3 + a];
        }
        speed[k] = float(std::sqrt(s2));
        rho[k] = p.rho[i];
        pr[k] = p.p[i];
        ids[k] = std::uint32_t(k);
    }
    for (std::size_t i = 0; i < n; ++i) conn[i] = std::int32_t(i), offs[i] = std::int32_t(i + 1);
    std::string out;
    out += "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\" "
           "header_type=\"UInt32\">\n  <PolyData>\n    <Piece NumberOfPoints=\"" +
           std::to_string(n) + "\" NumberOfVerts=\"" + std::to_string(n) +
           "\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n";
    out += "      <PointData Scalars=\"speed\" Vectors=\"velocity\">\n";
    data_array(out, "Float32", "velocity", 3, vel);
    data_array(out, "Float32", "speed", 1, speed);
    data_array(out, "Float32", "density", 1, rho);
    data_array(out, "Float32", "pressure", 1, pr);
    data_array(out, "UInt32", "id", 1, ids);
    out += "      </PointData>\n      <Points>\n";
    data_array(out, "Float32", "Points", 3, pos);
    out += "      </Points>\n      <Verts>\n";
    data_array(out, "Int32", "connectivity", 1, conn);
    data_array(out, "Int32", "offsets", 1, offs);
    out += "      </Verts>\n    </Piece>\n  </PolyData>\n</VTKFile>\n";
    io::write_file_atomically(path, out);
}

void write_pvd(const std::string& path, const std::vector<std::pair<double, std::string>>& frames) {
    std::ostringstream o;
    o.precision(9);
    o << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
         "  <Collection>\n";
    for (const auto& [t, file] : frames) o << "    <DataSet timestep=\"" << t << "\" group=\"\" part=\"0\" file=\"" << file << "\"/>\n";
    o << "  </Collection>\n</VTKFile>\n";
    io::write_file_atomically(path, o.str());
}

}  // namespace frnn::sim

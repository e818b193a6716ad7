// frnn::lattice_grid (frnn/lattice.hpp): image copies of the atoms near the cell's faces,
// searched with the atoms by the open-boundary grid, every candidate decided by ASE's formula
// on the caller's coordinates.
#include "frnn/lattice.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <utility>

#include "cpu/parallel.hpp"
#include "frnn/error.hpp"

namespace frnn {

namespace {

template <int D>
using matrix = std::array<std::array<double, D>, D>;

std::string number_text(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.17g", v);
    return text;
}

template <int D>
double norm(const std::array<double, D>& v) {
    double s = 0;
    for (int c = 0; c < D; ++c) s += v[c] * v[c];
    return std::sqrt(s);
}

std::array<double, 3> cross(const std::array<double, 3>& a, const std::array<double, 3>& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

double dot3(const std::array<double, 3>& a, const std::array<double, 3>& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

template <int D>
std::array<double, D> scaled(std::array<double, D> v, double s) {
    for (auto& x : v) x *= s;
    return v;
}

/// Searches of fewer points (atoms and copies) run on the calling thread: waking the pool's
/// workers for their few steps cost more than it saved (64 atoms of diamond at 3.5 A: 63 us
/// per Python call on 1 thread, 88 us on 2).
inline bool small_search(std::size_t points) { return points < 4096; }

/// Component c of S . cell, as the formula takes it: sum_k S_k rows[k][c] in double, k in order.
template <int D>
double shift_vector(const matrix<D>& rows, const std::array<std::int32_t, D>& shift, int c) {
    double v = 0;
    for (int k = 0; k < D; ++k) v += double(shift[k]) * rows[k][c];
    return v;
}

/// Relative size below which periodic vectors count as not spanning their space.
constexpr double degenerate_tolerance = 1e-10;
/// Atoms may lie at most this many cells out along a periodic vector (shifts stay in int32).
constexpr double max_cells_out = double(1 << 28);

/// The cell's frame: a basis whose periodic rows are the lattice vectors and whose open rows
/// are unit vectors completing them (their choice changes nothing: shifts there are 0), and the
/// reciprocal vectors r_k (x = sum_k f_k basis[k] gives f_k = x . r_k; 1/|r_k| is the distance
/// between the cell's faces across axis k).
template <int D>
struct cell_frame {
    matrix<D> basis{};
    matrix<D> reciprocal{};
    std::array<bool, D> pbc{};
};

template <int D>
[[noreturn]] void throw_degenerate(const lattice<D>& cell, const char* what) {
    std::string axes;
    for (int k = 0; k < D; ++k)
        if (cell.pbc[k]) axes += (axes.empty() ? "" : ", ") + std::to_string(k);
    throw error(std::string("lattice: ") + what + " (periodic vectors " + axes + ")");
}

/// The basis completed on the open axes (see cell_frame); throws for a cell that does not span
/// space along its periodic axes, or with a non-finite value.
template <int D>
cell_frame<D> make_frame(const lattice<D>& cell) {
    cell_frame<D> f;
    f.pbc = cell.pbc;
    std::array<std::array<double, 3>, 3> b{};  // the basis in 3D (2D embedded, z = unit)
    int periodic = 0;
    for (int k = 0; k < D; ++k) {
        for (int c = 0; c < D; ++c) {
            const double v = cell.vectors[k][c];
            if (!std::isfinite(v))
                throw error("lattice: vector " + std::to_string(k) + ", component " + std::to_string(c) + " is " +
                            number_text(v));
            if (cell.pbc[k]) b[k][c] = v;
        }
        if (cell.pbc[k]) {
            ++periodic;
            if (norm<3>(b[k]) == 0) throw error("lattice: periodic vector " + std::to_string(k) + " is zero");
        }
    }
    if constexpr (D == 2) b[2] = {0, 0, 1};
    // Complete the open rows: normal to the periodic ones, then to each other.
    std::array<int, 3> open{}, per{};
    int n_open = 0, n_per = 0;
    for (int k = 0; k < D; ++k) (cell.pbc[k] ? per[n_per++] : open[n_open++]) = k;
    if (D == 2) per[n_per] = 2;  // the unit z row takes part in the cross products
    const int rows = D == 2 ? n_per + 1 : n_per;
    if (rows == 2) {
        const auto& p = b[per[0]];
        const auto& q = b[per[1]];
        const auto n = cross(p, q);
        if (norm<3>(n) <= degenerate_tolerance * norm<3>(p) * norm<3>(q))
            throw_degenerate(cell, "the periodic vectors are parallel");
        b[open[0]] = scaled<3>(n, 1 / norm<3>(n));
    } else if (rows == 1) {
        const auto& p = b[per[0]];
        int m = 0;
        for (int c = 1; c < 3; ++c)
            if (std::abs(p[c]) < std::abs(p[m])) m = c;
        std::array<double, 3> axis{};
        axis[m] = 1;
        const auto u = cross(p, axis);
        b[open[0]] = scaled<3>(u, 1 / norm<3>(u));
        const auto v = cross(p, b[open[0]]);
        b[open[1]] = scaled<3>(v, 1 / norm<3>(v));
    } else if (rows == 0) {
        for (int k = 0; k < 3; ++k) b[k] = {0, 0, 0}, b[k][k] = 1;
    }
    const double det = dot3(b[0], cross(b[1], b[2]));
    if (periodic == D && !(std::abs(det) > degenerate_tolerance * norm<3>(b[0]) * norm<3>(b[1]) * norm<3>(b[2])))
        throw_degenerate(cell, "the periodic vectors do not span space");
    const std::array<std::array<double, 3>, 3> r{scaled<3>(cross(b[1], b[2]), 1 / det),
                                                 scaled<3>(cross(b[2], b[0]), 1 / det),
                                                 scaled<3>(cross(b[0], b[1]), 1 / det)};
    for (int k = 0; k < D; ++k)
        for (int c = 0; c < D; ++c) f.basis[k][c] = b[k][c], f.reciprocal[k][c] = r[k][c];
    return f;
}

/// The atoms wrapped into the cell: how many cells each lies out along every periodic vector,
/// its fractional coordinate inside the cell, and its wrapped position (for binning only).
template <class T, int D>
struct wrapped_atoms {
    std::vector<std::int32_t> cells_out;  // D per atom
    std::vector<double> inside;           // D per atom: fractional coordinate in [0, 1] (periodic axes)
    std::vector<double> position;         // D per atom
    double largest = 0;                   // largest |coordinate| of the caller's atoms
};

template <class T, int D>
wrapped_atoms<T, D> wrap_atoms(std::span<const T> coords, const cell_frame<D>& frame, const lattice<D>& cell) {
    const std::size_t n = coords.size() / D;
    wrapped_atoms<T, D> w;
    w.cells_out.assign(n * D, 0);
    w.inside.assign(n * D, 0);
    w.position.resize(n * D);
    for (std::size_t i = 0; i < n; ++i) {
        std::array<double, D> x;
        for (int c = 0; c < D; ++c) {
            x[c] = double(coords[i * D + c]);
            if (!std::isfinite(x[c]))
                throw error("lattice_grid: point " + std::to_string(i) + " has coordinate " + std::to_string(c) +
                            " = " + number_text(x[c]));
            w.largest = std::max(w.largest, std::abs(x[c]));
        }
        std::array<double, D> p = x;
        for (int k = 0; k < D; ++k) {
            if (!frame.pbc[k]) continue;
            double f = 0;
            for (int c = 0; c < D; ++c) f += x[c] * frame.reciprocal[k][c];
            const double out = std::floor(f);
            if (!(std::abs(out) < max_cells_out))
                throw error("lattice_grid: point " + std::to_string(i) + " lies " + number_text(out) +
                            " cells out along lattice vector " + std::to_string(k) + " (at most 2^28)");
            w.cells_out[i * D + k] = std::int32_t(out);
            w.inside[i * D + k] = std::clamp(f - out, 0.0, 1.0);
            for (int c = 0; c < D; ++c) p[c] -= out * cell.vectors[k][c];
        }
        for (int c = 0; c < D; ++c) w.position[i * D + c] = p[c];
    }
    return w;
}

/// Per periodic axis, how many cells beyond [0, 1] an image may lie and still be within
/// `reach` of the cell: reach / (distance between the faces), plus a little for rounding.
template <int D>
std::array<double, D> margins(const cell_frame<D>& frame, double reach) {
    std::array<double, D> m{};
    for (int k = 0; k < D; ++k)
        if (frame.pbc[k]) m[k] = reach * norm<D>(frame.reciprocal[k]) * (1 + 1e-12) + 1e-12;
    return m;
}

/// The shifts of atom `i`'s images within the margins: [lo_k, hi_k] per axis (0 on open axes).
template <class T, int D>
void image_range(const wrapped_atoms<T, D>& w, std::size_t i, const std::array<double, D>& m,
                 std::array<std::int64_t, D>& lo, std::array<std::int64_t, D>& hi) {
    for (int k = 0; k < D; ++k) {
        lo[k] = hi[k] = 0;
        if (m[k] == 0) continue;
        const double f = w.inside[i * D + k];
        lo[k] = std::int64_t(std::ceil(-m[k] - f));
        hi[k] = std::int64_t(std::floor(1 + m[k] - f));
    }
}

/// Image copies of all atoms, counted in double (an overflow-free bound check comes first).
template <class T, int D>
double image_total(const wrapped_atoms<T, D>& w, const std::array<double, D>& m, double& largest_per_atom) {
    double total = 0;
    largest_per_atom = 0;
    const std::size_t n = w.inside.size() / D;
    for (std::size_t i = 0; i < n; ++i) {
        double count = 1;
        for (int k = 0; k < D; ++k) {
            if (m[k] == 0) continue;
            const double f = w.inside[i * D + k];
            count *= std::floor(1 + m[k] - f) - std::ceil(-m[k] - f) + 1;
        }
        total += count - 1;
        largest_per_atom = std::max(largest_per_atom, count - 1);
    }
    return total;
}

/// Refuses, before anything is allocated, image counts beyond the index type or the memory.
void check_image_count(double images, double per_atom, std::size_t atoms, std::size_t dims) {
    const double points = images + double(atoms);
    const double bytes = points * double(dims * 8 * 4 + 24);
    const double memory = double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGESIZE));
    if (points <= double(UINT32_MAX - 1) && (memory <= 0 || bytes <= memory / 2)) return;
    throw error("lattice_grid: the cutoff reaches " + number_text(images) + " periodic images of the " +
                std::to_string(atoms) + " atoms (up to " + number_text(per_atom) + " per atom), about " +
                number_text(std::ceil(bytes / 1e9)) + " GB to search; at most " + std::to_string(UINT32_MAX - 1) +
                " points and half of this machine's " + number_text(std::floor(memory / 1e9)) +
                " GB: use a larger cell (a supercell) or a smaller cutoff");
}

/// A bound, 16 times too large, on how far rounding moves a distance: of the wrapped copies
/// (double) from the true one, and of the formula's (T) from the true one.
template <class T>
double rounding_bound(double limit, double largest, double image_span) {
    const double scale = 4 * largest + 2 * image_span + limit;
    return 16 * double(std::numeric_limits<T>::epsilon()) * scale;
}

/// The search radius: the largest limit plus what rounding of the wrapped copies (double) and
/// of the formula (T) can move a distance by, so that no pair within the limit is missed.
template <class T>
double search_reach(double limit, double largest, double image_span) {
    return limit + 4 * rounding_bound<T>(limit, largest, image_span);
}

/// A bound on |S . cell| over the shifts of the image copies (m: margins<D> of a first reach,
/// whose copies reach at most ceil(m) + 1 cells out), so that the rounding bound holds for
/// strongly sheared cells too, whose copies can lie many vectors' lengths away.
template <int D>
double image_span(const lattice<D>& cell, const std::array<double, D>& m) {
    double s = 0;
    for (int k = 0; k < D; ++k)
        if (cell.pbc[k]) s += (std::ceil(m[k]) + 2) * norm<D>(cell.vectors[k]);
    return s;
}

/// The search radius and the rounding bound for a limit (see rounding_bound).
template <class T, int D>
std::pair<double, double> reach_and_rounding(double limit, double largest, const cell_frame<D>& frame,
                                             const lattice<D>& cell) {
    const double first = limit + limit * 1e-6;  // the rounding bound is far below this
    const double span = image_span<D>(cell, margins<D>(frame, first));
    return {search_reach<T>(limit, largest, span), rounding_bound<T>(limit, largest, span)};
}

}  // namespace

template <class T, int D>
void lattice_grid<T, D>::build(std::span<const T> coords, const lattice<D>& cell, T cutoff,
                               const lattice_options& options) {
    if (!(std::isfinite(cutoff) && cutoff > 0))
        throw error("lattice_grid: cutoff must be finite and > 0, got " + number_text(double(cutoff)));
    build_with(coords, cell, cutoff, {}, options);
}

template <class T, int D>
void lattice_grid<T, D>::build(std::span<const T> coords, const lattice<D>& cell, std::span<const T> radii,
                               const lattice_options& options) {
    if (radii.size() * D != coords.size())
        throw error("lattice_grid: " + std::to_string(radii.size()) + " radii for " +
                    std::to_string(coords.size() / D) + " points");
    T largest = 0;
    for (std::size_t i = 0; i < radii.size(); ++i) {
        if (!(std::isfinite(radii[i]) && radii[i] >= 0))
            throw error("lattice_grid: radius " + std::to_string(i) + " is " + number_text(double(radii[i])) +
                        " (must be finite and >= 0)");
        largest = std::max(largest, radii[i]);
    }
    const T limit = largest + largest;
    if (!std::isfinite(limit)) throw error("lattice_grid: the largest radius doubled is not finite");
    build_with(coords, cell, limit, std::vector<T>(radii.begin(), radii.end()), options);
}

template <class T, int D>
std::size_t lattice_grid<T, D>::count_images(std::span<const T> coords, const lattice<D>& cell, T reach) {
    if (coords.size() % D) throw error("lattice_grid: " + std::to_string(coords.size()) + " values are not whole points");
    const cell_frame<D> f = make_frame(cell);
    const auto w = wrap_atoms<T, D>(coords, f, cell);
    double per_atom = 0;
    const double search = reach_and_rounding<T, D>(double(reach), w.largest, f, cell).first;
    const double total = image_total<T, D>(w, margins<D>(f, search), per_atom);
    return std::size_t(std::min(total, double(std::numeric_limits<std::size_t>::max() / 2)));
}

template <class T, int D>
void lattice_grid<T, D>::build_with(std::span<const T> coords, const lattice<D>& cell, T max_limit,
                                    std::vector<T> radii, const lattice_options& options) {
    if (coords.size() % D)
        throw error("lattice_grid: " + std::to_string(coords.size()) + " values are not whole points of " +
                    std::to_string(D) + " coordinates");
    const std::size_t n = coords.size() / D;
    if (n > UINT32_MAX - 1) throw error("lattice_grid: at most 2^32 - 2 points are supported");
    const cell_frame<D> f = make_frame(cell);
    auto w = wrap_atoms<T, D>(coords, f, cell);
    // A zero limit (all radii 0) still searches a tiny ball: no pair but exact duplicates.
    const double limit = std::max(double(max_limit), std::numeric_limits<double>::min());
    const auto [reach, rounding] = reach_and_rounding<T, D>(limit, w.largest, f, cell);
    const auto m = margins<D>(f, reach);
    double per_atom = 0;
    const double images = image_total<T, D>(w, m, per_atom);
    check_image_count(images, per_atom, n, D);

    // Everything is checked: fill the new state.
    std::vector<double> points(w.position);
    std::vector<std::uint32_t> image_atom;
    std::vector<std::int32_t> image_shift;
    std::vector<T> image_offset;
    matrix<D> rows{};  // the lattice vectors, 0 on open axes: S . cell with S = 0 there
    for (int k = 0; k < D; ++k)
        for (int c = 0; c < D; ++c) rows[k][c] = cell.pbc[k] ? cell.vectors[k][c] : 0.0;
    image_atom.reserve(std::size_t(images));
    image_offset.reserve(std::size_t(images) * D);
    image_shift.reserve(std::size_t(images) * D);
    points.reserve(points.size() + std::size_t(images) * D);
    std::array<std::int64_t, D> lo, hi, s;
    for (std::size_t i = 0; i < n; ++i) {
        image_range<T, D>(w, i, m, lo, hi);
        s = lo;
        while (true) {
            bool zero = true;
            for (int k = 0; k < D; ++k) zero = zero && s[k] == 0;
            if (!zero) {
                image_atom.push_back(std::uint32_t(i));
                for (int c = 0; c < D; ++c) {
                    double shift = 0;
                    for (int k = 0; k < D; ++k) shift += double(s[k]) * f.basis[k][c] * double(f.pbc[k]);
                    points.push_back(w.position[i * D + c] + shift);
                }
                std::array<std::int32_t, D> shift;
                for (int k = 0; k < D; ++k) shift[k] = std::int32_t(s[k]), image_shift.push_back(shift[k]);
                for (int c = 0; c < D; ++c) image_offset.push_back(T(shift_vector<D>(rows, shift, c)));
            }
            int k = 0;  // next shift, first axis fastest
            while (k < D && s[k] == hi[k]) s[k] = lo[k], ++k;
            if (k == D) break;
            ++s[k];
        }
    }
    grid_options search_options;
    search_options.threads = small_search(points.size() / D) ? 1 : options.threads;
    grid<double, D> search(points, reach, search_options);

    cell_ = cell;
    options_ = options;
    rounding_ = rounding;
    cutoff_ = max_limit;
    radii_ = std::move(radii);
    coords_.assign(coords.begin(), coords.end());
    wrap_ = std::move(w.cells_out);
    image_atom_ = std::move(image_atom);
    image_shift_ = std::move(image_shift);
    image_offset_ = std::move(image_offset);
    shift_rows_ = rows;
    search_ = std::move(search);
}

namespace {

/// One entry of a row: the neighbor, its shift, the distance vector and the distance.
template <class T, int D>
struct entry {
    std::uint32_t j;
    std::array<std::int32_t, D> shift;
    std::array<T, D> vector;
    T distance;
};

template <int D>
bool positive(const std::array<std::int32_t, D>& s) {
    for (int k = 0; k < D; ++k)
        if (s[k] != 0) return s[k] > 0;
    return false;
}

}  // namespace

// Two passes over the candidates of each chunk of rows: the first counts the entries each row
// keeps, the second writes them in place. Deciding a candidate twice costs less than gathering
// the entries in growing arrays and copying them (page faults and copies took 3/4 of the time).
template <class T, int D>
lattice_csr<T, D> lattice_grid<T, D>::neighbor_lists(const lattice_list_options& options) const {
    const std::size_t n = size();
    list_options rows;
    rows.rows = n;
    rows.distances = true;
    const csr<double> candidates = search_.neighbor_lists(rows);
    const int threads = small_search(n + image_count()) ? 1 : resolve_thread_count(options_.threads);
    const std::size_t parts = detail::chunk_count(n, threads, 256);

    // Whether candidate g of row i is kept, and its entry.
    auto decide = [&](std::size_t i, std::uint32_t g, entry<T, D>& x) {
        std::array<std::int32_t, D> image{};
        if (g < n) {
            x.j = g;
        } else {
            x.j = image_atom_[g - n];
            for (int k = 0; k < D; ++k) image[k] = image_shift_[std::size_t(g - n) * D + k];
        }
        bool same_cell = true;  // i and j lie in the same cell: S is the copy's shift
        for (int k = 0; k < D; ++k) {
            x.shift[k] = image[k] + wrap_[i * D + k] - wrap_[std::size_t(x.j) * D + k];
            same_cell = same_cell && x.shift[k] == image[k];
        }
        if (options.half && !(x.j > i || (x.j == i && positive<D>(x.shift)))) return false;
        T d2 = 0;
        for (int c = 0; c < D; ++c) {
            T offset;
            if (same_cell) {
                offset = g < n ? T(0) : image_offset_[std::size_t(g - n) * D + c];
            } else {
                offset = T(shift_vector<D>(shift_rows_, x.shift, c));
            }
            const T delta = coords_[std::size_t(x.j) * D + c] - coords_[i * D + c];
            x.vector[c] = delta + offset;
            d2 += x.vector[c] * x.vector[c];
        }
        x.distance = std::sqrt(d2);
        const T limit = radii_.empty() ? cutoff_ : radii_[i] + radii_[x.j];
        return options_.strict ? x.distance < limit : x.distance <= limit;
    };
    auto has_self = [&](std::size_t i) {
        const T limit = radii_.empty() ? cutoff_ : radii_[i] + radii_[i];
        return options.self && (options_.strict ? T(0) < limit : T(0) <= limit);
    };

    lattice_csr<T, D> result;
    result.offsets.resize(n + 1);
    result.offsets[0] = 0;
    detail::for_each_chunk(n, parts, threads, [&](std::size_t, std::size_t b, std::size_t e) {
        entry<T, D> x;
        for (std::size_t i = b; i < e; ++i) {
            std::uint64_t kept = has_self(i) ? 1 : 0;
            const std::uint64_t first = candidates.offsets[i], end = candidates.offsets[i + 1];
            for (std::uint64_t c = first; c < end; ++c) {
                // A candidate whose distance among the copies is below its limit by more than
                // rounding can move it is kept without the formula (most are).
                const std::uint32_t g = candidates.indices[c];
                const std::uint32_t j = g < n ? g : image_atom_[g - n];
                const double limit = radii_.empty() ? double(cutoff_) : double(radii_[i] + radii_[j]);
                const bool sure = candidates.distances[c] < limit - rounding_ && (!options.half || j > i);
                if (sure)
                    ++kept;
                else if (!options.half || j >= i)
                    kept += decide(i, g, x);
            }
            result.offsets[i + 1] = kept;
        }
    });
    for (std::size_t i = 0; i < n; ++i) result.offsets[i + 1] += result.offsets[i];
    const std::size_t total = result.offsets[n];
    result.indices.resize(total);
    result.shifts.resize(total * D);
    if (options.distances) result.distances.resize(total);
    if (options.vectors) result.vectors.resize(total * D);
    detail::for_each_chunk(n, parts, threads, [&](std::size_t, std::size_t b, std::size_t e) {
        std::vector<entry<T, D>> row;
        auto put = [&](std::uint64_t at, const entry<T, D>& x) {
            result.indices[at] = x.j;
            for (int k = 0; k < D; ++k) result.shifts[at * D + k] = x.shift[k];
            if (options.distances) result.distances[at] = x.distance;
            if (options.vectors)
                for (int c = 0; c < D; ++c) result.vectors[at * D + c] = x.vector[c];
        };
        entry<T, D> x;
        for (std::size_t i = b; i < e; ++i) {
            std::uint64_t at = result.offsets[i];
            if (has_self(i)) put(at++, entry<T, D>{std::uint32_t(i), {}, {}, T(0)});
            if (options.order == row_order::none) {
                for (std::uint32_t g : candidates.row(i))
                    if (decide(i, g, x)) put(at++, x);
                continue;
            }
            row.clear();
            for (std::uint32_t g : candidates.row(i))
                if (decide(i, g, x)) row.push_back(x);
            auto by_index = [](const entry<T, D>& p, const entry<T, D>& q) {
                return p.j != q.j ? p.j < q.j : p.shift < q.shift;
            };
            if (options.order == row_order::index)
                std::sort(row.begin(), row.end(), by_index);
            else
                std::sort(row.begin(), row.end(), [&](const entry<T, D>& p, const entry<T, D>& q) {
                    return p.distance != q.distance ? p.distance < q.distance : by_index(p, q);
                });
            for (const auto& y : row) put(at++, y);
        }
    });
    return result;
}

template class lattice_grid<float, 2>;
template class lattice_grid<float, 3>;
template class lattice_grid<double, 2>;
template class lattice_grid<double, 3>;

}  // namespace frnn

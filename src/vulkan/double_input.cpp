// frnn::vulkan::search for double input: float candidates on the device, the decision in double
// on the host, so the answer is the CPU grid's in double and never a float approximation.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "frnn/brute_force.hpp"
#include "device.hpp"
#include "frnn/vulkan.hpp"

namespace frnn::vulkan {

namespace {

const std::string who = "vulkan::search (double input, float device)";

// Float copies of double coordinates, wrapped into the box first on periodic axes (in double,
// as the decision takes them); `largest` grows to the largest magnitude seen.
template <int D>
std::vector<float> to_float(std::span<const double> in, const char* what, const std::vector<double>& periodic,
                            double& largest) {
    if (in.size() % D != 0)
        throw error(who + ": " + std::to_string(in.size()) + " " + what + " coordinates is not a multiple of " +
                    std::to_string(D));
    std::vector<float> out(in.size());
    for (std::size_t i = 0; i < in.size(); ++i) {
        double v = in[i];
        if (!std::isfinite(v))
            throw error(who + ": " + what + " point " + std::to_string(i / D) + " has a non-finite coordinate (axis " +
                        std::to_string(i % D) + ")");
        const std::size_t a = i % D;
        if (a < periodic.size() && periodic[a] > 0 && std::isfinite(periodic[a])) v = wrap_into_box(v, periodic[a]);
        if (std::abs(v) > double(std::numeric_limits<float>::max()))
            throw error(who + ": " + what + " point " + std::to_string(i / D) + " has coordinate " +
                        std::to_string(v) + " on axis " + std::to_string(i % D) +
                        ", beyond the float range of the device; use the CPU grid for such doubles");
        out[i] = float(v);
        largest = std::max(largest, std::abs(v));
    }
    return out;
}

// The float radius within which the device finds every pair the double test accepts. Rounding a
// coordinate v to float moves it by at most 2^-24 |v| (plus 2^-150 for subnormals), so a pair's
// float difference is off by at most 2^-23 sqrt(D) M (M: the largest magnitude, or the box
// length in periodic boxes, whose images are rounded too) before the device's own rounding,
// a few 2^-24 relative, which the factor 1 + 2^-20 covers. The bound is doubled for margin.
template <int D>
float candidate_radius(double r, double largest, const grid_options& o) {
    double box = 0;
    for (std::size_t a = 0; a < o.periodic.size(); ++a) {
        if (o.periodic[a] == 0) continue;  // an open axis
        if (!(o.periodic[a] >= 2 * r) || !std::isfinite(o.periodic[a]))
            throw error(who + ": periodic box length " + std::to_string(o.periodic[a]) + " on axis " +
                        std::to_string(a) + " is not a finite length of at least twice the radius");
        box = std::max(box, o.periodic[a]);
    }
    const double shift = std::ldexp(std::sqrt(double(D)) * (largest + box), -21) + 0x1p-140;
    if (!(shift <= r))
        throw error(who + ": rounding coordinates up to " + std::to_string(largest) +
                    " to float moves pairs by up to " + std::to_string(shift) + ", more than the radius " +
                    std::to_string(r) + ", so the device cannot bound the double answer; use the CPU grid");
    const double wide = (r + shift) * (1 + 0x1p-20);
    float rc = float(wide);
    if (double(rc) < wide) rc = std::nextafter(rc, std::numeric_limits<float>::infinity());
    if (!std::isfinite(rc))
        throw error(who + ": radius " + std::to_string(r) + " is beyond the float range of the device");
    for (std::size_t a = 0; a < o.periodic.size(); ++a)
        if (o.periodic[a] != 0 && double(float(o.periodic[a])) < 2 * double(rc))
            throw error(who + ": periodic box length " + std::to_string(o.periodic[a]) + " on axis " +
                        std::to_string(a) + " is less than twice the widened float radius " +
                        std::to_string(rc) + " the device would search; use the CPU grid");
    return rc;
}

template <int D>
basic_search_result<double> search_double(context& ctx, std::span<const double> coords, double r,
                                          const grid_options& go, const list_options& lo,
                                          std::span<const double> queries, std::size_t k) {
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    if (!(r > 0) || !std::isfinite(r))
        throw error(who + ": radius must be positive and finite, got " + std::to_string(r));
    if (lo.space == index_space::sorted)
        throw error(who + ": index_space::sorted needs the grid's cell order, which search does not return");
    if (lo.rows != list_options::all_rows) throw error(who + ": list_options.rows (rows for some points only) runs on the CPU grid only");
    double largest = 0;
    const std::vector<float> xf = to_float<D>(coords, "data", go.periodic, largest);
    const std::vector<float> qf = to_float<D>(queries, "query", go.periodic, largest);
    grid<D> g(ctx);
    g.build(xf, candidate_radius<D>(r, largest, go), go);
    const auto t1 = clock::now();

    // Candidates: full rows in the caller's numbering, whatever the caller's list options.
    list_options all;
    all.order = row_order::index;
    const bool own = queries.empty();
    const csr<float> cand = own ? g.neighbor_lists(all) : g.query(qf, all);
    basic_search_result<double> out;
    csr<double>& lists = out.lists;
    const std::size_t rows = own ? coords.size() / D : queries.size() / D;
    lists.offsets.assign(rows + 1, 0);
    const double r2 = r * r;
    std::vector<std::pair<double, std::uint32_t>> row;
    for (std::size_t i = 0; i < rows; ++i) {
        const double* x = own ? &coords[i * D] : &queries[i * D];
        row.clear();
        if (own && lo.self) row.emplace_back(0.0, std::uint32_t(i));
        for (std::uint64_t e = cand.offsets[i]; e < cand.offsets[i + 1]; ++e) {
            const std::uint32_t j = cand.indices[e];
            if (own && lo.half && j <= i) continue;
            const double d2 = brute_distance_squared<double, D>(x, &coords[std::size_t(j) * D], go.periodic);
            if (d2 <= r2) row.emplace_back(d2, j);
        }
        // Candidates come by index; by distance (ties by index) for k nearest and that order.
        if (k > 0 || lo.order == row_order::distance) std::sort(row.begin(), row.end());
        else if (own && lo.self) std::sort(row.begin(), row.end(), [](auto& a, auto& b) { return a.second < b.second; });
        if (k > 0 && row.size() > k) row.resize(k);
        for (const auto& [d2, j] : row) {
            lists.indices.push_back(j);
            if (lo.distances) lists.distances.push_back(std::sqrt(d2));
        }
        lists.offsets[i + 1] = lists.indices.size();
    }
    out.kind = g.kind();
    out.slots = g.slot_count();
    out.build_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
    out.query_ms = std::chrono::duration<double, std::milli>(clock::now() - t1).count();
    return out;
}

}  // namespace

basic_search_result<double> search(context& ctx, std::span<const double> coords, int dim, double radius,
                                   const grid_options& grid_opts, const list_options& lists,
                                   std::span<const double> queries, std::size_t k) {
    if (dim != 2 && dim != 3) throw error(who + ": dimension must be 2 or 3, got " + std::to_string(dim));
    return dim == 2 ? search_double<2>(ctx, coords, radius, grid_opts, lists, queries, k)
                    : search_double<3>(ctx, coords, radius, grid_opts, lists, queries, k);
}

}  // namespace frnn::vulkan

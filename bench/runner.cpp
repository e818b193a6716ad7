#include "frnn/bench/runner.hpp"

#include <algorithm>
#include <cstdio>
#include <numeric>
#include <optional>
#include <span>
#include <thread>

#include "frnn/bench/brute_baseline.hpp"
#include "frnn/bench/cell_list.hpp"
#include "frnn/bench/lammps_baseline.hpp"
#include "frnn/bench/measure.hpp"
#include "frnn/bench/nanoflann_baseline.hpp"
#include "frnn/bench/workloads.hpp"
#include "frnn/error.hpp"
#include "frnn/grid.hpp"

namespace frnn::bench {
namespace {

constexpr double mib = 1024.0 * 1024.0;

std::uint64_t total(const std::vector<std::uint32_t>& counts) {
    return std::accumulate(counts.begin(), counts.end(), std::uint64_t(0));
}

// One workload at one size, with its points: records rows, memory and notes into the report.
template <class T, int D>
class case_runner {
public:
    case_runner(const config& cfg, const workload& w, std::size_t size, report& rep, contention* load)
        : cfg_(cfg), rep_(rep), load_(load), coords_(generate<T>(w, size)), radius_(T(w.radius)),
          md_(w.md), box_(periodic_box(w, size)) {
        info_.workload = w.id;
        info_.name = w.name;
        info_.side = lattice_side(w, size);
        info_.n = coords_.size() / D;
        info_.dim = D;
        info_.radius = w.radius;
    }

    void run() {
        if (info_.workload == "W7") {
            for (int t : cfg_.threads) run_radii(t);
            for (auto& text : disagreements(rep_.rows, info_.workload, info_.n)) void_note(text);
            rep_.cases.push_back(std::move(info_));
            return;
        }
        for (int t : cfg_.threads) run_frnn(t);
        if (md_) {
            info_.notes.push_back("periodic cube of side " + std::to_string(box_) + ", double coordinates; pairs of half lists are counted twice, like the others");
            if (cfg_.baselines) run_lammps();
        } else if (cfg_.baselines) {
            for (int t : cfg_.threads) run_nanoflann(t);
            run_cell_list();
            run_brute();
        }
        for (auto& text : disagreements(rep_.rows, info_.workload, info_.n)) void_note(text);
        rep_.cases.push_back(std::move(info_));
    }

private:
    std::span<const T> points() const { return coords_; }
    std::size_t n() const { return info_.n; }

    void say(const std::string& text) const {
        if (cfg_.progress) *cfg_.progress << "bench: " << text << std::endl;
    }
    void void_note(const std::string& text) {
        if (cfg_.progress)
            *cfg_.progress << "\n!!!!!!!! " << text << " !!!!!!!!\n" << std::endl;
        info_.voids.push_back(text);
    }
    void step(const std::string& method, int threads) {
        say(info_.workload + " " + info_.name + " N=" + std::to_string(n()) + ": " + method + ", " +
            std::to_string(threads) + (threads == 1 ? " thread" : " threads"));
        rep_.rss_per_method = reset_peak_rss() && rep_.rss_per_method;
    }
    void add(int threads, const std::string& method, const std::string& phase,
             const measurement& m) {
        rep_.rows.push_back({info_.workload, n(), threads, method, phase, m.median_ms,
                             m.median_ms * 1e6 / double(n()), m.pairs, m.contended_ms, m.load_pairs});
        if (!m.pairs_agree)
            void_note("VOID " + info_.workload + " n=" + std::to_string(n()) + ": " + method + "/" +
                      phase + "/t" + std::to_string(threads) + " found different pair counts in its repetitions" +
                      (load_ ? " (quiet and under load)" : ""));
    }
    void add_memory(int threads, const std::string& method, std::size_t structure_bytes) {
        rep_.memory.push_back({info_.workload, n(), threads, method,
                               double(structure_bytes) / double(n()),
                               double(peak_rss_bytes()) / mib});
    }

    // build, count, list and build+list of one method, plus its memory: make() builds the
    // structure, counts(s) and lists(s) query it. Results are dropped outside the timing.
    template <class Make, class Counts, class Lists>
    void run_method(int threads, const std::string& method, Make make, Counts counts, Lists lists) {
        const int r = cfg_.repeat;
        add(threads, method, "build", measure(r, [&] {
                stopwatch sw;
                sw.start();
                const auto structure = make();
                return sample{sw.stop(), {}};
            }, load_));
        std::size_t structure_bytes = 0;
        {
            const auto structure = make();
            structure_bytes = structure.memory_bytes();
            add(threads, method, "count", measure(r, [&] {
                    stopwatch sw;
                    sw.start();
                    const auto c = counts(structure);
                    const double ms = sw.stop();
                    return sample{ms, total(c)};
                }, load_));
            add(threads, method, "list", measure(r, [&] {
                    stopwatch sw;
                    sw.start();
                    const auto l = lists(structure);
                    return sample{sw.stop(), l.size()};
                }, load_));
        }
        add(threads, method, "build+list", measure(r, [&] {
                stopwatch sw;
                sw.start();
                const auto structure = make();
                const auto l = lists(structure);
                return sample{sw.stop(), l.size()};
            }, load_));
        add_memory(threads, method, structure_bytes);
    }

    void run_frnn(int threads) {
        step("frnn", threads);
        grid_options go;
        go.kind = cfg_.kind;
        go.cell_size = cfg_.cell_factor * double(radius_);
        go.threads = threads;
        if (md_) go.periodic.assign(D, box_);
        list_options lo;
        lo.space = cfg_.space;
        run_method(
            threads, "frnn", [&] { return grid<T, D>(points(), radius_, go); },
            [&](const grid<T, D>& g) { return g.count_neighbors(lo.space); },
            [&](const grid<T, D>& g) { return g.neighbor_lists(lo); });
        if (md_) run_half_lists(threads, go);

        // The next step: every point moved a little; the moved copy is made outside the timing.
        const std::vector<T> moved = moved_copy<T>(points());
        add(threads, "frnn", "update", measure(cfg_.repeat, [&] {
                grid<T, D> g(points(), radius_, go);
                stopwatch sw;
                sw.start();
                g.rebuild(moved);
                return sample{sw.stop(), {}};
            }, load_));
    }

    // W7: the points with a radius per point, uniform in [lo, 2] for lo = 0.5 and 0.2, under
    // each rule, beside the fixed-radius search at 2 (the largest) and at the mean radius.
    void run_radii(int threads) {
        grid_options go;
        go.kind = cfg_.kind;
        go.threads = threads;
        go.cell_size = cfg_.cell_factor * double(radius_);
        list_options lo;
        lo.space = cfg_.space;
        const auto counts = [&](const grid<T, D>& g) { return g.count_neighbors(lo.space); };
        const auto lists = [&](const grid<T, D>& g) { return g.neighbor_lists(lo); };
        auto fixed = [&](double r) {
            step("frnn at r = " + short_number(r), threads);
            run_method(threads, "frnn r=" + short_number(r), [&] { return grid<T, D>(points(), T(r), go); }, counts, lists);
        };
        fixed(double(radius_));
        for (double low : {0.5, 0.2}) {
            fixed((low + double(radius_)) / 2);
            const std::vector<T> radii = point_radii<T>(n(), low, double(radius_), workload_seed + 2);
            for (auto rule : {radius_rule::gather, radius_rule::symmetric}) {
                grid_options per_point = go;
                per_point.rule = rule;
                const std::string method = "frnn " + std::string(to_string(rule)) + " " + short_number(low) + "-" +
                                           short_number(double(radius_));
                step(method, threads);
                run_method(threads, method, [&] { return grid<T, D>(points(), radii, per_point); }, counts, lists);
            }
        }
        info_.notes.push_back("W7: radii uniform in [0.5, 2] and [0.2, 2] (std::mt19937_64 seeded 44); 'frnn r=R' is the "
                              "fixed-radius search of the same points, at 2 and at the mean radius");
    }

    static std::string short_number(double v) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%g", v);
        return buf;
    }

    // The md phases: half lists in the caller's numbering (rows unsorted, then sorted by index,
    // as Python's neighbors(half=True) gives them) and in the grid's, and a build with the
    // sorted ones, which is what LAMMPS's neighbor build is timed against.
    void run_half_lists(int threads, const grid_options& go) {
        const auto half = [](index_space space, row_order order) {
            list_options o;
            o.half = true;
            o.space = space;
            o.order = order;
            return o;
        };
        const grid<T, D> g(points(), radius_, go);
        const auto lists = [&](const std::string& phase, const list_options& o) {
            add(threads, "frnn", phase, measure(cfg_.repeat, [&] {
                    stopwatch sw;
                    sw.start();
                    const auto l = g.neighbor_lists(o);
                    return sample{sw.stop(), 2 * l.size()};
                }, load_));
        };
        lists("half", half(index_space::original, row_order::none));
        lists("half sorted-space", half(index_space::sorted, row_order::none));
        lists("half by-index", half(index_space::original, row_order::index));
        const list_options sorted_rows = half(index_space::original, row_order::index);
        add(threads, "frnn", "build+half by-index", measure(cfg_.repeat, [&] {
                stopwatch sw;
                sw.start();
                const grid<T, D> built(points(), radius_, go);
                const auto l = built.neighbor_lists(sorted_rows);
                return sample{sw.stop(), 2 * l.size()};
            }, load_));
    }

    // LAMMPS's neighbor build (half lists, newton on) on the same atoms: one rank per thread.
    void run_lammps() {
        if (load_) {
            info_.notes.push_back("LAMMPS skipped under load: it runs as separate processes");
            return;
        }
        const std::vector<double> xyz(coords_.begin(), coords_.end());
        for (int t : cfg_.threads) {
            if (const std::string missing = lammps_missing(t); !missing.empty()) {
                info_.notes.push_back(missing);
                continue;
            }
            step("LAMMPS (" + std::to_string(t) + (t == 1 ? " rank)" : " MPI ranks)"), t);
            const lammps_timing l = time_lammps(xyz, box_, double(radius_), t, cfg_.repeat);
            rep_.rows.push_back({info_.workload, n(), t, "lammps", "build+half", l.ms_per_build,
                                 l.ms_per_build * 1e6 / double(n()), 2 * l.half_pairs, {}, 0});
        }
    }

    void run_nanoflann(int threads) {
        step("nanoflann (serial build, parallel searches)", threads);
        using tree = nanoflann_baseline<T, D>;
        run_method(
            threads, "nanoflann", [&] { return tree(points(), radius_); },
            [&](const tree& t) { return t.count_neighbors(threads); },
            [&](const tree& t) { return t.neighbor_lists(threads); });
    }

    void run_cell_list() {
        if (!cell_list<T, D>::cells_needed(points(), radius_)) {
            info_.notes.push_back("cell-list skipped: the bounding box needs more than max(8 N, "
                                  "2^20) cells of edge r, too many for a dense textbook cell list");
            return;
        }
        step("cell-list (textbook, single-threaded)", 1);
        using cells = cell_list<T, D>;
        run_method(
            1, "cell-list", [&] { return cells(points(), radius_); },
            [](const cells& c) { return c.count_neighbors(); },
            [](const cells& c) { return c.neighbor_lists(); });
    }

    void run_brute() {
        if (n() > brute_max_points) {
            info_.notes.push_back("brute skipped: N > " + std::to_string(brute_max_points));
            return;
        }
        step("brute (single-threaded)", 1);
        const int r = cfg_.repeat;
        add(1, "brute", "count", measure(r, [&] {
                stopwatch sw;
                sw.start();
                const auto counts = brute_count_neighbors<T, D>(points(), radius_);
                const double ms = sw.stop();
                return sample{ms, total(counts)};
            }, load_));
        // Brute force has no structure: its lists from scratch are its build+list.
        add(1, "brute", "build+list", measure(r, [&] {
                stopwatch sw;
                sw.start();
                const auto lists = brute_neighbor_lists<T, D>(points(), radius_);
                return sample{sw.stop(), lists.size()};
            }, load_));
        add_memory(1, "brute", 0);
    }

    const config& cfg_;
    report& rep_;
    contention* load_;  // null: no runs under load
    std::vector<T> coords_;
    T radius_;
    bool md_;     // the md workload: periodic, half-list phases, LAMMPS
    double box_;  // its periodic cube's side
    case_info info_;
};

template <class T>
void run_case(const config& cfg, const workload& w, std::size_t size, report& rep, contention* load) {
    if (w.dim == 2)
        case_runner<T, 2>(cfg, w, size, rep, load).run();
    else
        case_runner<T, 3>(cfg, w, size, rep, load).run();
}

std::string settings_text(const config& cfg) {
    std::string s = std::string(cfg.double_precision ? "double" : "float") + " coordinates (W8 always double); grid kind " +
                    std::string(to_string(cfg.kind)) + "; cell size ";
    s += cfg.cell_factor > 0 ? std::to_string(cfg.cell_factor) + " r" : "default";
    s += "; frnn lists in ";
    s += cfg.space == index_space::sorted ? "sorted (cell) order" : "the caller's order";
    if (cfg.contend > 0)
        s += "; median of " + std::to_string(std::max(cfg.repeat, min_load_pairs)) +
             " runs after 1 warm-up, each followed by one under load";
    else
        s += "; median of " + std::to_string(cfg.repeat) + " runs after 1 warm-up";
    return s;
}

}  // namespace

namespace {

// A comma list of V (every workload) and W=V (workload W) items into `all` and `one`.
void parse_size_list(std::string_view text, const std::string& option, const std::string& forms,
                     std::vector<std::size_t>& all, std::map<std::string, std::vector<std::size_t>>& one) {
    if (text.empty()) return;
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        std::string item(text.substr(start, comma - start));
        start = comma + 1;
        std::string id;
        if (const auto eq = item.find('='); eq != std::string::npos) {
            id = find_workload(item.substr(0, eq)).id;
            item = item.substr(eq + 1);
        }
        std::size_t used = 0;
        unsigned long long value = 0;
        try {
            value = std::stoull(item, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used == 0 || used != item.size() || item.find('-') != std::string::npos)
            throw error("bench: " + option + ": '" + item + "' is not a size (expected " + forms + ")");
        (id.empty() ? all : one[id]).push_back(std::size_t(value));
    }
}

}  // namespace

void parse_sizes(std::string_view text, config& cfg) {
    parse_size_list(text, "--n", "N or W2=N", cfg.sizes, cfg.workload_sizes);
}

void parse_sides(std::string_view text, config& cfg) {
    std::vector<std::size_t> all;
    std::map<std::string, std::vector<std::size_t>> one;
    parse_size_list(text, "--side", "S or W1=S", all, one);
    for (const auto& [id, sides] : one)
        if (!find_workload(id).lattice)
            throw error("bench: --side: " + id + " is not a lattice workload (W1, W4, W5 and W8 are); give its --n");
    for (const auto& [id, sides] : one)
        cfg.workload_sides[id].insert(cfg.workload_sides[id].end(), sides.begin(), sides.end());
    cfg.sides.insert(cfg.sides.end(), all.begin(), all.end());
}

std::vector<std::size_t> sizes_for(const config& cfg, const std::string& id) {
    const workload& w = find_workload(id);
    const auto named = [&](const std::map<std::string, std::vector<std::size_t>>& per_workload) {
        const auto it = per_workload.find(w.id);
        return it == per_workload.end() ? std::vector<std::size_t>{} : it->second;
    };
    const auto counts = [&](const std::vector<std::size_t>& sizes, const std::vector<std::size_t>& sides) {
        std::vector<std::size_t> out;
        for (std::size_t n : sizes) out.push_back(point_count(w, n));
        if (w.lattice)
            for (std::size_t side : sides) out.push_back(side_count(w, side));
        return out;
    };
    // Requests for this workload win over those for every workload, which win over the defaults.
    std::vector<std::size_t> chosen = counts(named(cfg.workload_sizes), named(cfg.workload_sides));
    if (chosen.empty()) chosen = counts(cfg.sizes, cfg.sides);
    if (chosen.empty()) chosen = counts(w.sizes, {});
    std::vector<std::size_t> out;
    for (std::size_t n : chosen)
        if (std::find(out.begin(), out.end(), n) == out.end()) out.push_back(n);
    return out;
}

report run(const config& cfg) {
    if (cfg.repeat < 1) throw error("bench: --repeat must be >= 1");
    if (cfg.threads.empty()) throw error("bench: --threads needs at least one value");
    for (int t : cfg.threads)
        if (t < 1) throw error("bench: --threads values must be >= 1, got " + std::to_string(t));
    if (cfg.cell_factor != 0 && !(cfg.cell_factor >= 0.25 && cfg.cell_factor <= 1))
        throw error("bench: --cell must lie in [0.25, 1] (a fraction of r)");
    const auto selected = [&](const std::string& id) {
        return std::find(cfg.workloads.begin(), cfg.workloads.end(), id) != cfg.workloads.end();
    };
    for (const auto& [id, sizes] : cfg.workload_sizes)
        if (!selected(id)) throw error("bench: --n gives sizes for " + id + ", which --workload does not select");
    for (const auto& [id, sides] : cfg.workload_sides)
        if (!selected(id)) throw error("bench: --side gives sides for " + id + ", which --workload does not select");
    if (!cfg.sides.empty() &&
        std::none_of(cfg.workloads.begin(), cfg.workloads.end(), [](const std::string& id) { return find_workload(id).lattice; }))
        throw error("bench: --side needs a lattice workload (W1, W4, W5 or W8) in --workload");
    // Resolve every workload and size before the first (long) measurement.
    std::vector<std::pair<const workload*, std::size_t>> plan;
    for (const auto& id : cfg.workloads) {
        const workload& w = find_workload(id);
        for (std::size_t n : sizes_for(cfg, w.id)) plan.emplace_back(&w, n);
    }

    report rep;
    rep.command = cfg.command;
    rep.machine = cpu_model() + ", " + std::to_string(std::thread::hardware_concurrency()) +
                  " hardware threads";
    rep.build = build_description();
    rep.settings = settings_text(cfg);
    // Made before the points, so that busy children are forked from a small process.
    std::optional<contention> load;
    if (cfg.contend > 0) {
        load.emplace(cfg.contend, cfg.contend_mode);
        rep.load = load->describe();
        rep.autogroup = autogroup_scheduling();
    }
    contention* const load_ptr = load ? &*load : nullptr;
    for (const auto& [w, size] : plan) {
        if (cfg.double_precision || w->md)
            run_case<double>(cfg, *w, size, rep, load_ptr);
        else
            run_case<float>(cfg, *w, size, rep, load_ptr);
    }
    return rep;
}

}  // namespace frnn::bench

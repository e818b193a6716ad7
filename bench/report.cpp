#include "frnn/bench/report.hpp"

#include <algorithm>
#include <cstdio>
#include <set>

#include "frnn/bench/measure.hpp"

namespace frnn::bench {
namespace {

std::string format(const char* pattern, double value) {
    char buf[64];
    std::snprintf(buf, sizeof buf, pattern, value);
    return buf;
}

// About four significant digits, never scientific notation for the sizes we see.
std::string readable(double x) {
    if (x >= 1000) return format("%.0f", x);
    if (x >= 100) return format("%.1f", x);
    if (x >= 10) return format("%.2f", x);
    if (x >= 1) return format("%.3f", x);
    return format("%.3g", x);
}

std::string grouped(std::uint64_t v) {
    std::string digits = std::to_string(v), out;
    for (std::size_t k = 0; k < digits.size(); ++k) {
        if (k && (digits.size() - k) % 3 == 0) out += ',';
        out += digits[k];
    }
    return out;
}

std::string ratio(const row* frnn_row, const row* base) {
    if (!frnn_row || !base || frnn_row->ms <= 0) return "-";
    return readable(base->ms / frnn_row->ms) + "x";
}

std::vector<const row*> rows_of(const report& rep, const case_info& c) {
    std::vector<const row*> out;
    for (const auto& r : rep.rows)
        if (r.workload == c.workload && r.n == c.n) out.push_back(&r);
    return out;
}

std::vector<int> frnn_threads(const report& rep, const case_info& c) {
    std::set<int> t;
    for (const row* r : rows_of(rep, c))
        if (r->method == "frnn") t.insert(r->threads);
    return {t.begin(), t.end()};
}

void ratio_table(std::string& md, const report& rep, const case_info& c) {
    const bool any_baseline = std::any_of(rep.rows.begin(), rep.rows.end(), [&](const row& r) {
        return r.workload == c.workload && r.n == c.n && r.method != "frnn" && r.method != "lammps";
    });
    if (!any_baseline) return;
    md += "\nfrnn's speed-up over each baseline (baseline time / frnn time; nanoflann at the same "
          "thread count, cell-list and brute single-threaded):\n\n";
    md += "| frnn threads | phase | vs nanoflann | vs cell-list | vs brute |\n";
    md += "|---:|---|---:|---:|---:|\n";
    for (int t : frnn_threads(rep, c))
        for (const char* phase : {"build", "count", "list", "build+list"}) {
            const row* f = find_row(rep.rows, c.workload, c.n, t, "frnn", phase);
            if (!f) continue;
            md += "| " + std::to_string(t) + " | " + phase + " | " +
                  ratio(f, find_row(rep.rows, c.workload, c.n, t, "nanoflann", phase)) + " | " +
                  ratio(f, find_row(rep.rows, c.workload, c.n, 1, "cell-list", phase)) + " | " +
                  ratio(f, find_row(rep.rows, c.workload, c.n, 1, "brute", phase)) + " |\n";
        }
}

// The md workload: LAMMPS's neighbor build (half lists) against frnn's build with sorted half
// rows, at as many MPI ranks as frnn threads.
void lammps_table(std::string& md, const report& rep, const case_info& c) {
    std::string lines;
    for (int t : frnn_threads(rep, c)) {
        const row* l = find_row(rep.rows, c.workload, c.n, t, "lammps", "build+half");
        const row* f = find_row(rep.rows, c.workload, c.n, t, "frnn", "build+half by-index");
        if (l && f)
            lines += "| " + std::to_string(t) + " | " + readable(l->ms) + " | " + readable(f->ms) + " | " +
                     ratio(f, l) + " |\n";
    }
    if (lines.empty()) return;
    md += "\nLAMMPS's neighbor build (half lists, `neighbor 0.3 bin`, one MPI rank per frnn thread) "
          "against frnn's build + half lists with rows sorted by index:\n\n";
    md += "| threads (ranks) | LAMMPS ms | frnn ms | LAMMPS / frnn |\n|---:|---:|---:|---:|\n" + lines;
}

// Each row's quiet and contended medians side by side, under the line that names the load.
void load_table(std::string& md, const report& rep, const case_info& c) {
    if (rep.load.empty()) return;
    md += "\nUnder load: " + rep.load + "; kernel autogroup scheduling: " + rep.autogroup +
          ". Each timed run was followed by one under load (load on, " +
          std::to_string(load_settle.count()) + " ms to settle, the run, load off):\n\n";
    md += "| method | threads | phase | quiet ms | contended ms | contended/quiet | pairs of runs |\n";
    md += "|---|---:|---|---:|---:|---:|---:|\n";
    for (const row* r : rows_of(rep, c)) {
        if (!r->contended_ms) continue;
        md += "| " + r->method + " | " + std::to_string(r->threads) + " | " + r->phase + " | " +
              readable(r->ms) + " | " + readable(*r->contended_ms) + " | " +
              (r->ms > 0 ? format("%.2f", *r->contended_ms / r->ms) : std::string("-")) + " | " +
              std::to_string(r->load_pairs) + " |\n";
    }
}

void scaling_table(std::string& md, const report& rep, const case_info& c) {
    const auto threads = frnn_threads(rep, c);
    if (threads.size() < 2) return;
    const int base = threads.front();
    md += "\nfrnn thread scaling (time at " + std::to_string(base) +
          " thread(s) / time at T threads):\n\n";
    md += "| phase | T | ms at " + std::to_string(base) + " | ms at T | speed-up |\n";
    md += "|---|---:|---:|---:|---:|\n";
    for (const auto& phase : phases)
        for (std::size_t k = 1; k < threads.size(); ++k) {
            const row* b = find_row(rep.rows, c.workload, c.n, base, "frnn", phase);
            const row* t = find_row(rep.rows, c.workload, c.n, threads[k], "frnn", phase);
            if (!b || !t) continue;
            md += "| " + phase + " | " + std::to_string(threads[k]) + " | " + readable(b->ms) +
                  " | " + readable(t->ms) + " | " + ratio(t, b) + " |\n";
        }
}

void memory_table(std::string& md, const report& rep, const case_info& c) {
    md += "\nMemory (structure: the search structure alone, per particle; peak RSS: ";
    md += rep.rss_per_method ? "the process's peak while the method ran, input points included)"
                             : "the process's peak since it started: the kernel refused a reset)";
    md += ":\n\n| method | threads | structure bytes/particle | peak RSS MiB |\n|---|---:|---:|---:|\n";
    for (const auto& m : rep.memory)
        if (m.workload == c.workload && m.n == c.n)
            md += "| " + m.method + " | " + std::to_string(m.threads) + " | " +
                  readable(m.structure_bytes_per_particle) + " | " + readable(m.peak_rss_mib) + " |\n";
}

}  // namespace

std::string to_csv(const report& rep) {
    std::string out = std::string(csv_header) + "\n";
    for (const auto& c : rep.cases) {
        for (const row* r : rows_of(rep, c))
            out += r->workload + "," + std::to_string(r->n) + "," + std::to_string(r->threads) +
                   "," + r->method + "," + r->phase + "," + format("%.6g", r->ms) + "," +
                   format("%.6g", r->ns_per_particle) + "," +
                   (r->pairs ? std::to_string(*r->pairs) : std::string()) + "," +
                   (r->contended_ms ? format("%.6g", *r->contended_ms) : std::string()) + "," +
                   (r->load_pairs ? std::to_string(r->load_pairs) : std::string()) + "\n";
        for (const auto& v : c.voids) out += "# " + v + "\n";
    }
    return out;
}

std::string to_markdown(const report& rep) {
    std::string md = "# frnn bench\n\n";
    md += "- command: `" + rep.command + "`\n";
    md += "- machine: " + rep.machine + "\n";
    md += "- build: " + rep.build + "\n";
    md += "- settings: " + rep.settings + "\n";
    md += "- pairs: directed neighbor pairs (entries of the full lists, each pair counted twice); "
          "ns/particle: median time / N\n";
    for (const auto& c : rep.cases) {
        md += "\n## " + c.workload + " " + c.name + ": N = " + grouped(c.n);
        if (c.side != 0) md += " (lattice side " + std::to_string(c.side) + ")";
        md += ", " + std::to_string(c.dim) + "D, r = " + format("%g", c.radius) + "\n\n";
        for (const auto& v : c.voids) md += "**" + v + "** (the comparison is void)\n\n";
        md += "| method | threads | phase | ms | ns/particle | pairs |\n";
        md += "|---|---:|---|---:|---:|---:|\n";
        for (const row* r : rows_of(rep, c))
            md += "| " + r->method + " | " + std::to_string(r->threads) + " | " + r->phase + " | " +
                  readable(r->ms) + " | " + readable(r->ns_per_particle) + " | " +
                  (r->pairs ? grouped(*r->pairs) : std::string("-")) + " |\n";
        load_table(md, rep, c);
        ratio_table(md, rep, c);
        lammps_table(md, rep, c);
        scaling_table(md, rep, c);
        memory_table(md, rep, c);
        if (!c.notes.empty()) {
            md += "\n";
            for (const auto& note : c.notes) md += "- " + note + "\n";
        }
    }
    return md;
}

}  // namespace frnn::bench

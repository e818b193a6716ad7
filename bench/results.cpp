#include "frnn/bench/results.hpp"

#include <map>

namespace frnn::bench {

bool report::void_comparison() const {
    for (const auto& c : cases)
        if (!c.voids.empty()) return true;
    return false;
}

std::vector<std::string> disagreements(const std::vector<row>& rows, const std::string& workload,
                                       std::size_t n) {
    std::map<std::uint64_t, std::vector<std::string>> by_pairs;
    for (const auto& r : rows)
        if (r.workload == workload && r.n == n && r.pairs)
            by_pairs[*r.pairs].push_back(r.method + "/" + r.phase + "/t" + std::to_string(r.threads));
    if (by_pairs.size() <= 1) return {};
    std::string text = "VOID " + workload + " n=" + std::to_string(n) + ": pair counts differ:";
    for (const auto& [pairs, who] : by_pairs) {
        text.append(" ").append(std::to_string(pairs)).append(" (");
        for (std::size_t k = 0; k < who.size(); ++k) text.append(k ? " " : "").append(who[k]);
        text.append(")");
    }
    return {text};
}

const row* find_row(const std::vector<row>& rows, const std::string& workload, std::size_t n,
                    int threads, const std::string& method, const std::string& phase) {
    for (const auto& r : rows)
        if (r.workload == workload && r.n == n && r.threads == threads && r.method == method &&
            r.phase == phase)
            return &r;
    return nullptr;
}

}  // namespace frnn::bench

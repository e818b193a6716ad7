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
    // Methods of one search agree; "frnn r=1.25" or "frnn gather 0.5-2" name another search
    // (W7): what follows the method's first space.
    std::map<std::string, std::map<std::uint64_t, std::vector<std::string>>> by_search;
    for (const auto& r : rows) {
        if (r.workload != workload || r.n != n || !r.pairs) continue;
        const auto space = r.method.find(' ');
        const std::string search = space == std::string::npos ? "" : r.method.substr(space + 1);
        by_search[search][*r.pairs].push_back(r.method + "/" + r.phase + "/t" + std::to_string(r.threads));
    }
    std::vector<std::string> out;
    for (const auto& [search, by_pairs] : by_search) {
        if (by_pairs.size() <= 1) continue;
        std::string text = "VOID " + workload + " n=" + std::to_string(n) + ": pair counts differ:";
        for (const auto& [pairs, who] : by_pairs) {
            text.append(" ").append(std::to_string(pairs)).append(" (");
            for (std::size_t k = 0; k < who.size(); ++k) text.append(k ? " " : "").append(who[k]);
            text.append(")");
        }
        out.push_back(text);
    }
    return out;
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

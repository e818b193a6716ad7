// on_every_rank (frnn/sim/ranks.hpp).
#include <exception>
#include <string>

#include "frnn/sim/ranks.hpp"

namespace frnn::sim {

void on_every_rank(const std::shared_ptr<rank_comm>& ranks, const std::function<void()>& f) {
    if (!ranks || ranks->size() == 1) return f();
    std::string failure;
    try {
        f();
    } catch (const std::exception& e) {
        failure = e.what();
        if (failure.empty()) failure = "failed on rank " + std::to_string(ranks->rank());
    }
    for (const rank_bytes& b : ranks->all_gather(rank_bytes(failure.begin(), failure.end())))
        if (!b.empty()) throw ranks_agree_error(std::string(b.begin(), b.end()));
}

}  // namespace frnn::sim

#include <cstdio>
#include <cstdlib>

#include "fuzz_input.hpp"

namespace frnn::fuzz {

void fail(const char* what) {
    std::fprintf(stderr, "fuzz finding: %s\n", what);
    std::abort();
}

namespace {
std::size_t reached = 0;
}

void reached_checks() { ++reached; }
std::size_t checks_reached() { return reached; }

}  // namespace frnn::fuzz

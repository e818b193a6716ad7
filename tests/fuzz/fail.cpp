#include <cstdio>
#include <cstdlib>

#include "fuzz_input.hpp"

namespace frnn::fuzz {

void fail(const char* what) {
    std::fprintf(stderr, "fuzz finding: %s\n", what);
    std::abort();
}

}  // namespace frnn::fuzz

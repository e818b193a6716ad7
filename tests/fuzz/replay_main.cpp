// Runs a fuzz harness over saved inputs without libFuzzer: each argument is a file or a
// folder of files, each file one input. The replay tests run the committed corpus this way in
// every build, so an input that once found a bug keeps being checked. With --min-reached K,
// at least K inputs must get past the harness's refusals to its checks (reached_checks()).
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

std::size_t reached_inputs = 0;

void replay(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    const std::vector<char> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    const std::size_t before = frnn::fuzz::checks_reached();
    LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
    if (frnn::fuzz::checks_reached() > before) ++reached_inputs;
}

}  // namespace

int main(int argc, char** argv) {
    std::size_t inputs = 0, min_reached = 0;
    for (int k = 1; k < argc; ++k) {
        if (std::strcmp(argv[k], "--min-reached") == 0 && k + 1 < argc) {
            min_reached = std::strtoull(argv[++k], nullptr, 10);
            continue;
        }
        const std::filesystem::path path(argv[k]);
        if (std::filesystem::is_directory(path)) {
            std::vector<std::filesystem::path> files;
            for (const auto& e : std::filesystem::directory_iterator(path))
                if (e.is_regular_file()) files.push_back(e.path());
            std::sort(files.begin(), files.end());
            for (const auto& f : files) replay(f), ++inputs;
        } else if (std::filesystem::is_regular_file(path)) {
            replay(path), ++inputs;
        } else {
            std::fprintf(stderr, "%s: no such file or folder\n", argv[k]);
            return 2;
        }
    }
    if (inputs == 0) {
        std::fprintf(stderr, "no inputs\n");
        return 2;
    }
    std::printf("%zu inputs replayed, %zu reached the checks\n", inputs, reached_inputs);
    if (reached_inputs < min_reached) {
        std::fprintf(stderr, "only %zu inputs reached the checks, fewer than the %zu required: does the harness refuse "
                             "what it should take?\n", reached_inputs, min_reached);
        return 1;
    }
    return 0;
}

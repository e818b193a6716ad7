#include "frnn/bench/measure.hpp"

#include <sys/resource.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <fstream>
#include <sstream>

#include "frnn/simd.hpp"

namespace frnn::bench {

double median(std::vector<double> values) {
    if (values.empty()) return 0;
    std::sort(values.begin(), values.end());
    const std::size_t mid = values.size() / 2;
    return values.size() % 2 ? values[mid] : 0.5 * (values[mid - 1] + values[mid]);
}

bool reset_peak_rss() {
#if defined(__GLIBC__)
    malloc_trim(0);  // give back what earlier methods freed, so it does not count for this one
#endif
    std::ofstream refs("/proc/self/clear_refs");
    if (!refs) return false;
    refs << "5";  // 5: reset the peak RSS (VmHWM) to the current RSS
    refs.close();
    return !refs.fail();
}

std::size_t peak_rss_bytes() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line)) {
        if (line.rfind("VmHWM:", 0) == 0) {
            std::istringstream in(line.substr(6));
            std::size_t kib = 0;
            if (in >> kib) return kib * 1024;
        }
    }
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return std::size_t(usage.ru_maxrss) * 1024;  // KiB on Linux
}

std::string cpu_model() {
    std::ifstream info("/proc/cpuinfo");
    std::string line;
    while (std::getline(info, line)) {
        if (line.rfind("model name", 0) == 0) {
            const auto colon = line.find(':');
            if (colon != std::string::npos) {
                const auto start = line.find_first_not_of(' ', colon + 1);
                if (start != std::string::npos) return line.substr(start);
            }
        }
    }
    return "unknown CPU";
}

std::string build_description() {
    std::string s;
#if defined(__clang__)
    s = "clang++ " __clang_version__;
#elif defined(__GNUC__)
    s = "g++ " + std::to_string(__GNUC__) + "." + std::to_string(__GNUC_MINOR__) + "." +
        std::to_string(__GNUC_PATCHLEVEL__);
#else
    s = "unknown compiler";
#endif
#ifdef NDEBUG
    s += ", NDEBUG";
#else
    s += ", assertions on (not a release build: figures are not representative)";
#endif
    s += ", frnn kernels " + std::string(simd_level());
    return s;
}

}  // namespace frnn::bench

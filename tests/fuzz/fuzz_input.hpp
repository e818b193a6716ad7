// Reading a fuzzer's bytes as the values a harness needs. Every read succeeds: past the end
// of the input it gives zeros, so any byte string is a valid input and the fuzzer's mutations
// always reach the code under test.
#pragma once
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string_view>

namespace frnn::fuzz {

class fuzz_input {
public:
    fuzz_input(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

    std::uint8_t byte() { return at_ < size_ ? data_[at_++] : 0; }
    bool flag() { return byte() & 1; }
    /// A value in [0, n).
    std::size_t below(std::size_t n) { return n == 0 ? 0 : byte() % n; }
    template <class U>
    U raw() {
        unsigned char bytes[sizeof(U)] = {};
        for (auto& b : bytes) b = byte();
        U v;
        std::memcpy(&v, bytes, sizeof v);
        return v;
    }
    /// The rest of the input.
    std::string_view rest() {
        const std::string_view r(reinterpret_cast<const char*>(data_) + at_, size_ - at_);
        at_ = size_;
        return r;
    }

    /// A coordinate or radius of type T: mostly quarter integers times `scale` (exact ties,
    /// lattices), else one of the type's special values or any bit pattern at all.
    template <class T>
    T value(T scale) {
        using lim = std::numeric_limits<T>;
        const std::uint8_t how = byte();
        if (how < 160) return T(std::int8_t(byte())) / 4 * scale;
        if (how < 224) {
            const T special[] = {T(0),          -T(0),        T(1),           lim::max(),      -lim::max(),
                                 lim::min(),    lim::denorm_min(), lim::epsilon(), T(1e7),        T(-1e7),
                                 T(2147483648.0), T(0.5),     lim::infinity(), -lim::infinity(), lim::quiet_NaN(),
                                 std::nextafter(T(1), T(2))};
            return special[byte() % (sizeof special / sizeof special[0])];
        }
        return raw<T>();
    }
    /// A power of two 2^e with e in [-range, range]: the magnitude of a whole input's values.
    template <class T>
    T scale(int range) {
        return std::ldexp(T(1), int(byte() % (2 * range + 1)) - range);
    }

private:
    const std::uint8_t* data_;
    std::size_t size_;
    std::size_t at_ = 0;
};

/// Stops the run with a message: a finding of the fuzzer (and a failed replay test).
[[noreturn]] void fail(const char* what);

/// Called by a harness when an input got past every refusal to its checks (the oracle, a
/// round trip). The replay tests require a minimum number of such inputs, so that a build that
/// refused every input could not pass them.
void reached_checks();
std::size_t checks_reached();  ///< calls of reached_checks() so far

}  // namespace frnn::fuzz

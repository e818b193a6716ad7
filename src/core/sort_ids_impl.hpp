// Sorting one neighbor row's ids, for one instruction-set level: included by sweep_impl.hpp
// inside the level's namespace (see there), after <algorithm>, <cstdint> and <cstring>.
//
// Rows are short (tens of ids) and arrive as a few increasing pieces in random order, where
// std::sort mispredicts a branch per comparison (W8 at 32,000 atoms: 440 ns a row of 39).
// A bitonic network on vectors of 16 ids has no data-dependent branch: at the AVX-512 level
// it sorts such rows 8x faster. GCC's code for it at narrower levels is slower than std::sort,
// which they keep.

#if FRNN_SWEEP_BYTES == 64
/// 16 ids.
typedef std::uint32_t id_vector __attribute__((vector_size(64)));

/// Sorts 16 * V ids held in x[0, V) in increasing order by a bitonic network: for each block
/// size k, each distance j < k, element i meets i ^ j, the smaller going first where i & k is 0.
template <int V>
inline void bitonic_sort(id_vector* x) {
    constexpr std::uint32_t n = 16 * V;
    const id_vector lane = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
#pragma GCC unroll 8
    for (std::uint32_t k = 2; k <= n; k *= 2) {
#pragma GCC unroll 8
        for (std::uint32_t j = k / 2; j > 0; j /= 2) {
            if (j >= 16) {
                // Partners in another vector, same lane; i & k (k > j >= 16) is one per vector.
#pragma GCC unroll 8
                for (int v = 0; v < V; ++v) {
                    const int w = v ^ int(j / 16);
                    if (w < v) continue;
                    const id_vector lo = x[v] < x[w] ? x[v] : x[w];
                    const id_vector hi = x[v] < x[w] ? x[w] : x[v];
                    const bool up = (std::uint32_t(v) * 16 & k) == 0;
                    x[v] = up ? lo : hi;
                    x[w] = up ? hi : lo;
                }
                continue;
            }
            const id_vector partner_lane = lane ^ j;
            const id_vector first = (lane & j) == 0;  // -1 where the lane is the pair's first
#pragma GCC unroll 8
            for (int v = 0; v < V; ++v) {
                const id_vector p = __builtin_shuffle(x[v], partner_lane);
                const id_vector lo = x[v] < p ? x[v] : p;
                const id_vector hi = x[v] < p ? p : x[v];
                const id_vector up = ((std::uint32_t(v) * 16 + lane) & k) == 0;
                x[v] = (first == up) ? lo : hi;
            }
        }
    }
}

template <int V>
inline void sort_padded(std::uint32_t* ids, std::uint32_t n) {
    id_vector x[V];
    std::uint32_t* flat = reinterpret_cast<std::uint32_t*>(x);
    std::memcpy(flat, ids, n * sizeof(std::uint32_t));
    // Padding sorts last: ids are below 2^32 - 1.
    for (std::uint32_t i = n; i < 16u * V; ++i) flat[i] = 0xFFFFFFFFu;
    bitonic_sort<V>(x);
    std::memcpy(ids, flat, n * sizeof(std::uint32_t));
}

#endif

/// Sorts ids[0, n) in increasing order.
inline void sort_ids(std::uint32_t* ids, std::uint32_t n) {
    if (n <= 1) return;
#if FRNN_SWEEP_BYTES == 64
    if (n <= 16) return sort_padded<1>(ids, n);
    if (n <= 32) return sort_padded<2>(ids, n);
    if (n <= 64) return sort_padded<4>(ids, n);
    if (n <= 128) return sort_padded<8>(ids, n);
#endif
    std::sort(ids, ids + n);
}

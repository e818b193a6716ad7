// The build's kernels (not sweeps, but compiled per level with them): the cell slots of
// input points, uniform and hashed, and the bounds of the input.
// Included by sweep_impl.hpp inside the instruction-set level's namespace (see there).

template <class T, int D>
void uniform_slots(const T* coords, std::size_t b, std::size_t e, const uniform_frame& f, std::uint32_t* out) {
    // grid_geometry's cell_of and slot_of_cell in 32-bit lanes (tests/unit/uniform_slots_test
    // checks that they agree); min/max rather than std::clamp, so that the loop is branch-free
    // and vectorizes.
    for (std::size_t i = b; i < e; ++i) {
        std::uint32_t cell[3] = {0, 0, 0};
        for (int a = 0; a < D; ++a) {
            const double u = (double(coords[i * D + a]) - f.lo[a]) * f.inv[a];
            cell[a] = std::uint32_t(std::int32_t(std::min(std::max(u, 0.0), f.top[a])));
        }
        out[i - b] = cell[0] + f.stride1 * cell[1] + f.stride2 * cell[2];
    }
}

template <class T, int D>
void hashed_slots(const T* coords, std::size_t b, std::size_t e, const hashed_frame& f, std::uint32_t* out) {
    for (std::size_t i = b; i < e; ++i) {
        std::int64_t cell[3] = {0, 0, 0};
        for (int a = 0; a < D; ++a)  // |v| < 2^52 cells is checked at build
            cell[a] = floor_to_int(double(coords[i * D + a]) * f.inv[a]);
        out[i - b] = std::uint32_t(hashed_slot(cell[0], cell[1], cell[2], f.mask));
    }
}

template <class T, int D>
void bounds(const T* coords, std::size_t b, std::size_t e, T* lo, T* hi, T* nonfinite) {
    // Over the interleaved values in blocks of 16 points, one accumulator per position: value
    // l of a block belongs to axis l % D, so the loop vectorizes without shuffles. v - v is 0
    // for a finite v and NaN otherwise.
    constexpr std::size_t w = 16 * D;
    T mn[w], mx[w], bad[w];
    for (std::size_t l = 0; l < w; ++l) mn[l] = T(INFINITY), mx[l] = -T(INFINITY), bad[l] = 0;
    const T* __restrict x = coords + b * D;
    const std::size_t total = (e - b) * D;
    auto take = [&](std::size_t l, T v) {
        mn[l] = v < mn[l] ? v : mn[l];
        mx[l] = v > mx[l] ? v : mx[l];
        bad[l] += v - v;
    };
    std::size_t i = 0;
    for (; i + w <= total; i += w)
        for (std::size_t l = 0; l < w; ++l) take(l, x[i + l]);
    for (; i < total; ++i) take(i % w, x[i]);
    for (int a = 0; a < D; ++a) lo[a] = T(INFINITY), hi[a] = -T(INFINITY), nonfinite[a] = 0;
    for (std::size_t l = 0; l < w; ++l) {
        const std::size_t a = l % D;
        lo[a] = std::min(lo[a], mn[l]);
        hi[a] = std::max(hi[a], mx[l]);
        nonfinite[a] += bad[l];
    }
}

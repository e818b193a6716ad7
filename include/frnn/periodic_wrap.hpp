// A coordinate brought into a periodic box [0, L): the one definition of where a point of a
// periodic axis lies, shared by the CPU grid, the brute-force oracle and (in GLSL, the same
// arithmetic) the Vulkan grid. Distances on a periodic axis are taken between wrapped
// coordinates, so a point many boxes out has the neighbors of its image in the box.
//
// fmod is exact (x - k L is a value of T for the integer k it takes), so the only rounding is
// the addition of L that brings a negative remainder up; a result that rounds up to L itself
// is the same point of the circle as 0 and is given as 0. Points already in [0, L) stay as
// they are, bit for bit. Header-only, a pure function: safe from any thread.
#pragma once
#include <cmath>

namespace frnn {

/// x wrapped into [0, length) (x finite, length finite and > 0), see above.
template <class T>
T wrap_into_box(T x, T length) {
    if (x >= 0 && x < length) return x;
    // One box out, the common case, without fmod: its results, in fewer steps (x - L is exact
    // for x in [L, 2L); for x in [-L, 0), fmod gives x itself).
    if (x >= length && x < 2 * length) return x - length;
    T w = x < 0 && x >= -length ? x : std::fmod(x, length);
    if (w < 0) w += length;
    if (!(w < length)) w = 0;
    return w + T(0);  // -0 becomes +0
}

}  // namespace frnn

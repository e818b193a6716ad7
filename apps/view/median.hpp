// The median of a list of times (the viewer's --timing figures): robust to the odd slow frame
// that a mean would carry. O(n) by partial sorting of a copy.
#pragma once
#include <algorithm>
#include <vector>

namespace frnn::view {

inline double median(std::vector<double> v) {
    if (v.empty()) return 0;
    const auto mid = v.begin() + std::ptrdiff_t(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    if (v.size() % 2 == 1) return *mid;
    return 0.5 * (*mid + *std::max_element(v.begin(), mid));
}

}  // namespace frnn::view

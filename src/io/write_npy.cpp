// The .npy writer of any numeric array, and the count of the pairs a filter keeps.
#include <string>

#include "frnn/io/write.hpp"
#include "npy_format.hpp"
#include "frnn/io/atomic_file.hpp"
#include "pairs.hpp"
#include "util.hpp"

namespace frnn::io {

template <class T>
std::uint64_t count_pairs(const csr<T>& lists, pair_filter filter) {
    if (filter == pair_filter::all) return lists.size();
    std::uint64_t m = 0;
    detail::for_each_pair(lists, filter, [&](std::size_t, std::uint32_t, std::uint64_t) { ++m; });
    return m;
}

template <class T>
void write_npy(const std::filesystem::path& file, std::span<const T> data,
               std::span<const std::uint64_t> shape) {
    std::uint64_t count = 1;
    for (std::uint64_t s : shape) count *= s;
    if (count != data.size())
        detail::fail(file.string(), "npy shape holds " + std::to_string(count) +
                                        " values but the array has " + std::to_string(data.size()));
    output_file out(file);
    out.write(detail::make_npy_header(detail::npy_descr<T>(), shape));
    out.write(data.data(), data.size_bytes());
    out.commit();
}

#define FRNN_IO_PAIRS(T)                                                                      \
    template std::uint64_t count_pairs(const csr<T>&, pair_filter);
FRNN_IO_PAIRS(float)
FRNN_IO_PAIRS(double)
#undef FRNN_IO_PAIRS

#define FRNN_IO_NPY(T)                                                                       \
    template void write_npy(const std::filesystem::path&, std::span<const T>,                 \
                            std::span<const std::uint64_t>);
FRNN_IO_NPY(float)
FRNN_IO_NPY(double)
FRNN_IO_NPY(std::int32_t)
FRNN_IO_NPY(std::int64_t)
FRNN_IO_NPY(std::uint32_t)
FRNN_IO_NPY(std::uint64_t)
#undef FRNN_IO_NPY

}  // namespace frnn::io

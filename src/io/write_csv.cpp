// .csv pair writer: "i,j,distance" lines; distances use the shortest text that reads back to
// the same value (std::to_chars), so nothing is lost.
#include <charconv>

#include "frnn/io/write.hpp"
#include "frnn/io/atomic_file.hpp"
#include "pairs.hpp"
#include "util.hpp"

namespace frnn::io {

template <class T>
void write_pairs_csv(const std::filesystem::path& file, const csr<T>& lists, pair_filter filter) {
    if (lists.distances.size() != lists.indices.size())
        detail::fail(file.string(), "csv output needs neighbor lists with distances");
    output_file out(file);
    std::string text = "i,j,distance\n";
    constexpr std::size_t block = 1 << 16;
    text.reserve(block + 128);
    detail::for_each_pair(lists, filter, [&](std::size_t i, std::uint32_t j, std::uint64_t k) {
        char line[96];
        char* p = std::to_chars(line, line + 20, i).ptr;
        *p++ = ',';
        p = std::to_chars(p, p + 20, j).ptr;
        *p++ = ',';
        p = std::to_chars(p, line + sizeof line - 1, lists.distances[k]).ptr;
        *p++ = '\n';
        text.append(line, p);
        if (text.size() >= block) {
            out.write(text);
            text.clear();
        }
    });
    out.write(text);
    out.commit();
}

template void write_pairs_csv(const std::filesystem::path&, const csr<float>&, pair_filter);
template void write_pairs_csv(const std::filesystem::path&, const csr<double>&, pair_filter);

}  // namespace frnn::io

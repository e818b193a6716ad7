#include "frnn/bench/atomic_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "frnn/error.hpp"

namespace frnn::bench {

std::string temporary_path_for(const std::string& path) {
    return path + ".tmp." + std::to_string(::getpid());
}

void commit_file(const std::string& from, const std::string& to) {
    if (std::rename(from.c_str(), to.c_str()) != 0) {
        const std::string why = std::strerror(errno);
        std::remove(from.c_str());
        throw error("cannot write " + to + ": rename from " + from + " failed: " + why);
    }
}

void write_file_atomically(const std::string& path, std::string_view content) {
    if (path.empty()) throw error("cannot write a file with an empty name");
    const std::string temp = temporary_path_for(path);
    {
        std::ofstream out(temp, std::ios::binary | std::ios::trunc);
        if (!out) throw error("cannot write " + path + ": cannot create " + temp + ": " +
                              std::strerror(errno));
        out.write(content.data(), std::streamsize(content.size()));
        out.close();  // close() flushes: its failure (disk full) counts too
        if (out.fail()) {
            std::remove(temp.c_str());
            throw error("cannot write " + path + ": write to " + temp + " failed");
        }
    }
    commit_file(temp, path);
}

}  // namespace frnn::bench

#include "frnn/bench/lammps_baseline.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "frnn/bench/measure.hpp"
#include "frnn/error.hpp"

namespace frnn::bench {
namespace {

namespace fs = std::filesystem;

constexpr double skin = 0.3;
constexpr int builds_per_run = 20;

bool on_path(const std::string& program) {
    const char* path = std::getenv("PATH");
    std::stringstream dirs(path ? path : "");
    for (std::string dir; std::getline(dirs, dir, ':');)
        if (!dir.empty() && ::access((fs::path(dir) / program).c_str(), X_OK) == 0) return true;
    return false;
}

// A fresh folder under the system's temporary folder, removed with everything in it when the
// object goes, also on an exception.
class scratch_folder {
public:
    scratch_folder() {
        std::string pattern = (fs::temp_directory_path() / "frnn-lammps-XXXXXX").string();
        if (!::mkdtemp(pattern.data())) throw error("LAMMPS baseline: cannot make a temporary folder in " + fs::temp_directory_path().string());
        path_ = pattern;
    }
    ~scratch_folder() {
        std::error_code ignored;
        fs::remove_all(path_, ignored);
    }
    scratch_folder(const scratch_folder&) = delete;
    scratch_folder& operator=(const scratch_folder&) = delete;
    const fs::path& path() const { return path_; }

private:
    fs::path path_;
};

void write_inputs(const fs::path& folder, std::span<const double> xyz, double box, double cutoff) {
    std::ofstream data(folder / "atoms.data");
    data.precision(17);
    data << "frnn bench md workload\n\n" << xyz.size() / 3 << " atoms\n1 atom types\n\n";
    for (const char* axis : {"x", "y", "z"}) data << "0 " << box << ' ' << axis << "lo " << axis << "hi\n";
    data << "\nMasses\n\n1 1.0\n\nAtoms # atomic\n\n";
    for (std::size_t i = 0; i < xyz.size() / 3; ++i)
        data << i + 1 << " 1 " << xyz[3 * i] << ' ' << xyz[3 * i + 1] << ' ' << xyz[3 * i + 2] << '\n';
    std::ofstream in(folder / "in.neighbors");
    in.precision(17);
    in << "units lj\natom_style atomic\nboundary p p p\nread_data atoms.data\n"
       << "pair_style zero " << cutoff - skin << "\npair_coeff * *\n"
       << "neighbor " << skin << " bin\nneigh_modify every 1 delay 0 check no\n"
       << "velocity all set 0.0 0.0 0.0\nfix 1 all nve\nrun " << builds_per_run << "\n";
    if (!data || !in) throw error("LAMMPS baseline: cannot write its input into " + folder.string());
}

// The number after "key" on the first line that starts with it, or -1.
double number_after(const std::string& text, const std::string& key) {
    std::stringstream lines(text);
    for (std::string line; std::getline(lines, line);) {
        if (line.rfind(key, 0) != 0) continue;
        std::stringstream rest(line.substr(key.size()));
        double v = -1;
        rest >> v;
        return rest ? v : -1;
    }
    return -1;
}

}  // namespace

std::string lammps_missing(int ranks) {
    if (!on_path("lmp")) return "LAMMPS skipped: no `lmp` on PATH (Debian package lammps)";
    if (ranks > 1 && !on_path("mpirun")) return "LAMMPS skipped: no `mpirun` on PATH for " + std::to_string(ranks) + " ranks";
    return {};
}

lammps_timing time_lammps(std::span<const double> xyz, double box, double cutoff, int ranks, int runs) {
    if (!(cutoff > skin)) throw error("LAMMPS baseline: the cutoff must exceed the skin of 0.3");
    scratch_folder folder;
    write_inputs(folder.path(), xyz, box, cutoff);
    // Open MPI refuses root without these; they change nothing for other users.
    const std::string launcher = ranks > 1 ? "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun -np " +
                                                 std::to_string(ranks) + " "
                                           : std::string();
    const std::string command = "cd '" + folder.path().string() + "' && " + launcher +
                                "lmp -in in.neighbors -log none -screen screen.txt > output.txt 2>&1";
    std::vector<double> per_build;
    lammps_timing out;
    for (int r = 0; r < std::max(runs, 1); ++r) {
        const int status = std::system(command.c_str());
        std::ifstream screen_file(folder.path() / "screen.txt");
        std::stringstream screen;
        screen << screen_file.rdbuf();
        if (status != 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
            throw error("LAMMPS baseline: `" + launcher + "lmp` failed (status " + std::to_string(status) + "): " +
                        screen.str().substr(0, 400));
        // "Neigh | min | avg | max | ..." in seconds over all builds; with one rank all equal.
        std::string neigh_line;
        for (std::string line; std::getline(screen, line);)
            if (line.rfind("Neigh ", 0) == 0) neigh_line = line;
        std::stringstream fields(neigh_line);
        std::string name, bar;
        double min_s = -1, avg_s = -1;
        fields >> name >> bar >> min_s >> bar >> avg_s;
        const double builds = number_after(screen.str(), "Neighbor list builds =");
        const double neighbors = number_after(screen.str(), "Total # of neighbors =");
        if (!fields || avg_s < 0 || builds <= 0 || neighbors < 0)
            throw error("LAMMPS baseline: no Neigh time, build count or neighbor count in LAMMPS's output");
        per_build.push_back(avg_s * 1e3 / builds);
        out.half_pairs = std::uint64_t(neighbors);
    }
    out.ms_per_build = median(per_build);
    return out;
}

}  // namespace frnn::bench

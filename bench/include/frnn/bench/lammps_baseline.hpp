// LAMMPS (the `lmp` program, Debian package lammps; not a dependency of frnn) as the baseline
// of the md workload: its neighbor builds timed on the same atoms, held fixed.
//
// The atoms are written as a LAMMPS data file into a temporary folder (removed afterwards), with
// an input that builds half lists every step (`pair_style zero` at the cutoff minus a skin of
// 0.3, `neighbor 0.3 bin`, `neigh_modify every 1 delay 0 check no`, zero velocities, `run 20`);
// a build's time is the "Neigh" time of the run over its "Neighbor list builds". Several ranks
// run under `mpirun -np`. Not thread-safe (it runs child processes and writes files).
#pragma once
#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace frnn::bench {

struct lammps_timing {
    double ms_per_build = 0;       ///< median over the runs of Neigh time / builds
    std::uint64_t half_pairs = 0;  ///< LAMMPS's "Total # of neighbors": each pair once
};

/// Why LAMMPS cannot be run here (no `lmp` on PATH, or no `mpirun` for ranks > 1); empty when
/// it can.
std::string lammps_missing(int ranks);

/// Times LAMMPS's neighbor builds of the atoms `xyz` (x y z per atom) in the periodic cube
/// [0, box)^3 with cutoff `cutoff` (> 0.3), on `ranks` MPI ranks, `runs` runs of 20 builds.
/// Throws frnn::error when LAMMPS fails or its output lacks the figures.
lammps_timing time_lammps(std::span<const double> xyz, double box, double cutoff, int ranks, int runs);

}  // namespace frnn::bench

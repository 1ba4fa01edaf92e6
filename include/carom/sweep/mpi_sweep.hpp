// A sweep over MPI ranks (carom_mpi, built when MPI is found): rank 0 hands the tasks out one at a
// time to the other ranks as each asks for another, so that long and short tasks balance, and
// writes the tables once every rank is done. Tasks write to their folders in out_dir, which
// every rank must see (a cluster's shared file system).
#pragma once

#include <string>
#include <vector>

#include "carom/sweep/sweep.hpp"

namespace carom {

// The MPI library's own version line ("Open MPI v4.1.4, ...").
std::string mpi_library_version();

struct MpiSweepOutcome {
  int rank = 0, ranks = 1;
  std::vector<TaskResult> results;  // on rank 0: every task's, in the plan's order
};

// Every rank calls this with the same plan (rank 0's is the one run: its text is sent to the
// others) and out_dir. Initialises and finalises MPI. With one rank, runs the sweep on `jobs`
// threads (run_sweep). hooks.stop stops a rank's running task (its checkpoint saved) and, on
// rank 0, the handing out; hooks.progress is called on rank 0. Rank 0 writes the tables and the
// report (to `report`, empty for out_dir/report.html) from every task's result as its rank
// reported it: the same results.csv as run_sweep's. Throws on rank 0 what check_sweep_folder
// and lock_sweep_folder throw; the other ranks then return with no results.
MpiSweepOutcome run_sweep_mpi(const SweepPlan& plan, const std::string& out_dir, unsigned jobs,
                              const SweepHooks& hooks = {}, const std::string& report = {});

}  // namespace carom

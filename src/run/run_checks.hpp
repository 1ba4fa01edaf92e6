// What Runner::check refuses of a run before it runs (run.hpp describes it): check_run_spec,
// check_run_in_box, and the checks against the run's start and the disks its files go to.
#pragma once

#include <vector>

#include "carom/run/run.hpp"

namespace carom {

// Throws what Runner::check throws for `spec` run from `start`, whose simulation is `simulation`;
// `other_outputs` are the front end's own files.
template <std::size_t D>
void check_run(const Simulation<D>& simulation, const Start& start, const RunSpec& spec,
               const std::vector<NamedFile>& other_outputs);

extern template void check_run(const Simulation<2>&, const Start&, const RunSpec&,
                               const std::vector<NamedFile>&);
extern template void check_run(const Simulation<3>&, const Start&, const RunSpec&,
                               const std::vector<NamedFile>&);

}  // namespace carom

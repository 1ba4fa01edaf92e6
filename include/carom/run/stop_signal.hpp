// Opt-in: for a program that wants Ctrl-C to stop a run cleanly. The library never installs a
// handler by itself; a program calls this once and hands the flag to Simulation::set_stop_flag.
#pragma once

#include <atomic>
#include <string>

namespace carom {

// Installs handlers for SIGINT, SIGTERM and SIGHUP that store the signal's number in `flag`
// (lock-free, so safe in a handler); a second signal ends the process at once, the default way.
// SIGPIPE is ignored, so that writing to a closed pipe is an ordinary write error.
void install_stop_handlers(std::atomic<int>& flag);

// "interrupted (SIGINT)", "terminated (SIGTERM)", "hung up (SIGHUP)".
std::string describe_signal(int signal);

}  // namespace carom

#include "carom/run/stop_signal.hpp"

#include <csignal>

namespace carom {

namespace {

// A signal handler can reach only globals: the flag handed over by the one program that asked.
std::atomic<std::atomic<int>*> installed_flag{nullptr};

extern "C" void on_stop_signal(int signal) {
  std::atomic<int>* flag = installed_flag.load();
  // A second request means "now": the default action ends the process.
  if (flag == nullptr || flag->exchange(signal) != 0) {
    std::signal(signal, SIG_DFL);
    std::raise(signal);
  }
}

}  // namespace

void install_stop_handlers(std::atomic<int>& flag) {
  static_assert(
      std::atomic<int>::is_always_lock_free && std::atomic<std::atomic<int>*>::is_always_lock_free,
      "a signal handler may only touch lock-free atomics");
  installed_flag = &flag;
  for (const int signal : {SIGINT, SIGTERM, SIGHUP}) std::signal(signal, on_stop_signal);
  std::signal(SIGPIPE, SIG_IGN);
}

std::string describe_signal(int signal) {
  switch (signal) {
    case SIGINT:
      return "interrupted (SIGINT)";
    case SIGTERM:
      return "terminated (SIGTERM)";
    case SIGHUP:
      return "hung up (SIGHUP)";
    default:
      return "stopped by signal " + std::to_string(signal);
  }
}

}  // namespace carom

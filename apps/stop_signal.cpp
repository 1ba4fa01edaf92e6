#include <csignal>
#include <cstring>

#include "cli_support.hpp"

namespace carom::cli {

namespace {

std::atomic<int> requested{0};

extern "C" void on_stop_signal(int signal) {
  // A second request means "now": the default action ends the process.
  if (requested.exchange(signal) != 0) {
    std::signal(signal, SIG_DFL);
    std::raise(signal);
  }
}

}  // namespace

std::atomic<int>& stop_signal() {
  return requested;
}

void install_stop_handlers() {
  static_assert(std::atomic<int>::is_always_lock_free, "the handler may only touch lock-free data");
  for (const int signal : {SIGINT, SIGTERM, SIGHUP}) std::signal(signal, on_stop_signal);
  // A closed pipe (`carom run ... | head`) is a write error, handled like any other, not a
  // silent death that leaves temporary files behind.
  std::signal(SIGPIPE, SIG_IGN);
}

void stop_if_asked(const std::string& what) {
  if (const int signal = requested.load(); signal != 0) {
    throw Interrupted(signal, signal_name(signal) + ": " + what);
  }
}

std::string signal_name(int signal) {
  switch (signal) {
    case SIGINT:
      return "interrupted (SIGINT)";
    case SIGTERM:
      return "terminated (SIGTERM)";
    case SIGHUP:
      return "hung up (SIGHUP)";
    default:
      return std::string("stopped by signal ") + std::to_string(signal);
  }
}

}  // namespace carom::cli

// libFuzzer entry point: `make fuzz-plan` builds it with clang and runs it on
// tests/fuzz/plan/corpus. Anything but a plan read or refused with a PlanError naming its line (a
// crash, a sanitizer report, another exception) is a finding.
#include "fuzz_plan.hpp"

#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (carom::fuzz::plan(data, size).violations > 0) std::abort();
  return 0;
}

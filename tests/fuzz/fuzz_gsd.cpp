// libFuzzer entry point: `make fuzz-gsd` builds it with clang and runs it on tests/fuzz/gsd/corpus.
// Anything but a clean InputError or a sound start (a crash, a sanitizer report, a start that
// breaks an invariant) is a finding.
#include <cstdlib>

#include "fuzz_checkpoint.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (carom::fuzz::gsd(data, size).violations > 0) std::abort();
  return 0;
}

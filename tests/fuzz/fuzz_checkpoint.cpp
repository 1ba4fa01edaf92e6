// libFuzzer entry point: `make fuzz-checkpoint` builds it with clang and runs it on
// tests/fuzz/checkpoint/corpus.
#include "fuzz_checkpoint.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (carom::fuzz::checkpoint(data, size).violations > 0) std::abort();
  return 0;
}

// libFuzzer entry point: `make fuzz` builds it with clang and runs it on tests/fuzz/corpus.
#include "fuzz_classic_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (carom::fuzz::classic_input(data, size).mismatches > 0) std::abort();
  return 0;
}

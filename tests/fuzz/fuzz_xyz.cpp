// libFuzzer entry point: `make fuzz-xyz` builds it with clang and runs it on
// tests/fuzz/xyz/corpus. Anything but a clean InputError (a crash, a sanitizer report, another
// exception) is a finding.
#include "fuzz_checkpoint.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  carom::fuzz::xyz(data, size);
  return 0;
}

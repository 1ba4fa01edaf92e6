// Replays the fuzzing corpus and every input the fuzzer ever crashed on (tests/fuzz/regressions)
// through the fuzzed code path, with the ordinary compiler: they stay fixed.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "fuzz/fuzz_classic_input.hpp"

namespace {

TEST(FuzzReplay, CorpusAndRegressionsRunClean) {
  int replayed = 0;
  for (const char* folder : {"corpus", "regressions"}) {
    const std::filesystem::path dir = std::filesystem::path(CAROM_FUZZ_DIR) / folder;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
      std::ifstream in(entry.path(), std::ios::binary);
      const std::string bytes((std::istreambuf_iterator<char>(in)), {});
      carom::fuzz::classic_input(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
      ++replayed;
    }
  }
  EXPECT_GT(replayed, 5);
}

}  // namespace

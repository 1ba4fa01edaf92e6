// Replays the fuzzing corpus and every input the fuzzer ever failed on (tests/fuzz/regressions)
// through the fuzzed code path, with the ordinary compiler: they stay fixed, and each does what
// it was kept for.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>

#include "fuzz/fuzz_classic_input.hpp"

namespace {

using carom::fuzz::Outcome;

Outcome replay(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  return carom::fuzz::classic_input(reinterpret_cast<const std::uint8_t*>(bytes.data()),
                                    bytes.size());
}

TEST(FuzzReplay, CorpusAndRegressionsRunCleanAndDoWhatTheyWereKeptFor) {
  std::map<std::string, Outcome> outcomes;
  for (const char* folder : {"corpus", "regressions"}) {
    const std::filesystem::path dir = std::filesystem::path(CAROM_FUZZ_DIR) / folder;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
      const Outcome o = replay(entry.path());
      EXPECT_EQ(o.mismatches, 0) << entry.path() << ": the engines disagree";
      outcomes[entry.path().filename().string()] = o;
    }
  }
  ASSERT_GE(outcomes.size(), 15u);
  // The seed's cases run, events and all, in both boxes.
  for (const char* valid : {"normal.txt", "particles1.txt", "walls_only.txt"}) {
    EXPECT_EQ(outcomes[valid].simulated, 2) << valid;
    EXPECT_GT(outcomes[valid].events, 0) << valid;
  }
  // Spheres: random ones, and a touching cube of eight with ties, run in both boxes.
  for (const char* spheres : {"spheres.txt", "spheres_touching.txt"}) {
    EXPECT_EQ(outcomes[spheres].simulated, 2) << spheres;
    EXPECT_GT(outcomes[spheres].events, 100) << spheres;
  }
  EXPECT_EQ(outcomes["overlap.txt"].refused, 2);  // overlapping disks are refused in both boxes
  EXPECT_EQ(outcomes["spheres_overlap.txt"].refused, 2);
  EXPECT_EQ(outcomes["extreme.txt"].refused, 2);
  // A disk as wide as the box: too wide for a periodic one; with walls, events at t = 0 (the
  // engines' jam guard, tested in engine_test, stops it later than the 50 events run here).
  EXPECT_EQ(outcomes["wedged.txt"].refused, 1);
  EXPECT_EQ(outcomes["wedged.txt"].events, 100);
  // Inputs whose disks could cross the box astronomically often are read, then left to the
  // run-length guard (the CLI refuses them; here they are skipped as too long to replay).
  for (const char* long_run : {"fast-disk-many-crossings.txt", "heavy-disk-speed-bound.txt",
                               "periodic-horizon-below-time-resolution.txt"}) {
    EXPECT_EQ(outcomes[long_run].refused, 0) << long_run;
    EXPECT_EQ(outcomes[long_run].simulated, 0) << long_run;
  }
  // The one that saw a pair through the wrong image now runs, identically in both engines.
  EXPECT_EQ(outcomes["periodic-image-at-half-box.txt"].events, 200);
}

}  // namespace

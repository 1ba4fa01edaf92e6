// Replays the fuzzing corpus and every input the fuzzer ever failed on (tests/fuzz/regressions)
// through the fuzzed code path, with the ordinary compiler: they stay fixed, and each does what
// it was kept for.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>

#include "fuzz/fuzz_checkpoint.hpp"
#include "fuzz/fuzz_classic_input.hpp"
#include "fuzz/fuzz_plan.hpp"

namespace {

using carom::fuzz::Outcome;

std::string bytes_of(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

// Every input named `prefix`... (a hand-made bad one) or crash-... (a fuzzer's find) is refused.
template <class Outcome>
void expect_refused_when_named(const std::map<std::string, Outcome>& outcomes,
                               const std::string& prefix) {
  for (const auto& [name, o] : outcomes) {
    if (name.rfind(prefix, 0) == 0 || name.rfind("crash-", 0) == 0) {
      EXPECT_EQ(o.refused, 1) << name;
    }
  }
}

Outcome replay(const std::filesystem::path& path) {
  const std::string bytes = bytes_of(path);
  return carom::fuzz::classic_input(reinterpret_cast<const std::uint8_t*>(bytes.data()),
                                    bytes.size());
}

// Every file of a fuzzer's corpus and regressions (under tests/fuzz/`reader`), by name.
template <class Outcome, class Replay>
std::map<std::string, Outcome> replay_all(const std::string& reader, const Replay& replay) {
  std::map<std::string, Outcome> outcomes;
  for (const char* folder : {"corpus", "regressions"}) {
    const std::filesystem::path dir = std::filesystem::path(CAROM_FUZZ_DIR) / reader / folder;
    if (!std::filesystem::is_directory(dir)) continue;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
      if (!entry.is_regular_file() || entry.path().filename().string().front() == '.') continue;
      const std::string bytes = bytes_of(entry.path());
      outcomes[entry.path().filename().string()] =
          replay(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
    }
  }
  return outcomes;
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
  // The classic assignment's cases run, events and all, in both boxes.
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
  // Compressions that spun forever (disks pinned between walls) end, in a box with walls; the
  // small valid cases are compressed too, and every packing reads back.
  for (const char* pinned : {"one-disk-in-a-box.txt", "channel.txt"}) {
    EXPECT_GE(outcomes[pinned].compressed, 1) << pinned;
  }
  EXPECT_GE(outcomes["walls_only.txt"].compressed, 1);
}

// The checkpoint reader's corpus: what it accepts resumes without breaking an invariant or going
// back in time; the tampered seeds and the fuzzer's finds are refused.
TEST(FuzzReplay, CheckpointCorpusAndRegressions) {
  const auto outcomes =
      replay_all<carom::fuzz::CheckpointOutcome>("checkpoint", carom::fuzz::checkpoint);
  ASSERT_GE(outcomes.size(), 6u);
  for (const auto& [name, o] : outcomes) EXPECT_EQ(o.violations, 0) << name;
  for (const char* valid : {"walls.ckpt", "periodic.ckpt", "spheres.ckpt", "v1.ckpt"}) {
    ASSERT_TRUE(outcomes.count(valid)) << valid;
    EXPECT_EQ(outcomes.at(valid).resumed, 1) << valid;
    EXPECT_GT(outcomes.at(valid).events, 0) << valid;
  }
  expect_refused_when_named(outcomes, "tampered-");
}

// carom view's reader: carom's own dumps are read; malformed headers and rows are refused with a
// message (a crash or a sanitizer report fails the fuzzer and this replay under test-sanitize).
TEST(FuzzReplay, TrajectoryCorpusAndRegressions) {
  const auto outcomes = replay_all<carom::fuzz::XyzOutcome>("xyz", carom::fuzz::xyz);
  ASSERT_GE(outcomes.size(), 6u);
  for (const char* valid : {"disks.xyz", "spheres.xyz"}) {
    ASSERT_TRUE(outcomes.count(valid)) << valid;
    EXPECT_GT(outcomes.at(valid).frames, 1) << valid;
  }
  expect_refused_when_named(outcomes, "bad-");
}

// The GSD readers: carom's own dumps are read and run, and analysed; truncated and corrupt files
// are refused with a message (a crash or a sanitizer report fails this replay under test-sanitize).
TEST(FuzzReplay, GsdCorpusAndRegressions) {
  const auto outcomes = replay_all<carom::fuzz::GsdOutcome>("gsd", carom::fuzz::gsd);
  ASSERT_GE(outcomes.size(), 4u);
  for (const auto& [name, o] : outcomes) EXPECT_EQ(o.violations, 0) << name;
  for (const char* valid : {"disks.gsd", "spheres.gsd", "lean-on-frame-zero.gsd"}) {
    ASSERT_TRUE(outcomes.count(valid)) << valid;
    EXPECT_EQ(outcomes.at(valid).started, 1) << valid;
    EXPECT_GT(outcomes.at(valid).events, 0) << valid;
    EXPECT_EQ(outcomes.at(valid).analysed, 1) << valid;
  }
  // gsd.hoomd's own file of one disk at the centre, position left at the schema's default.
  ASSERT_TRUE(outcomes.count("default-position.gsd"));
  EXPECT_EQ(outcomes.at("default-position.gsd").started, 1);
  expect_refused_when_named(outcomes, "bad-");
}

// The plan reader (and the tables and report of what it accepts): the documentation's plans and a
// few more are read; plans nested 100,000 deep, and every plan named bad-..., are refused with a
// message naming the line; none breaks anything.
TEST(FuzzReplay, PlanCorpusAndRegressions) {
  const auto outcomes = replay_all<carom::fuzz::PlanOutcome>("plan", carom::fuzz::plan);
  ASSERT_GE(outcomes.size(), 8u);
  for (const auto& [name, o] : outcomes) EXPECT_EQ(o.violations, 0) << name;
  for (const char* valid :
       {"eos.toml", "jamming.toml", "file-start.toml", "many-keys.toml", "sheared.toml",
        "near-equal-axis-values.toml", "same-folder-names.toml"}) {
    ASSERT_TRUE(outcomes.count(valid)) << valid;
    EXPECT_EQ(outcomes.at(valid).accepted, 1) << valid;
    EXPECT_GT(outcomes.at(valid).tasks, 0u) << valid;
  }
  for (const char* deep : {"deep-dotted-key.toml", "deep-table-header.toml"}) {
    ASSERT_TRUE(outcomes.count(deep)) << deep;
    EXPECT_EQ(outcomes.at(deep).refused, 1) << deep;
  }
  expect_refused_when_named(outcomes, "bad-");
}

}  // namespace

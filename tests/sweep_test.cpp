// The sweep's plan (what it accepts and refuses, and where it says the fault is), its tasks and
// their commands, resumable tasks and the tables.
#include "carom/sweep/sweep.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <regex>
#include <set>
#include <sstream>
#include <thread>

namespace carom {
namespace {

namespace fs = std::filesystem;

// The plan of the documentation (README, carom sweep --help).
constexpr const char* kPlan = R"([start]
n = 256
dim = 2
boundary = "periodic"

[run]
end_time = 40
equilibrate = 10
rule = "elastic"

[sweep]
phi = [0.3, 0.5]
seed = [1, 2]
)";

SweepPlan parse(const std::string& text) {
  return SweepPlan::parse(text, "plan.toml", ".");
}

// The message of the PlanError `text` raises ("" if it parses).
std::string refusal(const std::string& text) {
  try {
    parse(text);
  } catch (const PlanError& e) {
    return e.what();
  }
  return "";
}

// The message of the PlanError `text` raises, read as a plan in `folder` ("" if it parses).
std::string refusal_in(const std::string& text, const std::string& folder) {
  try {
    SweepPlan::parse(text, "plan.toml", folder);
  } catch (const PlanError& e) {
    return e.what();
  }
  return "";
}

std::string read(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

class Folder {
 public:
  Folder() : path_(fs::temp_directory_path() / ("carom_sweep_test_" + std::to_string(::getpid()))) {
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~Folder() { fs::remove_all(path_); }
  std::string operator/(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

TEST(SweepPlan, TheDocumentedPlanMakesTheProductOfItsAxesFirstAxisOutermost) {
  const SweepPlan plan = parse(kPlan);
  EXPECT_EQ(plan.kind(), TaskKind::run);
  EXPECT_EQ(plan.axes(), (std::vector<std::string>{"phi", "seed"}));
  std::vector<std::string> names;
  for (const SweepTask& task : plan.tasks()) names.push_back(task.name);
  EXPECT_EQ(names, (std::vector<std::string>{"phi=0.3,seed=1", "phi=0.3,seed=2", "phi=0.5,seed=1",
                                             "phi=0.5,seed=2"}));
}

TEST(SweepPlan, ATaskIsTheCommandsOfCaromInitAndRunWithItsFilesInItsFolder) {
  const SweepPlan plan = parse(kPlan);
  const std::vector<std::string> commands = task_commands(plan, 3, "out/phi=0.5,seed=2");
  ASSERT_EQ(commands.size(), 2u);
  // seed is carom init's option, so a swept seed makes another start.
  EXPECT_EQ(commands[0],
            "carom init --n 256 --dim 2 --boundary periodic --phi 0.5 --seed 2 -o "
            "out/phi=0.5,seed=2/start.txt");
  EXPECT_EQ(commands[1],
            "carom run out/phi=0.5,seed=2/start.txt 40 --equilibrate 10 --rule elastic --log "
            "out/phi=0.5,seed=2/log.csv --log-every 0.15 --summary out/phi=0.5,seed=2/summary.json "
            "--checkpoint out/phi=0.5,seed=2/checkpoint.ckpt --checkpoint-every 600s -q -o "
            "/dev/null");
}

TEST(SweepPlan, KeysOnlyARunHasAreSweptInTheRunAndCompressionsHaveTheirOwn) {
  const SweepPlan plan = parse(R"([start]
n = 64
phi = 0.3
[run]
end_time = 5
[sweep]
equilibrate = [1, 2]
checkpoint_every = ["10s", 1000]
)");
  ASSERT_EQ(plan.tasks().size(), 4u);
  EXPECT_EQ(plan.tasks()[1].name, "equilibrate=1,checkpoint_every=1000");
  EXPECT_NE(task_commands(plan, 1, "d")[1].find("--equilibrate 1 "), std::string::npos);
  EXPECT_NE(task_commands(plan, 1, "d")[1].find("--checkpoint-every 1000 "), std::string::npos);

  const SweepPlan compressions = parse(R"([start]
n = 64
phi = 0.3
boundary = "periodic"
[compress]
jam = true
[sweep]
rate = [0.1, 0.01]
)");
  EXPECT_EQ(compressions.kind(), TaskKind::compress);
  EXPECT_EQ(task_commands(compressions, 1, "d")[1],
            "carom compress d/start.txt --jam --rate 0.01 -o d/packing.txt --summary "
            "d/summary.json -q");
}

// 64 polydisperse disks that jam short of 0.8 when compressed fast (rate 1000).
constexpr const char* kJamsShortOf08 = R"([start]
n = 64
phi = 0.3
polydispersity = 0.2
boundary = "periodic"
[compress]
phi = 0.8
)";

// [compress] and [run] together: each task is carom init's gas, compressed to the swept packing,
// then run there; phi swept is the compression's, seed carom init's (and the chains').
constexpr const char* kFluidStartPlan = R"([start]
n = 64
phi = 0.3
boundary = "periodic"
[compress]
unit_diameter = true
[run]
sampler = "ecmc"
end_time = 4
equilibrate = 1
[sweep]
phi = [0.6, 0.65]
rate = [0.1]
seed = [1, 2]
)";

TEST(SweepPlan, ARunFromACompressedStartIsInitCompressAndRun) {
  const SweepPlan plan = parse(kFluidStartPlan);
  EXPECT_EQ(plan.kind(), TaskKind::run);
  EXPECT_TRUE(plan.compresses_start());
  EXPECT_FALSE(parse(kPlan).compresses_start());
  ASSERT_EQ(plan.tasks().size(), 4u);
  EXPECT_EQ(plan.tasks()[3].name, "phi=0.65,rate=0.1,seed=2");
  const std::vector<std::string> commands = task_commands(plan, 3, "d");
  ASSERT_EQ(commands.size(), 3u);
  EXPECT_EQ(commands[0], "carom init --n 64 --phi 0.3 --boundary periodic --seed 2 -o d/start.txt");
  EXPECT_EQ(commands[1],
            "carom compress d/start.txt --unit-diameter --phi 0.65 --rate 0.1 -o d/packing.txt "
            "--summary d/compression.json -q");
  EXPECT_EQ(commands[2],
            "carom run d/packing.txt 4 --sampler ecmc --equilibrate 1 --seed 2 --log d/log.csv "
            "--log-every 0.015 --summary d/summary.json --checkpoint d/checkpoint.ckpt "
            "--checkpoint-every 600s -q -o /dev/null");
}

// After carom init, kT is the compression's (it gives the particles new velocities), swept or
// set; jam = false is no jam; a lattice start's swept seed is not idle when the start is
// compressed (carom init's velocities shape the packing).
TEST(SweepPlan, ACompressedStartTakesItsKTAndSeedsItsGas) {
  const SweepPlan plan = parse(R"([start]
n = 64
phi = 0.3
lattice = true
[compress]
phi = 0.6
jam = false
[run]
end_time = 4
kT = 1
seed = 5
[sweep]
seed = [1, 2]
)");
  EXPECT_EQ(task_commands(plan, 1, "d")[0],
            "carom init --n 64 --phi 0.3 --lattice --seed 2 -o d/start.txt");
  const SweepPlan swept = parse(R"([start]
n = 64
phi = 0.3
[compress]
phi = 0.6
[run]
end_time = 4
[sweep]
kT = [0.5, 2]
)");
  const std::vector<std::string> commands = task_commands(swept, 1, "d");
  EXPECT_EQ(commands[0], "carom init --n 64 --phi 0.3 -o d/start.txt");
  EXPECT_EQ(commands[1],
            "carom compress d/start.txt --phi 0.6 --kT 2 -o d/packing.txt --summary "
            "d/compression.json -q");
  EXPECT_EQ(commands[2].find("--kT"), std::string::npos) << commands[2];
  const SweepPlan compressions = parse(R"([start]
n = 64
phi = 0.3
[compress]
phi = 0.6
[sweep]
kT = [0.5, 2]
)");
  EXPECT_EQ(task_commands(compressions, 1, "d")[1],
            "carom compress d/start.txt --phi 0.6 --kT 2 -o d/packing.txt --summary "
            "d/summary.json -q");
}

// A task stopped while it compresses keeps no packing and compresses again; stopped in its run,
// it goes on from the packing and its checkpoint: the same files as a task run whole.
TEST(SweepTask, ARunFromACompressedStartStoppedAnywhereEndsTheSame) {
  const Folder folder;
  const SweepPlan plan = parse(kFluidStartPlan);
  ASSERT_EQ(run_task(plan, 2, folder / "whole").status, TaskStatus::done);
  const fs::path whole = fs::path(folder / "whole") / plan.tasks()[2].name;
  const fs::path piece = fs::path(folder / "pieces") / plan.tasks()[2].name;
  const std::atomic<int> stop{15};
  EXPECT_EQ(run_task(plan, 2, folder / "pieces", {&stop, nullptr}).status, TaskStatus::stopped);
  EXPECT_TRUE(fs::exists(piece / "start.txt"));
  EXPECT_FALSE(fs::exists(piece / "packing.txt"));
  EXPECT_FALSE(fs::exists(piece / "checkpoint.ckpt"));
  ASSERT_EQ(run_task(plan, 2, folder / "pieces").status, TaskStatus::done);
  for (const char* name :
       {"start.txt", "packing.txt", "log.csv"}) {  // (a checkpoint names its folder)
    EXPECT_EQ(read(piece / name), read(whole / name)) << name;
  }
  // Stopped after its compression, before its run's first checkpoint: the run starts from the
  // packing kept.
  fs::remove(piece / "summary.json");
  fs::remove(piece / "checkpoint.ckpt");
  fs::remove(piece / "log.csv");
  fs::remove(piece / "start.txt");
  ASSERT_EQ(run_task(plan, 2, folder / "pieces").status, TaskStatus::done);
  EXPECT_FALSE(fs::exists(piece / "start.txt"));
  EXPECT_EQ(read(piece / "log.csv"), read(whole / "log.csv"));
  EXPECT_EQ(read_task_results(plan, folder / "pieces")[2].measures,
            read_task_results(plan, folder / "whole")[2].measures);
  EXPECT_NEAR(read_task_results(plan, folder / "whole")[2].measure("packing_fraction"), 0.65,
              1e-12);
}

// A packing no finished compression vouches for (its compression.json missing, as when killed
// between the two files, or saying the compression was interrupted, as a hand-run carom compress
// stopped part way leaves it) is not the task's state point: it is compressed again.
TEST(SweepTask, APackingWhoseCompressionDidNotEndIsCompressedAgain) {
  const Folder folder;
  const SweepPlan plan = parse(kFluidStartPlan);
  ASSERT_EQ(run_task(plan, 0, folder / "whole").status, TaskStatus::done);
  const fs::path whole = fs::path(folder / "whole") / plan.tasks()[0].name;
  const fs::path piece = fs::path(folder / "pieces") / plan.tasks()[0].name;
  const std::string record = read(whole / "compression.json");
  ASSERT_NE(record.find("\"status\": \"reached_target\""), std::string::npos) << record;
  const std::string interrupted = std::regex_replace(
      record, std::regex("\"status\": \"reached_target\""), "\"status\": \"interrupted\"");
  for (const std::optional<std::string>& left :
       {std::optional<std::string>(), std::optional(interrupted)}) {
    fs::remove_all(folder / "pieces");
    fs::create_directories(piece);
    fs::copy_file(whole / "start.txt", piece / "start.txt");
    fs::copy_file(whole / "start.txt", piece / "packing.txt");  // the gas, uncompressed
    if (left) std::ofstream(piece / "compression.json") << *left;
    ASSERT_EQ(run_task(plan, 0, folder / "pieces").status, TaskStatus::done);
    EXPECT_EQ(read(piece / "packing.txt"), read(whole / "packing.txt"));
    EXPECT_EQ(read(piece / "log.csv"), read(whole / "log.csv"));
  }
}

// A compression that jams short of the run's packing fails the task, as carom compress fails:
// its packing and summary kept, no run, and run again it fails again without compressing again.
TEST(SweepTask, ARunWhoseCompressionJamsShortFailsWithoutARun) {
  const Folder folder;
  const SweepPlan plan = parse(std::string(kJamsShortOf08) + "rate = 1000\n[run]\nend_time = 2\n");
  const std::vector<TaskResult> results = run_sweep(plan, folder / "out", 1);
  ASSERT_EQ(results[0].status, TaskStatus::failed);
  const fs::path task = fs::path(folder / "out") / plan.tasks()[0].name;
  EXPECT_TRUE(results[0].error.starts_with("the disks jammed at packing fraction "))
      << results[0].error;
  EXPECT_TRUE(results[0].error.ends_with(" before reaching 0.8; the jammed packing is in " +
                                         (task / "packing.txt").string() +
                                         ": no run starts from it"))
      << results[0].error;
  EXPECT_TRUE(fs::exists(task / "packing.txt"));
  EXPECT_NE(read(task / "compression.json").find("\"status\": \"jammed\""), std::string::npos);
  EXPECT_FALSE(fs::exists(task / "summary.json"));
  EXPECT_FALSE(fs::exists(task / "log.csv"));
  EXPECT_EQ(read(task / "error.txt"), results[0].error + "\n");
  // Not compressed again: carom init's start, which a compression makes first, is not remade.
  fs::remove(task / "start.txt");
  const std::vector<TaskResult> again = run_sweep(plan, folder / "out", 1);
  EXPECT_EQ(again[0].status, TaskStatus::failed);
  EXPECT_EQ(again[0].error, results[0].error);
  EXPECT_FALSE(fs::exists(task / "start.txt"));
}

TEST(SweepPlan, AStartFromAFileIsReadFromThePlansFolder) {
  const Folder folder;
  const std::string text = "[start]\nfile = \"gas.txt\"\n[run]\nend_time = 5\nkT = 2\n";
  // Read with the plan: a start no task could read is refused before any runs.
  EXPECT_EQ(refusal_in(text, folder / "studies").rfind("plan.toml:2: [start] file: ", 0), 0u)
      << refusal_in(text, folder / "studies");
  fs::create_directories(folder / "studies");
  std::ofstream(folder / "studies/gas.txt") << "2\n0.5\n10 10\n2 2 1 0\n5 5 0 1\n";
  const SweepPlan plan = SweepPlan::parse(text, "studies/plan.toml", folder / "studies");
  const std::vector<std::string> commands = task_commands(plan, 0, "d/task");
  ASSERT_EQ(commands.size(), 1u);  // no carom init
  EXPECT_EQ(commands[0].rfind("carom run " + folder / "studies/gas.txt" + " 5 --kT 2 ", 0), 0u)
      << commands[0];
}

TEST(SweepPlan, BadPlansAreRefusedNamingTheFileLineAndKey) {
  std::string thousand = "[";
  for (int i = 1; i <= 1000; ++i) thousand += std::to_string(i) + (i < 1000 ? ", " : "]");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"[start]\nn = 64\nphi = 0.3\n[run]\nend_time = 5\nvelocity = 2\n",
       "plan.toml:6: [run] velocity: not an option of carom run"},
      {"[start]\nn = 64\nphi = 0.3\n[run]\nend_time = 5\n[sweep]\nseed = []\n",
       "plan.toml:7: [sweep] seed: an axis is a non-empty list of values"},
      {"[start]\nn = 64\n[run]\nend_time = 5\n[sweep]\nphi = [0.3,\n 2.0]\n",
       "plan.toml:6: [sweep] phi = 2 (task phi=2): --phi 2 is above close packing"},
      {"[start]\nn = 64\nphi = 0.3\n[run]\nend_time = 5\nrule = \"sticky\"\n",
       "plan.toml:6: [run] rule: takes swap or elastic"},
      {"[start]\nn = 64.5\nphi = 0.3\n[run]\nend_time = 5\n",
       "plan.toml:2: [start] n: takes a whole number >= 0"},
      {"[start]\nn = 64\nphi = 0.3\n[run]\nequilibrate = 5\n", "plan.toml:4: [run] needs end_time"},
      {"[start]\nn = 64\nphi = 0.3\n[run]\nend_time = 5\nsummary = \"s.json\"\n",
       "plan.toml:6: [run] summary: the sweep writes each task's summary"},
      {"[start]\nn = 64\nphi = 0.3\n[run]\nend_time = 5\n[sweep]\nphi = [0.2]\n",
       "plan.toml:7: [sweep] phi: also set on line 3"},
      {"[start]\nn = 64\nphi = 0.3\n[run]\nend_time = 5\n[sweep]\nseed = [1, 1]\n",
       "plan.toml:7: [sweep] seed: 1 is listed twice"},
      {"[start]\nn = 64\nphi = 0.3\n[run]\nend_time = 5\nrestitution = 2\n",
       "plan.toml:6: [run] restitution = 2: "},
      {"[start]\nn = 64\nphi = 0.3\n[run]\nend_time = 5\ndump = \"../x.gsd\"\n",
       "plan.toml:6: [run] dump: takes a file name, without a folder"},
      {"[start]\nn = 64\nphi = 0.3\n[run]\nend_time = 5\n[runs]\n",
       "plan.toml:6: unknown section [runs]"},
      {"[start]\nn = 64\nphi = 0.3\n",
       "plan.toml:1: a plan has [run] (carom run's options), "
       "[compress] (carom compress's), or both"},
      {"[start]\nn = 64\nphi = 0.3\n[run]\nend_time = 5\n[compress]\njam = true\n",
       "plan.toml:7: [compress] jam: a run starts from its compression's packing"},
      {"[start]\nn = 64\nphi = 0.3\n[run]\nend_time = 5\n[compress]\nrate = 0.1\n",
       "plan.toml:6: [compress] needs phi (the packing fraction each run starts at)"},
      {"[start]\nn = 64\n[run]\nend_time = 5\n[compress]\n[sweep]\nphi = [0.6]\n",
       "plan.toml:1: [start] needs phi (carom init --phi: the gas each run's start is compressed "
       "from), set; a swept phi is the compression's"},
      {"[start]\nn = 64\nphi = 0.3\n[run]\nend_time = 5\n[compress]\nphi = 0.6\n[sweep]\n"
       "jam_presure = [1e6]\n",
       "plan.toml:9: [sweep] jam_presure: not an option of [start], [compress] or [run]"},
      {"[start]\nn = 64\nphi = 0.3\n[run]\nend_time = 5\n[compress]\nphi = 0.6\n[sweep]\n"
       "phi = [0.5]\n",
       "plan.toml:9: [sweep] phi: also set on line 7"},
      {"[start]\nfile = \"a.txt\"\nn = 3\n[run]\nend_time = 5\n",
       "plan.toml:3: [start] n: a start read from a file takes no carom init options"},
      {"[start]\nn = 64\nphi = 0.3\n[run]\nend_time = = 5\n", "plan.toml:5: "},
      {"[start]\nn = 64\nphi = 0.3\n[run]\nend_time = 5\ncheckpoint_every = \"10m\"\n",
       "plan.toml:6: [run] checkpoint_every: --checkpoint-every"},
      // What the compression after carom init replaces, and what a later command sets again.
      {"[start]\nn = 64\nphi = 0.3\nkT = 2\n[run]\nend_time = 5\n[compress]\nphi = 0.6\n",
       "plan.toml:4: [start] kT: the compression gives the particles new velocities at [compress] "
       "kT"},
      {"[start]\nn = 64\nphi = 0.3\nkT = 2\n[compress]\nphi = 0.6\n",
       "plan.toml:4: [start] kT: the compression gives the particles new velocities"},
      {"[start]\nn = 64\nphi = 0.3\n[run]\nend_time = 5\nkT = 1\n[sweep]\nkT = [0.5, 2]\n",
       "plan.toml:8: [sweep] kT: [run] kT on line 6 replaces it in every task"},
      {"[start]\nn = 64\nphi = 0.3\n[run]\nend_time = 5\nboundary = \"periodic\"\n[sweep]\n"
       "boundary = [\"walls\", \"periodic\"]\n",
       "plan.toml:8: [sweep] boundary: [run] boundary on line 6 replaces it in every task"},
      {"[start]\nn = 64\nphi = 0.3\n[run]\nend_time = 5\n[compress]\nphi = 0.6\n"
       "boundary = \"periodic\"\n[sweep]\nboundary = [\"walls\", \"periodic\"]\n",
       "plan.toml:10: [sweep] boundary: [compress] boundary on line 8 replaces it in every task"},
      {"[start]\nn = 64\nphi = 0.3\n[run]\nend_time = 5\nkT = 1\n[compress]\nphi = 0.6\n"
       "[sweep]\nkT = [0.5, 2]\n",
       "plan.toml:10: [sweep] kT: [run] kT on line 6 replaces it in every task"},
      {"[start]\nn = 64\nphi = 0.3\n[run]\nend_time = 5\n[compress]\nphi = 0.6\nkT = 2\n"
       "[sweep]\nkT = [0.5, 2]\n",
       "plan.toml:10: [sweep] kT: also set on line 8"},
      // What the compression would refuse, before it runs.
      {"[start]\nn = 64\nphi = 0.4\n[run]\nend_time = 5\n[compress]\n[sweep]\nphi = [0.6, 0.3]\n",
       "plan.toml:8: [sweep] phi = 0.3 (task phi=0.3): the target packing fraction 0.3 is not "
       "above "
       "the start's, 0.4"},
      {"[start]\nn = 64\nphi = 0.4\n[run]\nend_time = 5\n[compress]\n[sweep]\nphi = [0.95]\n",
       "plan.toml:8: [sweep] phi = 0.95 (task phi=0.95): the target packing fraction 0.95 is "
       "beyond 0.9068996821171089 (close packing)"},
      {"[start]\nn = 64\nphi = 0.4\n[run]\nend_time = 5\n[compress]\nphi = 0.6\n[sweep]\n"
       "rate = [0.1, -1]\n",
       "plan.toml:9: [sweep] rate = -1 (task rate=-1): the growth rate must be a positive number"},
      {"[start]\nn = 64\nphi = 0.4\n[compress]\njam = false\n",
       "plan.toml:4: [compress] needs phi (the packing fraction to stop at) or jam = true"},
      {"[start]\nn = 64\nphi = 0.4\n[compress]\nphi = 0.6\nkT = 0\n",
       "plan.toml:6: [compress] kT = 0: the temperature must be a positive number"},
      {"[start]\nn = 64\nphi = 0.4\n[compress]\njam = true\njam_pressure = 1e20\n",
       "plan.toml:6: [compress] jam_pressure = 1e+20: the jamming pressure must be at most 1e+14"},
      {"[start]\nn = 64\nphi = 0.3\n[run]\nend_time = 5\n[sweep]\nseed = " + thousand +
           "\nequilibrate = " + thousand + "\n",
       "plan.toml:7: [sweep] makes 1000000 tasks, more than a plan may have (100000)"},
  };
  for (const auto& [text, expected] : cases) {
    const std::string said = refusal(text);
    EXPECT_EQ(said.rfind(expected, 0), 0u) << "plan:\n" << text << "said: " << said;
  }
}

TEST(SweepPlan, AMissingPlanATaskOutOfRangeAndResultsOfAnotherPlanAreRefused) {
  EXPECT_THROW(SweepPlan::read("/nonexistent/plan.toml"), PlanError);
  const SweepPlan plan = parse(kPlan);
  EXPECT_THROW(task_commands(plan, 4, "d"), RequestError);
  EXPECT_THROW(run_task(plan, 4, "d"), RequestError);
  EXPECT_THROW(check_task_results(plan, std::vector<TaskResult>(3)), std::invalid_argument);
}

// A small plan whose tasks take milliseconds.
constexpr const char* kSmallPlan = R"([start]
n = 16
boundary = "periodic"
[run]
end_time = 2
equilibrate = 1
rule = "elastic"
checkpoint_every = 100
[sweep]
phi = [0.2, 0.3]
seed = [1, 2]
)";

TEST(SweepTask, ADoneTaskIsReadNotRunAgainAndAChangedPlanIsRefused) {
  const Folder folder;
  const SweepPlan plan = parse(kSmallPlan);
  const TaskResult first = run_task(plan, 0, folder / "out");
  ASSERT_EQ(first.status, TaskStatus::done) << first.error;
  EXPECT_EQ(first.dimension, 2);
  const fs::path summary = fs::path(folder / "out") / plan.tasks()[0].name / "summary.json";
  const auto written = fs::last_write_time(summary);
  const TaskResult again = run_task(plan, 0, folder / "out");
  EXPECT_EQ(fs::last_write_time(summary), written);
  EXPECT_EQ(again.measures, first.measures);

  std::string changed = kSmallPlan;
  changed.replace(changed.find("end_time = 2"), 12, "end_time = 3");
  EXPECT_THROW(check_sweep_folder(parse(changed), folder / "out"), RequestError);
  EXPECT_THROW(run_task(parse(changed), 0, folder / "out"), RequestError);
}

TEST(SweepTask, ATransportPlanMeasuresTransportCoefficients) {
  const Folder folder;
  std::string text = kSmallPlan;
  text.replace(text.find("n = 16"), 6, "n = 60\ndim = 3");
  text.replace(text.find("end_time = 2"), 12, "end_time = 8\ntransport = true");
  const SweepPlan plan = parse(text);
  const std::vector<std::string> names = measure_names(plan);
  for (const char* name : {"self_diffusion", "shear_viscosity", "thermal_conductivity"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << name;
  }
  EXPECT_NE(task_commands(plan, 0, "out").back().find(" --transport"), std::string::npos);
  const TaskResult result = run_task(plan, 0, folder / "out");
  ASSERT_EQ(result.status, TaskStatus::done) << result.error;
  EXPECT_GT(result.measure("self_diffusion"), 0.0);
  EXPECT_GT(result.measure("shear_viscosity"), 0.0);
  // Without it, no such columns.
  const std::vector<std::string> plain = measure_names(parse(kSmallPlan));
  EXPECT_EQ(std::find(plain.begin(), plain.end(), "self_diffusion"), plain.end());
}

TEST(SweepTask, AShearedPlanMeasuresItsViscosity) {
  const Folder folder;
  std::string text = kSmallPlan;
  text.replace(text.find("n = 16"), 6, "n = 60");
  text.replace(text.find("end_time = 2"), 12,
               "end_time = 4\nshear = 0.5\nvelocity_profile = true\nkT = 1\n"
               "thermostat = \"rescale\"\nthermostat_every = 0.25");
  const SweepPlan plan = parse(text);
  const std::vector<std::string> names = measure_names(plan);
  for (const char* name : {"shear_rate", "shear_stress", "shear_viscosity"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << name;
  }
  const std::string command = task_commands(plan, 0, "out").back();
  EXPECT_NE(command.find(" --shear 0.5"), std::string::npos) << command;
  EXPECT_NE(command.find(" --velocity-profile"), std::string::npos) << command;
  const TaskResult result = run_task(plan, 0, folder / "out");
  ASSERT_EQ(result.status, TaskStatus::done) << result.error;
  EXPECT_EQ(result.measure("shear_rate"), 0.5);
  EXPECT_GT(result.measure("shear_viscosity"), 0.0);
  EXPECT_DOUBLE_EQ(result.measure("shear_viscosity"), result.measure("shear_stress") / 0.5);
}

TEST(SweepPlan, ThermostatsAreRunOptionsCheckedTaskByTask) {
  std::string text = kSmallPlan;
  text.replace(text.find("end_time = 2"), 12,
               "end_time = 2\nkT = 1.5\nthermostat = \"andersen\"\nthermostat_every = 0.5");
  // Andersen's without its rate: refused, naming the plan's line.
  const std::string why = refusal(text);
  EXPECT_NE(why.find("plan.toml:"), std::string::npos) << why;
  EXPECT_NE(why.find("thermostat-rate"), std::string::npos) << why;
  text += "thermostat_rate = [0.5, 2.0]\n";
  const SweepPlan plan = parse(text);
  EXPECT_EQ(plan.tasks().size(), 8u);
  const std::string command = task_commands(plan, 0, "out").back();
  for (const char* option :
       {"--kT 1.5", "--thermostat andersen", "--thermostat-every 0.5", "--thermostat-rate 0.5"}) {
    EXPECT_NE(command.find(option), std::string::npos) << command;
  }
  EXPECT_NE(refusal("[start]\nn = 16\n[run]\nend_time = 1\nthermostat = \"hot\"\n").find("rescale"),
            std::string::npos);
}

TEST(SweepTask, AStoppedTaskContinuesFromItsCheckpointToTheSameFiles) {
  const Folder folder;
  const SweepPlan plan = parse(kSmallPlan);
  ASSERT_EQ(run_task(plan, 1, folder / "whole").status, TaskStatus::done);
  // Stopped at once: the start is made, the checkpoint saved at t = 0, no summary.
  const std::atomic<int> stop{15};
  EXPECT_EQ(run_task(plan, 1, folder / "pieces", {&stop, nullptr}).status, TaskStatus::stopped);
  const fs::path piece = fs::path(folder / "pieces") / plan.tasks()[1].name;
  EXPECT_TRUE(fs::exists(piece / "checkpoint.ckpt"));
  EXPECT_FALSE(fs::exists(piece / "summary.json"));
  EXPECT_EQ(read_task_results(plan, folder / "pieces")[1].status, TaskStatus::pending);
  // Continued from the checkpoint, the task does not make its start again; what a kill left
  // half written is removed.
  fs::remove(piece / "start.txt");
  std::ofstream(piece / "summary.json.tmp.k1LL3d") << "{";
  ASSERT_EQ(run_task(plan, 1, folder / "pieces").status, TaskStatus::done);
  EXPECT_FALSE(fs::exists(piece / "start.txt"));
  EXPECT_FALSE(fs::exists(piece / "summary.json.tmp.k1LL3d"));
  const fs::path whole = fs::path(folder / "whole") / plan.tasks()[1].name;
  EXPECT_EQ(read(piece / "log.csv"), read(whole / "log.csv"));
  EXPECT_EQ(read_task_results(plan, folder / "pieces")[1].measures,
            read_task_results(plan, folder / "whole")[1].measures);
}

// Only carom's own temporaries are leftovers: a dump named "run.tmp.xyz" and a user's note whose
// names hold ".tmp." stay when a stopped task goes on.
TEST(SweepTask, AResumedTaskRemovesOnlyCaromsOwnTemporaries) {
  const Folder folder;
  std::string text = kSmallPlan;
  text.replace(text.find("n = 16"), 6, "n = 1000");  // progress is told every 4096 events
  text.replace(text.find("end_time = 2"), 12, "end_time = 10\ndump = \"run.tmp.xyz\"\nevery = 1");
  const SweepPlan plan = parse(text);
  ASSERT_EQ(run_task(plan, 1, folder / "whole").status, TaskStatus::done);
  std::atomic<int> stop{0};
  const TaskHooks halfway{&stop, [&](double fraction) {
                            if (fraction > 0.5) stop = 15;
                          }};
  ASSERT_EQ(run_task(plan, 1, folder / "pieces", halfway).status, TaskStatus::stopped);
  const fs::path piece = fs::path(folder / "pieces") / plan.tasks()[1].name;
  ASSERT_TRUE(fs::exists(piece / "run.tmp.xyz"));
  std::ofstream(piece / "notes.tmp.txt") << "mine";
  std::ofstream(piece / "checkpoint.ckpt.tmp.Ab9xYz") << "{";
  std::ofstream(piece / "checkpoint.ckpt.tmp.Ab9xYz.old") << "mine too";
  const TaskResult resumed = run_task(plan, 1, folder / "pieces");
  ASSERT_EQ(resumed.status, TaskStatus::done) << resumed.error;
  EXPECT_FALSE(fs::exists(piece / "checkpoint.ckpt.tmp.Ab9xYz"));
  EXPECT_EQ(read(piece / "notes.tmp.txt"), "mine");
  EXPECT_EQ(read(piece / "checkpoint.ckpt.tmp.Ab9xYz.old"), "mine too");
  EXPECT_TRUE(read(piece / "run.tmp.xyz") ==
              read(fs::path(folder / "whole") / plan.tasks()[1].name / "run.tmp.xyz"))
      << "the dump lost its frames";
  // A dump may not take the name of carom's own file or of its temporary: what a resumed task
  // removes is never the user's.
  for (const char* name : {"task.lock", "checkpoint.ckpt.tmp.Ab9xYz"}) {
    std::string own = kSmallPlan;
    own.replace(own.find("end_time = 2"), 12,
                fmt::format("end_time = 2\ndump = \"{}\"\nevery = 1", name));
    EXPECT_NE(refusal(own).find(fmt::format("plan.toml:6: [run] dump: {}", name)),
              std::string::npos)
        << refusal(own);
  }
}

// Stopped inside its measurement window, a task continues the window its checkpoint holds.
TEST(SweepTask, AStoppedTaskContinuesItsMeasurementWindow) {
  const Folder folder;
  std::string text = kSmallPlan;
  text.replace(text.find("n = 16"), 6, "n = 1000");  // progress is told every 4096 events
  text.replace(text.find("end_time = 2"), 12, "end_time = 20");
  text.replace(text.find("equilibrate = 1"), 15, "equilibrate = 10");
  const SweepPlan plan = parse(text);
  ASSERT_EQ(run_task(plan, 2, folder / "whole").status, TaskStatus::done);
  std::atomic<int> stop{0};
  TaskHooks hooks{&stop, [&](double fraction) {
                    if (fraction > 0.6) stop = 15;  // after equilibrate = 10 of end_time = 20
                  }};
  ASSERT_EQ(run_task(plan, 2, folder / "pieces", hooks).status, TaskStatus::stopped);
  const TaskResult resumed = run_task(plan, 2, folder / "pieces");
  ASSERT_EQ(resumed.status, TaskStatus::done) << resumed.error;
  EXPECT_EQ(resumed.measures, read_task_results(plan, folder / "whole")[2].measures);
  const fs::path task = plan.tasks()[2].name;
  EXPECT_EQ(read(fs::path(folder / "pieces") / task / "log.csv"),
            read(fs::path(folder / "whole") / task / "log.csv"));
  // The summary too, its drift verdict included (the checkpoint keeps Z's intervals so far);
  // only the wall time and the folder's name differ.
  const auto summary = [&](const std::string& run) {
    std::istringstream in(read(fs::path(folder / run) / task / "summary.json"));
    std::string kept;
    for (std::string line; std::getline(in, line);) {
      if (line.find("wall_seconds") == std::string::npos &&
          line.find("events_per_second") == std::string::npos &&
          line.find("\"input\"") == std::string::npos) {
        kept += line + '\n';
      }
    }
    return kept;
  };
  EXPECT_NE(summary("whole").find("\"intervals\": 20"), std::string::npos) << summary("whole");
  EXPECT_EQ(summary("pieces"), summary("whole"));
}

// Two tasks of which the second fails: a random placement at packing 0.7 jams.
constexpr const char* kOneTaskFails = R"([start]
n = 400
random = true
boundary = "periodic"
[run]
end_time = 1
[sweep]
phi = [0.2, 0.7]
)";

TEST(SweepTask, AFailingTaskKeepsItsErrorAndTheSweepGoesOn) {
  const Folder folder;
  const SweepPlan plan = parse(kOneTaskFails);
  const std::vector<TaskResult> results = run_sweep(plan, folder / "out", 2);
  EXPECT_EQ(results[0].status, TaskStatus::done);
  ASSERT_EQ(results[1].status, TaskStatus::failed);
  EXPECT_NE(results[1].error.find("random placement jammed"), std::string::npos)
      << results[1].error;
  EXPECT_EQ(read_task_results(plan, folder / "out")[1].error, results[1].error);
  const std::string table = read(fs::path(folder / "out") / "results.csv");
  EXPECT_NE(table.find("\n0.7,failed,,,,,,,,,,random placement jammed"), std::string::npos)
      << table;
}

// The steps every runner takes, as carom.sweep takes them around Dask workers that return only a
// status and an error: the tasks' folders give the measures where they agree with what returned.
TEST(SweepTask, PreparedReturnedAndFinishedTasksMakeTheTables) {
  const Folder folder;
  const SweepPlan plan = parse(kOneTaskFails);
  const std::string out = folder / "out";
  std::vector<TaskResult> returned;
  {
    PreparedSweep sweep = prepare_sweep(plan, out);
    EXPECT_EQ(sweep.waiting, (std::vector<std::size_t>{0, 1}));
    EXPECT_THROW(prepare_sweep(plan, out), RequestError);  // the folder is locked meanwhile
    for (const std::size_t index : sweep.waiting) {
      const TaskResult result = run_task(plan, index, out);
      returned.push_back(TaskResult::with(result.status, result.error));
    }
    // A failure that reached no error.txt is kept as it returned.
    returned[1].error = "lost on the way";
    const std::vector<TaskResult> results = returned_results(plan, out, sweep.waiting, returned);
    EXPECT_EQ(results[0].status, TaskStatus::done);
    EXPECT_FALSE(std::isnan(results[0].measure("Z")));  // from the task's summary
    EXPECT_EQ(results[1].error, "lost on the way");
    EXPECT_THROW(returned_results(plan, out, {0}, returned), std::invalid_argument);
    finish_sweep(plan, out, results);
  }
  const std::string table = read(fs::path(out) / "results.csv");
  EXPECT_NE(table.find("\n0.7,failed,,,,,,,,,,lost on the way"), std::string::npos) << table;
  EXPECT_TRUE(fs::exists(sweep_report_page(out)));
  EXPECT_EQ(prepare_sweep(plan, out).waiting, (std::vector<std::size_t>{1}));  // lock let go
}

// As carom compress exits 1 for it, a compression that jams before its target is a failed task,
// its packing and summary kept, the command's own error in results.csv; run again, it stays so.
TEST(SweepTask, ACompressionThatJamsShortOfItsTargetFails) {
  const Folder folder;
  const SweepPlan plan = parse(std::string(kJamsShortOf08) + "[sweep]\nrate = [0.1, 1000]\n");
  const std::vector<TaskResult> results = run_sweep(plan, folder / "out", 1);
  EXPECT_EQ(results[0].status, TaskStatus::done) << results[0].error;
  ASSERT_EQ(results[1].status, TaskStatus::failed);
  const fs::path task = fs::path(folder / "out") / plan.tasks()[1].name;
  // carom compress's message, naming the task's packing.
  const std::string& why = results[1].error;
  EXPECT_TRUE(why.starts_with("the disks jammed at packing fraction ")) << why;
  EXPECT_TRUE(why.ends_with(" before reaching 0.8; the jammed packing is in " +
                            (task / "packing.txt").string()))
      << why;
  EXPECT_LT(results[1].measure("packing_fraction"), 0.8);
  EXPECT_TRUE(fs::exists(task / "packing.txt"));
  EXPECT_TRUE(fs::exists(task / "summary.json"));
  EXPECT_EQ(read(task / "error.txt"), results[1].error + "\n");
  const auto written = fs::last_write_time(task / "summary.json");
  const std::vector<TaskResult> again = run_sweep(plan, folder / "out", 1);
  EXPECT_EQ(fs::last_write_time(task / "summary.json"), written);
  EXPECT_EQ(again[1].status, TaskStatus::failed);
  EXPECT_EQ(again[1].error, results[1].error);
  EXPECT_EQ(read_task_results(plan, folder / "out")[1].error, results[1].error);
  const std::string table = read(fs::path(folder / "out") / "results.csv");
  EXPECT_NE(table.find("\n1000,failed,"), std::string::npos) << table;
}

// A task whose lock another holds (a worker of an earlier sweep still at it) is not touched
// until it is let go; a folder another sweep holds is refused.
TEST(SweepTask, ATaskOrSweepAnotherHoldsIsLeftAlone) {
  const Folder folder;
  const SweepPlan plan = parse(kSmallPlan);
  const fs::path task = fs::path(folder / "out") / plan.tasks()[0].name;
  fs::create_directories(task);
  std::optional<HeldLock> held = HeldLock::try_take((task / "task.lock").string());
  ASSERT_TRUE(held);
  // The lock is the open file's, not the process's: a thread of this one is kept out too.
  EXPECT_FALSE(HeldLock::try_take((task / "task.lock").string()));
  const std::atomic<int> stop{15};
  EXPECT_EQ(run_task(plan, 0, folder / "out", {&stop, nullptr}).status, TaskStatus::stopped);
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(task)) names.push_back(entry.path().filename());
  EXPECT_EQ(names, std::vector<std::string>{"task.lock"});
  TaskResult waited;
  std::thread waiter([&] { waited = run_task(plan, 0, folder / "out"); });
  held->release();
  waiter.join();
  EXPECT_EQ(waited.status, TaskStatus::done) << waited.error;

  const HeldLock sweep = lock_sweep_folder(folder / "out");
  try {
    run_sweep(plan, folder / "out", 1);
    ADD_FAILURE() << "a second sweep ran in a held folder";
  } catch (const RequestError& e) {
    EXPECT_NE(std::string(e.what()).find("another sweep is running in"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find(fmt::format("pid {} on ", ::getpid())), std::string::npos)
        << e.what();
  }
}

TEST(SweepTables, ResultsKeepFullPrecisionAndSummariesAverageOverSeeds) {
  const Folder folder;
  const SweepPlan plan = parse(kSmallPlan);
  std::vector<TaskResult> results(4, TaskResult::with(TaskStatus::done));
  const double z[] = {1.0, 2.0, 0.1 + 0.2, 5.0};
  for (std::size_t i = 0; i < 4; ++i) {
    results[i].measures = {{"Z", z[i]}, {"Z_error", 0.25}, {"pressure", 1.0}};
  }
  results[3] = TaskResult::with(TaskStatus::failed, "it broke, \"badly\"");
  write_sweep_tables(plan, folder / "", results);
  const std::string table = read(folder / "results.csv");
  EXPECT_EQ(table.substr(0, table.find('\n')),
            "phi,seed,status,Z,Z_error,pressure,pressure_error,temperature,collision_rate,"
            "packing_fraction,Z_drift,Z_correlation,error");
  EXPECT_NE(table.find("\n0.3,1,done,0.30000000000000004,0.25,1,,,,,,,\n"), std::string::npos)
      << table;
  EXPECT_NE(table.find("\n0.3,2,failed,,,,,,,,,,\"it broke, \"\"badly\"\"\"\n"), std::string::npos);
  const std::string summary = read(folder / "summary.csv");
  // phi 0.2: two seeds, Z 1 and 2: mean 1.5, standard error 0.5. phi 0.3: one done task, whose
  // own error stands.
  EXPECT_NE(summary.find("\n0.2,2,2,1.5,0.5,1,0,"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\n0.3,2,1,0.30000000000000004,0.25,1,,"), std::string::npos) << summary;
}

// A task whose Z drifted past three standard errors over its measurement window shows its drift
// in results.csv, is counted in its state point's row of summary.csv, and is named in the report;
// one within three is counted nowhere, and the drift is not averaged as a measure.
TEST(SweepTables, TasksWhoseZDriftedAreFlagged) {
  const Folder folder;
  const SweepPlan plan = parse(kSmallPlan);
  std::vector<TaskResult> results(4, TaskResult::with(TaskStatus::done));
  const double drift[] = {-3.5, 2.9, std::nan(""), 3.25};
  for (std::size_t i = 0; i < 4; ++i) {
    results[i].measures = {{"Z", 1.0}, {"Z_error", 0.25}, {"Z_drift", drift[i]}};
  }
  write_sweep_tables(plan, folder / "", results);
  const std::string table = read(folder / "results.csv");
  EXPECT_NE(table.find("\n0.2,1,done,1,0.25,,,,,,-3.5,,\n"), std::string::npos) << table;
  EXPECT_NE(table.find("\n0.3,1,done,1,0.25,,,,,,,,\n"), std::string::npos) << table;
  const std::string summary = read(folder / "summary.csv");
  EXPECT_EQ(summary.substr(0, summary.find('\n')).find("Z_drift"), std::string::npos) << summary;
  EXPECT_NE(summary.find(",drifted\n"), std::string::npos) << summary;
  // phi 0.2: -3.5 and 2.9, one drifted; phi 0.3: none and 3.25, one drifted.
  EXPECT_EQ(std::count(summary.begin(), summary.end(), '\n'), 3) << summary;
  EXPECT_NE(summary.find("\n0.2,2,2,1,0,"), std::string::npos) << summary;
  for (const char* point : {"\n0.2,", "\n0.3,"}) {
    const std::size_t row = summary.find(point);
    const std::string line = summary.substr(row + 1, summary.find('\n', row + 1) - row - 1);
    EXPECT_EQ(line.substr(line.rfind(',')), ",1") << line;
  }
  std::ostringstream page;
  write_sweep_report(page, plan, results);
  const std::string html = page.str();
  EXPECT_NE(html.find("Tasks whose Z drifted"), std::string::npos);
  EXPECT_NE(html.find(plan.tasks()[0].name + "</b>: -3.5 standard errors"), std::string::npos);
  EXPECT_NE(html.find(plan.tasks()[3].name + "</b>: 3.2 standard errors"), std::string::npos)
      << html;
  EXPECT_EQ(html.find(plan.tasks()[1].name + "</b>"), std::string::npos);
  EXPECT_NE(html.find("<td class=\"drifted\">1 of 2</td>"), std::string::npos);
}

// A task whose Z's blocks were correlated past two spreads of independent ones shows it in
// results.csv and is named in the report (unless it drifted, which says more); the correlation
// is averaged nowhere.
TEST(SweepTables, TasksWhoseZBlocksAreCorrelatedAreFlagged) {
  const Folder folder;
  const SweepPlan plan = parse(kSmallPlan);
  std::vector<TaskResult> results(4, TaskResult::with(TaskStatus::done));
  const double drift[] = {0.5, 0.5, 4.0, std::nan("")};
  const double correlation[] = {2.5, 1.5, 3.0, std::nan("")};
  for (std::size_t i = 0; i < 4; ++i) {
    results[i].measures = {{"Z", 1.0}, {"Z_error", 0.25}, {"Z_drift", drift[i]},
                           {"Z_correlation", correlation[i]}};
  }
  write_sweep_tables(plan, folder / "", results);
  const std::string table = read(folder / "results.csv");
  EXPECT_NE(table.find("\n0.2,1,done,1,0.25,,,,,,0.5,2.5,\n"), std::string::npos) << table;
  const std::string summary = read(folder / "summary.csv");
  EXPECT_EQ(summary.find("Z_correlation"), std::string::npos) << summary;
  std::ostringstream page;
  write_sweep_report(page, plan, results);
  const std::string html = page.str();
  EXPECT_NE(html.find("Tasks whose Z fluctuated over longer than a block"), std::string::npos);
  EXPECT_NE(html.find(plan.tasks()[0].name + "</b>: 2.50</li>"), std::string::npos) << html;
  EXPECT_EQ(html.find(plan.tasks()[1].name + "</b>"), std::string::npos);  // 1.5: independent
  EXPECT_EQ(html.find(plan.tasks()[2].name + "</b>: 3.0"), std::string::npos);  // drifted
  EXPECT_NE(html.find(plan.tasks()[2].name + "</b>: 4.0 standard errors"), std::string::npos);
  // What the console and carom.sweep say of each: the correlation, nothing, the drift alone,
  // nothing.
  ASSERT_TRUE(unsettled_warning(results[0]));
  EXPECT_EQ(unsettled_warning(results[0])->rfind("Z's blocks are correlated (Z_correlation = 2.50)",
                                                 0),
            0u);
  EXPECT_FALSE(unsettled_warning(results[1]));
  ASSERT_TRUE(unsettled_warning(results[2]));
  EXPECT_EQ(unsettled_warning(results[2])->rfind("Z drifted by 4.0 standard errors", 0), 0u);
  EXPECT_FALSE(unsettled_warning(results[3]));
}

// A plan nested deeper than any plan needs (a dotted key or a table header of
// thousands of levels) is refused before the TOML parser recurses into it.
TEST(SweepPlan, DeepNestingIsRefusedBeforeTheTomlParserRecurses) {
  std::string dotted = "[start]\nn = 16\nphi = 0.3\n[run]\nend_time = 1\n[sweep]\nx";
  for (int i = 0; i < 100'000; ++i) dotted += ".x";
  dotted += " = 1\n";
  std::string header = "[start]\nn = 16\nphi = 0.3\n[run]\nend_time = 1\n[x";
  for (int i = 0; i < 50'000; ++i) header += ".x";
  header += "]\n";
  std::string arrays = "[start]\nn = 16\nphi = 0.3\n[run]\nend_time = 1\n[sweep]\nphi = ";
  arrays += std::string(100'000, '[');
  for (const std::string& text : {dotted, header, arrays}) {
    const std::string why = refusal(text);
    EXPECT_EQ(why.rfind(text == header ? "plan.toml:6: " : "plan.toml:7: ", 0), 0u) << why;
    EXPECT_NE(why.find("nest"), std::string::npos) << why;
  }
  // What a plan does nest (an inline table in a list, quoted keys with dots) is read as before.
  EXPECT_NE(refusal("[start]\nn = 16\nphi = 0.3\n\"a.b.c\" = 1\n[run]\nend_time = 1\n")
                .find("[start] a.b.c: not an option"),
            std::string::npos);
}

// Every task has a folder of its own, whatever its values' characters or length.
TEST(SweepPlan, TaskFoldersAreDistinctAndFitAFileName) {
  const std::string long_name = std::string(246, 'a') + ".xyz";
  const SweepPlan plan = parse(
      "[start]\nn = 16\nphi = 0.3\n[run]\nend_time = 1\nevery = 0.5\n[sweep]\ndump = [\"a b.xyz\", "
      "\"a_b.xyz\", \"" +
      long_name + "\", \"" + long_name.substr(1) + "\"]\n");
  std::set<std::string> names;
  for (const SweepTask& task : plan.tasks()) {
    names.insert(task.name);
    EXPECT_LE(task.name.size(), 200u) << task.name;
    EXPECT_EQ(task.name.find_first_of("/ \\"), std::string::npos) << task.name;
  }
  EXPECT_EQ(names.size(), plan.tasks().size());
  // Names that need no change keep it (folders of earlier sweeps are found again).
  EXPECT_EQ(plan.tasks()[1].name, "dump=a_b.xyz");
  // A file name no file system takes (over 255 bytes) is refused, not failed in every task.
  const std::string too_long =
      refusal("[start]\nn = 16\nphi = 0.3\n[run]\nend_time = 1\nevery = 0.5\ndump = \"" +
              std::string(296, 'a') + ".xyz\"\n");
  EXPECT_EQ(too_long.rfind("plan.toml:7: [run] dump: takes a file name of at most 255 bytes", 0),
            0u)
      << too_long;
}

// A sweep folder spelled another way (./out, an absolute path, out/) is the same sweep.
TEST(SweepTask, AFolderSpelledAnotherWayHoldsTheSameTasks) {
  const Folder folder;
  const SweepPlan plan = parse(kSmallPlan);
  ASSERT_EQ(run_task(plan, 0, folder / "out").status, TaskStatus::done);
  const fs::path out = folder / "out";
  for (const fs::path& spelled : {out / ".", out.parent_path() / "." / "out",
                                  out.parent_path() / ".." / out.parent_path().filename() / "out",
                                  fs::path(folder / "out/")}) {
    EXPECT_NO_THROW(check_sweep_folder(plan, spelled.string())) << spelled;
    EXPECT_EQ(run_task(plan, 0, spelled.string()).status, TaskStatus::done) << spelled;
  }
  // A start file named through another spelling of the plan's folder: the same task too.
  fs::create_directories(folder / "study");
  std::ofstream(folder / "study/gas.txt") << "2\n0.5\n10 10\n2 2 1 0\n5 5 0 1\n";
  const std::string text = "[start]\nfile = \"gas.txt\"\n[run]\nend_time = 1\nkT = 1\n";
  const SweepPlan here = SweepPlan::parse(text, "plan.toml", folder / "study");
  ASSERT_EQ(run_task(here, 0, folder / "files").status, TaskStatus::done);
  const SweepPlan there = SweepPlan::parse(text, "plan.toml", folder / "study/../study/.");
  EXPECT_NO_THROW(check_sweep_folder(there, folder / "files"));
  // Another task is still refused.
  std::string changed = kSmallPlan;
  changed.replace(changed.find("end_time = 2"), 12, "end_time = 3");
  EXPECT_THROW(check_sweep_folder(parse(changed), (out / ".").string()), RequestError);
}

// A plan whose start file was edited to another file holds other tasks: the results of the old
// file are not taken as done, though the tasks' folders are spelled alike.
TEST(SweepTask, AStartFileEditedToAnotherFileIsAnotherTask) {
  const Folder folder;
  const std::string gas = "2\n0.5\n10 10\n2 2 1 0\n5 5 0 1\n";
  std::ofstream(folder / "a.txt") << gas;
  std::ofstream(folder / "b.txt") << gas;
  const std::string text = "[start]\nfile = \"a.txt\"\n[run]\nend_time = 1\nkT = 1\n";
  ASSERT_EQ(run_task(SweepPlan::parse(text, "plan.toml", folder / ""), 0, folder / "out").status,
            TaskStatus::done);
  std::string edited = text;
  edited.replace(edited.find("a.txt"), 5, "b.txt");
  const SweepPlan other = SweepPlan::parse(edited, "plan.toml", folder / "");
  EXPECT_THROW(check_sweep_folder(other, folder / "out"), RequestError);
  EXPECT_THROW(run_task(other, 0, folder / "out"), RequestError);
}

// A swept seed reaches every random draw of its tasks, or the plan is refused; the tasks
// of a state point are never copies of one run.
TEST(SweepPlan, EverySweptSeedMakesIndependentTasks) {
  const Folder folder;
  std::ofstream(folder / "gas.txt") << "2\n0.5\n10 10\n2 2 1 0\n5 5 0 1\n";
  // A start file and no kT: the seed would seed nothing (carom run refuses --seed without --kT).
  const std::string no_draw = refusal_in(
      "[start]\nfile = \"gas.txt\"\n[run]\nend_time = 1\n[sweep]\nseed = [1, 2, 3]\n", folder / "");
  EXPECT_EQ(no_draw.rfind("plan.toml:6: [sweep] seed", 0), 0u) << no_draw;
  EXPECT_NE(no_draw.find("kT"), std::string::npos) << no_draw;
  // A lattice start (phi 0.45) whose velocities the run draws again: the task's seed draws them.
  const std::string lattice =
      "[start]\nn = 16\nphi = 0.45\nboundary = \"periodic\"\n[run]\nend_time = 2\nkT = 1\n"
      "thermostat = \"rescale\"\nthermostat_every = 0.5\n[sweep]\nseed = [1, 2]\n";
  const SweepPlan plan = parse(lattice);
  for (std::size_t i = 0; i < 2; ++i) {
    const std::string run = task_commands(plan, i, "d").back();
    EXPECT_NE(run.find(" --seed " + std::to_string(i + 1) + " "), std::string::npos) << run;
  }
  const std::vector<TaskResult> results = run_sweep(plan, folder / "out", 1);
  ASSERT_EQ(results[0].status, TaskStatus::done) << results[0].error;
  ASSERT_EQ(results[1].status, TaskStatus::done) << results[1].error;
  EXPECT_NE(results[0].measure("Z"), results[1].measure("Z"));
  // A seed of the run's own fixed beside the swept one: the lattice tasks would be one run.
  std::string fixed = lattice;
  fixed.replace(fixed.find("kT = 1\n"), 7, "kT = 1\nseed = 5\n");
  const std::string copies = refusal(fixed);
  EXPECT_EQ(copies.rfind("plan.toml:12: [sweep] seed", 0), 0u) << copies;
  EXPECT_NE(copies.find("the same run"), std::string::npos) << copies;
  // Random placement, or radii drawn at random, keep the seed's mark: accepted.
  std::string random = fixed;
  random.replace(random.find("phi = 0.45"), 10, "phi = 0.3");
  EXPECT_EQ(refusal(random), "");
}

// A plan is valid exactly when each task's commands are: what carom init and carom run
// would refuse, the plan refuses, naming its line and key.
TEST(SweepPlan, WhatTheTasksCommandsWouldRefuseThePlanRefuses) {
  const std::string start = "[start]\nn = 16\nphi = 0.3\n";
  const std::string periodic = start + "boundary = \"periodic\"\n";
  const std::string walls = start + "boundary = \"walls\"\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {walls + "[run]\nend_time = 1\ntransport = true\n",
       "plan.toml:7: [run] transport = true: --transport needs a periodic box"},
      {walls + "[run]\nend_time = 1\n[sweep]\nshear = [0.5]\n",
       "plan.toml:8: [sweep] shear = 0.5 (task shear=0.5): --shear needs a periodic box"},
      {periodic + "[run]\nend_time = 1\nrule = \"swap\"\nshear = 0.5\n",
       "plan.toml:8: [run] shear = 0.5: --shear needs --rule elastic"},
      {start + "[run]\nend_time = 100\ndump = \"a.xyz\"\nevery = 1e-9\n",
       "plan.toml:7: [run] every = 1e-09: --every 1e-09 would write more than 10^7 frames"},
      {start + "[run]\nend_time = 1e300\n",
       "plan.toml:5: [run] end_time = 1e+300: 1e+300 is beyond"},
      {start + "dim = 4294967298\n[run]\nend_time = 1\n",
       "plan.toml:4: [start] dim = 4294967298: dim must be 2 (disks) or 3 (spheres)"},
      {start + "box = []\n[run]\nend_time = 1\n", "plan.toml:4: [start] box: takes a list of"},
      {start + "[run]\nend_time = 1\ndump = \"a\\rb.xyz\"\nevery = 0.5\n",
       "plan.toml:6: [run] dump: takes a file name"},
      // Options carom init's and compress's command lines refuse together.
      {start + "lattice = true\nrandom = true\n[run]\nend_time = 1\n",
       "plan.toml:5: [start] random = true: --random excludes --lattice"},
      {"[start]\nn = 16\nphi = 0.3\nbox = [20, 20]\naspect = 2\n[run]\nend_time = 1\n",
       "plan.toml:5: [start] aspect = 2: --aspect excludes --box"},
      {start + "[compress]\nphi = 0.5\n[sweep]\njam = [true, false]\n",
       "plan.toml:7: [sweep] jam = true (task jam=true): --jam excludes --phi"},
  };
  for (const auto& [text, expected] : cases) {
    const std::string said = refusal(text);
    EXPECT_EQ(said.rfind(expected, 0), 0u) << "plan:\n" << text << "said: " << said;
  }
}

// A row of results.csv keeps to its line whatever a value or an error holds.
TEST(SweepTables, LineBreaksInAnErrorStayInsideItsRow) {
  const Folder folder;
  const SweepPlan plan = parse(kSmallPlan);
  std::vector<TaskResult> results(4, TaskResult::with(TaskStatus::pending));
  results[1] = TaskResult::with(TaskStatus::failed, "first\rsecond\nthird, \"fourth\"");
  write_sweep_tables(plan, folder / "", results);
  const std::string table = read(folder / "results.csv");
  EXPECT_EQ(table.find('\r'), std::string::npos);
  EXPECT_EQ(std::count(table.begin(), table.end(), '\n'), 5);
  EXPECT_NE(table.find(",\"first second third, \"\"fourth\"\"\"\n"), std::string::npos) << table;
}

// A sweep of 100,000 state points is tabled and reported (what a stopped sweep does
// before it exits) in a second or so: the state points and the report's series are grouped by
// hashing, not by a search of those seen so far (minutes).
TEST(SweepTables, AHundredThousandStatePointsAreTabledQuickly) {
  const Folder folder;
  std::string kT = "[";
  for (int i = 1; i <= 50'000; ++i) kT += std::to_string(i) + (i < 50'000 ? ", " : "]");
  const SweepPlan plan = parse(
      "[start]\nn = 16\nboundary = \"periodic\"\n[run]\nend_time = 1\n"
      "[sweep]\nphi = [0.2, 0.3]\nkT = " +
      kT + "\n");
  ASSERT_EQ(plan.tasks().size(), 100'000u);
  std::vector<TaskResult> results(plan.tasks().size(), TaskResult::with(TaskStatus::done));
  for (std::size_t i = 0; i < results.size(); ++i) {
    results[i].dimension = 2;
    results[i].measures = {{"Z", 1.0 + static_cast<double>(i % 7)}, {"Z_error", 0.1}};
  }
  const auto begun = std::chrono::steady_clock::now();
  write_sweep_tables(plan, folder / "", results);
  std::ostringstream page;
  write_sweep_report(page, plan, results);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - begun).count();
  EXPECT_LT(seconds, 20.0);
  const std::string summary = read(folder / "summary.csv");
  EXPECT_EQ(std::count(summary.begin(), summary.end(), '\n'), 100'001);
}

}  // namespace
}  // namespace carom

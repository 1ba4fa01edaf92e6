// The carom command line, run as a user runs it: the classic assignment's outputs exactly, formats,
// errors.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

namespace fs = std::filesystem;

namespace {

const std::string kCases = std::string(CAROM_TEST_DATA) + "/cases/";

struct Result {
  int exit_code;
  std::string out;
  std::string err;
};

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           fmt::format("carom-cli-{}-{}", ::getpid(),
                       ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Each `carom run START 1` with the options given is refused (exit 2) with the message given.
  void expect_runs_refused(
      const fs::path& start,
      const std::vector<std::pair<std::vector<std::string>, std::string>>& refused) {
    for (const auto& [options, message] : refused) {
      std::vector<std::string> args = {"run", start, "1", "-o", dir_ / "out.txt"};
      args.insert(args.end(), options.begin(), options.end());
      const Result r = carom(args);
      EXPECT_EQ(r.exit_code, 2) << options.front();
      EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    }
  }

  // `carom init`'s n spheres at packing 0.3 in a periodic box, written to dir_ / name.
  fs::path spheres_at_0_3(std::uint64_t n, const std::string& name = "spheres.txt") {
    const fs::path start = dir_ / name;
    const Result r = carom({"init", "--dim", "3", "--n", std::to_string(n), "--phi", "0.3",
                            "--boundary", "periodic", "-o", start});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return start;
  }

  Result carom(const std::vector<std::string>& args, const std::string& stdin_text = "") {
    std::string command = quote(CAROM_EXE);
    for (const auto& a : args) command.append(" ").append(quote(a));
    const fs::path in = dir_ / "stdin", out = dir_ / "stdout", err = dir_ / "stderr";
    std::ofstream(in) << stdin_text;
    command += " <" + quote(in) + " >" + quote(out) + " 2>" + quote(err);
    const int status = std::system(command.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_file(out), read_file(err)};
  }

  // Starts carom in the background, its output to files in the test's folder; returns its pid.
  pid_t spawn(const std::vector<std::string>& args) {
    const pid_t pid = ::fork();
    if (pid == 0) {
      if (!std::freopen((dir_ / "stdout").c_str(), "w", stdout) ||
          !std::freopen((dir_ / "stderr").c_str(), "w", stderr)) {
        ::_exit(126);
      }
      std::vector<char*> argv{const_cast<char*>(CAROM_EXE)};
      for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      ::execv(CAROM_EXE, argv.data());
      ::_exit(127);
    }
    return pid;
  }

  pid_t start_run(const fs::path& input, std::vector<std::string> args) {
    args.insert(args.begin(), {"run", input.string()});
    return spawn(args);
  }

  // Ctrl-C to a run started by start_run with `--dump movie`, once it has written its first
  // frame: it is simulating then, its stop handlers in place, however loaded the machine. Its
  // exit code, or nullopt if it wrote no frame, ignored the signal or was killed by it.
  std::optional<int> interrupted_exit_code(pid_t pid, const fs::path& movie) {
    if (!wait_until([&] { return holds(movie, "Time="); })) return std::nullopt;
    ::kill(pid, SIGINT);
    int status = 0;
    if (!wait_until([&] { return ::waitpid(pid, &status, WNOHANG) == pid; })) return std::nullopt;
    if (!WIFEXITED(status)) return std::nullopt;
    return WEXITSTATUS(status);
  }

  // Waits for a process started by spawn(): its exit code, or -1 if a signal ended it.
  static int finish(pid_t pid) {
    int status = 0;
    ::waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  // Polls until `ready` holds (the run has got somewhere), at most a minute.
  static bool wait_until(const std::function<bool()>& ready) {
    for (int i = 0; i < 6000; ++i) {
      if (ready()) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  }

  // Whether a file holds `text` yet.
  static bool holds(const fs::path& path, const std::string& text) {
    return read_file(path).find(text) != std::string::npos;
  }

  fs::path write(const std::string& name, const std::string& text) {
    const fs::path path = dir_ / name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }

  fs::path dir_;
};

// Lines of `text` after its first line (the table header).
std::string without_header(const std::string& text) {
  return text.substr(text.find('\n') + 1);
}

// From a --trace output, the lines a case's .trace file holds: each `TIME = t` and the particle
// lines of the block after it (the initial and final blocks are not in the .trace files).
std::string trace_essentials(const std::string& trace) {
  std::istringstream in(trace);
  std::string line, kept;
  bool in_event = false;
  while (std::getline(in, line)) {
    const std::string trimmed = line.substr(std::min(line.find_first_not_of(' '), line.size()));
    if (trimmed.rfind("TIME = ", 0) == 0) {
      in_event = true;
      kept += trimmed + "\n";
    } else if (trimmed.rfind("======== Final", 0) == 0) {
      in_event = false;
    } else if (in_event && trimmed.rfind("particle ", 0) == 0 &&
               trimmed.rfind("particle id:", 0) != 0) {
      kept += trimmed + "\n";
    }
  }
  return kept;
}

TEST_F(Cli, SeedWallsOnlyTableIsExact) {
  const Result r = carom({"run", kCases + "walls_only.txt", "20"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.substr(0, r.out.find('\n')),
            "particle id: (xpos, ypos) (xvel, yvel): last_update : (cwall, cpart)");
  EXPECT_EQ(without_header(r.out), read_file(kCases + "walls_only.T20.expected"));
  // A plain classic file runs as the classic assignment's, and says so once (not with -q).
  EXPECT_EQ(r.err, "carom: note: " + kCases +
                       "walls_only.txt records no box or rule (a plain classic file): run between "
                       "walls with the swap rule, as the classic assignment does (--boundary "
                       "periodic --rule elastic for a bulk fluid)\n");
  EXPECT_EQ(carom({"run", kCases + "walls_only.txt", "20", "-q"}).err, "");
}

TEST_F(Cli, SeedParticlesOnlyTableIsExact) {
  const Result r = carom({"run", kCases + "particles_only.txt", "18"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(without_header(r.out), read_file(kCases + "particles_only.T18.expected"));
}

TEST_F(Cli, ReferenceEngineGivesTheSameSeedTables) {
  for (const auto& [input, end, expected] :
       {std::tuple{"walls_only.txt", "20", "walls_only.T20.expected"},
        std::tuple{"particles_only.txt", "18", "particles_only.T18.expected"}}) {
    const Result r = carom({"run", kCases + input, end, "--engine", "reference"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(without_header(r.out), read_file(kCases + expected)) << input;
  }
}

TEST_F(Cli, AssignmentCasesCsvIsExact) {
  for (const auto& [input, end, expected] :
       {std::tuple{"normal.txt", "20", "normal.T20.csv"},
        std::tuple{"normal.txt", "100", "normal.T100.csv"},
        std::tuple{"particles1.txt", "15", "particles1.T15.csv"},
        std::tuple{"particles1.txt", "100", "particles1.T100.csv"}}) {
    const Result r = carom({"run", kCases + input, end, "--format", "csv"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.out, read_file(kCases + expected)) << input << " to " << end;
  }
}

TEST_F(Cli, TracesMatchTheCasesEventByEvent) {
  for (const auto& [input, end, expected] :
       {std::tuple{"normal.txt", "20", "normal.T20.trace"},
        std::tuple{"particles1.txt", "100", "particles1.T100.trace"}}) {
    const Result r = carom({"run", kCases + input, end, "--trace"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(trace_essentials(r.out), read_file(kCases + expected)) << input;
  }
}

TEST_F(Cli, TraceHasTheDocumentedLayout) {
  const Result r = carom({"run", kCases + "walls_only.txt", "20", "--trace"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string header =
      "particle id: (xpos, ypos) (xvel, yvel): last_update : (cwall, cpart)\n";
  const std::string expected_start =
      "Input File: " + kCases +
      "walls_only.txt\nTarget Time: 20.000000\n"
      "======== Initial Particles =========\n" +
      header +
      "particle 0: (2.100000, 5.000000) (-0.200000, -0.150000): 0.000000 : (0, 0)\n"
      "particle 1: (18.000000, 7.000000) (0.100000, -0.200000): 0.000000 : (0, 0)\n"
      "particle 2: (12.000000, 3.200000) (0.150000, -0.200000): 0.000000 : (0, 0)\n"
      "particle 3: (7.000000, 8.500000) (-0.250000, 0.100000): 0.000000 : (0, 0)\n"
      "                 TIME = 9.500000\n"
      "Collision: particle 0 with wall -1 (left)\n"
      "======== Particles =========\n" +
      header +
      "particle 0: (0.200000, 3.575000) (0.200000, -0.150000): 9.500000 : (1, 0)\n"
      "particle 1: (18.000000, 7.000000) (0.100000, -0.200000): 0.000000 : (0, 0)\n";
  EXPECT_EQ(r.out.substr(0, expected_start.size()), expected_start);
  // The four wall events of the case, in order, then the final block.
  for (const char* event : {"TIME = 13.000000\nCollision: particle 3 with wall -4 (top)",
                            "TIME = 15.000000\nCollision: particle 2 with wall -3 (bottom)",
                            "TIME = 18.000000\nCollision: particle 1 with wall -2 (right)"}) {
    EXPECT_NE(r.out.find(event), std::string::npos) << event;
  }
  const std::string final_block = "======== Final Particles =========\n" + header +
                                  read_file(kCases + "walls_only.T20.expected");
  ASSERT_GE(r.out.size(), final_block.size());
  EXPECT_EQ(r.out.substr(r.out.size() - final_block.size()), final_block);
}

TEST_F(Cli, JsonCarriesStateAndCounts) {
  const Result r = carom({"run", kCases + "particles_only.txt", "18", "--format", "json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* field :
       {"\"events\": 2", "\"pair_collisions\": 2", "\"wall_collisions\": 0", "\"rule\": \"swap\"",
        "\"boundary\": \"walls\"", "\"end_time\": 18.0", "\"n\": 8", "\"last_update\":18.0"}) {
    EXPECT_NE(r.out.find(field), std::string::npos) << field << "\n" << r.out;
  }
}

TEST_F(Cli, OutputFileIsWrittenAndStdoutStaysEmpty) {
  const fs::path out = dir_ / "result.csv";
  const Result r = carom({"run", kCases + "normal.txt", "20", "--format", "csv", "-o", out});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(read_file(out), read_file(kCases + "normal.T20.csv"));
  for (const auto& entry : fs::directory_iterator(dir_)) {
    EXPECT_EQ(entry.path().string().find(".tmp."), std::string::npos) << entry.path();
  }
}

TEST_F(Cli, StdinIsReadWithDash) {
  const Result r = carom({"run", "-", "20"}, read_file(kCases + "walls_only.txt"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(without_header(r.out), read_file(kCases + "walls_only.T20.expected"));
}

TEST_F(Cli, ElasticRuleIsSelectable) {
  const std::string input = kCases + "particles_only.txt";
  const Result elastic = carom({"run", input, "18", "--rule", "Elastic", "--format", "json"});
  ASSERT_EQ(elastic.exit_code, 0) << elastic.err;
  const Result swap = carom({"run", input, "18", "--format", "json"});
  ASSERT_EQ(swap.exit_code, 0) << swap.err;
  const auto e = nlohmann::json::parse(elastic.out), w = nlohmann::json::parse(swap.out);
  EXPECT_EQ(e["rule"], "elastic");
  // The same two collisions, but with oblique contacts elastic disks leave with other velocities.
  EXPECT_GT(e["pair_collisions"].get<int>(), 0);
  EXPECT_NE(e["particles"][1]["vx"], w["particles"][1]["vx"]);
  // Energy and momentum are conserved (the swap rule conserves them too, for equal masses).
  EXPECT_NEAR(e["kinetic_energy_final"].get<double>(), e["kinetic_energy_initial"].get<double>(),
              1e-12);
  double px = 0.0;
  for (const auto& p : e["particles"]) px += p["vx"].get<double>();
  EXPECT_NEAR(px, e["momentum_final"][0].get<double>(), 1e-12);
  for (const auto& p : w["particles"]) px -= p["vx"].get<double>();
  EXPECT_NEAR(px, 0.0, 1e-12);  // the same total as the swap run's
}

TEST_F(Cli, HelpTeachesAndVersionAnswers) {
  const Result help = carom({"run", "--help"});
  EXPECT_EQ(help.exit_code, 0);
  for (const char* text : {"END_TIME", "--format", "--trace", "--rule", "x y vx vy", "Examples"}) {
    EXPECT_NE(help.out.find(text), std::string::npos) << text;
  }
  const Result top = carom({"--help"});
  EXPECT_EQ(top.exit_code, 0);
  EXPECT_NE(top.out.find("run"), std::string::npos);
  const Result version = carom({"--version"});
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_EQ(version.out.rfind("carom 1.", 0), 0u) << version.out;
}

TEST_F(Cli, NoArgumentsPrintTheHelpAndMistakesGetSuggestions) {
  const Result none = carom({});
  EXPECT_EQ(none.exit_code, 0);
  EXPECT_NE(none.out.find("Subcommands:"), std::string::npos) << none.out;
  EXPECT_NE(none.out.find("Examples:"), std::string::npos);

  const Result option = carom({"run", kCases + "normal.txt", "10", "--formt", "csv"});
  EXPECT_EQ(option.exit_code, 2);
  EXPECT_EQ(option.err.rfind("carom: error: ", 0), 0u) << option.err;
  EXPECT_NE(option.err.find("did you mean '--format'?"), std::string::npos) << option.err;
  EXPECT_NE(option.err.find("Run 'carom run --help'"), std::string::npos) << option.err;
  EXPECT_EQ(option.out, "");

  const Result command = carom({"rnu", kCases + "normal.txt", "10"});
  EXPECT_EQ(command.exit_code, 2);
  EXPECT_NE(command.err.find("did you mean 'run'?"), std::string::npos) << command.err;

  const Result lonely = carom({"run", kCases + "normal.txt", "10", "--checkpoint-every", "5"});
  EXPECT_EQ(lonely.exit_code, 2);
  EXPECT_NE(lonely.err.find("--checkpoint-every needs --checkpoint"), std::string::npos)
      << lonely.err;
}

TEST_F(Cli, InitWritesNoPeriodicFileThatRunWouldRefuse) {
  // Two disks at 0.5: a square box of side 1.77, under two diameters.
  const Result tiny = carom({"init", "--n", "2", "--phi", "0.5", "--boundary", "periodic", "-o",
                             (dir_ / "tiny.txt").string()});
  EXPECT_EQ(tiny.exit_code, 2);
  EXPECT_NE(tiny.err.find("too small"), std::string::npos) << tiny.err;
  EXPECT_FALSE(fs::exists(dir_ / "tiny.txt"));
  // Every periodic file it does write runs.
  for (const char* n : {"3", "4", "5", "6", "12", "40"}) {
    const fs::path start = dir_ / "small.txt";
    const Result made =
        carom({"init", "--n", n, "--phi", "0.5", "--boundary", "periodic", "-o", start});
    if (made.exit_code != 0) continue;
    const Result run = carom(
        {"run", start, "5", "--boundary", "periodic", "--rule", "elastic", "--format", "csv"});
    EXPECT_EQ(run.exit_code, 0) << n << ": " << run.err;
  }
}

// Files carom writes record their box and rule; a run takes them unless told otherwise, and says
// so. A plain file is the classic assignment's: walls and swap, silently.
TEST_F(Cli, ARunTakesTheBoxAndRuleItsFileRecordsAndSaysSo) {
  const fs::path start = dir_ / "gas.txt";
  ASSERT_EQ(
      carom({"init", "--n", "50", "--phi", "0.3", "--boundary", "periodic", "-o", start}).exit_code,
      0);
  EXPECT_EQ(read_file(start).substr(0, 40), "# carom: boundary=periodic rule=elastic\n");
  const Result recorded = carom({"run", start, "1", "--format", "json"});
  ASSERT_EQ(recorded.exit_code, 0) << recorded.err;
  EXPECT_EQ(recorded.err, "carom: note: periodic boundary and elastic rule, as " + start.string() +
                              " records (--boundary and --rule choose otherwise)\n");
  EXPECT_NE(recorded.out.find("\"rule\": \"elastic\""), std::string::npos);
  EXPECT_NE(recorded.out.find("\"boundary\": \"periodic\""), std::string::npos);
  // The same run asked for in full: the same output, no note.
  const Result asked =
      carom({"run", start, "1", "--boundary", "periodic", "--rule", "elastic", "--format", "json"});
  EXPECT_EQ(asked.err, "");
  EXPECT_EQ(asked.out.substr(asked.out.find("\"particles\"")),
            recorded.out.substr(recorded.out.find("\"particles\"")));
  EXPECT_EQ(carom({"run", start, "1", "--format", "csv", "--quiet"}).err, "");
  // Swap asked for in a periodic box: allowed, with the physics spelled out.
  const Result swap = carom({"run", start, "1", "--rule", "swap", "--format", "csv"});
  EXPECT_EQ(swap.exit_code, 0);
  EXPECT_NE(swap.err.find("--rule elastic is the physical one"), std::string::npos) << swap.err;
  // A plain file with --boundary periodic: elastic, said so.
  const std::string plain = read_file(start).substr(40);
  const fs::path bare = write("bare.txt", plain);
  const Result inferred = carom({"run", bare, "1", "--boundary", "periodic", "--format", "json"});
  EXPECT_NE(inferred.err.find("elastic rule, the physical one in a periodic box"),
            std::string::npos)
      << inferred.err;
  EXPECT_NE(inferred.out.find("\"rule\": \"elastic\""), std::string::npos);
  // A plain file whose particles reach through the walls: the error suggests the periodic box.
  const fs::path edge = write("edge.txt", "1\n0.5\n10 10\n0.2 5 1 0\n");
  const Result wall = carom({"run", edge, "1"});
  EXPECT_EQ(wall.exit_code, 2);
  EXPECT_NE(wall.err.find("run it with --boundary periodic"), std::string::npos) << wall.err;
  // The classic assignment's own files: walls, swap, said once.
  const Result classic = carom({"run", kCases + "normal.txt", "1", "--format", "json"});
  EXPECT_NE(classic.err.find("normal.txt records no box or rule (a plain classic file): run "
                             "between walls with the swap rule"),
            std::string::npos)
      << classic.err;
  // Asked for (either of them): nothing to say.
  EXPECT_EQ(carom({"run", kCases + "normal.txt", "1", "--rule", "swap"}).err, "");
  EXPECT_NE(classic.out.find("\"rule\": \"swap\""), std::string::npos);
  // A box with walls that init made: elastic, said so.
  const fs::path walled = dir_ / "walled.txt";
  ASSERT_EQ(carom({"init", "--n", "50", "--phi", "0.3", "--boundary", "walls", "-o", walled})
                .exit_code,
            0);
  EXPECT_EQ(
      carom({"run", walled, "1", "--format", "csv"}).err,
      "carom: note: elastic rule, as " + walled.string() + " records (--rule chooses otherwise)\n");
  // compress reads the record too, and writes its own.
  const fs::path dense = dir_ / "dense.txt";
  const Result compressed = carom({"compress", start, "--phi", "0.35", "-o", dense, "-q"});
  ASSERT_EQ(compressed.exit_code, 0) << compressed.err;
  EXPECT_EQ(read_file(dense).substr(0, 40), "# carom: boundary=periodic rule=elastic\n");
  // A restitution below 1 is the elastic rule's.
  const Result granular = carom({"run", walled, "1", "--restitution", "0.9", "--format", "json"});
  EXPECT_EQ(granular.err, "");
  EXPECT_NE(granular.out.find("\"rule\": \"elastic\""), std::string::npos);
}

// Each bad input: exit code 2, one message naming the file and line, nothing on stdout and no
// output file.
struct BadInput {
  const char* name;
  const char* text;
  const char* location;  // "FILE:LINE" suffix expected in the message
  const char* says;      // part of the message
};

TEST_F(Cli, BadInputGetsAClearErrorAndNoOutput) {
  const BadInput cases[] = {
      {"empty", "", "empty:", "empty"},
      {"letters_n", "five\n1\n10 10\n", "letters_n:1:", "whole number"},
      {"fraction_n", "2.5\n1\n10 10\n", "fraction_n:1:", "whole number"},
      {"zero_n", "0\n1\n10 10\n", "zero_n:1:", "at least 1"},
      {"negative_n", "-3\n1\n10 10\n", "negative_n:1:", "at least 1"},
      {"zero_radius", "1\n0\n10 10\n5 5 1 1\n", "zero_radius:2:", "radius"},
      {"negative_radius", "1\n-1\n10 10\n5 5 1 1\n", "negative_radius:2:", "radius"},
      {"two_radii", "1\n1 2\n10 10\n5 5 1 1\n", "two_radii:2:", "expected 1 number"},
      {"flat_box", "1\n1\n10 0\n5 5 1 1\n", "flat_box:3:", "positive"},
      {"one_side", "1\n1\n10\n5 5 1 1\n", "one_side:3:", "expected 2 or 3 numbers"},
      {"three_tokens", "1\n1\n10 10\n5 5 1\n", "three_tokens:4:", "expected 4 to 6 numbers"},
      {"seven_tokens", "1\n1\n10 10\n5 5 1 1 1 1 1\n",
       "seven_tokens:4:", "expected 4 to 6 numbers"},
      {"zero_mass", "1\n1\n10 10\n5 5 1 1 1 0\n", "zero_mass:4:", "mass of particle 0"},
      {"negative_own_radius", "1\n1\n10 10\n5 5 1 1 -1\n",
       "negative_own_radius:4:", "radius of particle 0"},
      {"not_a_number", "1\n1\n10 10\n5 5 1 x1\n", "not_a_number:4:", "not a number"},
      {"nan", "1\n1\n10 10\n5 5 nan 1\n", "nan:4:", "not a finite number"},
      {"inf", "1\n1\n10 10\n5 inf 1 1\n", "inf:4:", "not a finite number"},
      {"huge", "1\n1\n10 10\n5 5 1e999 1\n", "huge:4:", "out of range"},
      {"missing_lines", "3\n1\n10 10\n5 5 1 1\n", "missing_lines:4:", "ends"},
      {"extra_lines", "1\n1\n10 10\n5 5 1 1\n2 2 0 0\n", "extra_lines:5:", "unexpected data"},
      {"outside", "1\n1\n10 10\n11 5 1 1\n", "outside:4:", "outside the box"},
      {"wall_overlap", "1\n1\n10 10\n0.5 5 1 1\n", "wall_overlap:4:", "left wall"},
      {"top_overlap", "1\n1\n10 10\n5 9.5 1 1\n", "top_overlap:4:", "top wall"},
      {"pair_overlap", "2\n1\n10 10\n3 3 0 0\n4.5 3 0 0\n",
       "pair_overlap:5:", "overlaps particle 0"},
      {"binary", "2\n1\n10 10\n\x01\x02\x03 4 5 6\n", "binary:4:", "not a number"},
  };
  for (const BadInput& c : cases) {
    const fs::path input = write(c.name, c.text);
    const fs::path out = dir_ / "out.txt";
    const Result r = carom({"run", input, "10", "-o", out});
    EXPECT_EQ(r.exit_code, 2) << c.name << ": " << r.err;
    EXPECT_NE(r.err.find(std::string(c.location)), std::string::npos) << c.name << ": " << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << c.name << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << c.name << ": " << r.err;
    EXPECT_EQ(r.out, "") << c.name;
    EXPECT_FALSE(fs::exists(out)) << c.name;
  }
}

TEST_F(Cli, AFailedRunLeavesAnExistingOutputFileAlone) {
  const fs::path out = write("keep.txt", "precious\n");
  const Result r = carom({"run", (dir_ / "missing.txt").string(), "10", "-o", out});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("missing.txt"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("No such file"), std::string::npos) << r.err;
  EXPECT_EQ(read_file(out), "precious\n");
}

TEST_F(Cli, BadEndTimeAndUsageAreUsageErrors) {
  const std::string input = kCases + "walls_only.txt";
  for (const std::vector<std::string>& args : {std::vector<std::string>{"run", input, "-1"},
                                               {"run", input, "nan"},
                                               {"run", input, "inf"},
                                               {"run", input, "soon"},
                                               {"run", input},
                                               {"run", input, "10", "--format", "xml"},
                                               {"run", input, "10", "--rule", "sticky"},
                                               {"run", input, "10", "--trace", "--format", "csv"},
                                               {"fly"}}) {
    const Result r = carom(args);
    EXPECT_EQ(r.exit_code, 2) << fmt::format("{}", fmt::join(args, " ")) << ": " << r.err;
    EXPECT_EQ(r.out, "") << fmt::format("{}", fmt::join(args, " "));
    EXPECT_FALSE(r.err.empty());
  }
}

TEST_F(Cli, UnwritableOutputIsAUsageError) {
  const Result r = carom({"run", kCases + "walls_only.txt", "20", "-o", "/nonexistent/dir/out"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("/nonexistent/dir/out"), std::string::npos) << r.err;
  // Every file the run would write is checked before it starts: nothing is created.
  const fs::path frames = dir_ / "frames.xyz", log = dir_ / "log.csv";
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"--dump", frames, "--every", "1", "--checkpoint", "/no/dir/ck"},
        {"--dump", frames, "--every", "1", "--events", "/no/dir/e.csv"},
        {"--dump", frames, "--every", "1", "--summary", "/no/dir/s.json"},
        {"--events", log, "--dump", "/no/dir/m.xyz", "--every", "1"}}) {
    std::vector<std::string> command = {"run", kCases + "walls_only.txt", "20"};
    command.insert(command.end(), args.begin(), args.end());
    const Result bad = carom(command);
    EXPECT_EQ(bad.exit_code, 2) << bad.err;
    EXPECT_NE(bad.err.find("/no/dir/"), std::string::npos) << bad.err;
    EXPECT_FALSE(fs::exists(frames)) << bad.err;
    EXPECT_FALSE(fs::exists(log)) << bad.err;
  }
}

TEST_F(Cli, AJamIsARuntimeErrorWithNoOutput) {
  const fs::path input = write("wedged.txt", "1\n0.5\n1 10\n0.5 5 1 0\n");
  const fs::path out = dir_ / "out.txt";
  const Result r = carom({"run", input, "1", "--trace", "-o", out});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("jammed"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  for (const auto& entry : fs::directory_iterator(dir_)) {
    EXPECT_EQ(entry.path().string().find(".tmp."), std::string::npos) << entry.path();
  }
}

TEST_F(Cli, OutputThroughASymlinkKeepsTheLink) {
  const fs::path target = write("real.csv", "old\n");
  const fs::path link = dir_ / "link.csv";
  fs::create_symlink(target, link);
  const Result r = carom({"run", kCases + "normal.txt", "20", "--format", "csv", "-o", link});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(read_file(target), read_file(kCases + "normal.T20.csv"));
}

TEST_F(Cli, AnInterruptedRunLeavesNoPartialResultAndKeepsItsFrames) {
  const fs::path start = dir_ / "gas.txt";
  ASSERT_EQ(carom({"init", "--n", "20000", "--phi", "0.5", "-o", start}).exit_code, 0);
  const fs::path out = dir_ / "out.json", movie = dir_ / "movie.xyz";
  const pid_t pid = start_run(start, {"500", "--rule", "elastic", "--format", "json", "-o",
                                      out.string(), "--dump", movie.string(), "--every", "0.5"});
  ASSERT_TRUE(wait_until([&] { return holds(movie, "Time=0.5"); }));
  ::kill(pid, SIGTERM);
  EXPECT_EQ(finish(pid), 143);
  const std::string err = read_file(dir_ / "stderr");
  EXPECT_NE(err.find("terminated (SIGTERM)"), std::string::npos) << err;
  EXPECT_NE(err.find("nothing to resume from"), std::string::npos) << err;
  EXPECT_NE(err.find("frames up to then are in"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(out));
  for (const auto& entry : fs::directory_iterator(dir_)) {
    EXPECT_EQ(entry.path().string().find(".tmp."), std::string::npos) << entry.path();
  }
  // Every frame written is whole.
  const std::string frames = read_file(movie);
  EXPECT_EQ(std::count(frames.begin(), frames.end(), '\n') % 20002, 0);
}

// Regression: with --checkpoint-every, the first periodic save installed its own signal
// handlers, so Ctrl-C ended the run silently and the checkpoint held the last periodic save.
TEST_F(Cli, CtrlCSavesTheInterruptedStateNotTheLastPeriodicOne) {
  const fs::path start = dir_ / "gas.txt", checkpoint = dir_ / "ck", movie = dir_ / "m.xyz";
  ASSERT_EQ(carom({"init", "--n", "20000", "--phi", "0.5", "-o", start}).exit_code, 0);
  // A signal that arrives while a periodic checkpoint is being written stops the run at that
  // very event, where both saves are one state: try again then, to tell them apart.
  std::uint64_t events = 0;
  for (int attempt = 0; attempt < 3 && events % 250000 == 0; ++attempt) {
    fs::remove(movie);
    const pid_t pid = start_run(
        start, {"500", "--rule", "elastic", "--checkpoint", checkpoint.string(),
                "--checkpoint-every", "250000", "--dump", movie.string(), "--every", "1"});
    ASSERT_TRUE(wait_until([&] { return holds(movie, "Time=2"); }));
    ::kill(pid, SIGINT);
    EXPECT_EQ(finish(pid), 130);
    const std::string err = read_file(dir_ / "stderr");
    EXPECT_NE(err.find("interrupted (SIGINT)"), std::string::npos) << err;
    EXPECT_NE(err.find("carom run --resume " + checkpoint.string()), std::string::npos) << err;
    EXPECT_EQ(read_file(dir_ / "stdout"), "");  // no final table for a run that did not finish
    const auto saved = nlohmann::json::parse(read_file(checkpoint));
    events = saved["counts"]["events"];
    EXPECT_NE(err.find(fmt::format("after {} events", events)), std::string::npos) << err;
    EXPECT_GE(saved["time"].get<double>(), 2.0);
    EXPECT_TRUE(saved["settled"].get<bool>());
  }
  EXPECT_NE(events % 250000, 0u);  // not a periodic save
}

// Regression: the stop flag was looked at only after events, so two disks flying side by
// side in a periodic box (cell crossings, never a collision) ignored Ctrl-C until SIGKILL.
TEST_F(Cli, CtrlCStopsARunWithoutEventsAndSavesIt) {
  const fs::path start = write("parallel.txt", "2\n0.5\n10 10\n1 1 1 0\n1 5 1 0\n");
  const fs::path checkpoint = dir_ / "ck";
  const fs::path movie = dir_ / "movie.xyz";
  const pid_t pid =
      start_run(start, {"1e11", "--boundary", "periodic", "--checkpoint", checkpoint.string(),
                        "--dump", movie, "--every", "1e10", "-q"});
  ASSERT_EQ(interrupted_exit_code(pid, movie), 130) << "the run ignored SIGINT";
  const auto saved = nlohmann::json::parse(read_file(checkpoint));
  EXPECT_EQ(saved["counts"]["events"], 0);
  const double stopped_at = saved["time"].get<double>();
  EXPECT_GT(stopped_at, 0.0);
  // Resumed to a little later than it stopped, wherever that was (a fast machine gets far in
  // 300 ms: an end time fixed in advance could lie before it).
  const std::string end = fmt::format("{}", stopped_at + 1000.0);
  EXPECT_EQ(carom({"run", "--resume", checkpoint, end, "-q"}).exit_code, 0);
}

// A sheared box renews its predictions at every image horizon, however few events there are:
// two disks sheared at 1e9 make renewals all the time and no collisions. The stop is heard
// within the slice the renewals are counted in. (Regression: 10 s to 10 min after SIGINT.)
TEST_F(Cli, CtrlCStopsAShearedRunOfRenewalsAndSavesIt) {
  const fs::path start = write("two.txt", "2\n0.5\n10 10\n1 1 1 0\n1 5 1 0\n");
  const fs::path checkpoint = dir_ / "ck";
  const fs::path movie = dir_ / "movie.xyz";
  const pid_t pid = start_run(
      start, {"1", "--boundary", "periodic", "--rule", "elastic", "--shear", "1e9", "--checkpoint",
              checkpoint.string(), "--dump", movie, "--every", "1", "-q"});
  ASSERT_EQ(interrupted_exit_code(pid, movie), 130) << "the sheared run ignored SIGINT";
  EXPECT_GT(nlohmann::json::parse(read_file(checkpoint))["time"].get<double>(), 0.0);
}

// Work without bound is refused before the run (exit 2), from the command line and so from every
// front end: a thermostat acting astronomically often, a shear whose images slide across the box
// more often than could ever be processed, shears beyond the numbers carom reads.
TEST_F(Cli, RunsThatCouldNeverFinishAreRefused) {
  const fs::path start = dir_ / "gas.txt";
  ASSERT_EQ(
      carom({"init", "--n", "50", "--phi", "0.3", "--boundary", "periodic", "-o", start}).exit_code,
      0);
  const std::vector<std::pair<std::vector<std::string>, std::string>> refused = {
      {{"--thermostat", "rescale", "--kT", "1", "--thermostat-every", "1e-100"},
       "check --thermostat-every"},
      {{"--thermostat", "andersen", "--kT", "1", "--thermostat-rate", "1e100"},
       "check --thermostat-rate"},
      {{"--rule", "elastic", "--shear", "1e99"}, "could cross the box"},
      {{"--rule", "elastic", "--shear", "1e80", "--velocity-profile"}, "could cross the box"},
      {{"--thermostat", "rescale", "--kT", "1e101", "--thermostat-every", "1"}, "--kT"},
  };
  expect_runs_refused(start, refused);
}

TEST_F(Cli, LongRunsShowProgressOnATerminalOnly) {
  const fs::path start = dir_ / "gas.txt";
  ASSERT_EQ(
      carom({"init", "--n", "20000", "--phi", "0.5", "--boundary", "walls", "-o", start}).exit_code,
      0);
  // `script` gives the run a terminal; its output is what the terminal showed.
  const auto on_terminal = [&](const std::string& extra) {
    const std::string command = quote(CAROM_EXE) + " run " + quote(start) +
                                " 30 --rule elastic --format csv -o " + quote(dir_ / "out.csv") +
                                extra;
    const fs::path screen = dir_ / "screen";
    std::system(("script -qec " + quote(command) + " /dev/null > " + quote(screen)).c_str());
    return read_file(screen);
  };
  EXPECT_NE(on_terminal("").find("events/s"), std::string::npos);
  EXPECT_EQ(on_terminal(" --quiet").find("events/s"), std::string::npos);
  // Not a terminal: nothing on stderr.
  const Result piped = carom({"run", start, "30", "--rule", "elastic", "--format", "csv", "-o",
                              (dir_ / "out.csv").string()});
  EXPECT_EQ(piped.err, "");
}

// Z whose blocks remember each other: 1024 disks at 0.71 (inside the coexistence region) by
// event chains, measured over 100 units, blocks of 4: no drift, but Z fluctuates over longer
// than a block, and the run says its error understates the uncertainty. (The steady gas of the
// test below is told nothing.)
TEST_F(Cli, ARunSaysWhenZsBlocksAreCorrelated) {
  const fs::path start = dir_ / "dense.txt";
  ASSERT_EQ(carom({"init", "--n", "1024", "--phi", "0.71", "--boundary", "periodic", "-o", start})
                .exit_code,
            0);
  const Result slow = carom({"run", start, "600", "--equilibrate", "500", "--sampler", "ecmc",
                             "--format", "json"});
  ASSERT_EQ(slow.exit_code, 0) << slow.err;
  const auto verdict = nlohmann::json::parse(slow.out)["compressibility_factor_drift"];
  EXPECT_LT(std::abs(verdict["sigmas"].get<double>()), 3.0);
  const double blocks = verdict["intervals"].get<double>();
  EXPECT_GT(verdict["block_correlation"].get<double>(), 2.0 / std::sqrt(blocks)) << verdict;
  EXPECT_NE(slow.err.find("carom: warning: Z's blocks of the measurement window are correlated"),
            std::string::npos)
      << slow.err;
  EXPECT_EQ(slow.err.find("drifted"), std::string::npos) << slow.err;
}

// Z over the first half of the measurement window against the second: a run still changing is
// told so; an equilibrated one is not.
TEST_F(Cli, ARunSaysWhenZDriftedOverItsWindow) {
  const fs::path start = dir_ / "gas.txt";
  ASSERT_EQ(carom({"init", "--n", "500", "--phi", "0.3", "--boundary", "periodic", "-o", start})
                .exit_code,
            0);
  const Result steady = carom({"run", start, "60", "--equilibrate", "10", "--format", "json"});
  ASSERT_EQ(steady.exit_code, 0) << steady.err;
  EXPECT_EQ(steady.err.find("warning"), std::string::npos) << steady.err;
  const auto calm = nlohmann::json::parse(steady.out)["compressibility_factor_drift"];
  EXPECT_EQ(calm["intervals"], 25);  // blocks of 2 from t = 10 to 60
  EXPECT_LT(std::abs(calm["sigmas"].get<double>()), 3.0);
  EXPECT_LT(calm["block_correlation"].get<double>(), 2.0 / 5.0);  // 25 blocks
  // A cooling granular gas changes all along.
  const Result cooling = carom({"run", start, "30", "--restitution", "0.5", "--format", "json"});
  ASSERT_EQ(cooling.exit_code, 0) << cooling.err;
  EXPECT_NE(cooling.err.find("carom: warning: Z drifted from"), std::string::npos) << cooling.err;
  const auto drift = nlohmann::json::parse(cooling.out)["compressibility_factor_drift"];
  EXPECT_LT(drift["sigmas"].get<double>(), -3.0);
  EXPECT_GT(drift["first_half"].get<double>(), drift["second_half"].get<double>());
  EXPECT_EQ(carom({"run", start, "30", "--restitution", "0.5", "-q", "-o", dir_ / "q.txt"}).err,
            "");
  // No window, no verdict.
  const Result none = carom({"run", start, "5", "--equilibrate", "5", "--format", "json"});
  EXPECT_TRUE(nlohmann::json::parse(none.out)["compressibility_factor_drift"].is_null());
  // Nor a pressure: the window lasted no time (not a pressure of 0).
  for (const char* key : {"compressibility_factor", "pressure", "collision_rate"}) {
    EXPECT_TRUE(nlohmann::json::parse(none.out)[key].is_null()) << key;
  }
}

// A dump that a resumed run begins (not one it continues) starts with a frame at the resumed
// time when that is a multiple of --every, as any new dump's first frame is at its first instant.
TEST_F(Cli, ADumpBegunByAResumedRunStartsAtItsTime) {
  const fs::path start = dir_ / "gas.txt", checkpoint = dir_ / "ck", movie = dir_ / "late.xyz";
  ASSERT_EQ(
      carom({"init", "--n", "60", "--phi", "0.3", "--boundary", "periodic", "-o", start}).exit_code,
      0);
  ASSERT_EQ(carom({"run", start, "2", "--checkpoint", checkpoint, "-q"}).exit_code, 0);
  ASSERT_EQ(carom({"run", "--resume", checkpoint, "4", "--dump", movie, "--every", "0.5", "-q"})
                .exit_code,
            0);
  const std::string frames = read_file(movie);
  EXPECT_EQ(frames.find("Time=1.5"), std::string::npos);
  const std::size_t first = frames.find("Time=");
  ASSERT_NE(first, std::string::npos);
  EXPECT_EQ(frames.substr(first, 7), "Time=2\n");
  std::size_t count = 0;
  for (std::size_t at = frames.find("Time="); at != std::string::npos;
       at = frames.find("Time=", at + 1)) {
    ++count;
  }
  EXPECT_EQ(count, 5u);  // 2, 2.5, 3, 3.5, 4
}

// A start at rest (a GSD frame without velocities, say) does nothing: said so, Z undefined (null),
// and --kT gives it Maxwell-Boltzmann velocities, reproducibly.
TEST_F(Cli, AStartAtRestIsNotedAndKTGivesItVelocities) {
  const fs::path rest = write("rest.txt",
                              "# carom: boundary=periodic rule=elastic\n4\n0.5\n6 6\n"
                              "1 1 0 0\n4 1 0 0\n1 4 0 0\n4 4 0 0\n");
  const Result still = carom({"run", rest, "5", "--format", "json"});
  ASSERT_EQ(still.exit_code, 0) << still.err;
  EXPECT_NE(still.err.find("every particle is at rest (kT = 0)"), std::string::npos) << still.err;
  const auto at_rest = nlohmann::json::parse(still.out);
  EXPECT_EQ(at_rest["events"], 0);
  EXPECT_TRUE(at_rest["compressibility_factor"].is_null());
  const auto thermal = [&](const std::string& seed) {
    const Result r = carom({"run", rest, "5", "--kT", "2", "--seed", seed, "--format", "json"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err.find("at rest"), std::string::npos) << r.err;
    EXPECT_NE(r.out.find("\"seed\": " + seed), std::string::npos);
    return r.out.substr(r.out.find("\"particles\""));
  };
  const Result first = carom({"run", rest, "5", "--kT", "2", "--seed", "3", "--format", "json"});
  const auto moving = nlohmann::json::parse(first.out);
  EXPECT_GT(moving["events"], 0);
  // kT exactly (to round-off) over D (N - 1) degrees of freedom, conserved by elastic collisions.
  EXPECT_NEAR(moving["temperature"].get<double>(), 2.0, 1e-12);
  EXPECT_NEAR(moving["kinetic_energy_initial"].get<double>(), 0.5 * 2.0 * 6.0, 1e-12);
  EXPECT_TRUE(moving["compressibility_factor"].is_number());
  EXPECT_EQ(thermal("3"), thermal("3"));
  EXPECT_NE(thermal("3"), thermal("4"));
  EXPECT_EQ(carom({"run", rest, "5", "--seed", "3"}).exit_code, 2);  // --seed needs --kT
  EXPECT_EQ(carom({"run", rest, "5", "--kT", "0"}).exit_code, 2);
  EXPECT_EQ(carom({"run", rest, "5", "--kT", "-1"}).exit_code, 2);
  const fs::path checkpoint = dir_ / "ck";
  ASSERT_EQ(carom({"run", rest, "1", "--kT", "1", "--checkpoint", checkpoint, "-q"}).exit_code, 0);
  EXPECT_EQ(carom({"run", "--resume", checkpoint, "2", "--kT", "1"}).exit_code, 2);
}

// --progress: whole lines at the period asked for, terminal or not (a batch job's log).
TEST_F(Cli, BatchJobsGetProgressLinesOnRequest) {
  const fs::path start = dir_ / "gas.txt";
  ASSERT_EQ(carom({"init", "--n", "20000", "--phi", "0.5", "-o", start}).exit_code, 0);
  const auto lines_of = [](const std::string& err, const std::string& word) {
    EXPECT_EQ(err.find('\r'), std::string::npos) << err;
    std::size_t count = 0;
    std::istringstream in(err);
    for (std::string line; std::getline(in, line);) count += line.find(word) != std::string::npos;
    return count;
  };
  const Result run = carom({"run", start, "30", "--format", "csv", "-o",
                            (dir_ / "out.csv").string(), "--progress", "0.1", "-q"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_GE(lines_of(run.err, "events/s"), 1u) << run.err;
  EXPECT_NE(run.err.find(" left  Z = "), std::string::npos) << run.err;
  const Result compress = carom({"compress", start, "--phi", "0.6", "-o",
                                 (dir_ / "dense.txt").string(), "--progress", "0.05"});
  ASSERT_EQ(compress.exit_code, 0) << compress.err;
  EXPECT_GE(lines_of(compress.err, "packing fraction"), 1u) << compress.err;
  for (const char* command : {"run gas 1", "compress gas --jam"}) {
    std::vector<std::string> args;
    std::istringstream words(command);
    for (std::string word; words >> word;) args.push_back(word == "gas" ? start.string() : word);
    args.insert(args.end(), {"--progress", "0"});
    const Result bad = carom(args);
    EXPECT_EQ(bad.exit_code, 2);
    EXPECT_NE(bad.err.find("--progress must be a number of seconds above 0"), std::string::npos)
        << bad.err;
  }
}

TEST_F(Cli, InitWritesAReproducibleValidStartFile) {
  const Result a = carom({"init", "--n", "300", "--phi", "0.5", "--seed", "42"});
  const Result b = carom({"init", "--n", "300", "--phi", "0.5", "--seed", "42"});
  const Result c = carom({"init", "--n", "300", "--phi", "0.5", "--seed", "43"});
  ASSERT_EQ(a.exit_code, 0) << a.err;
  EXPECT_EQ(a.out, b.out);
  EXPECT_NE(a.out, c.out);
  // Periodic unless asked for walls: the bulk a study means.
  EXPECT_EQ(a.out.substr(0, 44), "# carom: boundary=periodic rule=elastic\n300\n");
  EXPECT_EQ(carom({"init", "--n", "300", "--phi", "0.5", "--boundary", "walls"}).out.substr(0, 41),
            "# carom: boundary=walls rule=elastic\n300\n");
  const fs::path start = write("start.txt", a.out);
  const Result run = carom({"run", start, "5", "--format", "json"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("\"packing_fraction\": 0.5"), std::string::npos) << run.out.substr(0, 900);
}

TEST_F(Cli, InitRefusesImpossibleRequests) {
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"init", "--n", "10", "--phi", "0.95"},
        {"init", "--n", "10", "--phi", "0"},
        {"init", "--n", "0", "--phi", "0.3"},
        {"init", "--n", "10", "--phi", "0.3", "--box", "10", "10", "--radius", "1"},
        {"init", "--n", "10", "--phi", "0.3", "--lattice", "--random"},
        {"init", "--n", "500", "--phi", "0.7", "--random"},
        {"init", "--n", "10", "--phi", "0.3", "--polydispersity", "0.9"},
        {"init", "--n", "10", "--phi", "0.3", "--radius", "0"},
        {"init", "--n", "10", "--phi", "0.3", "--box", "10", "0"},
        {"init", "--n", "10"}}) {
    const Result r = carom(args);
    EXPECT_EQ(r.exit_code, 2) << fmt::format("{}", fmt::join(args, " ")) << ": " << r.err;
    EXPECT_EQ(r.out, "");
  }
  const Result dense = carom({"init", "--n", "10", "--phi", "0.95"});
  EXPECT_NE(dense.err.find("close packing"), std::string::npos) << dense.err;
}

TEST_F(Cli, PhysicsOptionsAreCheckedTogether) {
  const std::string input = kCases + "particles_only.txt";
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"run", input, "10", "--rule", "swap", "--restitution", "0.9"},
        {"run", input, "10", "--rule", "elastic", "--restitution", "0"},
        {"run", input, "10", "--rule", "elastic", "--restitution", "1.5"},
        {"run", input, "10", "--tc", "-1"},
        {"run", input, "10", "--equilibrate", "11"},
        {"run", input, "10", "--boundary", "toroidal"}}) {
    const Result r = carom(args);
    EXPECT_EQ(r.exit_code, 2) << fmt::format("{}", fmt::join(args, " ")) << ": " << r.err;
  }
  const Result ok = carom({"run", input, "10", "--rule", "elastic", "--restitution", "0.9",
                           "--boundary", "periodic", "--format", "json"});
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_NE(ok.out.find("\"boundary\": \"periodic\""), std::string::npos);
  EXPECT_NE(ok.out.find("\"restitution\": 0.9"), std::string::npos);
}

TEST_F(Cli, SummaryFileCarriesTheObservables) {
  const fs::path summary = dir_ / "summary.json";
  const Result r = carom({"run", kCases + "normal.txt", "50", "--summary", summary});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string text = read_file(summary);
  for (const char* field : {"\"events\"",
                            "\"pair_collisions\"",
                            "\"wall_collisions\"",
                            "\"kinetic_energy_initial\"",
                            "\"kinetic_energy_final\"",
                            "\"momentum_final\"",
                            "\"temperature\"",
                            "\"pressure\"",
                            "\"wall_pressure\"",
                            "\"compressibility_factor\"",
                            "\"collision_rate\"",
                            "\"mean_free_time\"",
                            "\"wall_seconds\"",
                            "\"events_per_second\"",
                            "\"rule\"",
                            "\"boundary\"",
                            "\"restitution\"",
                            "\"n\"",
                            "\"box\"",
                            "\"end_time\""}) {
    EXPECT_NE(text.find(field), std::string::npos) << field;
  }
  EXPECT_EQ(text.find("\"particles\""), std::string::npos);
}

TEST_F(Cli, EventLogListsEveryCollision) {
  const fs::path log = dir_ / "events.csv";
  const Result r = carom({"run", kCases + "walls_only.txt", "20", "--events", log});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_file(log),
            "time,kind,first,partner\n9.5,wall,0,-1\n13.000000000000007,wall,3,-4\n"
            "15,wall,2,-3\n18.000000000000007,wall,1,-2\n");
}

TEST_F(Cli, TrajectoryOptionsAreChecked) {
  const std::string input = kCases + "walls_only.txt";
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"run", input, "10", "--dump", (dir_ / "t.pdb").string(), "--every",
                                 "1"},
        {"run", input, "10", "--dump", (dir_ / "t.xyz").string()},
        {"run", input, "10", "--dump", (dir_ / "t.xyz").string(), "--every", "0"},
        {"run", input, "10", "--dump", (dir_ / "t.xyz").string(), "--every", "1e-9"},
        {"run", input, "10", "--every", "1"}}) {
    const Result r = carom(args);
    EXPECT_EQ(r.exit_code, 2) << fmt::format("{}", fmt::join(args, " ")) << ": " << r.err;
  }
  EXPECT_FALSE(fs::exists(dir_ / "t.xyz"));
  const Result ok =
      carom({"run", input, "10", "--dump", (dir_ / "t.xyz").string(), "--every", "2.5"});
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  const std::string xyz = read_file(dir_ / "t.xyz");
  EXPECT_EQ(std::count(xyz.begin(), xyz.end(), '\n'), 5 * 6);  // t = 0, 2.5, 5, 7.5, 10
  EXPECT_NE(xyz.find("Time=7.5"), std::string::npos);
}

// The particles of a json result, for comparing runs bit for bit (full-precision numbers).
std::string particles_of(const std::string& json) {
  return json.substr(json.find("\"particles\""));
}

TEST_F(Cli, ACheckpointedRunResumesBitForBit) {
  const fs::path start = dir_ / "gas.txt", checkpoint = dir_ / "run.ckpt";
  for (const std::string boundary : {"walls", "periodic"}) {
    ASSERT_EQ(carom({"init", "--n", "500", "--phi", "0.6", "--boundary", boundary, "-o", start})
                  .exit_code,
              0);
    const std::vector<std::string> physics = {"--rule", "elastic",       "--boundary",
                                              boundary, "--equilibrate", "3"};
    std::vector<std::string> direct = {"run", start, "20", "--format", "json"};
    direct.insert(direct.end(), physics.begin(), physics.end());
    const Result whole = carom(direct);
    ASSERT_EQ(whole.exit_code, 0) << whole.err;
    // Stop at 1.7 (before equilibration ends) and at 9.2, resume twice.
    std::vector<std::string> first = {"run", start, "1.7", "--checkpoint", checkpoint};
    first.insert(first.end(), physics.begin(), physics.end());
    ASSERT_EQ(carom(first).exit_code, 0);
    ASSERT_EQ(carom({"run", "--resume", checkpoint, "9.2", "--checkpoint", checkpoint}).exit_code,
              0);
    const Result resumed = carom({"run", "--resume", checkpoint, "20", "--format", "json"});
    ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
    EXPECT_EQ(particles_of(resumed.out), particles_of(whole.out)) << boundary;
    for (const char* same : {"\"events\"", "\"pressure\"", "\"kinetic_energy_initial\""}) {
      const auto line = [&](const std::string& text) {
        const auto at = text.find(same);
        return text.substr(at, text.find('\n', at) - at);
      };
      EXPECT_EQ(line(resumed.out), line(whole.out)) << same;
    }
  }
}

// Regression: a stop that landed after the final checkpoint was written and before the summary
// left a checkpoint without the window's records, and `--resume` of it reported no drift
// verdict, no pressure tensor errors, no transport and no seed. A run resumed where its end is
// reached writes the summary of the run (here: the summary it wrote itself).
TEST_F(Cli, ARunResumedAtItsEndWritesTheSummaryOfTheRunNeverStopped) {
  const fs::path start = dir_ / "gas.txt", checkpoint = dir_ / "run.ckpt";
  ASSERT_EQ(carom({"init", "--n", "100", "--phi", "0.3", "--boundary", "periodic", "-o", start})
                .exit_code,
            0);
  const auto summary_without_clock = [](const fs::path& path) {
    nlohmann::json summary = nlohmann::json::parse(read_file(path));
    summary.erase("wall_seconds");
    summary.erase("events_per_second");
    return summary.dump(2);
  };
  // The physics, then the measurements asked for (which a resumed run is asked for again).
  using Options = std::vector<std::string>;
  for (const auto& [physics, measured] :
       {std::pair{Options{"--kT", "1", "--seed", "5"}, Options{"--transport"}},
        std::pair{Options{"--shear", "0.2", "--velocity-profile", "--thermostat", "rescale", "--kT",
                          "1", "--thermostat-every", "1"},
                  Options{}}}) {
    Options run = {"run",
                   start,
                   "20",
                   "--rule",
                   "elastic",
                   "--equilibrate",
                   "4",
                   "--checkpoint",
                   checkpoint,
                   "--summary",
                   dir_ / "whole.json",
                   "-o",
                   dir_ / "out.txt"};
    run.insert(run.end(), physics.begin(), physics.end());
    run.insert(run.end(), measured.begin(), measured.end());
    ASSERT_EQ(carom(run).exit_code, 0) << physics.front();
    Options resume = {"run", "--resume",      checkpoint, "20", "--summary", dir_ / "resumed.json",
                      "-o",  dir_ / "out.txt"};
    resume.insert(resume.end(), measured.begin(), measured.end());
    const Result resumed = carom(resume);
    ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
    const std::string whole = summary_without_clock(dir_ / "whole.json");
    EXPECT_EQ(summary_without_clock(dir_ / "resumed.json"), whole) << physics.front();
    // Blocks of 0.5 from t = 4 to 20.
    EXPECT_EQ(nlohmann::json::parse(whole)["compressibility_factor_drift"]["intervals"], 32);
  }
}

// A run with --transport stopped at one end and resumed to a later one reports the transport
// coefficients of one run to the later end, where both windows hold ten blocks of the lag (a
// resumed run once measured them over its own piece only).
TEST_F(Cli, TransportContinuedToALaterEndIsTheRunInOne) {
  const fs::path start = spheres_at_0_3(200), checkpoint = dir_ / "run.ckpt";
  const auto transport_of = [&](const fs::path& summary) {
    return nlohmann::json::parse(read_file(summary))["transport"];
  };
  // Blocks of about 20 time units: 210 holds ten of them.
  ASSERT_EQ(carom({"run", start, "230", "--transport", "--summary", dir_ / "one.json", "-o",
                   dir_ / "one.txt"})
                .exit_code,
            0);
  ASSERT_EQ(carom({"run", start, "210", "--transport", "--checkpoint", checkpoint,
                   "--checkpoint-every", "100", "-o", dir_ / "first.txt"})
                .exit_code,
            0);
  ASSERT_EQ(carom({"run", "--resume", checkpoint, "230", "--transport", "--summary",
                   dir_ / "two.json", "-o", dir_ / "two.txt"})
                .exit_code,
            0);
  const auto one = transport_of(dir_ / "one.json");
  ASSERT_TRUE(one.is_object());
  EXPECT_EQ(one["blocks"], 11);
  EXPECT_EQ(transport_of(dir_ / "two.json"), one);
}

TEST_F(Cli, SummariesHaveThePressureTensorAndTransportCoefficientsWhenAsked) {
  const fs::path start = spheres_at_0_3(300), summary = dir_ / "summary.json";
  ASSERT_EQ(carom({"run", start, "20", "--equilibrate", "5", "--transport", "--summary", summary,
                   "-o", dir_ / "out.txt"})
                .exit_code,
            0);
  const auto j = nlohmann::json::parse(read_file(summary));
  for (const char* c : {"xx", "yy", "zz", "xy", "xz", "yz"}) {
    EXPECT_TRUE(j["pressure_tensor"][c].is_number()) << c;
    EXPECT_GT(j["pressure_tensor_error"][c].get<double>(), 0.0) << c;
  }
  EXPECT_NEAR(j["pressure_tensor"]["xx"].get<double>() / j["pressure"].get<double>(), 1.0, 0.1);
  const auto& t = j["transport"];
  EXPECT_EQ(t["blocks"], 10);
  for (const char* key : {"self_diffusion", "shear_viscosity", "thermal_conductivity",
                          "self_diffusion_yeh_hummer", "enskog_shear_viscosity"}) {
    EXPECT_GT(t[key].get<double>(), 0.0) << key;
  }
  // Without --transport: none; with walls: refused.
  ASSERT_EQ(carom({"run", start, "2", "--summary", summary, "-o", dir_ / "out.txt"}).exit_code, 0);
  EXPECT_TRUE(nlohmann::json::parse(read_file(summary))["transport"].is_null());
  const fs::path walled = dir_ / "walled.txt";
  ASSERT_EQ(carom({"init", "--n", "50", "--phi", "0.3", "--boundary", "walls", "-o", walled})
                .exit_code,
            0);
  const Result walls = carom({"run", walled, "2", "--transport", "-o", dir_ / "out.txt"});
  EXPECT_EQ(walls.exit_code, 2);
  EXPECT_NE(walls.err.find("--transport needs a periodic box"), std::string::npos) << walls.err;
}

TEST_F(Cli, ThermostatsHoldTheTemperatureAndBadOnesAreRefused) {
  const fs::path start = dir_ / "gas.txt", summary = dir_ / "summary.json";
  ASSERT_EQ(carom({"init", "--n", "100", "--phi", "0.3", "--boundary", "periodic", "-o", start})
                .exit_code,
            0);
  // An inelastic gas rescaled to kT = 2 at t = 1, 2, 3: at t = 3 its temperature is 2.
  ASSERT_EQ(
      carom({"run", start, "3", "--restitution", "0.7", "--kT", "2", "--thermostat", "rescale",
             "--thermostat-every", "1", "--summary", summary, "-o", dir_ / "out.txt"})
          .exit_code,
      0);
  const auto j = nlohmann::json::parse(read_file(summary));
  EXPECT_NEAR(j["temperature"].get<double>(), 2.0, 1e-12);
  EXPECT_EQ(j["thermostat"]["kind"], "rescale");
  // Andersen's without an interval: resets as events, no "every".
  ASSERT_EQ(carom({"run", start, "3", "--kT", "2", "--thermostat", "andersen", "--thermostat-rate",
                   "1", "--summary", summary, "-o", dir_ / "out.txt"})
                .exit_code,
            0);
  const auto events = nlohmann::json::parse(read_file(summary));
  EXPECT_EQ(events["thermostat"]["kind"], "andersen");
  EXPECT_TRUE(events["thermostat"]["every"].is_null());
  EXPECT_EQ(events["thermostat"]["rate"], 1.0);
  const std::vector<std::pair<std::vector<std::string>, std::string>> refused = {
      {{"--thermostat", "rescale", "--thermostat-every", "1"}, "needs --kT"},
      {{"--thermostat", "rescale", "--kT", "1"}, "needs --thermostat-every"},
      {{"--thermostat", "andersen", "--kT", "1", "--thermostat-every", "1"}, "--thermostat-rate"},
      {{"--thermostat", "rescale", "--kT", "1", "--thermostat-every", "-1"}, "greater than 0"},
      {{"--thermostat-every", "1"}, "need --thermostat KIND"},
      {{"--thermostat", "berendsen"}, "berendsen"},
  };
  expect_runs_refused(start, refused);
}

TEST_F(Cli, AShearedRunReportsItsStressAndBadShearsAreRefused) {
  const fs::path start = dir_ / "gas.txt", summary = dir_ / "summary.json";
  ASSERT_EQ(carom({"run", "--help"}).out.find("--velocity-profile") != std::string::npos, true);
  ASSERT_EQ(carom({"init", "--dim", "3", "--n", "200", "--phi", "0.3", "--boundary", "periodic",
                   "-o", start})
                .exit_code,
            0);
  ASSERT_EQ(carom({"run", start, "10", "--rule", "elastic", "--shear", "0.5", "--velocity-profile",
                   "--thermostat", "rescale", "--kT", "1", "--thermostat-every", "0.5", "--summary",
                   summary, "-o", dir_ / "out.txt"})
                .exit_code,
            0);
  const auto j = nlohmann::json::parse(read_file(summary));
  EXPECT_NEAR(j["temperature"].get<double>(), 1.0, 1e-12);  // relative to the profile
  const auto& shear = j["shear"];
  EXPECT_EQ(shear["rate"], 0.5);
  EXPECT_GT(shear["shear_stress"].get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(shear["shear_stress"].get<double>(), -j["pressure_tensor"]["xy"].get<double>());
  EXPECT_DOUBLE_EQ(shear["shear_viscosity"].get<double>(),
                   shear["shear_stress"].get<double>() / 0.5);
  EXPECT_GT(shear["shear_viscosity_error"].get<double>(), 0.0);
  ASSERT_EQ(
      carom({"run", start, "1", "--rule", "elastic", "--summary", summary, "-o", dir_ / "out.txt"})
          .exit_code,
      0);
  EXPECT_TRUE(nlohmann::json::parse(read_file(summary))["shear"].is_null());
  const fs::path walled = dir_ / "walled.txt";
  ASSERT_EQ(carom({"init", "--n", "50", "--phi", "0.3", "--boundary", "walls", "-o", walled})
                .exit_code,
            0);
  const Result walls =
      carom({"run", walled, "1", "--rule", "elastic", "--shear", "1", "-o", dir_ / "out.txt"});
  EXPECT_EQ(walls.exit_code, 2);
  EXPECT_NE(walls.err.find("--shear needs a periodic box"), std::string::npos) << walls.err;
  const std::vector<std::pair<std::vector<std::string>, std::string>> refused = {
      {{"--shear", "1", "--rule", "swap"}, "--shear needs --rule elastic"},
      {{"--velocity-profile", "--rule", "elastic"}, "--velocity-profile needs --shear"},
      {{"--shear", "0", "--velocity-profile", "--rule", "elastic"}, "other than 0"},
      {{"--shear", "nan", "--rule", "elastic"}, "--shear"},
      {{"--shear", "1", "--rule", "elastic", "--transport"}, "a sheared run gives its viscosity"},
  };
  expect_runs_refused(start, refused);
}

TEST_F(Cli, TheTimeSeriesIsARunsThermoOutputAndContinuesAcrossResumes) {
  const fs::path start = dir_ / "gas.txt", checkpoint = dir_ / "run.ckpt";
  ASSERT_EQ(carom({"init", "--n", "400", "--phi", "0.5", "--boundary", "periodic", "-o", start})
                .exit_code,
            0);
  const std::vector<std::string> physics = {"--rule",   "elastic",       "--boundary",
                                            "periodic", "--equilibrate", "3"};
  const auto with = [&](std::vector<std::string> args, const std::vector<std::string>& more) {
    args.insert(args.end(), more.begin(), more.end());
    return args;
  };
  const fs::path whole_log = dir_ / "whole.csv", summary = dir_ / "summary.json";
  ASSERT_EQ(carom(with({"run", start, "20", "-o", dir_ / "out.txt", "--summary", summary, "--log",
                        whole_log, "--log-every", "0.5"},
                       physics))
                .exit_code,
            0);
  const std::string text = read_file(whole_log);
  ASSERT_EQ(text.substr(0, text.find('\n') + 1),
            "time,events,pair_collisions,virial,wall_momentum,temperature,pressure,Z,"
            "collision_rate,pressure_mean,pressure_error,Z_mean,Z_error,pxx,pyy,pxy,Gxx,Gyy,Gxy\n");
  std::vector<std::vector<std::string>> rows;
  for (std::size_t from = text.find('\n') + 1; from < text.size();) {
    const std::size_t end = text.find('\n', from);
    std::vector<std::string> fields;
    std::string line = text.substr(from, end - from), item;
    std::istringstream in(line);
    while (std::getline(in, item, ',')) fields.push_back(item);
    if (line.back() == ',') fields.emplace_back();
    rows.push_back(fields);
    from = end + 1;
  }
  ASSERT_EQ(rows.size(), 41u);  // t = 0, 0.5, ..., 20
  EXPECT_EQ(rows[6][0], "3");
  EXPECT_EQ(rows[6][11], "") << "no averages while equilibrating";
  EXPECT_EQ(rows[7][11], rows[7][7]) << "the first row of the window is its own mean";
  // The mean of the intervals' Z over the window is the window's Z, as the summary gives it.
  const auto z = nlohmann::json::parse(read_file(summary))["compressibility_factor"].get<double>();
  const double z_mean = std::stod(rows.back()[11]), z_error = std::stod(rows.back()[12]);
  EXPECT_NEAR(z_mean, z, 1e-9 * z);
  EXPECT_GT(z_error, 0.0);
  EXPECT_LT(z_error, 0.05 * z);

  // In pieces: stopped before the window opens and in it, with a row a killed run wrote after the
  // checkpoint and a row cut short, both dropped when resuming: the same file byte for byte.
  const fs::path log = dir_ / "log.csv";
  ASSERT_EQ(carom(with({"run", start, "1.7", "--checkpoint", checkpoint, "--log", log,
                        "--log-every", "0.5"},
                       physics))
                .exit_code,
            0);
  ASSERT_EQ(carom({"run", "--resume", checkpoint, "9.2", "--checkpoint", checkpoint, "--log", log,
                   "--log-every", "0.5"})
                .exit_code,
            0);
  {
    std::ofstream append(log, std::ios::app);
    append << "9.5,1,2,3,0,1,2,3,4,,,,\n9.";
  }
  const Result resumed =
      carom({"run", "--resume", checkpoint, "20", "--log", log, "--log-every", "0.5"});
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_TRUE(read_file(log) == text) << "the time series differ";

  EXPECT_EQ(carom({"run", start, "2", "--log", log}).exit_code, 2);
  EXPECT_EQ(carom({"run", start, "2", "--log-every", "1"}).exit_code, 2);
  EXPECT_EQ(carom({"run", start, "2", "--log", log, "--log-every", "0"}).exit_code, 2);
  // Rows without end would fill the disk: refused up front, as frames are (regression).
  const Result endless = carom({"run", start, "2", "--log", log, "--log-every", "1e-100"});
  EXPECT_EQ(endless.exit_code, 2);
  EXPECT_NE(endless.err.find("more than 10^7 rows"), std::string::npos) << endless.err;
  EXPECT_EQ(carom({"run", start, "2", "--log", log, "--log-every", "1", "--events", log}).exit_code,
            2);
}

// Regression: a resumed run refused to continue a .gsd dump, so a sweep with one could never be
// resumed. It continues carom's own, byte for byte, and refuses another program's (exit 2, the
// file left as it was).
TEST_F(Cli, GsdTrajectoriesAreWrittenAndContinuedByAResumedRun) {
  const fs::path start = dir_ / "gas.txt", checkpoint = dir_ / "run.ckpt", movie = dir_ / "m.gsd",
                 whole = dir_ / "whole.gsd";
  ASSERT_EQ(carom({"init", "--n", "100", "--phi", "0.3", "--boundary", "periodic", "-o", start})
                .exit_code,
            0);
  const std::vector<std::string> physics = {"--rule", "elastic", "--boundary", "periodic"};
  const auto with = [&](std::vector<std::string> args) {
    args.insert(args.end(), physics.begin(), physics.end());
    return args;
  };
  ASSERT_EQ(carom(with({"run", start, "4", "--dump", whole, "--every", "0.5"})).exit_code, 0);
  ASSERT_EQ(carom(with({"run", start, "2.2", "--dump", movie, "--every", "0.5", "--checkpoint",
                        checkpoint}))
                .exit_code,
            0);
  EXPECT_EQ(read_file(movie).substr(0, 8), std::string("\xDF\x65\xDF\x65\xDF\x65\xDF\x65", 8));
  const Result resumed =
      carom({"run", "--resume", checkpoint, "4", "--dump", movie, "--every", "0.5"});
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_TRUE(read_file(movie) == read_file(whole)) << "the trajectories differ";

  const fs::path theirs = write("theirs.gsd", std::string("\xDF\x65\xDF\x65\xDF\x65\xDF\x65", 8) +
                                                  std::string(20000, '\x01'));
  const Result refused =
      carom({"run", "--resume", checkpoint, "4", "--dump", theirs, "--every", "0.5"});
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.err.find("not a GSD trajectory carom wrote"), std::string::npos) << refused.err;
  EXPECT_EQ(fs::file_size(theirs), 20008u);
}

// Regression: a .gsd dump of numbers beyond single precision (a box of 1e50) was written with
// inf in it, and refused by every reader. Refused up front, exit 2, naming the value; nothing is
// written. A speed a collision raises beyond it later stops the run as a failed write does: the
// value named, the run saved, the file holding its frames so far, readable.
TEST_F(Cli, GsdDumpsBeyondSinglePrecisionAreRefused) {
  const fs::path movie = dir_ / "m.gsd";
  // (A particle that fast crosses the box 10^5 times by t = 1e-33.)
  for (const auto& [start, end, named] :
       {std::tuple{write("huge.txt", "1\n1e41\n1e50 1e50\n5e49 5e49 1 0\n"), "1",
                   "box side Lx is 1e+50"},
        std::tuple{write("fast.txt", "2\n0.5\n10 10\n5 5 1 0\n2 2 0 1e39\n"), "1e-33",
                   "vy of particle 1 at t = 0 is 1e+39"}}) {
    const Result r =
        carom({"run", start, end, "--dump", movie, "--every", "0.5", "-o", dir_ / "out.txt"});
    EXPECT_EQ(r.exit_code, 2) << named;
    EXPECT_NE(r.err.find(named), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(movie));
    // .xyz holds every double: the same run dumps there.
    EXPECT_EQ(carom({"run", start, end, "--dump", dir_ / "m.xyz", "--every", "0.5", "-o",
                     dir_ / "out.txt"})
                  .exit_code,
              0);
  }
  // A heavy disk at 2e38 hits a light one at rest, which leaves at twice that (by t = 1e-9 it
  // has gone 2e29, two radii, from where it was; the box is 1.5e9 diameters across, which a
  // double resolves).
  const fs::path hit = write(
                     "hit.txt",
                     "2\n1e29\n3e38 3e38\n1e30 1e30 2e38 0 1e29 1e6\n1.3e30 1e30 0 0 1e29 1\n"),
                 checkpoint = dir_ / "c.ckpt";
  const Result r = carom({"run", hit, "3e-9", "--rule", "elastic", "--dump", movie, "--every",
                          "1e-9", "--checkpoint", checkpoint, "-o", dir_ / "out.txt"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("vx of particle 1 at t = 1e-09 is 4e+38"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("is saved in " + checkpoint.string()), std::string::npos) << r.err;
  const Result viewed = carom({"view", movie, "-o", dir_ / "page.html"});
  EXPECT_EQ(viewed.exit_code, 0) << viewed.err;
  EXPECT_EQ(carom({"run", "--resume", checkpoint, "3e-9", "--dump", dir_ / "hit.xyz", "--every",
                   "1e-9", "-o", dir_ / "out.txt"})
                .exit_code,
            0);
}

TEST_F(Cli, ASignalSavesACheckpointAndTheResumedRunMatches) {
  // A slow run (an overlap check after every event): frames, events and the result of the
  // interrupted and resumed run are those of the uninterrupted one, byte for byte.
  const fs::path start = dir_ / "gas.txt", checkpoint = dir_ / "run.ckpt";
  ASSERT_EQ(carom({"init", "--n", "1000", "--phi", "0.5", "--boundary", "periodic", "-o", start})
                .exit_code,
            0);
  const std::vector<std::string> physics = {"--rule",   "elastic",       "--boundary",
                                            "periodic", "--check-every", "1"};
  const auto with = [&](std::vector<std::string> args, const std::vector<std::string>& more) {
    args.insert(args.end(), more.begin(), more.end());
    return args;
  };
  const fs::path whole_xyz = dir_ / "whole.xyz", whole_events = dir_ / "whole.csv";
  const Result whole = carom(with({"run", start, "8", "--format", "json", "--dump", whole_xyz,
                                   "--every", "0.5", "--events", whole_events, "--check"},
                                  physics));
  ASSERT_EQ(whole.exit_code, 0) << whole.err;

  const fs::path movie = dir_ / "movie.xyz", events = dir_ / "events.csv";
  const pid_t pid = spawn(with({"run", start.string(), "8", "--format", "json", "--check",
                                "--checkpoint", checkpoint.string(), "--dump", movie.string(),
                                "--every", "0.5", "--events", events.string()},
                               physics));
  ASSERT_TRUE(wait_until([&] { return holds(movie, "Time=2"); }));
  ::kill(pid, SIGINT);
  ASSERT_EQ(finish(pid), 130) << read_file(dir_ / "stderr");
  EXPECT_LT(read_file(movie).size(), read_file(whole_xyz).size());
  const Result resumed = carom({"run", "--resume", checkpoint, "8", "--format", "json", "--dump",
                                movie, "--every", "0.5", "--events", events});
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_EQ(particles_of(resumed.out), particles_of(whole.out));
  EXPECT_TRUE(read_file(movie) == read_file(whole_xyz)) << "the trajectories differ";
  EXPECT_TRUE(read_file(events) == read_file(whole_events)) << "the event logs differ";
}

TEST_F(Cli, PeriodicCheckpointsSurviveAHardKill) {
  // SIGKILL cannot be caught: what survives is the last checkpoint written every 2000 events and
  // the frames written up to the kill. Resuming drops the frames after the checkpoint and gives
  // the uninterrupted result and trajectory.
  const fs::path start = dir_ / "gas.txt", checkpoint = dir_ / "run.ckpt";
  ASSERT_EQ(carom({"init", "--n", "1000", "--phi", "0.5", "-o", start}).exit_code, 0);
  const fs::path whole_xyz = dir_ / "whole.lammpstrj", movie = dir_ / "movie.lammpstrj";
  const Result whole = carom({"run", start, "8", "--rule", "elastic", "--format", "json", "--dump",
                              whole_xyz, "--every", "0.25"});
  ASSERT_EQ(whole.exit_code, 0);
  const pid_t pid =
      start_run(start, {"8", "--rule", "elastic", "--format", "json", "--check", "--check-every",
                        "1", "--checkpoint", checkpoint.string(), "--checkpoint-every", "2000",
                        "--dump", movie.string(), "--every", "0.25"});
  ASSERT_TRUE(wait_until([&] { return fs::exists(checkpoint) && holds(movie, "TIMESTEP\n12\n"); }));
  ::kill(pid, SIGKILL);
  finish(pid);
  const auto saved = nlohmann::json::parse(read_file(checkpoint));
  EXPECT_EQ(saved["counts"]["events"].get<std::uint64_t>() % 2000, 0u);
  const Result resumed = carom(
      {"run", "--resume", checkpoint, "8", "--format", "json", "--dump", movie, "--every", "0.25"});
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_EQ(particles_of(resumed.out), particles_of(whole.out));
  EXPECT_TRUE(read_file(movie) == read_file(whole_xyz)) << "the trajectories differ";
}

// Regression: --equilibrate was refused with --resume, so a run equilibrated, checkpointed and
// resumed could not measure its production part alone.
TEST_F(Cli, AResumedRunCanStartItsMeasurementAtAnyLaterTime) {
  const fs::path start = dir_ / "gas.txt", checkpoint = dir_ / "eq.ckpt";
  ASSERT_EQ(carom({"init", "--n", "300", "--phi", "0.4", "--boundary", "periodic", "-o", start})
                .exit_code,
            0);
  const std::vector<std::string> physics = {"--rule", "elastic", "--boundary", "periodic"};
  std::vector<std::string> direct = {"run", start, "20", "--format", "json", "--equilibrate", "8"};
  direct.insert(direct.end(), physics.begin(), physics.end());
  const Result whole = carom(direct);
  ASSERT_EQ(whole.exit_code, 0) << whole.err;
  std::vector<std::string> first = {"run", start, "5", "--checkpoint", checkpoint, "-q"};
  first.insert(first.end(), physics.begin(), physics.end());
  ASSERT_EQ(carom(first).exit_code, 0);
  const Result resumed =
      carom({"run", "--resume", checkpoint, "20", "--equilibrate", "8", "--format", "json"});
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  const auto a = nlohmann::json::parse(whole.out), b = nlohmann::json::parse(resumed.out);
  for (const char* same : {"equilibrate", "events", "window_events", "pressure", "temperature",
                           "kinetic_energy_initial", "collision_rate"}) {
    EXPECT_EQ(a[same], b[same]) << same;
  }
  EXPECT_EQ(b["equilibrate"], 8.0);
  EXPECT_LT(a["window_events"], a["events"]);
  // Each rate is its own process's: every event of the run, or every event since the checkpoint.
  const auto rate_of = [](const nlohmann::json& j, std::uint64_t events) {
    return static_cast<double>(events) / j["wall_seconds"].get<double>();
  };
  EXPECT_DOUBLE_EQ(a["events_per_second"].get<double>(),
                   rate_of(a, a["events"].get<std::uint64_t>()));
  const auto saved = nlohmann::json::parse(read_file(checkpoint));
  EXPECT_DOUBLE_EQ(b["events_per_second"].get<double>(),
                   rate_of(b, b["events"].get<std::uint64_t>() -
                                  saved["counts"]["events"].get<std::uint64_t>()));
  // Not before the checkpoint: that part of the run is not in it.
  const Result early = carom({"run", "--resume", checkpoint, "20", "--equilibrate", "3"});
  EXPECT_EQ(early.exit_code, 2);
  EXPECT_NE(early.err.find("before the checkpoint's time"), std::string::npos) << early.err;
}

TEST_F(Cli, AClosedPipeIsAWriteErrorThatLeavesNoTemporaryFiles) {
  const fs::path start = dir_ / "gas.txt", movie = dir_ / "movie.xyz";
  ASSERT_EQ(carom({"init", "--n", "400", "--phi", "0.5", "-o", start}).exit_code, 0);
  const std::string command = quote(CAROM_EXE) + " run " + quote(start) +
                              " 50 --rule elastic --trace --summary " + quote(dir_ / "s.json") +
                              " --dump " + quote(movie) + " --every 0.1 2>" + quote(dir_ / "err") +
                              " | head -c 100000 > /dev/null";
  std::system(("sh -c " + quote(command)).c_str());
  EXPECT_NE(read_file(dir_ / "err").find("cannot write"), std::string::npos)
      << read_file(dir_ / "err");
  EXPECT_TRUE(fs::exists(movie));  // the frames so far are kept
  EXPECT_FALSE(fs::exists(dir_ / "s.json"));
  for (const auto& entry : fs::directory_iterator(dir_)) {
    EXPECT_EQ(entry.path().string().find(".tmp."), std::string::npos) << entry.path();
  }
}

TEST_F(Cli, BadCheckpointsAreRefusedClearly) {
  const fs::path garbage = write("garbage.ckpt", "{\"carom_checkpoint\": 1, \"input\": 3");
  const Result a = carom({"run", "--resume", garbage, "10"});
  EXPECT_EQ(a.exit_code, 2);
  EXPECT_NE(a.err.find("not a carom checkpoint"), std::string::npos) << a.err;
  const fs::path future = write("future.ckpt", "{\"carom_checkpoint\": 99}");
  const Result b = carom({"run", "--resume", future, "10"});
  EXPECT_EQ(b.exit_code, 2);
  EXPECT_NE(b.err.find("format 99"), std::string::npos) << b.err;
  const Result c = carom({"run", "--resume", kCases + "walls_only.txt", "10"});
  EXPECT_EQ(c.exit_code, 2);
  const fs::path checkpoint = dir_ / "ok.ckpt";
  ASSERT_EQ(carom({"run", kCases + "walls_only.txt", "10", "--checkpoint", checkpoint}).exit_code,
            0);
  EXPECT_EQ(carom({"run", "--resume", checkpoint, "20", "--rule", "elastic"}).exit_code, 2);
  EXPECT_EQ(carom({"run", "--resume", checkpoint, "5"}).exit_code, 2);  // before the checkpoint
  const Result resumed = carom({"run", "--resume", checkpoint, "20"});
  EXPECT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_EQ(without_header(resumed.out), read_file(kCases + "walls_only.T20.expected"));
}

TEST_F(Cli, ViewWritesOnePageAndRefusesWhatIsNotATrajectory) {
  const fs::path movie = dir_ / "movie.xyz", page = dir_ / "movie.html";
  ASSERT_EQ(carom({"run", kCases + "normal.txt", "10", "--dump", movie, "--every", "1"}).exit_code,
            0);
  const Result ok = carom({"view", movie, "-o", page});
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  const std::string html = read_file(page);
  EXPECT_NE(html.find("<canvas id=\"box\""), std::string::npos);
  EXPECT_NE(html.find("\"n\":5"), std::string::npos);
  EXPECT_EQ(html.find("http"), std::string::npos);  // nothing fetched from the network
  EXPECT_NE(html.find("\"times\":[0.0,1.0,2.0,3.0,4.0,5.0,6.0,7.0,8.0,9.0,10.0]"),
            std::string::npos);
  // --frames A:B and --stride K choose the frames; nothing is said of a small page.
  const Result part = carom({"view", movie, "-o", page, "--frames", "2:9", "--stride", "3"});
  ASSERT_EQ(part.exit_code, 0) << part.err;
  EXPECT_EQ(part.err, "");
  EXPECT_NE(read_file(page).find("\"times\":[2.0,5.0,8.0]"), std::string::npos);
  EXPECT_NE(carom({"view", movie, "-o", page, "--frames", ":2"}).exit_code, 2);
  EXPECT_NE(read_file(page).find("\"times\":[0.0,1.0]"), std::string::npos);
  for (const std::vector<std::string>& bad_choice : {std::vector<std::string>{"--frames", "5:5"},
                                                     {"--frames", "20:"},
                                                     {"--frames", "3"},
                                                     {"--frames", "a:b"},
                                                     {"--stride", "0"}}) {
    std::vector<std::string> command = {"view", movie, "-o", (dir_ / "none.html").string()};
    command.insert(command.end(), bad_choice.begin(), bad_choice.end());
    EXPECT_EQ(carom(command).exit_code, 2) << bad_choice[1];
    EXPECT_FALSE(fs::exists(dir_ / "none.html"));
  }
  for (const std::string& bad : {std::string("not a trajectory\n"),
                                 std::string("2\nLattice=\"1 0 0 0 1 0 0 0 1\"\nH 0.5 0.5 0\n"),
                                 std::string("1\nno box here\nH 0 0 0\n")}) {
    const Result r = carom({"view", write("bad.xyz", bad), "-o", dir_ / "bad.html"});
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("bad.xyz:"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "bad.html"));
  }
}

// Help names what an option takes: a number is not TEXT.
TEST_F(Cli, AnalyzeHelpNamesWhatItsOptionsTake) {
  const Result help = carom({"analyze", "--help"});
  EXPECT_EQ(help.exit_code, 0);
  for (const char* shown : {"--equilibrate T", "--bin WIDTH", "--r-max R", "--contact-width WIDTH",
                            "--k-max K", "--fs-k K", "--order-cutoff R", "--log FILE",
                            "--only LIST", "TRAJECTORY FILE"}) {
    EXPECT_NE(help.out.find(shown), std::string::npos) << shown << "\n" << help.out;
  }
  EXPECT_EQ(help.out.find("TEXT"), std::string::npos) << help.out;
}

// A page a browser loads slowly gets a note saying how much --stride would keep.
TEST_F(Cli, ViewSaysWhenAPageIsLarge) {
  const fs::path start = dir_ / "gas.txt", movie = dir_ / "big.gsd", page = dir_ / "big.html";
  ASSERT_EQ(carom({"init", "--n", "2000", "--phi", "0.3", "--boundary", "periodic", "-o", start})
                .exit_code,
            0);
  ASSERT_EQ(carom({"run", start, "100", "--dump", movie, "--every", "0.1", "-q", "-o",
                   (dir_ / "end.txt").string()})
                .exit_code,
            0);
  const Result big = carom({"view", movie, "-o", page});
  ASSERT_EQ(big.exit_code, 0) << big.err;
  EXPECT_NE(big.err.find("(1001 frames of 2000 particles) and will load slowly in a browser: "
                         "--stride 2 (one frame in 2)"),
            std::string::npos)
      << big.err;
  const Result thinned = carom({"view", movie, "-o", page, "--stride", "2"});
  EXPECT_EQ(thinned.err, "");
  EXPECT_LT(fs::file_size(page), 50'000'000u);
}

TEST_F(Cli, AnalyzeSummarisesWritesJsonAndAPageAndRefusesWhatItCannotDo) {
  const fs::path start = dir_ / "gas.txt", movie = dir_ / "run.gsd", log = dir_ / "run.csv";
  ASSERT_EQ(carom({"init", "--n", "200", "--phi", "0.4", "--boundary", "periodic", "-o", start})
                .exit_code,
            0);
  ASSERT_EQ(
      carom({"run", start, "5", "--rule", "elastic", "--boundary", "periodic", "--dump", movie,
             "--every", "0.5", "--log", log, "--log-every", "0.5", "-o", dir_ / "end.txt"})
          .exit_code,
      0);
  const fs::path json = dir_ / "analysis.json", page = dir_ / "report.html";
  const Result ok =
      carom({"analyze", movie, "--equilibrate", "1", "--log", log, "-o", json, "--html", page});
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_NE(ok.out.find("200 disks, periodic box"), std::string::npos) << ok.out;
  EXPECT_NE(ok.out.find("frames: 9 of 11, t = 1 to 5"), std::string::npos) << ok.out;
  EXPECT_NE(ok.out.find("Z = "), std::string::npos) << ok.out;
  EXPECT_EQ(ok.err, "");
  const nlohmann::json analysis = nlohmann::json::parse(read_file(json));
  EXPECT_EQ(analysis["particles"], 200);
  EXPECT_EQ(analysis["frames"]["count"], 9);
  EXPECT_EQ(analysis["log"]["rows"].size(), 11u);
  EXPECT_EQ(analysis["warnings"].size(), 0u);
  // S(k) up to 20 / d, and F_s(k,t) at its main peak with alpha2 at the MSD's lags.
  EXPECT_NE(ok.out.find("S(k): "), std::string::npos) << ok.out;
  EXPECT_NE(ok.out.find("tau_alpha = "), std::string::npos) << ok.out;
  const nlohmann::json& structure = analysis["structure_factor"];
  ASSERT_TRUE(structure.is_object()) << analysis.dump();
  EXPECT_EQ(structure["k"].size(), structure["s"].size());
  EXPECT_GT(structure["k"].size(), 10u);
  EXPECT_LE(structure["k"].back().get<double>(), 20.0);
  EXPECT_GT(structure["k_peak"].get<double>(), 5.0);  // near 2 pi / d in a dense fluid
  EXPECT_LT(structure["k_peak"].get<double>(), 8.0);
  const nlohmann::json& scattering = analysis["self_scattering"];
  ASSERT_TRUE(scattering.is_object()) << analysis.dump();
  EXPECT_EQ(scattering["k"], structure["k_peak"]);
  EXPECT_EQ(scattering["t"], analysis["msd"]["t"]);
  EXPECT_NEAR(scattering["fs"][0].get<double>(), 1.0, 1e-14);
  EXPECT_EQ(scattering["fs"].size(), scattering["alpha2"].size());
  EXPECT_TRUE(scattering["alpha2"][0].is_null());  // no displacement at t = 0
  EXPECT_TRUE(scattering["alpha2"][1].is_number());
  EXPECT_GT(scattering["tau_alpha"].get<double>(), 0.0);
  const Result at_k = carom({"analyze", movie, "--k-max", "4", "--fs-k", "2", "-o", "-"});
  ASSERT_EQ(at_k.exit_code, 0) << at_k.err;
  const nlohmann::json narrow = nlohmann::json::parse(at_k.out);
  EXPECT_LE(narrow["structure_factor"]["k"].back().get<double>(), 4.0);
  EXPECT_NEAR(narrow["self_scattering"]["k"].get<double>(), 2.0, 0.3);
  EXPECT_TRUE(analysis["steinhardt"].is_null());  // spheres only
  const std::string html = read_file(page);
  EXPECT_EQ(html.find("/*CAROM_DATA*/"), std::string::npos);
  // Nothing fetched from the network (the SVG namespace is a name, not a request; the browser
  // test watches the requests themselves).
  EXPECT_EQ(html.find("https:"), std::string::npos);
  EXPECT_EQ(html.find("src=\"http"), std::string::npos);
  // -o - puts the JSON alone on standard output, --html - the page.
  const Result to_stdout = carom({"analyze", movie, "-o", "-"});
  ASSERT_EQ(to_stdout.exit_code, 0) << to_stdout.err;
  EXPECT_EQ(nlohmann::json::parse(to_stdout.out)["particles"], 200);
  const Result page_to_stdout = carom({"analyze", movie, "--html", "-"});
  ASSERT_EQ(page_to_stdout.exit_code, 0) << page_to_stdout.err;
  EXPECT_EQ(page_to_stdout.out.rfind("<!", 0), 0u) << page_to_stdout.out.substr(0, 80);

  // What does not apply is left out, with the reason: the MSD of a periodic .xyz without
  // image flags.
  const std::string old_xyz =
      "8\nLattice=\"4 0 0 0 4 0 0 0 1\" Properties=species:S:1:pos:R:3 pbc=\"T T T\" Time=0\n" +
      std::string("H 0.5 0.5 0\nH 1.5 0.5 0\nH 2.5 0.5 0\nH 3.5 0.5 0\n") +
      "H 0.5 2.5 0\nH 1.5 2.5 0\nH 2.5 2.5 0\nH 3.5 2.5 0\n";
  const Result no_images = carom({"analyze", write("old.xyz", old_xyz), "--r-max", "1.5"});
  EXPECT_EQ(no_images.exit_code, 0) << no_images.err;
  EXPECT_NE(no_images.err.find("carom: note: no MSD: the MSD of a periodic trajectory needs "
                               "image flags, and frame 0 (t = 0) has none"),
            std::string::npos)
      << no_images.err;
  EXPECT_NE(no_images.err.find("carom: note: no F_s(k,t): like the MSD, it needs image flags"),
            std::string::npos)
      << no_images.err;

  // Usage and input errors: exit 2, a message naming what is wrong, nothing written.
  const std::vector<std::pair<std::vector<std::string>, std::string>> bad = {
      {{"analyze", (dir_ / "missing.gsd").string()}, "missing.gsd: cannot open"},
      {{"analyze", write("bad.xyz", "not a trajectory\n").string()}, "bad.xyz:1:"},
      {{"analyze", write("bad.gsd", "not a gsd file at all").string()}, "bad.gsd"},
      {{"analyze", movie.string(), "--bin", "-0.1"}, "--bin must be greater than 0"},
      {{"analyze", movie.string(), "--r-max", "1e3"}, "g(r) reaches r = "},
      {{"analyze", movie.string(), "--k-max", "0"}, "--k-max must be greater than 0"},
      {{"analyze", movie.string(), "--k-max", "0.1"}, "S(k) starts at k = 2 pi / L_min = "},
      {{"analyze", movie.string(), "--fs-k", "0.01"}, "F_s(k,t) needs k of at least"},
      {{"analyze", movie.string(), "--equilibrate", "6"}, "no frame at or after t = 6"},
      {{"analyze", movie.string(), "--log", write("bad.csv", "time,Z\n1\n").string()},
       "bad.csv:2: expected 2 fields, found 1"},
      {{"analyze", movie.string(), "-o", (dir_ / "no/such/folder.json").string()}, "no folder"},
      {{"analyze", write("run.lammpstrj", "ITEM: TIMESTEP\n0\n").string()}, "not LAMMPS dumps"},
      {{"analyze", movie.string(), "-o", "-", "--html", "-"}, "cannot both write to standard"},
      {{"analyze", movie.string(), "-o", (dir_ / "x").string(), "--html", (dir_ / "x").string()},
       "name the same file"}};
  for (const auto& [args, message] : bad) {
    std::vector<std::string> with_output = args;
    if (std::find(args.begin(), args.end(), "--html") == args.end()) {
      with_output.insert(with_output.end(), {"--html", (dir_ / "bad.html").string()});
    }
    const Result r = carom(with_output);
    EXPECT_EQ(r.exit_code, 2) << args.back() << ": " << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "bad.html"));
  }
}

// Spheres get the Steinhardt bond order and its solid-like clusters: per frame, and the last
// frame's particle by particle; --order-cutoff sets the neighbours' reach.
TEST_F(Cli, AnalyzeGivesTheBondOrderOfSpheres) {
  const fs::path start = dir_ / "balls.txt", movie = dir_ / "balls.gsd";
  ASSERT_EQ(carom({"init", "--dim", "3", "--n", "200", "--phi", "0.4", "--boundary", "periodic",
                   "-o", start})
                .exit_code,
            0);
  ASSERT_EQ(carom({"run", start, "2", "--rule", "elastic", "--boundary", "periodic", "--dump",
                   movie, "--every", "0.5", "-q", "-o", dir_ / "end.txt"})
                .exit_code,
            0);
  const fs::path json = dir_ / "analysis.json";
  const Result ok = carom({"analyze", movie, "-o", json});
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_NE(ok.out.find("bond order (last frame, neighbours within 1.5): q4 "), std::string::npos)
      << ok.out;
  const nlohmann::json order = nlohmann::json::parse(read_file(json))["steinhardt"];
  EXPECT_EQ(order["cutoff"], 1.5);
  EXPECT_EQ(order["t"].size(), 5u);
  for (const char* key : {"q4", "q6", "w4", "w6", "q4_bar", "q6_bar", "w4_bar", "w6_bar",
                          "solid_like", "largest_cluster", "cluster_sizes"}) {
    EXPECT_EQ(order[key].size(), 5u) << key;
  }
  // A fluid at packing 0.4: some order in each sphere's shell, little in the averages, no crystal.
  EXPECT_GT(order["q6"][4].get<double>(), order["q6_bar"][4].get<double>());
  EXPECT_LT(order["largest_cluster"][4].get<int>(), 20);
  const nlohmann::json& last = order["last_frame"];
  EXPECT_EQ(last["time"], 2.0);
  for (const char* key : {"neighbours", "q4", "q6", "w4", "w6", "q4_bar", "q6_bar", "w4_bar",
                          "w6_bar", "solid_bonds", "solid_like", "cluster"}) {
    EXPECT_EQ(last[key].size(), 200u) << key;
  }
  const Result nearer = carom({"analyze", movie, "--order-cutoff", "1.3", "-o", json});
  ASSERT_EQ(nearer.exit_code, 0) << nearer.err;
  EXPECT_EQ(nlohmann::json::parse(read_file(json))["steinhardt"]["cutoff"], 1.3);
  for (const auto& [cutoff, message] : {std::pair{"0", "--order-cutoff must be greater than 0"},
                                        std::pair{"4", "the bond order's neighbours reach r = "}}) {
    const Result r = carom({"analyze", movie, "--order-cutoff", cutoff});
    EXPECT_EQ(r.exit_code, 2) << cutoff;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
  }
}

TEST_F(Cli, CompressWritesAStartThatRunsAndRefusesWhatCannotBe) {
  const fs::path start = dir_ / "gas.txt", dense = dir_ / "dense.txt", summary = dir_ / "s.json";
  ASSERT_EQ(carom({"init", "--n", "300", "--phi", "0.3", "--polydispersity", "0.1", "--boundary",
                   "periodic", "-o", start})
                .exit_code,
            0);
  const Result ok = carom({"compress", start, "--phi", "0.75", "--boundary", "periodic", "-o",
                           dense, "--summary", summary});
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  const nlohmann::json s = nlohmann::json::parse(read_file(summary));
  EXPECT_EQ(s["status"], "reached_target");
  EXPECT_NEAR(s["packing_fraction"].get<double>(), 0.75, 1e-13);
  EXPECT_EQ(s["n"], 300);
  EXPECT_GT(s["events"].get<std::uint64_t>(), 0u);
  // The diameters grew: the note and the summary say by how much, --unit-diameter undoes it.
  EXPECT_GT(s["mean_diameter"].get<double>(), 1.2);
  EXPECT_EQ(s["unit_diameter"], false);
  EXPECT_NE(ok.err.find("carom: note: the disks grew to a mean diameter of"), std::string::npos)
      << ok.err;
  const fs::path unit = dir_ / "unit.txt", unit_summary = dir_ / "u.json";
  const Result rescaled = carom({"compress", start, "--phi", "0.75", "--unit-diameter", "-o", unit,
                                 "--summary", unit_summary});
  ASSERT_EQ(rescaled.exit_code, 0) << rescaled.err;
  EXPECT_EQ(rescaled.err, "");
  const nlohmann::json u = nlohmann::json::parse(read_file(unit_summary));
  EXPECT_NEAR(u["mean_diameter"].get<double>(), 1.0, 1e-14);
  EXPECT_EQ(u["unit_diameter"], true);
  EXPECT_NEAR(u["box"][0].get<double>() * s["mean_diameter"].get<double>(),
              s["box"][0].get<double>(), 1e-12);
  EXPECT_NEAR(u["packing_fraction"].get<double>(), 0.75, 1e-13);
  EXPECT_EQ(carom({"run", unit, "2", "--check", "-q", "-o", dir_ / "u.txt"}).exit_code, 0);
  // The packing runs as it is, checked for overlaps as it goes.
  const Result run = carom({"run", dense, "5", "--rule", "elastic", "--boundary", "periodic",
                            "--check", "--summary", dir_ / "run.json", "-o", dir_ / "end.txt"});
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NEAR(nlohmann::json::parse(read_file(dir_ / "run.json"))["packing_fraction"].get<double>(),
              0.75, 1e-13);
  // Jammed disks between walls: a valid start too.
  const fs::path walls = dir_ / "walls.txt", jammed = dir_ / "jammed.txt";
  ASSERT_EQ(carom({"init", "--n", "100", "--phi", "0.3", "--polydispersity", "0.2", "-o", walls})
                .exit_code,
            0);
  const Result jam =
      carom({"compress", walls, "--jam", "--rate", "0.1", "-o", jammed, "--summary", summary});
  ASSERT_EQ(jam.exit_code, 0) << jam.err;
  const nlohmann::json jammed_summary = nlohmann::json::parse(read_file(summary));
  EXPECT_EQ(jammed_summary["status"], "jammed");
  // The jamming density is said, as the summary has it.
  EXPECT_NE(jam.err.find(fmt::format("carom: the disks jammed at packing fraction {:.6f} (Z = ",
                                     jammed_summary["packing_fraction"].get<double>())),
            std::string::npos)
      << jam.err;
  EXPECT_EQ(ok.err.find("jammed"), std::string::npos) << ok.err;
  EXPECT_EQ(
      carom({"run", jammed, "1", "--rule", "elastic", "--check", "-o", dir_ / "e.txt"}).exit_code,
      0);

  // Unequal disks may pass the close packing of equal ones: a target they cannot reach ends
  // jammed, exit 1, the jammed packing kept.
  const Result short_of = carom({"compress", start, "--phi", "0.95", "--boundary", "periodic",
                                 "--rate", "0.1", "-o", dir_ / "short.txt"});
  EXPECT_EQ(short_of.exit_code, 1) << short_of.err;
  EXPECT_NE(short_of.err.find("jammed at packing fraction"), std::string::npos) << short_of.err;
  EXPECT_TRUE(fs::exists(dir_ / "short.txt"));

  const fs::path mono = dir_ / "mono.txt";
  ASSERT_EQ(
      carom({"init", "--n", "100", "--phi", "0.3", "--boundary", "periodic", "-o", mono}).exit_code,
      0);
  const std::vector<std::pair<std::vector<std::string>, std::string>> bad = {
      {{"compress", mono.string(), "--phi", "0.95", "--boundary", "periodic"}, "close packing"},
      {{"compress", start.string(), "--phi", "0.2", "--boundary", "periodic"}, "not above"},
      {{"compress", start.string(), "--phi", "0.7", "--jam"}, "excludes"},
      {{"compress", start.string(), "--boundary", "periodic"}, "give --phi TARGET or --jam"},
      {{"compress", start.string(), "--jam", "--rate", "-1", "--boundary", "periodic"},
       "growth rate must be a positive number"},
      {{"compress", write("overlap.txt", "2\n0.5\n10 10\n5 5 1 0\n5.5 5 -1 0\n").string(), "--jam"},
       "overlap"},
      {{"compress", (dir_ / "missing.txt").string(), "--jam"}, "missing.txt"}};
  for (const auto& [args, message] : bad) {
    std::vector<std::string> with_output = args;
    with_output.insert(with_output.end(), {"-o", (dir_ / "bad.txt").string()});
    const Result r = carom(with_output);
    EXPECT_EQ(r.exit_code, 2) << args.back() << ": " << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "bad.txt"));
  }
}

TEST_F(Cli, CtrlCKeepsThePackingACompressionHasReached) {
  const fs::path start = dir_ / "gas.txt", out = dir_ / "so_far.txt", summary = dir_ / "s.json";
  ASSERT_EQ(carom({"init", "--dim", "3", "--n", "20000", "--phi", "0.3", "--boundary", "periodic",
                   "-o", start})
                .exit_code,
            0);
  const pid_t pid = spawn({"compress", start.string(), "--jam", "--rate", "0.001", "--boundary",
                           "periodic", "-o", out.string(), "--summary", summary.string()});
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  ::kill(pid, SIGINT);
  EXPECT_EQ(finish(pid), 130);
  const std::string err = read_file(dir_ / "stderr");
  EXPECT_NE(err.find("the packing so far"), std::string::npos) << err;
  const nlohmann::json s = nlohmann::json::parse(read_file(summary));
  EXPECT_EQ(s["status"], "interrupted");
  EXPECT_GT(s["packing_fraction"].get<double>(), 0.3);
  const Result run = carom({"run", out, "0.1", "--rule", "elastic", "--boundary", "periodic",
                            "--check", "--summary", dir_ / "run.json", "-o", dir_ / "end.txt"});
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(nlohmann::json::parse(read_file(dir_ / "run.json"))["packing_fraction"],
            s["packing_fraction"]);
}

TEST_F(Cli, CheckedRunsFindNothingWrongAndChangeNothing) {
  // --check looks at every event and, every 50, at every pair: a dense run passes, and the
  // checks (observers that only read) leave its result as it is, bit for bit.
  const fs::path start = dir_ / "gas.txt";
  for (const std::string boundary : {"walls", "periodic"}) {
    ASSERT_EQ(carom({"init", "--n", "400", "--phi", "0.7", "--boundary", boundary, "-o", start})
                  .exit_code,
              0);
    const std::vector<std::string> run{"run",        start,    "20",       "--rule", "elastic",
                                       "--boundary", boundary, "--format", "json"};
    std::vector<std::string> checked = run;
    checked.insert(checked.end(), {"--check", "--check-every", "50"});
    const Result r = carom(checked);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    const Result unchecked = carom(run);
    ASSERT_EQ(unchecked.exit_code, 0) << unchecked.err;
    EXPECT_EQ(particles_of(r.out), particles_of(unchecked.out)) << boundary;
    EXPECT_GT(nlohmann::json::parse(r.out)["pair_collisions"].get<double>(), 10000) << boundary;
  }
}

TEST_F(Cli, ThreeBoxSidesRunSpheresInEveryFormat) {
  // Three spheres: 0 and 1 meet head on along z at t = 1; 2 reaches the front wall (z = 7) at 2.
  const fs::path input =
      write("spheres.txt", "3\n0.5\n5 6 7\n2 2 2 0 0 1\n2 2 5 0 0 -1\n4 4 5 0 0 0.75\n");
  const Result table = carom({"run", input, "2.5"});
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_EQ(table.out,
            "particle id: (xpos, ypos, zpos) (xvel, yvel, zvel): last_update : (cwall, cpart)\n"
            "particle 0: (2.000000, 2.000000, 1.500000) (0.000000, 0.000000, -1.000000): "
            "2.500000 : (0, 1)\n"
            "particle 1: (2.000000, 2.000000, 5.500000) (0.000000, 0.000000, 1.000000): "
            "2.500000 : (0, 1)\n"
            "particle 2: (4.000000, 4.000000, 6.125000) (0.000000, 0.000000, -0.750000): "
            "2.500000 : (1, 0)\n");
  const Result csv = carom({"run", input, "2.5", "--format", "csv"});
  EXPECT_EQ(csv.out.substr(0, csv.out.find('\n')), "2.000000, 2.000000, 1.500000, 0, 1");
  const fs::path log = dir_ / "events.csv";
  const Result json = carom({"run", input, "2.5", "--format", "json", "--events", log});
  const auto j = nlohmann::json::parse(json.out);
  EXPECT_EQ(j["dimension"], 3);
  EXPECT_EQ(j["particles"][2]["z"], 6.125);
  EXPECT_EQ(read_file(log), "time,kind,first,partner\n1,pair,0,1\n2,wall,2,-6\n");
  const Result trace = carom({"run", input, "2.5", "--trace"});
  EXPECT_NE(trace.out.find("Collision: particle 2 with wall -6 (front)"), std::string::npos);

  // Checkpointed and resumed: the same run, bit for bit, in a periodic box too.
  const fs::path checkpoint = dir_ / "s.ckpt";
  for (const std::string boundary : {"walls", "periodic"}) {
    const std::vector<std::string> physics = {"--rule", "elastic", "--boundary", boundary};
    std::vector<std::string> whole = {"run", input, "9", "--format", "json"};
    whole.insert(whole.end(), physics.begin(), physics.end());
    std::vector<std::string> first = {"run", input, "3.3", "--checkpoint", checkpoint};
    first.insert(first.end(), physics.begin(), physics.end());
    ASSERT_EQ(carom(first).exit_code, 0);
    const Result resumed = carom({"run", "--resume", checkpoint, "9", "--format", "json"});
    ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
    EXPECT_EQ(particles_of(resumed.out), particles_of(carom(whole).out)) << boundary;
  }
}

TEST_F(Cli, InitMakesSpheresThatRunAndRefusesWhatCannotBe) {
  const fs::path start = dir_ / "spheres.txt";
  for (const std::string boundary : {"walls", "periodic"}) {
    const Result made = carom({"init", "--dim", "3", "--n", "500", "--phi", "0.45", "--boundary",
                               boundary, "--seed", "3", "-o", start});
    ASSERT_EQ(made.exit_code, 0) << made.err;
    const std::string file = read_file(start);
    EXPECT_EQ(file, carom({"init", "--dim", "3", "--n", "500", "--phi", "0.45", "--boundary",
                           boundary, "--seed", "3"})
                        .out);
    const Result run = carom({"run", start, "2", "--rule", "elastic", "--boundary", boundary,
                              "--check", "--format", "json"});
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const auto j = nlohmann::json::parse(run.out);
    EXPECT_EQ(j["dimension"], 3);
    EXPECT_NEAR(j["packing_fraction"].get<double>(), 0.45, 1e-12);
    EXPECT_NEAR(j["temperature"].get<double>(), 1.0, 1e-9);
  }
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"init", "--dim", "3", "--n", "10", "--phi", "0.75"},
        {"init", "--dim", "4", "--n", "10", "--phi", "0.3"},
        {"init", "--dim", "3", "--n", "10", "--phi", "0.3", "--box", "10", "10"},
        {"init", "--n", "10", "--phi", "0.3", "--box", "10", "10", "10"},
        {"init", "--dim", "3", "--n", "1000", "--phi", "0.5", "--random"}}) {
    const Result r = carom(args);
    EXPECT_EQ(r.exit_code, 2) << fmt::format("{}", fmt::join(args, " ")) << ": " << r.err;
    EXPECT_EQ(r.out, "");
  }
}

// Regressions: hostile numbers are usage errors (exit 2) before anything runs, whatever
// option carries them, and no file appears.
TEST_F(Cli, HostileNumbersAreRefusedUpFront) {
  const std::string input = kCases + "normal.txt";
  const fs::path dump = dir_ / "m.xyz", checkpoint = dir_ / "c.ckpt";
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"run", input, "0", "--dump", dump, "--every", "inf"},
        {"run", input, "0", "--dump", dump, "--every", "Infinity"},
        {"run", input, "0", "--dump", dump, "--every", "1e400"},
        {"run", input, "1", "--dump", dump, "--every", "0x1p-3"},
        {"run", input, "1", "--rule", "elastic", "--restitution", "nan"},
        {"run", input, "1", "--tc", "0x10"},
        {"run", input, "1", "--equilibrate", "-inf"},
        {"run", input, "10", "--checkpoint", checkpoint, "--checkpoint-every", "0.5"},
        {"run", input, "10", "--checkpoint", checkpoint, "--checkpoint-every", "1e30"},
        {"init", "--n", "10", "--phi", "1e-310"},
        {"init", "--n", "10", "--phi", "1e-200"},
        {"init", "--n", "10", "--phi", "0.3", "--box", "1e-300", "1e-300"},
        {"init", "--n", "10", "--phi", "0.3", "--aspect", "1e-50"},
        {"init", "--n", "10", "--phi", "0.3", "--kT", "1e300"},
        {"init", "--n", "-5", "--phi", "0.3"}}) {
    const Result r = carom(args);
    EXPECT_EQ(r.exit_code, 2) << fmt::format("{}", fmt::join(args, " ")) << ": " << r.err;
    EXPECT_EQ(r.out, "") << fmt::format("{}", fmt::join(args, " "));
    EXPECT_FALSE(fs::exists(dump) || fs::exists(checkpoint))
        << fmt::format("{}", fmt::join(args, " "));
  }
  EXPECT_NE(carom({"init", "--n", "-5", "--phi", "0.3"})
                .err.find("--n must be a whole number of at least 1, got '-5'"),
            std::string::npos);
}

// Regression: two outputs naming one file overwrote each other with exit 0.
TEST_F(Cli, OutputsThatAreOneFileAreRefused) {
  const std::string input = kCases + "normal.txt";
  const fs::path out = dir_ / "out.txt";
  write("existing.txt", "x");
  fs::create_hard_link(dir_ / "existing.txt", dir_ / "hardlink.txt");
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"run", input, "1", "-o", out, "--summary", out},
        {"run", input, "1", "-o", out, "--checkpoint", (dir_ / "." / "out.txt").string()},
        {"run", input, "1", "--dump", (dir_ / "x.xyz").string(), "--every", "1", "--events",
         (dir_ / "sub" / ".." / "x.xyz").string()},
        {"run", input, "1", "-o", (dir_ / "existing.txt").string(), "--summary",
         (dir_ / "hardlink.txt").string()},
        {"run", input, "1", "-o", input}}) {
    if (args.size() > 7) fs::create_directories(dir_ / "sub");
    const Result r = carom(args);
    EXPECT_EQ(r.exit_code, 2) << fmt::format("{}", fmt::join(args, " ")) << ": " << r.err;
    EXPECT_NE(r.err.find("name the same file"), std::string::npos) << r.err;
  }
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(read_file(dir_ / "existing.txt"), "x");
  // A resumed run may keep its checkpoint where it read it.
  const fs::path checkpoint = dir_ / "c.ckpt";
  ASSERT_EQ(carom({"run", input, "5", "--checkpoint", checkpoint}).exit_code, 0);
  EXPECT_EQ(carom({"run", "--resume", checkpoint, "10", "--checkpoint", checkpoint}).exit_code, 0);
}

// Regression: view, analyze and compress wrote over their own inputs (run refused the same):
// every command refuses an output that is one of its inputs, however it is spelled.
TEST_F(Cli, EveryCommandRefusesAnOutputThatIsItsInput) {
  const fs::path start = dir_ / "gas.txt", movie = dir_ / "run.xyz", log = dir_ / "run.csv";
  ASSERT_EQ(
      carom({"init", "--n", "20", "--phi", "0.3", "--boundary", "periodic", "-o", start}).exit_code,
      0);
  ASSERT_EQ(carom({"run", start, "2", "--dump", movie, "--every", "1", "--log", log, "--log-every",
                   "1", "-q"})
                .exit_code,
            0);
  ASSERT_EQ(carom({"run", start, "2", "--dump", dir_ / "run.gsd", "--every", "1", "-q"}).exit_code,
            0);
  fs::create_directories(dir_ / "sub");
  fs::create_symlink(movie, dir_ / "link.xyz");
  const std::string dotted = (dir_ / "sub" / ".." / "run.xyz").string();
  const std::map<fs::path, std::string> before = {{start, read_file(start)},
                                                  {movie, read_file(movie)},
                                                  {log, read_file(log)},
                                                  {dir_ / "run.gsd", read_file(dir_ / "run.gsd")}};
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"view", movie, "-o", movie},
        {"view", movie, "-o", dotted},
        {"view", dir_ / "link.xyz", "-o", movie},
        {"analyze", movie, "--html", movie},
        {"analyze", movie, "-o", dotted},
        {"analyze", movie, "--log", log, "-o", log},
        {"analyze", movie, "--log", log, "--html", (dir_ / "." / "run.csv").string()},
        {"compress", start, "--phi", "0.4", "-o", start},
        {"compress", start, "--phi", "0.4", "--summary", (dir_ / "sub" / ".." / "gas.txt")},
        {"compress", (dir_ / "run.gsd:1").string(), "--phi", "0.4", "-o", dir_ / "run.gsd"},
        {"run", (dir_ / "run.gsd:0").string(), "1", "--dump", dir_ / "run.gsd", "--every", "1"}}) {
    const Result r = carom(args);
    EXPECT_EQ(r.exit_code, 2) << fmt::format("{}", fmt::join(args, " ")) << ": " << r.err;
    EXPECT_NE(r.err.find("name the same file"), std::string::npos) << r.err;
  }
  for (const auto& [path, text] : before) EXPECT_EQ(read_file(path), text) << path;
}

// Regression: a start file or folder whose name is not UTF-8 ran, then lost everything to
// "invalid UTF-8 byte" (exit 1): no summary, checkpoint or output. Such a name is written into
// JSON as \udcXX escapes, and read back as the same bytes: the resumed run names the same file.
TEST_F(Cli, ANameThatIsNotUtf8IsKeptInEveryFileAndReadBack) {
  const fs::path folder = dir_ / "dossier\xe9";
  fs::create_directories(folder);
  const fs::path start = folder / "caf\xe9.txt", checkpoint = folder / "c\xe9.ckpt",
                 summary = folder / "s.json", movie = folder / "m\xe9.xyz";
  ASSERT_EQ(
      carom({"init", "--n", "20", "--phi", "0.3", "--boundary", "periodic", "-o", start}).exit_code,
      0);
  const Result ran = carom({"run", start, "2", "--summary", summary, "--checkpoint", checkpoint,
                            "--dump", movie, "--every", "1", "-o", folder / "end.txt", "-q"});
  ASSERT_EQ(ran.exit_code, 0) << ran.err;
  // The value of a string field as written (nlohmann::json refuses lone surrogate escapes).
  const auto written = [&](const fs::path& json, const std::string& key) {
    const std::string text = read_file(json), opening = "\"" + key + "\": \"";
    const std::size_t from = text.find(opening) + opening.size();
    return text.substr(from, text.find('"', from) - from);
  };
  EXPECT_NE(read_file(summary).find("dossier\\udce9/caf\\udce9.txt"), std::string::npos)
      << read_file(summary);
  EXPECT_NE(read_file(checkpoint).find("dossier\\udce9/caf\\udce9.txt"), std::string::npos);
  EXPECT_TRUE(fs::exists(folder / "end.txt"));
  // The checkpoint names its start file, read back as the same bytes: the resumed run's summary
  // says so.
  const Result resumed = carom({"run", "--resume", checkpoint, "4", "--checkpoint", checkpoint,
                                "--summary", summary, "--format", "json", "-q"});
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_NE(resumed.out.find("dossier\\udce9/caf\\udce9.txt"), std::string::npos) << resumed.out;
  EXPECT_EQ(written(summary, "input"), written(checkpoint, "source"));
  EXPECT_EQ(written(summary, "input"), (dir_ / "dossier\\udce9" / "caf\\udce9.txt").string());
  // The other commands that write names: analyze (json and page), compress's summary.
  const Result analysed =
      carom({"analyze", movie, "-o", folder / "a.json", "--html", folder / "a.html"});
  ASSERT_EQ(analysed.exit_code, 0) << analysed.err;
  EXPECT_NE(read_file(folder / "a.json").find("m\\udce9.xyz"), std::string::npos);
  const Result compressed = carom({"compress", start, "--phi", "0.35", "-o", folder / "d.txt",
                                   "--summary", folder / "d.json", "-q"});
  ASSERT_EQ(compressed.exit_code, 0) << compressed.err;
  EXPECT_NE(read_file(folder / "d.json").find("caf\\udce9.txt"), std::string::npos);
  // A sweep into such a folder: its tasks' summaries are read back for the tables.
  std::ofstream(dir_ / "plan.toml") << "[start]\nn = 16\nboundary = \"periodic\"\n[run]\n"
                                       "end_time = 1\nrule = \"elastic\"\n[sweep]\nphi = [0.2]\n";
  const Result swept = carom({"sweep", dir_ / "plan.toml", "-o", folder / "sweep", "-q"});
  EXPECT_EQ(swept.exit_code, 0) << swept.err;
  EXPECT_NE(read_file(folder / "sweep" / "results.csv").find("done"), std::string::npos);
}

// Regression: integer options took "-5" as 2^64 - 5 (--check-every -5: no check ever ran), "010"
// as octal and "0x10" as hex; --stride 0 was refused with a 309-digit bound.
TEST_F(Cli, IntegerOptionsTakeWholeNumbersAndSaySo) {
  const std::string input = kCases + "normal.txt";
  for (const auto& [args, message] : std::vector<std::pair<std::vector<std::string>, std::string>>{
           {{"run", input, "1", "--check", "--check-every", "-5"},
            "--check-every must be a whole number of at least 1, got '-5'"},
           {{"run", input, "1", "--check", "--check-every", "0"}, "at least 1, got '0'"},
           {{"run", input, "1", "--check", "--check-every", "1.5"}, "got '1.5'"},
           {{"run", input, "1", "--check", "--check-every", "0x10"}, "got '0x10'"},
           {{"run", input, "1", "--kT", "1", "--seed", "-1"}, "--seed must be a whole number"},
           {{"run", input, "1", "--check", "--check-every", "99999999999999999999"},
            "at most 18446744073709551615, got '99999999999999999999'"},
           {{"init", "--n", "-5", "--phi", "0.3"}, "--n must be a whole number of at least 1"},
           {{"init", "--n", "0x10", "--phi", "0.3"}, "got '0x10'"},
           {{"init", "--n", "10", "--phi", "0.3", "--seed", "-2"}, "--seed must be a whole"},
           {{"init", "--n", "10", "--phi", "0.3", "--dim", "2.5"},
            "--dim must be a whole number from 2 to 3, got '2.5'"},
           {{"init", "--n", "10", "--phi", "0.3", "--dim", "0x3"}, "from 2 to 3, got '0x3'"},
           {{"init", "--n", "10", "--phi", "0.3", "--dim", "4"}, "from 2 to 3, got '4'"},
           {{"view", input, "-o", dir_ / "v.html", "--stride", "0"},
            "--stride must be a whole number of at least 1, got '0'"},
           {{"sweep", dir_ / "plan.toml", "-j", "-1"}, "--jobs must be a whole number"},
           {{"sweep", dir_ / "plan.toml", "-j", "0"}, "--jobs must be a whole number"}}) {
    const Result r = carom(args);
    EXPECT_EQ(r.exit_code, 2) << fmt::format("{}", fmt::join(args, " ")) << ": " << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("0000000"), std::string::npos) << r.err;  // no bound of 309 digits
  }
  // Leading zeros are decimal, not octal.
  const fs::path ten = dir_ / "ten.txt";
  ASSERT_EQ(carom({"init", "--n", "010", "--phi", "0.3", "-o", ten}).exit_code, 0);
  EXPECT_NE(read_file(ten).find("\n10\n"), std::string::npos) << read_file(ten);
}

// Regression: an inelastic collapse in a periodic box asked "is a disk wedged exactly between
// two walls?", where there are none. The message names what this run can have.
TEST_F(Cli, AStuckRunSaysWhatCanBeTrueOfIt) {
  // A granular gas without the TC model collapses (at t = 11 or so).
  const fs::path gas = dir_ / "gas.txt";
  ASSERT_EQ(
      carom({"init", "--n", "100", "--phi", "0.4", "--boundary", "periodic", "-o", gas}).exit_code,
      0);
  const Result collapse =
      carom({"run", gas, "1000", "--rule", "elastic", "--restitution", "0.3", "--tc", "0", "-q"});
  EXPECT_EQ(collapse.exit_code, 1) << collapse.err;
  EXPECT_NE(collapse.err.find("inelastic collapse"), std::string::npos) << collapse.err;
  EXPECT_NE(collapse.err.find("--tc 0"), std::string::npos) << collapse.err;
  EXPECT_EQ(collapse.err.find("wall"), std::string::npos) << collapse.err;
  const Result wedged = carom({"run", write("wedged.txt", "1\n0.5\n1 10\n0.5 5 1 0\n"), "1"});
  EXPECT_EQ(wedged.exit_code, 1) << wedged.err;
  EXPECT_NE(wedged.err.find("wedged exactly between two walls"), std::string::npos) << wedged.err;
}

// Regressions: small promises of the output.
TEST_F(Cli, EdgesOfTheOutputKeepTheirPromises) {
  const std::string input = kCases + "normal.txt";
  const std::string zero = carom({"run", input, "-0", "--format", "json"}).out;
  EXPECT_NE(zero.find("\"end_time\": 0.0,"), std::string::npos) << zero;  // not -0.0
  const auto j = nlohmann::json::parse(zero);
  EXPECT_TRUE(j["mean_free_time"].is_null());  // no time has passed: undefined, as documented
  EXPECT_TRUE(j["compressibility_factor"].is_null());
  EXPECT_TRUE(j["pressure"].is_null());
  const fs::path upper = dir_ / "MOVIE.XYZ";
  EXPECT_EQ(carom({"run", input, "1", "--dump", upper, "--every", "0.5"}).exit_code, 0);
  EXPECT_TRUE(holds(upper, "Time=1"));
}

// Regression: a dump far larger than the disk was accepted without a word, and a failed
// write was noticed only at the end, keeping nothing.
TEST_F(Cli, DumpsThatCannotFitAndWritesThatFailKeepTheState) {
  const fs::path start = dir_ / "gas.txt", checkpoint = dir_ / "c.ckpt";
  ASSERT_EQ(carom({"init", "--n", "10000", "--phi", "0.5", "-o", start}).exit_code, 0);
  const Result huge = carom({"run", start, "10", "--dump", dir_ / "m.xyz", "--every", "1e-6"});
  EXPECT_EQ(huge.exit_code, 2);
  EXPECT_NE(huge.err.find("GB free"), std::string::npos) << huge.err;
  EXPECT_FALSE(fs::exists(dir_ / "m.xyz"));
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full to fill";
  const Result full = carom({"run", start, "100", "--rule", "elastic", "--events", "/dev/full",
                             "--checkpoint", checkpoint, "-q"});
  EXPECT_EQ(full.exit_code, 1);
  EXPECT_EQ(full.out, "");
  EXPECT_NE(full.err.find("is saved in " + checkpoint.string()), std::string::npos) << full.err;
  const auto saved = nlohmann::json::parse(read_file(checkpoint));
  EXPECT_LT(saved["time"].get<double>(), 100.0);  // saved when the write failed, not at the end
  EXPECT_EQ(carom({"run", "--resume", checkpoint, "1", "-q"}).exit_code, 0);  // and it goes on
}

TEST_F(Cli, TimeSeriesThatCannotFitAreRefused) {
  // A disk of 1 MB (a tmpfs, where the test may mount one): a million rows do not fit.
  const fs::path small = dir_ / "small";
  fs::create_directory(small);
  const std::string mount = "mount -t tmpfs -o size=1m tmpfs " + small.string() + " 2>/dev/null";
  if (::geteuid() != 0 || std::system(mount.c_str()) != 0) GTEST_SKIP() << "cannot mount a tmpfs";
  const Result r = carom({"run", kCases + "normal.txt", "1000", "--log", small / "log.csv",
                          "--log-every", "0.001", "-q"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("GB free: raise --log-every"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(small / "log.csv"));
  EXPECT_EQ(std::system(("umount " + small.string()).c_str()), 0);
}

TEST_F(Cli, BundledExamplesAreTheReferenceCasesAndReproduceThem) {
  // What a new user runs first (examples/) is the classic assignment's reference cases, byte for
  // byte, and gives their expected results: the table (after its header line) or the csv.
  const struct {
    const char* name;
    const char* end_time;
    const char* expected;
    bool csv;
  } cases[] = {{"walls_only", "20", "walls_only.T20.expected", false},
               {"particles_only", "18", "particles_only.T18.expected", false},
               {"normal", "20", "normal.T20.csv", true},
               {"particles1", "15", "particles1.T15.csv", true}};
  for (const auto& c : cases) {
    const std::string example = std::string(CAROM_EXAMPLES) + "/" + c.name + ".txt";
    EXPECT_EQ(read_file(example), read_file(kCases + c.name + ".txt")) << c.name;
    std::vector<std::string> args{"run", example, c.end_time};
    if (c.csv) args.insert(args.end(), {"--format", "csv"});
    const Result r = carom(args);
    ASSERT_EQ(r.exit_code, 0) << c.name << ": " << r.err;
    const std::string result = c.csv ? r.out : r.out.substr(r.out.find('\n') + 1);
    EXPECT_EQ(result, read_file(kCases + c.expected)) << c.name;
  }
}

}  // namespace

namespace {

constexpr const char* kSweepPlan = R"([start]
n = 64
boundary = "periodic"
[run]
end_time = 4
equilibrate = 1
rule = "elastic"
[sweep]
phi = [0.2, 0.3]
)";

}  // namespace

TEST_F(Cli, SweepListsItsTasksAsCommandsAndVersionSaysWhereItRuns) {
  std::ofstream(dir_ / "plan.toml") << kSweepPlan;
  const Result listed = carom({"sweep", (dir_ / "plan.toml").string(), "-o", "out", "--dry-run"});
  ASSERT_EQ(listed.exit_code, 0) << listed.err;
  EXPECT_NE(
      listed.out.find("2 tasks (phi)\nphi=0.2\n  carom init --n 64 --boundary periodic "
                      "--phi 0.2 -o out/phi=0.2/start.txt\n  carom run out/phi=0.2/start.txt 4 "),
      std::string::npos)
      << listed.out;
  EXPECT_FALSE(fs::exists("out"));  // nothing run, nothing written
  const Result version = carom({"--version"});
  EXPECT_NE(version.out.find("\nsweep: "), std::string::npos) << version.out;
}

TEST_F(Cli, SweepWritesItsTablesAndAnotherPlansFolderIsRefused) {
  std::ofstream(dir_ / "plan.toml") << kSweepPlan;
  const std::string out = (dir_ / "out").string();
  const Result ran = carom({"sweep", (dir_ / "plan.toml").string(), "-o", out, "-j", "2"});
  ASSERT_EQ(ran.exit_code, 0) << ran.err;
  EXPECT_NE(ran.err.find("2 of 2 tasks done"), std::string::npos) << ran.err;
  for (const char* file : {"results.csv", "summary.csv", "report.html", "phi=0.3/summary.json",
                           "phi=0.3/log.csv", "phi=0.3/checkpoint.ckpt", "phi=0.3/task.txt"}) {
    EXPECT_TRUE(fs::exists(dir_ / "out" / file)) << file;
  }
  const std::string results = read_file(dir_ / "out/results.csv");
  const Result again = carom({"sweep", (dir_ / "plan.toml").string(), "-o", out});
  EXPECT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(read_file(dir_ / "out/results.csv"), results);

  std::string changed = kSweepPlan;
  changed.replace(changed.find("end_time = 4"), 12, "end_time = 5");
  std::ofstream(dir_ / "plan.toml") << changed;
  const Result refused = carom({"sweep", (dir_ / "plan.toml").string(), "-o", out});
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.err.find("holds the files of another task"), std::string::npos) << refused.err;
  EXPECT_EQ(read_file(dir_ / "out/results.csv"), results);
}

// A plan nested 100,000 deep is refused (exit 2, the plan's line), not a crash
// of the TOML parser, and nothing is written.
TEST_F(Cli, SweepRefusesADeeplyNestedPlanBeforeParsingIt) {
  std::string deep = "[start]\nn = 16\nphi = 0.3\n[run]\nend_time = 1\n[sweep]\nx";
  for (int i = 0; i < 100'000; ++i) deep += ".x";
  std::ofstream(dir_ / "deep.toml") << deep << " = 1\n";
  const Result refused =
      carom({"sweep", (dir_ / "deep.toml").string(), "-o", (dir_ / "out").string()});
  EXPECT_EQ(refused.exit_code, 2) << refused.err;
  EXPECT_NE(refused.err.find("deep.toml:7: "), std::string::npos) << refused.err;
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

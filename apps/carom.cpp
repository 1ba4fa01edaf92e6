// The carom command line: parses arguments, calls the library, formats. Exit codes: 0 success,
// 2 usage or input error, 1 runtime failure.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "carom/atomic_file.hpp"
#include "carom/classic_input.hpp"
#include "carom/engine.hpp"
#include "carom/formats.hpp"
#include "carom/version.hpp"

namespace {

constexpr int kUsageError = 2;
constexpr int kRuntimeError = 1;

// A problem with the command line or its arguments, reported with exit code 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

constexpr const char* kFormatHelp = R"(The classic input FILE holds whitespace-separated numbers:
  line 1       N            the number of disks
  line 2       R            their radius
  line 3       Lx Ly        the box: hard walls at x = 0, x = Lx, y = 0, y = Ly
  N lines      x y vx vy    each disk's centre and velocity at t = 0
Walls are labelled -1 left, -2 right, -3 bottom, -4 top; disks 0..N-1.)";

constexpr const char* kExamples = R"(Examples:
  carom run examples/walls_only.txt 20            final state, the seed's table
  carom run examples/normal.txt 20 --format csv   x, y, wall and disk collision counts
  carom run examples/normal.txt 20 --trace        every collision, step by step
  carom run examples/normal.txt 100 --format json -o result.json)";

struct RunArguments {
  std::string input;
  std::string end_time;
  carom::Format format = carom::Format::table;
  bool trace = false;
  std::string output;
  carom::Rule rule = carom::Rule::swap;
  carom::EngineKind engine = carom::EngineKind::fast;
};

// An option whose value is one of a few names; help lists them and anything else is refused.
template <class T>
CLI::Option* add_choice(CLI::App* app, const std::string& flag, T& target,
                        const std::vector<std::pair<std::string, T>>& names,
                        const std::string& help) {
  std::vector<std::string> keys;
  for (const auto& [key, value] : names) keys.push_back(key);
  return app
      ->add_option_function<std::string>(
          flag,
          [&target, names](const std::string& chosen) {
            for (const auto& [key, value] : names) {
              if (CLI::detail::to_lower(chosen) == key) target = value;
            }
          },
          help)
      ->check(CLI::IsMember(keys, CLI::ignore_case))
      ->default_str(keys.front());
}

double parse_end_time(const std::string& text) {
  double value = 0.0;
  try {
    value = carom::parse_finite_double(text);
  } catch (const std::invalid_argument& e) {
    throw UsageError(fmt::format("END_TIME: {}", e.what()));
  }
  if (value < 0.0) throw UsageError(fmt::format("END_TIME must not be negative, got {}", text));
  return value;
}

void write_result(std::ostream& out, const RunArguments& args, double end_time,
                  carom::Engine<2>& engine) {
  const auto& particles = engine.system().particles;
  if (args.trace) {
    carom::TraceWriter trace(out);
    trace.start(args.input, end_time, particles);
    carom::run(engine, end_time, [&](const carom::Event& event) { trace.event(event, particles); });
    trace.finish(particles);
    return;
  }
  carom::run(engine, end_time);
  switch (args.format) {
    case carom::Format::table:
      carom::write_table(out, particles);
      break;
    case carom::Format::csv:
      carom::write_csv(out, particles);
      break;
    case carom::Format::json:
      carom::write_json(out, {args.input, end_time, args.rule, args.engine}, engine);
      break;
  }
}

void run_command(const RunArguments& args) {
  if (args.trace && args.format != carom::Format::table) {
    throw UsageError(
        "--trace prints the seed's step-by-step table; it cannot be combined with "
        "--format csv or json");
  }
  const double end_time = parse_end_time(args.end_time);
  carom::ClassicInput input = carom::read_classic_file(args.input);
  // The output file is set up before the run, so an unwritable path fails at once.
  std::unique_ptr<carom::AtomicFile> file;
  if (!args.output.empty()) {
    try {
      file = std::make_unique<carom::AtomicFile>(args.output);
    } catch (const std::runtime_error& e) {
      throw UsageError(e.what());
    }
  }
  auto engine = carom::make_engine(args.engine, std::move(input.system), args.rule);
  std::ostream& out = file ? file->stream() : std::cout;
  write_result(out, args, end_time, *engine);
  if (file) {
    file->commit();
  } else if (!std::cout.flush()) {
    throw std::runtime_error("cannot write to standard output");
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"carom: event-driven molecular dynamics of hard disks in a box with hard walls.\n",
               "carom"};
  app.set_version_flag("--version", std::string("carom ") + carom::kVersion);
  app.require_subcommand(1);
  app.footer(kExamples);

  RunArguments args;
  CLI::App* run = app.add_subcommand(
      "run", "Simulate FILE from t = 0 to END_TIME and print every disk's final state.");
  run->footer(std::string(kFormatHelp) + "\n\n" + kExamples);
  run->add_option("FILE", args.input, "Input in the classic format (see below); - reads stdin")
      ->required();
  run->add_option("END_TIME", args.end_time, "Time to simulate to (a number >= 0)")->required();
  add_choice<carom::Format>(
      run, "--format", args.format,
      {{"table", carom::Format::table}, {"csv", carom::Format::csv}, {"json", carom::Format::json}},
      "table: the seed's `particle i: (x, y) (vx, vy): t : (cwall, cpart)` lines; csv: `x, y, "
      "cwall, cpart` lines; json: full state and counts");
  run->add_flag("--trace", args.trace,
                "Print the initial state, then after every collision its time, what collided and "
                "every disk's stored state, then the final state");
  run->add_option("-o,--output", args.output,
                  "Write to this file (atomically: it appears complete or not at all) instead of "
                  "stdout");
  add_choice<carom::Rule>(run, "--rule", args.rule,
                          {{"swap", carom::Rule::swap}, {"elastic", carom::Rule::elastic}},
                          "swap: touching disks exchange whole velocities (the seed's rule); "
                          "elastic: they exchange momentum along the line of centres (real hard "
                          "disks)");
  add_choice<carom::EngineKind>(
      run, "--engine", args.engine,
      {{"fast", carom::EngineKind::fast}, {"reference", carom::EngineKind::reference}},
      "fast: cell grid and event queue, O(log N) per event; reference: the seed's algorithm, "
      "every pair checked after every event (O(N^2), for checking)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : kUsageError;
  }

  try {
    if (run->parsed()) run_command(args);
    return 0;
  } catch (const UsageError& e) {
    std::cerr << "carom: error: " << e.what() << "\nRun 'carom run --help' for usage.\n";
    return kUsageError;
  } catch (const carom::InputError& e) {
    std::cerr << "carom: error: " << e.what() << '\n';
    return kUsageError;
  } catch (const std::exception& e) {
    std::cerr << "carom: error: " << e.what() << '\n';
    return kRuntimeError;
  }
}

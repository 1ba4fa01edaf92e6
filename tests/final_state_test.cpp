// The end state written as a start (carom run --final): read back, every number is the state's,
// to the last bit, from GSD (carom's double-precision copies beside HOOMD's single-precision
// chunks) and from the classic start format; a GSD file changed by another program behind those
// copies is refused rather than trusted.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "carom/engine/initial.hpp"
#include "carom/engine/simulation.hpp"
#include "carom/io/classic_input.hpp"
#include "carom/io/final_state.hpp"
#include "carom/io/gsd.hpp"
#include "carom/io/input_error.hpp"
#include "io/gsd_format.hpp"

namespace carom {
namespace {

namespace fs = std::filesystem;

struct Folder {
  fs::path path = fs::temp_directory_path() / ("carom_final_state_" + std::to_string(::getpid()));
  Folder() { fs::create_directories(path); }
  ~Folder() { fs::remove_all(path); }
};

// A polydisperse periodic system some way into a run, its particles stored at their own times.
template <std::size_t D>
Simulation<D> a_run_under_way(double packing, double until) {
  InitialOptions options;
  options.n = D == 2 ? 300 : 250;
  options.packing_fraction = packing;
  options.polydispersity = 0.2;
  options.placement = Placement::random;
  options.boundary = Boundary::periodic;
  Simulation<D> simulation(make_initial<D>(options), Settings{{Rule::elastic}});
  simulation.run_until(until);
  return simulation;
}

template <std::size_t D>
void write(const fs::path& path, const Simulation<D>& simulation, bool at_rest = false) {
  std::ofstream out(path, std::ios::binary);
  write_final_state(out, final_format(path.string()), simulation.state(), simulation.time(),
                    Rule::elastic, at_rest);
}

template <std::size_t D>
void expect_the_state(const ClassicInput<D>& back, const Simulation<D>& simulation, bool at_rest) {
  const System<D>& system = simulation.state();
  const std::vector<Particle<D>> expected = simulation.snapshot();
  ASSERT_EQ(back.system.size(), system.size());
  EXPECT_EQ(back.system.box.size, system.box.size);
  EXPECT_EQ(back.system.box.boundary, Boundary::periodic);
  for (std::size_t i = 0; i < system.size(); ++i) {
    EXPECT_EQ(back.system.particles[i].position, expected[i].position) << i;
    EXPECT_EQ(back.system.particles[i].velocity, at_rest ? Vec<D>{} : expected[i].velocity) << i;
    EXPECT_EQ(back.system.particles[i].radius, system.particles[i].radius) << i;
    EXPECT_EQ(back.system.records[i].mass, system.records[i].mass) << i;
  }
}

template <std::size_t D>
void round_trip() {
  const Folder folder;
  const Simulation<D> simulation = a_run_under_way<D>(D == 2 ? 0.38 : 0.24, 3.0);
  ASSERT_GT(simulation.counts().events, 1000u);
  for (const bool at_rest : {false, true}) {
    const fs::path gsd = folder.path / "end.gsd", text = folder.path / "end.txt";
    write(gsd, simulation, at_rest);
    write(text, simulation, at_rest);
    expect_the_state(std::get<ClassicInput<D>>(read_gsd_start(gsd.string(), std::nullopt)),
                     simulation, at_rest);
    expect_the_state(read_classic_file<D>(text.string()), simulation, at_rest);
  }
}

TEST(FinalState, DisksComeBackToTheLastBitFromGsdAndTheStartFormat) { round_trip<2>(); }
TEST(FinalState, SpheresComeBackToTheLastBitFromGsdAndTheStartFormat) { round_trip<3>(); }

// Dense disks, read from the single-precision chunks alone, are not the state: the double copies
// are what makes the GSD file a start (without them, some positions differ).
TEST(FinalState, WithoutItsDoubleCopiesAGsdFrameIsNotTheState) {
  const Folder folder;
  const Simulation<2> simulation = a_run_under_way<2>(0.38, 1.0);
  const fs::path gsd = folder.path / "end.gsd";
  {
    std::ofstream out(gsd, std::ios::binary);
    GsdFormat<2>(false).frame(out, 0, simulation.time(), simulation.state());
  }
  const ClassicInput<2> back =
      std::get<ClassicInput<2>>(read_gsd_start(gsd.string(), std::nullopt));
  const std::vector<Particle<2>> expected = simulation.snapshot();
  std::size_t differ = 0;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    differ += back.system.particles[i].position != expected[i].position ? 1 : 0;
  }
  EXPECT_GT(differ, expected.size() / 2);
}

// A program that rewrites a particle's position (gsd.hoomd keeps the frame's log/ chunks) leaves
// carom's copy stale: the file is refused, naming it and why.
TEST(FinalState, AGsdFrameChangedBehindItsDoubleCopiesIsRefused) {
  const Folder folder;
  const Simulation<2> simulation = a_run_under_way<2>(0.38, 1.0);
  const fs::path gsd = folder.path / "end.gsd";
  write(gsd, simulation);
  std::string bytes;
  {
    std::ifstream in(gsd, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  // particles/position's first float: particle 0's x from the box's centre.
  const Particle<2> first = simulation.snapshot().front();
  const auto x = static_cast<float>(first.position[0] - 0.5 * simulation.state().box.size[0]);
  char pattern[sizeof x];
  std::memcpy(pattern, &x, sizeof x);
  const std::size_t at = bytes.find(std::string(pattern, sizeof x));
  ASSERT_NE(at, std::string::npos);
  const float moved = x + 0.25f;
  std::memcpy(bytes.data() + at, &moved, sizeof moved);
  {
    std::ofstream out(gsd, std::ios::binary);
    out << bytes;
  }
  try {
    read_gsd_start(gsd.string(), std::nullopt);
    ADD_FAILURE() << "a changed frame was read";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("end.gsd"), std::string::npos) << what;
    EXPECT_NE(what.find("changed by another program"), std::string::npos) << what;
  }
}

TEST(FinalState, TheFormatIsTheNames) {
  EXPECT_EQ(final_format("end.gsd"), FinalFormat::gsd);
  EXPECT_EQ(final_format("END.GSD"), FinalFormat::gsd);  // as a dump's name is read
  EXPECT_EQ(final_format("end.txt"), FinalFormat::classic);
  EXPECT_EQ(final_format("end"), FinalFormat::classic);
  EXPECT_THROW(final_format("end.xyz"), std::invalid_argument);
  EXPECT_THROW(final_format("end.lammpstrj"), std::invalid_argument);
  EXPECT_THROW(final_format("END.XYZ"), std::invalid_argument);
}

}  // namespace
}  // namespace carom

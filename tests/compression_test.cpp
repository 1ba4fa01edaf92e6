#include "carom/engine/compression.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <sstream>

#include "carom/core/observables.hpp"
#include "carom/engine/initial.hpp"
#include "carom/engine/overlap.hpp"
#include "carom/io/classic_input.hpp"
#include "carom/io/classic_output.hpp"
#include "carom/io/event_log.hpp"
#include "carom/run/run_report.hpp"

namespace carom {
namespace {

template <std::size_t D>
System<D> gas(std::uint64_t n, double phi, Boundary boundary, double polydispersity = 0.0,
              std::uint64_t seed = 1) {
  InitialOptions init;
  init.n = n;
  init.packing_fraction = phi;
  init.boundary = boundary;
  init.polydispersity = polydispersity;
  init.seed = seed;
  return make_initial<D>(init);
}

// Runs a compression to its end.
template <std::size_t D>
CompressionStatus finish(Compression<D>& c) {
  while (c.status() == CompressionStatus::running) c.run(1'000'000);
  return c.status();
}

template <std::size_t D>
void expect_valid(const System<D>& system, const std::string& label) {
  const auto wrong = find_violation(system, 0.0);
  EXPECT_FALSE(wrong) << label << ": " << wrong.value_or("");
}

TEST(Compression, StopsAtTheTargetExactlyKeepingSizeRatios) {
  for (const Boundary boundary : {Boundary::periodic, Boundary::walls}) {
    const System<2> start = gas<2>(300, 0.3, boundary, 0.1);
    CompressionSettings settings;
    settings.target = 0.72;
    Compression<2> c(start, settings);
    EXPECT_EQ(finish(c), CompressionStatus::reached_target);
    EXPECT_NEAR(c.packing_fraction(), 0.72, 1e-14);
    const System<2>& end = c.system();
    expect_valid(end, "2D");
    const double scale = end.particles[0].radius / start.particles[0].radius;
    EXPECT_NEAR(scale, std::sqrt(0.72 / 0.3), 1e-14);
    for (std::size_t i = 0; i < end.size(); ++i) {
      EXPECT_NEAR(end.particles[i].radius / start.particles[i].radius, scale, 1e-14) << i;
      EXPECT_EQ(end.particles[i].time, 0.0);
    }
    // At the temperature asked for, every particle still moving.
    EXPECT_NEAR(kinetic_temperature(end), 1.0, 1e-12);
    EXPECT_GT(c.events(), 0u);
  }
}

TEST(Compression, SpheresReachTheirTargetInBothEnginesAlike) {
  const System<3> start = gas<3>(60, 0.2, Boundary::periodic);
  CompressionSettings settings;
  settings.target = 0.5;
  settings.rate = 0.05;
  Compression<3> fast(start, settings);
  settings.engine = EngineKind::reference;
  Compression<3> reference(start, settings);
  EXPECT_EQ(finish(fast), CompressionStatus::reached_target);
  EXPECT_EQ(finish(reference), CompressionStatus::reached_target);
  EXPECT_EQ(fast.events(), reference.events());
  for (std::size_t i = 0; i < start.size(); ++i) {
    EXPECT_EQ(fast.system().particles[i].position, reference.system().particles[i].position) << i;
    EXPECT_EQ(fast.system().particles[i].velocity, reference.system().particles[i].velocity) << i;
  }
  expect_valid(fast.system(), "3D");
}

TEST(Compression, EqualSpheresJamNearRandomClosePacking) {
  CompressionSettings settings;  // --jam at the default rate
  Compression<3> c(gas<3>(256, 0.3, Boundary::periodic), settings);
  EXPECT_EQ(finish(c), CompressionStatus::jammed);
  EXPECT_GT(c.compressibility_factor(), kJammedPressure);
  EXPECT_GT(c.packing_fraction(), 0.62);
  EXPECT_LT(c.packing_fraction(), 0.66);
  expect_valid(c.system(), "jammed spheres");
}

TEST(Compression, ABidisperseMixtureOfDisksJamsNearItsJammingDensity) {
  // 50:50, diameters 1 and 1.4 (O'Hern et al. 2003: 0.84 for large systems).
  System<2> start = gas<2>(200, 0.3, Boundary::periodic);
  for (std::size_t i = 0; i < start.size(); i += 2) start.particles[i].radius /= 1.4;
  CompressionSettings settings;
  settings.rate = 0.05;
  Compression<2> c(start, settings);
  EXPECT_EQ(finish(c), CompressionStatus::jammed);
  EXPECT_GT(c.packing_fraction(), 0.81);
  EXPECT_LT(c.packing_fraction(), 0.86);
  expect_valid(c.system(), "jammed disks");
}

TEST(Compression, RefusesWhatCannotBeDone) {
  const System<2> start = gas<2>(100, 0.3, Boundary::periodic);
  const auto refused = [](const System<2>& system, const CompressionSettings& settings) {
    try {
      Compression<2> c(system, settings);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  CompressionSettings s;
  s.target = 0.25;
  EXPECT_NE(refused(start, s).find("not above the start's"), std::string::npos);
  s.target = 0.91;
  EXPECT_NE(refused(start, s).find("beyond 0.9068996821171089 (close packing)"), std::string::npos);
  s.target = 0.7;
  s.rate = 0.0;
  EXPECT_NE(refused(start, s).find("growth rate must be a positive number"), std::string::npos);
  s.rate = std::nan("");
  EXPECT_NE(refused(start, s).find("growth rate"), std::string::npos);
  s = {};
  System<2> overlapping = start;
  overlapping.particles[1].position = overlapping.particles[0].position;
  EXPECT_NE(refused(overlapping, s).find("overlap"), std::string::npos);
  System<2> still = start;
  for (Particle<2>& p : still.particles) p.velocity = {};
  EXPECT_NE(refused(still, s).find("do not move"), std::string::npos);
  // Four disks cannot jam in a periodic box: its sides would come within two diameters.
  EXPECT_NE(refused(gas<2>(4, 0.3, Boundary::periodic), s).find("too small"), std::string::npos);
  // Unequal disks may pass the close packing of equal ones, but not fill the box.
  System<2> unequal = start;
  unequal.particles[0].radius *= 0.5;
  s.target = 0.95;
  EXPECT_EQ(refused(unequal, s), "accepted");
  s.target = 1.0;
  EXPECT_NE(refused(unequal, s).find("a full box"), std::string::npos);
}

// Hostile cases of a round of testing: compressions that spun forever, time frozen while the
// events went on (regressions).
TEST(Compression, ParticlesThatCanGrowNoMoreAreJammedNotSpunForever) {
  const auto system = [](std::vector<Particle<2>> particles, Vec2 box) {
    System<2> s;
    s.box.size = box;
    for (const Particle<2>& p : particles) s.add(p);
    return s;
  };
  Particle<2> a, b;
  a.position = {{10, 1}}, a.velocity = {{1, 0.3}}, a.radius = 0.5;
  b.position = {{30, 1}}, b.velocity = {{-1, 0.2}}, b.radius = 0.5;
  // Two disks across a channel as high as they can grow wide; one disk in a square box: they
  // end pinned between walls, which Z (pair collisions only) never shows.
  const std::vector<System<2>> pinned = {system({a, b}, {{100, 2}}), system({a}, {{12, 12}})};
  for (const System<2>& start : pinned) {
    for (const std::optional<double> target : {std::optional<double>(), std::optional(0.8)}) {
      CompressionSettings settings;
      settings.target = target;
      Compression<2> c(start, settings);
      EXPECT_EQ(finish(c), CompressionStatus::jammed);
      expect_valid(c.system(), "pinned");
      EXPECT_LT(c.events(), 100'000'000u);
    }
  }
  // A pressure doubles cannot reach is refused; the most that may be asked for ends.
  CompressionSettings beyond;
  beyond.jammed_pressure = 1e16;
  EXPECT_THROW(Compression<2>(gas<2>(50, 0.3, Boundary::periodic), beyond), std::invalid_argument);
  CompressionSettings most;
  most.jammed_pressure = kMostJammedPressure;
  most.rate = 0.1;
  Compression<2> dense(gas<2>(50, 0.3, Boundary::periodic), most);
  EXPECT_EQ(finish(dense), CompressionStatus::jammed);
}

TEST(Compression, EveryPackingItWritesIsAStartCaromReads) {
  // A fast jam leaves rattlers with velocities like 1e-115 after the rescaling, which a start
  // file cannot carry (magnitudes from 1e-100): they are 0, so that the file reads back, the same
  // doubles. A stopped compression's packing too.
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    CompressionSettings settings;
    settings.rate = 100.0;
    Compression<2> c(gas<2>(50, 0.3, Boundary::periodic, 0.0, seed), settings);
    EXPECT_EQ(finish(c), CompressionStatus::jammed);
    std::stringstream file;
    write_start(file, c.system(), Rule::elastic);
    const ClassicInput<2> read = read_classic<2>(file, "packing");
    EXPECT_EQ(read.system.particles, c.system().particles) << seed;
  }
  std::atomic<int> stop{1};
  Compression<3> stopped(gas<3>(100, 0.3, Boundary::periodic), {});
  stopped.set_stop_flag(&stop);
  EXPECT_EQ(stopped.run(1000), CompressionStatus::running);
  std::stringstream file;
  write_start(file, stopped.system(), Rule::elastic);
  EXPECT_NO_THROW(read_classic<3>(file, "stopped"));
}

}  // namespace
}  // namespace carom

#include "carom/compression.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "carom/initial.hpp"
#include "carom/observables.hpp"
#include "carom/overlap.hpp"

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

}  // namespace
}  // namespace carom

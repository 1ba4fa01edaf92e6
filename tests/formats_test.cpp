#include "carom/formats.hpp"

#include <gtest/gtest.h>

#include <sstream>

namespace carom {
namespace {

Particle<2> sample() {
  Particle<2> p;
  p.position = {8.3001204, 11.4604334};
  p.velocity = {0.3, -0.31};
  p.time = 18;
  p.wall_collisions = 2;
  p.pair_collisions = 7;
  return p;
}

TEST(Formats, ParticleLineIsTheSeedsPrintf) {
  EXPECT_EQ(particle_line(1, sample()),
            "particle 1: (8.300120, 11.460433) (0.300000, -0.310000): 18.000000 : (2, 7)");
}

TEST(Formats, TableHasTheHeaderThenOneLineADisk) {
  std::ostringstream out;
  write_table(out, {sample(), sample()});
  EXPECT_EQ(out.str(),
            "particle id: (xpos, ypos) (xvel, yvel): last_update : (cwall, cpart)\n"
            "particle 0: (8.300120, 11.460433) (0.300000, -0.310000): 18.000000 : (2, 7)\n"
            "particle 1: (8.300120, 11.460433) (0.300000, -0.310000): 18.000000 : (2, 7)\n");
}

TEST(Formats, CsvIsPositionsAndCounts) {
  std::ostringstream out;
  write_csv(out, {sample()});
  EXPECT_EQ(out.str(), "8.300120, 11.460433, 2, 7\n");
}

TEST(Formats, RoundingIsPrintfs) {
  Particle<2> p;
  p.position = {0.0078125, -1e-9};  // an exact tie rounds to even; a tiny negative keeps its sign
  std::ostringstream out;
  write_csv(out, {p});
  EXPECT_EQ(out.str(), "0.007812, -0.000000, 0, 0\n");
}

TEST(Formats, EventsAreDescribedByLabel) {
  EXPECT_EQ(describe(Event{1.0, 3, -2}), "Collision: particle 3 with wall -2 (right)");
  EXPECT_EQ(describe(Event{1.0, 1, 2}), "Collision: particle 1 with particle 2");
}

}  // namespace
}  // namespace carom

// `carom view`'s reader: the trajectories carom writes, of disks and of spheres, read back with
// their dimension, and what the page is handed.
#include "carom/viewer.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "carom/classic_input.hpp"
#include "carom/system.hpp"
#include "carom/trajectory.hpp"

namespace carom {
namespace {

template <std::size_t D>
Particle<D> particle(Vec<D> position, Vec<D> velocity, double r) {
  Particle<D> p;
  p.position = position;
  p.velocity = velocity;
  p.radius = r;
  return p;
}

template <std::size_t D>
std::vector<Frame> written_and_read(const System<D>& system, int frames) {
  std::stringstream file;
  auto xyz = trajectory_format_for<D>("m.xyz");
  for (int k = 0; k < frames; ++k) xyz->frame(file, k, 0.25 * k, system);
  return read_xyz_frames(file, "m.xyz");
}

TEST(Viewer, ReadsSpheresWithTheirZ) {
  System<3> system;
  system.box = {{{4, 5, 6}}, Boundary::walls};
  system.add(particle<3>({{1, 2, 3.25}}, {{0.5, -0.25, 1}}, 0.5));
  system.add(particle<3>({{3, 3, 1.5}}, {{0, 0, -0.75}}, 0.75));
  const std::vector<Frame> frames = written_and_read(system, 2);
  ASSERT_EQ(frames.size(), 2u);
  for (const Frame& f : frames) {
    EXPECT_EQ(f.dimension, 3);
    EXPECT_EQ(f.box, (Vec<3>{{4, 5, 6}}));
    EXPECT_FALSE(f.periodic);
    ASSERT_EQ(f.position.size(), 2u);
    EXPECT_EQ(f.radius, (std::vector<double>{0.5, 0.75}));
  }
  EXPECT_EQ(frames[0].position[0], (Vec<3>{{1, 2, 3.25}}));
  EXPECT_EQ(frames[0].position[1], (Vec<3>{{3, 3, 1.5}}));
  EXPECT_EQ(frames[0].velocity[1], (Vec<3>{{0, 0, -0.75}}));
  EXPECT_EQ(frames[1].time, 0.25);
  EXPECT_DOUBLE_EQ(frames[1].position[0][2], 3.5);
  EXPECT_DOUBLE_EQ(frames[1].position[1][2], 1.5 - 0.1875);

  system.box.boundary = Boundary::periodic;
  const std::vector<Frame> periodic = written_and_read(system, 1);
  EXPECT_EQ(periodic[0].dimension, 3);
  EXPECT_TRUE(periodic[0].periodic);
}

TEST(Viewer, ReadsDisksAsDisks) {
  System<2> system;
  system.box = {{{10, 8}}, Boundary::periodic};
  system.add(particle<2>({{5, 5}}, {{1, 0.5}}, 1));
  system.add(particle<2>({{2, 2}}, {{-0.5, 0}}, 0.5));
  const std::vector<Frame> frames = written_and_read(system, 3);
  ASSERT_EQ(frames.size(), 3u);
  for (const Frame& f : frames) {
    EXPECT_EQ(f.dimension, 2);
    EXPECT_EQ(f.box[0], 10);
    EXPECT_EQ(f.box[1], 8);
    EXPECT_TRUE(f.periodic);
    for (std::size_t i = 0; i < 2; ++i) {
      EXPECT_EQ(f.position[i][2], 0);
      EXPECT_EQ(f.velocity[i][2], 0);
    }
  }
  EXPECT_EQ(frames[0].position[0], (Vec<3>{{5, 5, 0}}));
  EXPECT_EQ(frames[2].position[1], (Vec<3>{{1.75, 2, 0}}));
}

TEST(Viewer, OneSphereOffThePlaneMakesTheWholeFileSpheres) {
  // Two columns of pos are disks; z (or a z velocity) anywhere in the file makes spheres.
  std::istringstream flat(
      "1\nLattice=\"3 0 0 0 3 0 0 0 1\" Properties=species:S:1:pos:R:2\nH 1 2\n");
  EXPECT_EQ(read_xyz_frames(flat, "flat.xyz")[0].dimension, 2);
  const auto header = [](int t) {
    return fmt::format(
        "2\nLattice=\"3 0 0 0 3 0 0 0 3\" Properties=species:S:1:pos:R:3:velo:R:3 Time={}\n", t);
  };
  std::istringstream deep(header(0) + "H 1 1 0 1 0 0\nH 2 2 0 0 1 0\n" + header(1) +
                          "H 2 1 0 1 0 0\nH 2 2 0 0 1 0.5\n");
  const std::vector<Frame> frames = read_xyz_frames(deep, "deep.xyz");
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[0].dimension, 3);
  EXPECT_EQ(frames[1].dimension, 3);
  EXPECT_EQ(frames[1].velocity[1][2], 0.5);
}

TEST(Viewer, ABadLineNamesTheFileAndTheLine) {
  std::istringstream in(
      "1\nLattice=\"3 0 0 0 3 0 0 0 3\" Properties=species:S:1:pos:R:3 Time=0\nH 1 1 1\n"
      "1\nLattice=\"3 0 0 0 3 0 0 0 3\" Properties=species:S:1:pos:R:3 Time=1\nH 1 1\n");
  try {
    read_xyz_frames(in, "bad.xyz");
    FAIL() << "read a line with too few columns";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "bad.xyz");
    EXPECT_EQ(e.line(), 6u);
  }
}

TEST(Viewer, ThePageIsToldTheDimensionAndTheWholeBox) {
  System<3> system;
  system.box = {{{4, 5, 6}}, Boundary::walls};
  system.add(particle<3>({{1, 2, 3}}, {{0, 0, 1}}, 0.5));
  std::ostringstream page;
  write_viewer_html(page, written_and_read(system, 1));
  EXPECT_NE(page.str().find("\"box\":[4.0,5.0,6.0]"), std::string::npos);
  EXPECT_NE(page.str().find("\"dimension\":3"), std::string::npos);
  System<2> disks;
  disks.box = {{{4, 5}}, Boundary::walls};
  disks.add(particle<2>({{1, 2}}, {{1, 0}}, 0.5));
  std::ostringstream flat;
  write_viewer_html(flat, written_and_read(disks, 1));
  EXPECT_NE(flat.str().find("\"box\":[4.0,5.0]"), std::string::npos);
  EXPECT_NE(flat.str().find("\"dimension\":2"), std::string::npos);
}

}  // namespace
}  // namespace carom

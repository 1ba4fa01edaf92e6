// `carom view`'s reader: the trajectories carom writes, of disks and of spheres, read back with
// their dimension, and what the page is handed.
#include "carom/analysis/viewer.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "carom/core/system.hpp"
#include "carom/io/classic_input.hpp"
#include "carom/io/trajectory.hpp"

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

// Regression: malformed headers crashed `carom view` or read past a row's end.
// Every one is now an InputError naming the file and the line at fault.
TEST(Viewer, MalformedFilesAreRefusedWithTheirLine) {
  const auto frame = [](const std::string& comment, const std::string& rows, int n = 1) {
    return fmt::format("{}\n{}\n{}", n, comment, rows);
  };
  const std::string box = "Lattice=\"3 0 0 0 3 0 0 0 3\" ";
  const std::string ok = "Properties=species:S:1:pos:R:3:velo:R:3:radius:R:1:collisions:I:1 ";
  const std::string row = "H 1 1 0 0.5 0 0 0.5 3\n";
  // The well-formed one first: the cases below break one thing each.
  std::istringstream good(frame(box + ok + "Time=0", row));
  ASSERT_EQ(read_xyz_frames(good, "good.xyz").size(), 1u);
  struct Bad {
    std::string text;
    std::size_t line;
    std::string message;
  };
  const std::vector<Bad> cases = {
      {frame(box + "Properties=species:S:1:pos:R:0", "H\n"), 2, "width '0'"},
      {frame(box + "Properties=species:S:1:pos:R:-3", "H 1 1 0\n"), 2, "width '-3'"},
      {frame(box + "Properties=species:S:1:pos:R:1e300", "H 1 1 0\n"), 2, "width '1e300'"},
      {frame(box + "Properties=species:S:1:pos:R:1.5", "H 1 1 0\n"), 2, "width '1.5'"},
      {frame(box + "Properties=species:S:1:junk:R:18446744073709551613:pos:R:3", "H 1 1 0\n"), 2,
       "width '18446744073709551613'"},
      {frame(box + "Properties=species:S:1:pos:R:3:velo:R:-2", "H 1 1 0\n"), 2, "width '-2'"},
      {frame(box + "Properties=species:S:1:pos:R:3:pos:R:3", "H 1 1 0 1 1 0\n"), 2,
       "names 'pos' twice"},
      {frame(box + "Properties=species:S:1:pos:R", "H 1 1 0\n"), 2, "name:type:width"},
      {frame(box + "Properties=species:S:1:pos:Q:3", "H 1 1 0\n"), 2, "type 'Q'"},
      {frame(box + "Properties=species:S:1:pos:S:3", "H 1 1 0\n"), 2, "pos must be numbers"},
      {frame(box + "Properties=species:S:1:pos:R:1", "H 1\n"), 2, "pos has width 1"},
      {frame(box + "Properties=species:S:1:pos:R:4", "H 1 1 0 0\n"), 2, "pos has width 4"},
      {frame(box + "Properties=species:S:1:velo:R:3", "H 1 1 0\n"), 2, "no pos property"},
      {frame(box + "Properties=species:S:1:pos:R:3:radius:R:2", "H 1 1 0 1 1\n"), 2,
       "radius has width 2"},
      {frame(box + ok, "H 1 1 0\n"), 3, "expected 9 columns, found 4"},
      {frame(box + ok, "H 1 1 0 0.5 0 0 0.5 3 7\n"), 3, "expected 9 columns, found 10"},
      {frame(box + ok, "H 1 x 0 0.5 0 0 0.5 3\n"), 3, "'x' is not a number"},
      {frame(box + ok, "H 1 1 0 0.5 0 0 -0.5 3\n"), 3, "radius must be greater than 0"},
      {frame(box + ok, "H 1 1 0 0.5 0 0 0 3\n"), 3, "radius must be greater than 0"},
      {frame(box + ok, "H 1 1 0 0.5 0 0 0.5 -1\n"), 3, "collision count must be a whole number"},
      {frame(box + ok, "H 1 1 0 0.5 0 0 0.5 2.5\n"), 3, "collision count must be a whole number"},
      {frame(box + ok, "H 1 1 0 0.5 0 0 0.5 1e20\n"), 0, ""},  // read: shown as 2^32 - 1
      {frame("Lattice=\"3 0 0 0 -3 0 0 0 3\" " + ok, row), 2, "sides must be greater than 0"},
      {frame("Lattice=\"3 1 0 0 3 0 0 0 3\" " + ok, row), 2, "rectangular box"},
      {frame("Lattice=\"3 0 0 0 3 0 0 0\" " + ok, row), 2, "no Lattice"},
      {frame(box + ok + "Time=soon", row), 2, "'soon' is not a number"},
      {frame(box + ok, row, 2), 3, "the file ends where a particle line"},
      {frame(box + ok, row, 0), 1, "the number of particles"},
      {frame(box + ok, row, -1), 1, "the number of particles"},
      {"100000000000000000000\n", 1, "the number of particles"},
      {"99999999\n" + box + ok + "\n" + row, 3, "the file ends where a particle line"},
      {frame(box + ok, row) + frame(box + ok, row + row, 2), 4, "changes between frames"},
      {frame(box + ok, std::string("H 1 1 0 0.5 0 0 0.5 3") + '\0' + "\n"), 3, "NUL byte"},
      {frame(box + ok, std::string(70000, ' ') + row), 3, "line longer than"},
      {"", 0, "no frames"},
  };
  for (const Bad& bad : cases) {
    std::istringstream in(bad.text);
    if (bad.message.empty()) {
      EXPECT_EQ(read_xyz_frames(in, "bad.xyz")[0].collisions[0], 4294967295u);
      continue;
    }
    try {
      read_xyz_frames(in, "bad.xyz");
      ADD_FAILURE() << "accepted: " << bad.text.substr(0, 200);
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), "bad.xyz");
      EXPECT_EQ(e.line(), bad.line) << e.what();
      EXPECT_NE(std::string(e.what()).find(bad.message), std::string::npos)
          << "expected \"" << bad.message << "\" in: " << e.what();
    }
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

#include "carom/io/classic_input.hpp"

#include <gtest/gtest.h>

#include <sstream>

namespace carom {
namespace {

// What a wall overlap adds when the particle would be fine in a periodic box.
const std::string kPeriodicHint =
    "; if the file is for a periodic box, run it with --boundary periodic (boundary=\"periodic\" "
    "in Python)";

ClassicInput<2> read(const std::string& text) {
  std::istringstream in(text);
  return read_classic<2>(in, "test.txt");
}

// The message of the InputError that reading `text` throws.
std::string error_of(const std::string& text) {
  try {
    read(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ClassicInput, ReadsThePlainFormat) {
  const ClassicInput<2> input = read("2\n0.5\n10 8\n1 1 0.1 -0.2\n5 5 -1 0\n");
  ASSERT_EQ(input.system.particles.size(), 2u);
  EXPECT_EQ(input.radius, 0.5);
  EXPECT_EQ(input.system.box.size, (Vec2{{10, 8}}));
  EXPECT_EQ(input.system.particles[1].position, (Vec2{{5, 5}}));
  EXPECT_EQ(input.system.particles[0].velocity, (Vec2{{0.1, -0.2}}));
  EXPECT_EQ(input.system.particles[0].radius, 0.5);
  EXPECT_EQ(input.system.records[0].mass, 1.0);
  EXPECT_EQ(input.system.particles[0].time, 0.0);
  EXPECT_EQ(input.line_of, (std::vector<std::size_t>{4, 5}));
}

TEST(ClassicInput, ReadsWhatRealFilesLookLike) {
  // CRLF, tabs, double spaces, -.38, +1, 1e-3, blank and comment lines, no final newline.
  const ClassicInput<2> input =
      read("# made by hand\r\n2\r\n\r\n1\r\n15.1\t 13.2\r\n5  6 -0.09 -.38\r\n3 2 +1 1e-3");
  ASSERT_EQ(input.system.particles.size(), 2u);
  EXPECT_EQ(input.system.box.size, (Vec2{{15.1, 13.2}}));
  EXPECT_EQ(input.system.particles[0].velocity, (Vec2{{-0.09, -0.38}}));
  EXPECT_EQ(input.system.particles[1].velocity, (Vec2{{1, 1e-3}}));
  EXPECT_EQ(input.line_of, (std::vector<std::size_t>{6, 7}));
}

TEST(ClassicInput, ParticlesMayCarryTheirOwnRadiusAndMass) {
  const ClassicInput<2> input = read("3\n1\n20 20\n5 5 0 0\n10 10 0 0 2\n15 15 0 0 0.5 3\n");
  const auto& p = input.system.particles;
  EXPECT_EQ(p[0].radius, 1.0);
  EXPECT_EQ(input.system.records[0].mass, 1.0);
  EXPECT_EQ(p[1].radius, 2.0);
  EXPECT_EQ(input.system.records[1].mass, 1.0);
  EXPECT_EQ(p[2].radius, 0.5);
  EXPECT_EQ(input.system.records[2].mass, 3.0);
  // Overlap and wall checks use each disk's own radius.
  EXPECT_EQ(error_of("2\n1\n20 20\n5 5 0 0\n8.5 5 0 0 2.6\n"),
            "test.txt:5: particle 1 at (8.5, 5) overlaps particle 0 at (5, 5) on line 4: their "
            "centres are 3.5 apart, less than the sum of their radii, 3.6");
  EXPECT_EQ(error_of("1\n1\n20 20\n1.5 5 0 0 2\n"),
            "test.txt:4: particle 0 at (1.5, 5) with radius 2 overlaps the left wall (its centre "
            "must be at least R from every wall)" +
                kPeriodicHint);
}

TEST(ClassicInput, PeriodicBoxesIgnoreWallsAndMeasureThroughImages) {
  std::istringstream near_edge("1\n1\n10 10\n0.5 5 1 0\n");
  EXPECT_NO_THROW(read_classic<2>(near_edge, "test.txt", Boundary::periodic));
  std::istringstream across("2\n1\n10 10\n0.5 5 0 0\n9 5 0 0\n");
  try {
    read_classic<2>(across, "test.txt", Boundary::periodic);
    ADD_FAILURE() << "overlap through the boundary not found";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "test.txt:5: particle 1 at (9, 5) overlaps particle 0 at (0.5, 5) on line 4: their "
              "centres are 1.5 apart, less than 2R = 2");
  }
  std::istringstream small("1\n1\n3.9 10\n2 5 0 0\n");
  EXPECT_THROW(read_classic<2>(small, "test.txt", Boundary::periodic), InputError);
}

TEST(ClassicInput, AcceptsAByteOrderMarkAndAPlusSignedCount) {
  const ClassicInput<2> input = read("\xEF\xBB\xBF+1\n1\n10 10\n5 5 1 0\n");
  EXPECT_EQ(input.system.particles.size(), 1u);
}

TEST(ClassicInput, RefusesMagnitudesWhoseSquaresOverflow) {
  // Regression: velocities of 1e160 overflowed in the contact time and disks passed through each
  // other silently.
  EXPECT_EQ(error_of("2\n1\n10 10\n3 5 1e160 0\n7 5 -1e160 0\n"),
            "test.txt:4: '1e160' is out of range: carom takes magnitudes from 1e-100 to 1e+100 (in "
            "x y vx vy [r [m]] of particle 0)");
  EXPECT_EQ(error_of("1\n1e-200\n10 10\n"),
            "test.txt:2: '1e-200' is out of range: carom takes magnitudes from 1e-100 to 1e+100 "
            "(in the radius R)");
  EXPECT_EQ(error_of("1\n1e-400\n10 10\n"),
            "test.txt:2: '1e-400' is out of range: carom takes magnitudes from 1e-100 to 1e+100 "
            "(in the radius R)");
  EXPECT_NO_THROW(read("1\n1\n10 10\n5 5 0 1e-90\n"));
}

TEST(ClassicInput, RefusesBoxesTooLargeToResolveAContact) {
  // Regression: a disk of radius 1 in a box of 3e38 (positions resolved to about 7e22) ran to an
  // all-NaN state with exit 0, and its checkpoint was refused on resume.
  EXPECT_EQ(error_of("2\n1\n3e38 3e38\n1e38 5 2e38 0 1 1e6\n2e38 5 0 0 1 1\n"),
            "test.txt:4: particle 0 with radius 1 is too small for a box of side 3e+38: a double "
            "places it to about 6.66e+22 there, and its contacts need 1e-06 of a diameter (the box "
            "may be at most 4.5e+09 diameters across)");
  // A dilute gas far from that bound is a start like any other.
  EXPECT_NO_THROW(read("1\n1\n1e9 1e9\n5e8 5e8 0 0\n"));
}

TEST(ClassicInput, TouchingIsAllowed) {
  // Touching each other and the walls, as the classic assignment's second case starts.
  EXPECT_NO_THROW(read("3\n1\n10 10\n1 1 0 0\n3 1 0 0\n9 9 0 0\n"));
  // Touching in decimal, overlapping by an ulp in binary.
  EXPECT_NO_THROW(read("2\n0.1\n1 1\n0.3 0.5 0 0\n0.1 0.5 0 0\n"));
}

TEST(ClassicInput, ErrorsNameTheFileAndLine) {
  EXPECT_EQ(error_of(""), "test.txt: the file is empty (expected N on line 1)");
  EXPECT_EQ(error_of("2 3\n"), "test.txt:1: expected 1 number (the particle count N), found 2");
  EXPECT_EQ(error_of("particle id: (xpos, ypos) (xvel, yvel): last_update : (cwall, cpart)\n"
                     "particle 0: (1.000000, 1.000000) (0.000000, 0.000000): 0.000000 : (0, 0)\n"),
            "test.txt:1: this is a run's result table (`carom run -o`), not a start; write the state "
            "a run ends in with `--final FILE` and start from that");
  EXPECT_EQ(error_of("1e3\n"),
            "test.txt:1: the particle count N must be a whole number, found '1e3'");
  EXPECT_EQ(error_of("99999999999\n1\n1 1\n"),
            "test.txt:1: the particle count N = 99999999999 is more than carom supports "
            "(2147483632)");
  EXPECT_EQ(error_of("1\n"), "test.txt:1: the file ends where the radius R was expected");
  EXPECT_EQ(error_of("1\n1\n10 10\n5 5 1 abc\n"),
            "test.txt:4: 'abc' is not a number (in x y vx vy [r [m]] of particle 0)");
  EXPECT_EQ(error_of("1\n1\n10 10\n5 5 1 --1\n"),
            "test.txt:4: '--1' is not a number (in x y vx vy [r [m]] of particle 0)");
  EXPECT_EQ(error_of("1\n1\n10 10\n5 5 1 +-1\n"),
            "test.txt:4: '+-1' is not a number (in x y vx vy [r [m]] of particle 0)");
  EXPECT_EQ(error_of("1\n1\n10 10\n5 5 1 0x10\n"),
            "test.txt:4: '0x10' is not a number (in x y vx vy [r [m]] of particle 0)");
  EXPECT_EQ(error_of("1\n1\n10 10\n5 5 1 1,\n"),
            "test.txt:4: '1,' is not a number (in x y vx vy [r [m]] of particle 0)");
  EXPECT_EQ(error_of("1\n-0\n1 1\n"), "test.txt:2: the radius R must be greater than 0, found -0");
  EXPECT_EQ(error_of("2\n1\n10 10\n5 5 0 0\n\n# c\n6 5 0 0\n"),
            "test.txt:7: particle 1 at (6, 5) overlaps particle 0 at (5, 5) on line 4: their "
            "centres are 1 apart, less than 2R = 2");
  EXPECT_EQ(error_of("1\n1\n10 10\n9.5 5 0 0\n"),
            "test.txt:4: particle 0 at (9.5, 5) with radius 1 overlaps the right wall (its "
            "centre must be at least R from every wall)" +
                kPeriodicHint);
  EXPECT_EQ(error_of("1\n1\n10 10\n5 -5 0 0\n"),
            "test.txt:4: particle 0 at (5, -5) is outside the box [0, 10] x [0, 10]");
}

TEST(ClassicInput, AHeaderPromisingMoreThanTheFileHoldsIsCaughtAtTheEnd) {
  EXPECT_EQ(error_of("100000000\n1\n10 10\n5 5 0 0\n"),
            "test.txt:4: the file ends where x y vx vy [r [m]] of particle 1 was expected");
}

TEST(ClassicInput, GarbageIsRefusedAtTheFirstLongLine) {
  EXPECT_EQ(error_of(std::string(10000, 'x')),
            "test.txt:1: line longer than 4095 characters: this is not a classic input file");
  EXPECT_EQ(error_of(std::string("1\n1\0\n", 5)),
            "test.txt:2: contains a NUL byte: this is not a text file");
}

TEST(ParseFiniteDouble, AcceptsWhatStrtodAcceptsButOnlyFiniteWholeTokens) {
  EXPECT_EQ(parse_finite_double("-.5"), -0.5);
  EXPECT_EQ(parse_finite_double("+2"), 2.0);
  EXPECT_EQ(parse_finite_double("1E-3"), 1e-3);
  EXPECT_EQ(parse_finite_double("1e100"), 1e100);
  EXPECT_EQ(parse_finite_double("0"), 0.0);
  EXPECT_THROW(parse_finite_double("1e308"), std::invalid_argument);
  EXPECT_THROW(parse_finite_double(""), std::invalid_argument);
  EXPECT_THROW(parse_finite_double("+"), std::invalid_argument);
  EXPECT_THROW(parse_finite_double("1e309"), std::invalid_argument);
  EXPECT_THROW(parse_finite_double("NaN"), std::invalid_argument);
  EXPECT_THROW(parse_finite_double("-infinity"), std::invalid_argument);
  EXPECT_THROW(parse_finite_double("2x"), std::invalid_argument);
}

}  // namespace
}  // namespace carom

namespace carom {
namespace {

TEST(ClassicInput, ThreeBoxSidesMakeSpheres) {
  std::istringstream in("2\n0.5\n5 6 7\n1 1 1 0.3 0.2 0.1\n3 3 3 -0.2 0.1 0.4 0.25 2\n");
  const AnyClassicInput any = read_any_classic(in, "spheres.txt");
  ASSERT_TRUE(std::holds_alternative<ClassicInput<3>>(any));
  const auto& input = std::get<ClassicInput<3>>(any);
  EXPECT_EQ(input.system.box.size, (Vec<3>{{5, 6, 7}}));
  EXPECT_EQ(input.system.particles[1].position, (Vec<3>{{3, 3, 3}}));
  EXPECT_EQ(input.system.particles[1].velocity, (Vec<3>{{-0.2, 0.1, 0.4}}));
  EXPECT_EQ(input.system.particles[1].radius, 0.25);
  EXPECT_EQ(input.system.records[1].mass, 2.0);
  EXPECT_EQ(input.line_of, (std::vector<std::size_t>{4, 5}));
  // Two sides still make disks.
  std::istringstream disks("1\n0.5\n5 6\n1 1 0.3 0.2\n");
  EXPECT_TRUE(std::holds_alternative<ClassicInput<2>>(read_any_classic(disks, "disks.txt")));
}

TEST(ClassicInput, SpheresAreCheckedAsDisksAre) {
  const auto error = [](const std::string& text) -> std::string {
    std::istringstream in(text);
    try {
      read_any_classic(in, "s.txt");
    } catch (const InputError& e) {
      return e.what();
    }
    return "(no error)";
  };
  EXPECT_EQ(error("1\n0.5\n5 6 7\n1 1 1 0.3 0.2\n"),
            "s.txt:4: expected 6 to 8 numbers (x y z vx vy vz [r [m]] of particle 0), found 5");
  EXPECT_EQ(error("1\n0.5\n5 6 7\n1 1 0.2 0 0 0\n"),
            "s.txt:4: particle 0 at (1, 1, 0.2) with radius 0.5 overlaps the back wall (its "
            "centre must be at least R from every wall)" +
                kPeriodicHint);
  EXPECT_EQ(error("1\n0.5\n5 6 7\n1 1 6.8 0 0 0\n"),
            "s.txt:4: particle 0 at (1, 1, 6.8) with radius 0.5 overlaps the front wall (its "
            "centre must be at least R from every wall)" +
                kPeriodicHint);
  EXPECT_EQ(error("1\n0.5\n5 6 7\n1 1 8 0 0 0\n"),
            "s.txt:4: particle 0 at (1, 1, 8) is outside the box [0, 5] x [0, 6] x [0, 7]");
  EXPECT_EQ(error("2\n0.5\n5 6 7\n1 1 1 0 0 0\n1 1 1.5 0 0 0\n"),
            "s.txt:5: particle 1 at (1, 1, 1.5) overlaps particle 0 at (1, 1, 1) on line 4: "
            "their centres are 0.5 apart, less than 2R = 1");
  EXPECT_EQ(error("1\n0.5\n5 6 0\n1 1 1 0 0 0\n"),
            "s.txt:3: the box size must be positive, found 5 x 6 x 0");
  EXPECT_EQ(error("1\n0.5\n5 6 7 8\n"),
            "s.txt:3: expected 2 or 3 numbers (the box size: Lx Ly for disks, Lx Ly Lz for "
            "spheres), found 4");
  // A program that reads disks only says what it found.
  std::istringstream spheres("1\n0.5\n5 6 7\n1 1 1 0 0 0\n");
  try {
    read_classic<2>(spheres, "s.txt");
    ADD_FAILURE() << "read spheres as disks";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "s.txt: holds spheres (its line 3 has 3 box sides); disks were expected");
  }
}

}  // namespace
}  // namespace carom

namespace carom {
namespace {

TEST(StartRecord, AHeaderLineRecordsTheBoundaryAndTheRule) {
  const std::string data = "1\n0.5\n10 10\n0.2 5 1 0\n";  // touches the left wall's place
  std::istringstream plain(data);
  std::istringstream inside("1\n0.5\n10 10\n5 5 1 0\n");
  const ClassicInput<2> walls_file = read_classic<2>(inside, "a");
  EXPECT_FALSE(walls_file.record.boundary);
  EXPECT_FALSE(walls_file.record.rule);
  EXPECT_EQ(walls_file.system.box.boundary, Boundary::walls);
  // A plain file overlapping a wall is refused, with the hint; recorded as periodic it is read so.
  EXPECT_THROW(read_classic<2>(plain, "p"), InputError);
  std::istringstream recorded("# carom: boundary=periodic rule=elastic\n" + data);
  const ClassicInput<2> periodic = read_classic<2>(recorded, "r");
  EXPECT_EQ(periodic.system.box.boundary, Boundary::periodic);
  EXPECT_EQ(periodic.record.boundary, Boundary::periodic);
  EXPECT_EQ(periodic.record.rule, Rule::elastic);
  // An explicit boundary wins over the record.
  std::istringstream asked("# carom: boundary=walls\n" + data);
  EXPECT_EQ(read_classic<2>(asked, "w", Boundary::periodic).system.box.boundary,
            Boundary::periodic);
  // Other comments, before or after, are comments; the line is what carom writes.
  std::istringstream commented("# made by hand\n# carom: rule=swap\n# more\n" + data);
  EXPECT_EQ(read_classic<2>(commented, "c", Boundary::periodic).record.rule, Rule::swap);
  EXPECT_EQ(start_record_line(Boundary::periodic, Rule::elastic),
            "# carom: boundary=periodic rule=elastic");
}

TEST(StartRecord, ABadRecordIsRefusedWithItsLine) {
  const auto error = [](const std::string& text) -> std::string {
    std::istringstream in(text);
    try {
      read_classic<2>(in, "f.txt");
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  const std::string data = "1\n0.5\n10 10\n5 5 1 0\n";
  EXPECT_EQ(error("# carom: boundary=round\n" + data),
            "f.txt:1: 'round' is not a boundary: walls or periodic are");
  EXPECT_EQ(error("\n# carom: rule=sticky\n" + data),
            "f.txt:2: 'sticky' is not a rule: swap or elastic are");
  EXPECT_EQ(error("# carom: colour=red\n" + data),
            "f.txt:1: 'colour=red' is not a setting carom records (boundary=..., rule=..., "
            "types=...)");
  EXPECT_EQ(error("# carom: rule=swap rule=elastic\n" + data), "f.txt:1: rule is given twice");
  EXPECT_EQ(error("# carom: rule=swap\n# carom: boundary=walls\n" + data),
            "f.txt:2: a second '# carom:' line (the first is line 1)");
  EXPECT_EQ(error("1\n# carom: rule=swap\n0.5\n10 10\n5 5 1 0\n"),
            "f.txt:2: a '# carom:' line must come before the data");
}

TEST(StartRecord, TheDefaultRuleIsTheClassicAssignmentsOnlyInItsOwnBox) {
  EXPECT_EQ(default_rule({}, Boundary::walls), Rule::swap);
  EXPECT_EQ(default_rule({}, Boundary::periodic), Rule::elastic);
  EXPECT_EQ(default_rule({}, Boundary::walls, 0.9), Rule::elastic);
  EXPECT_EQ(default_rule({Boundary::walls, Rule::elastic, {}}, Boundary::walls), Rule::elastic);
  EXPECT_EQ(default_rule({std::nullopt, Rule::swap, {}}, Boundary::periodic), Rule::swap);
}

}  // namespace
}  // namespace carom

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <span>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "carom/engine/initial.hpp"
#include "carom/io/classic_input.hpp"
#include "carom/io/classic_output.hpp"
#include "carom/io/event_log.hpp"
#include "carom/io/trajectory.hpp"
#include "carom/io/trajectory_kind.hpp"
#include "carom/run/run_report.hpp"
#include "test_systems.hpp"

namespace carom {
namespace {

Particle<2> sample() {
  Particle<2> p;
  p.position = {8.3001204, 11.4604334};
  p.velocity = {0.3, -0.31};
  p.time = 18;
  return p;
}

ParticleRecord sample_record() {
  ParticleRecord r;
  r.wall_collisions = 2;
  r.pair_collisions = 7;
  return r;
}

TEST(Formats, ParticleLineIsTheSeedsPrintf) {
  EXPECT_EQ(particle_line(1, sample(), sample_record()),
            "particle 1: (8.300120, 11.460433) (0.300000, -0.310000): 18.000000 : (2, 7)");
}

TEST(Formats, TableHasTheHeaderThenOneLineADisk) {
  std::ostringstream out;
  System<2> system;
  system.epoch = 8.0;  // stored times count from it: 8 + 10 is printed
  Particle<2> stored = sample();
  stored.time -= system.epoch;
  system.particles = {stored, stored};
  system.records = {sample_record(), sample_record()};
  write_table(out, system);
  EXPECT_EQ(out.str(),
            "particle id: (xpos, ypos) (xvel, yvel): last_update : (cwall, cpart)\n"
            "particle 0: (8.300120, 11.460433) (0.300000, -0.310000): 18.000000 : (2, 7)\n"
            "particle 1: (8.300120, 11.460433) (0.300000, -0.310000): 18.000000 : (2, 7)\n");
}

TEST(Formats, CsvIsPositionsAndCounts) {
  std::ostringstream out;
  const std::vector<Particle<2>> particles{sample()};
  const std::vector<ParticleRecord> records{sample_record()};
  write_csv<2>(out, particles, records);
  EXPECT_EQ(out.str(), "8.300120, 11.460433, 2, 7\n");
}

TEST(Formats, RoundingIsPrintfs) {
  Particle<2> p;
  p.position = {0.0078125, -1e-9};  // an exact tie rounds to even; a tiny negative keeps its sign
  std::ostringstream out;
  const ParticleRecord r;
  write_csv<2>(out, std::span(&p, 1), std::span(&r, 1));
  EXPECT_EQ(out.str(), "0.007812, -0.000000, 0, 0\n");
}

TEST(Formats, EventsAreDescribedByLabel) {
  EXPECT_EQ(describe(Event{1.0, 3, -2}), "Collision: particle 3 with wall -2 (right)");
  EXPECT_EQ(describe(Event{1.0, 1, 2}), "Collision: particle 1 with particle 2");
}

TEST(Formats, ClassicFilesReadBackBitForBit) {
  InitialOptions o;
  o.n = 100;
  o.packing_fraction = 0.3;
  o.polydispersity = 0.1;
  o.boundary = Boundary::walls;  // a plain classic file is read with walls
  const System<2> system = make_initial<2>(o);
  std::stringstream file;
  write_classic(file, system, 0.5);
  const ClassicInput<2> back = read_classic<2>(file, "round-trip");
  ASSERT_EQ(back.system.particles.size(), 100u);
  EXPECT_EQ(back.system.box.size, system.box.size);
  for (std::size_t i = 0; i < 100; ++i) {
    EXPECT_EQ(back.system.particles[i].position, system.particles[i].position);
    EXPECT_EQ(back.system.particles[i].velocity, system.particles[i].velocity);
    EXPECT_EQ(back.system.particles[i].radius, system.particles[i].radius);
  }
}

TEST(Formats, JsonCountsTheWholeRunAndTheWindowApart) {
  // One disk between two walls, 9 apart: wall collisions at t = 4.5, 13.5, 22.5.
  System<2> system;
  system.box.size = {10, 10};
  Particle<2> p = sample();
  p.position = {5.0, 5.0};
  p.velocity = {1.0, 0.0};
  p.radius = 0.5;
  p.time = 0.0;
  system.add(p);
  Simulation<2> simulation(system);
  simulation.run_until(10.0);
  simulation.measure_from(10.0);
  simulation.run_until(30.0);
  std::ostringstream out;
  RunReport report;
  report.input = "in.txt";
  report.wall_seconds = 2.0;
  report.events = 40;
  write_json(out, simulation, report, false);
  const auto json = nlohmann::json::parse(out.str());
  EXPECT_EQ(json["events"], 3);
  EXPECT_EQ(json["wall_collisions"], 3);
  EXPECT_EQ(json["window_events"], 2);
  EXPECT_EQ(json["window_wall_collisions"], 2);
  EXPECT_EQ(json["window_pair_collisions"], 0);
  EXPECT_EQ(json["equilibrate"], 10.0);
  EXPECT_EQ(json["wall_seconds"], 2.0);
  EXPECT_EQ(json["events_per_second"], 20.0);  // the report's events over its seconds
}

TEST(Formats, JsonIsValidAndKeepsEveryBit) {
  System<2> system;
  system.box.size = {10, 10};
  Particle<2> a = sample(), b = sample();
  a.position = {2.0 / 3.0, 1.0};
  a.velocity = {0.1, 0.7};
  a.radius = 0.25;
  b.position = {5.0, 5.0};
  b.velocity = {-1.0 / 7.0, 0.0};
  b.radius = 0.25;
  a.time = b.time = 0.0;
  system.add(a);
  system.add(b, 2.5);
  Simulation<2> simulation(system);
  simulation.run_until(12.5);
  std::ostringstream out;
  RunReport report;
  report.input = "in.txt";
  write_json(out, simulation, report);
  const auto json = nlohmann::json::parse(out.str());
  EXPECT_EQ(json["input"], "in.txt");
  EXPECT_EQ(json["end_time"], 12.5);
  EXPECT_EQ(json["n"], 2);
  EXPECT_EQ(json["dimension"], 2);
  EXPECT_GT(simulation.counts().events, 0u);
  EXPECT_EQ(json["events"], simulation.counts().events);
  EXPECT_EQ(json["wall_collisions"], simulation.counts().wall_collisions);
  EXPECT_EQ(json["pair_collisions"], simulation.counts().pair_collisions);
  ASSERT_EQ(json["particles"].size(), 2u);
  const std::vector<Particle<2>> now = simulation.snapshot();
  for (std::size_t i = 0; i < 2; ++i) {
    const Particle<2>& p = now[i];
    const ParticleRecord& r = simulation.state().records[i];
    const auto& q = json["particles"][i];
    EXPECT_EQ(q["mass"].get<double>(), r.mass);
    EXPECT_EQ(q["id"], i);
    EXPECT_EQ(q["x"].get<double>(), p.position[0]);
    EXPECT_EQ(q["y"].get<double>(), p.position[1]);
    EXPECT_EQ(q["vx"].get<double>(), p.velocity[0]);
    EXPECT_EQ(q["vy"].get<double>(), p.velocity[1]);
    EXPECT_EQ(q["last_update"].get<double>(), 12.5);
    EXPECT_EQ(q["wall_collisions"], r.wall_collisions);
  }
}

}  // namespace
}  // namespace carom

namespace carom {
namespace {

// One reading of a trajectory's name for a dump, an end state and a result table: the ending
// after a dot, in any case.
TEST(Formats, ATrajectoryIsToldByItsEndingInAnyCase) {
  EXPECT_EQ(trajectory_kind_of("movie.xyz"), TrajectoryKind::xyz);
  EXPECT_EQ(trajectory_kind_of("dir.gsd/MOVIE.XYZ"), TrajectoryKind::xyz);
  EXPECT_EQ(trajectory_kind_of("run.LammpsTrj"), TrajectoryKind::lammpstrj);
  EXPECT_EQ(trajectory_kind_of("a/b.Gsd"), TrajectoryKind::gsd);
  for (const std::string_view other : {"movie.txt", "movie.gsd.txt", "movie_xyz", "xyz", ""}) {
    EXPECT_EQ(trajectory_kind_of(other), std::nullopt) << other;
  }
  for (const TrajectoryKind kind :
       {TrajectoryKind::xyz, TrajectoryKind::lammpstrj, TrajectoryKind::gsd}) {
    EXPECT_EQ(trajectory_kind_of("m." + std::string(extension_of(kind))), kind);
  }
}

// What a resumed run keeps of the files an earlier piece wrote: the whole lines and frames from
// before its checkpoint, nothing from after it or cut short.
TEST(Formats, AResumedRunKeepsWhatCameBeforeItsCheckpoint) {
  const std::string log = "time,kind,first,partner\n1,wall,0,-1\n2,pair,0,1\n2.5,wall,1,-3\n3,pa";
  const auto kept = [&](double t, bool inclusive) {
    std::istringstream in(log);
    return log.substr(0, EventLogWriter<2>::events_before(in, t, inclusive));
  };
  EXPECT_EQ(kept(2.0, true), "time,kind,first,partner\n1,wall,0,-1\n2,pair,0,1\n");
  EXPECT_EQ(kept(2.0, false), "time,kind,first,partner\n1,wall,0,-1\n");
  EXPECT_EQ(kept(9.0, true), "time,kind,first,partner\n1,wall,0,-1\n2,pair,0,1\n2.5,wall,1,-3\n");

  System<2> system = testing::boxed({10, 10}, {testing::disk({5, 5}, {1, 0}, 1)});
  std::ostringstream written;
  auto xyz = trajectory_format_for<2>("m.xyz");
  std::vector<std::size_t> ends;  // where each frame ends
  for (std::uint64_t k = 0; k < 4; ++k) {
    xyz->frame(written, k, 0.5 * k, system);
    ends.push_back(written.str().size());
  }
  const std::string frames = written.str();
  const auto frames_kept = [&](const std::string& file, double t, bool inclusive) {
    std::istringstream in(file);
    return xyz->whole_frames_before(in, t, inclusive, 0.5);
  };
  EXPECT_EQ(frames_kept(frames, 1.0, true), ends[2]);  // t = 0, 0.5, 1
  EXPECT_EQ(frames_kept(frames, 1.0, false), ends[1]);
  EXPECT_EQ(frames_kept(frames.substr(0, frames.size() - 3), 9.0, true), ends[2]);  // cut
}

// Regression: a resumed run refused to continue a .gsd dump. A GSD file holding frames from
// beyond a checkpoint (a run killed after it) is taken up at any time: cut to the frames up to
// it and continued, it is byte for byte the file of a run never interrupted, at the cut and at
// the end, across the index's moves to larger blocks (first after 20 frames) and when the next
// frame was being written.
TEST(Formats, AGsdFileIsContinuedAfterItsLastWholeFrameByteForByte) {
  const System<2> system = testing::boxed(
      {10, 10}, {testing::disk({5, 5}, {1, 0.5}, 1), testing::disk({2, 8}, {-0.3, 2}, 0.5)},
      Boundary::periodic);
  constexpr std::uint64_t kFrames = 90;
  const auto time_of = [](std::uint64_t k) { return 0.25 * static_cast<double>(k); };
  std::ostringstream written(std::ios::binary);
  auto gsd = trajectory_format_for<2>("m.gsd");
  std::vector<std::string> after = {""};  // the file after each frame
  for (std::uint64_t k = 0; k < kFrames; ++k) {
    gsd->frame(written, k, time_of(k), system);
    after.push_back(written.str());
  }
  const std::string whole = written.str();
  // Cut back to `t` and continued to the end by another writer, as a resumed run does.
  const auto continued = [&](const std::string& file, double t, bool inclusive,
                             std::uint64_t frames_kept) {
    auto resumed = trajectory_format_for<2>("m.gsd");
    std::istringstream in(file, std::ios::binary);
    const std::uint64_t kept = resumed->whole_frames_before(in, t, inclusive, 0.25);
    std::stringstream io(file.substr(0, kept), std::ios::in | std::ios::out | std::ios::binary);
    io.seekp(0, std::ios::end);
    resumed->continue_after_cut(io);
    EXPECT_TRUE(io.str() == after[frames_kept]) << "cut at t = " << t << ", " << inclusive;
    for (std::uint64_t k = frames_kept; k < kFrames; ++k) resumed->frame(io, k, time_of(k), system);
    return io.str();
  };
  for (std::uint64_t cut = 0; cut < kFrames; ++cut) {
    const double t = time_of(cut);
    EXPECT_TRUE(continued(whole, t, true, cut + 1) == whole) << cut;
    EXPECT_TRUE(continued(whole, t, false, cut) == whole) << cut;
    EXPECT_TRUE(continued(whole, t + 0.1, false, cut + 1) == whole) << cut;
    // A run killed as it wrote the next frame: part of its chunks, not yet indexed.
    EXPECT_TRUE(continued(after[cut + 1] + std::string(7, '\x01'), 1e9, true, cut + 1) == whole)
        << cut;
  }
  EXPECT_TRUE(continued("", 5.0, true, 0) == whole);
  EXPECT_TRUE(continued(whole.substr(0, 100), 5.0, true, 0) == whole);  // killed as it began
}

TEST(Formats, AGsdFileOfAnotherProgramIsNotContinued) {
  const System<2> system =
      testing::boxed({10, 10}, {testing::disk({5, 5}, {1, 0.5}, 1)}, Boundary::periodic);
  std::ostringstream written(std::ios::binary);
  trajectory_format_for<2>("m.gsd")->frame(written, 0, 0.0, system);
  const auto refused = [](std::string file) {
    std::istringstream in(file, std::ios::binary);
    try {
      trajectory_format_for<2>("m.gsd")->whole_frames_before(in, 1.0, true, 0.25);
      ADD_FAILURE() << "continued";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("not a GSD trajectory carom wrote"), std::string::npos)
          << e.what();
    }
  };
  std::string other_names = written.str();
  other_names[256] = 'C';  // "Configuration/box"
  refused(other_names);
  refused(std::string(written.str().size(), 'x'));
}

// Regression: a .gsd dump of numbers beyond single precision (a box of 1e50) was written with
// inf in it, which every reader refused. Every float of a frame (box, positions, velocities,
// diameters, masses) is checked before anything is written, and named when refused.
TEST(Formats, GsdFramesBeyondSinglePrecisionAreRefusedBeforeAnythingIsWritten) {
  const auto refused = [](const System<2>& system, const std::string& named) {
    auto gsd = trajectory_format_for<2>("m.gsd");
    std::ostringstream out(std::ios::binary);
    try {
      gsd->check_frame(system, 0.0);
      ADD_FAILURE() << "accepted; expected a refusal naming " << named;
    } catch (const std::range_error& e) {
      EXPECT_NE(std::string(e.what()).find(named), std::string::npos) << e.what();
    }
    EXPECT_THROW(gsd->frame(out, 0, 0.0, system), std::range_error);
    EXPECT_EQ(out.str(), "");
  };
  using testing::boxed;
  using testing::disk;
  refused(boxed({1e50, 10}, {disk({5, 5}, {1, 0}, 1)}), "the box side Lx is 1e+50");
  refused(boxed({10, 10}, {disk({5, 5}, {1, 0}, 1), disk({2, 2}, {0, -1e39}, 1)}),
          "vy of particle 1 at t = 0 is -1e+39");
  refused(boxed({10, 10}, {disk({5, 5}, {1, 0}, 1e-50)}), "the diameter of particle 0 is 2e-50");
  System<2> light = boxed({10, 10}, {disk({5, 5}, {1, 0}, 1)});
  light.records[0].mass = 1e-60;
  refused(light, "the mass of particle 0 is 1e-60");
  refused(boxed({10, 10}, {disk({5, 5}, {std::nan(""), 0}, 1)}),
          "particle 0 (from the box's centre) at t = 0 is not a number");
  // What single precision rounds but reads back is written: a tiny speed stored as 0.
  std::ostringstream out(std::ios::binary);
  trajectory_format_for<2>("m.gsd")->frame(out, 0, 0.0,
                                           boxed({10, 10}, {disk({5, 5}, {1e-50, 0}, 1)}));
  EXPECT_GT(out.str().size(), 0u);
}

}  // namespace
}  // namespace carom

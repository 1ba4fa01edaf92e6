// Checkpoints are validated when read: whatever a run can have reached is resumed, anything else
// (an edit, a bit flip, a truncation) is refused with a message naming the file and the fault,
// before a run could make a physically impossible result of it.
#include "carom/io/checkpoint.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "carom/engine/invariant_check.hpp"
#include "carom/io/classic_input.hpp"
#include "io/json_text.hpp"
#include "test_systems.hpp"

namespace carom {
namespace {

using Json = nlohmann::ordered_json;
using carom::testing::random_gas;

template <std::size_t D>
std::string written(const Checkpoint<D>& checkpoint) {
  std::ostringstream out;
  write_checkpoint(out, checkpoint);
  return out.str();
}

// A walls run of 20 disks, checkpointed at t = 5 (particles stored at many different times).
std::string saved(Boundary boundary = Boundary::walls) {
  pcg32 rng(16);
  System<2> gas = random_gas(rng, 20, 0.3, 0.5, 10, 8);
  gas.box.boundary = boundary;
  Simulation<2> simulation(gas, {{Rule::elastic}});
  simulation.measure_from(1.0);
  simulation.run_until(5.0);
  return written(simulation.checkpoint("gas.txt"));
}

AnyCheckpoint read(const std::string& text) {
  std::istringstream in(text);
  return read_checkpoint(in, "ck");
}

// The checkpoint edited by `edit` and written again without its checksum, as someone editing it
// by hand (or a tool) would: what the validation alone must catch.
std::string tampered(const std::string& text, const std::function<void(Json&)>& edit) {
  Json j = Json::parse(text);
  j.erase("checksum");
  edit(j);
  return j.dump(1);
}

void expect_refused(const std::string& text, const std::string& message) {
  try {
    read(text);
    ADD_FAILURE() << "accepted; expected a refusal with \"" << message << "\"";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "ck");
    EXPECT_NE(std::string(e.what()).find(message), std::string::npos)
        << "expected \"" << message << "\" in: " << e.what();
  }
}

TEST(Checkpoint, WhatRunsWriteIsReadBackWithAndWithoutItsChecksum) {
  // Walls and periodic boxes, swap, elastic and inelastic rules, settled or stopped between the
  // events of one instant, 2D and 3D: every checkpoint a run writes passes the validation.
  pcg32 rng(1616);
  int read_back = 0;
  for (int trial = 0; trial < 16; ++trial) {
    System<2> gas = random_gas(rng, 40, 0.2, 0.5, 10, 8);
    if (trial % 2 == 1) gas.box.boundary = Boundary::periodic;
    const Settings settings = trial % 4 == 0   ? Settings{}
                              : trial % 4 == 1 ? Settings{{Rule::elastic}}
                                               : Settings{{Rule::elastic, 0.5, 0.2}};
    Simulation<2> simulation(gas, settings);
    simulation.measure_from(3.0);
    for (int piece = 0; piece < 6; ++piece) {
      simulation.run_until(2.0 * piece + 1.0, 1 + rng() % 200);
      const std::string text = written(simulation.checkpoint("gas.txt"));
      ASSERT_NE(text.find("\"checksum\": \"fnv1a64:"), std::string::npos);
      EXPECT_NO_THROW(read(text)) << "trial " << trial << " piece " << piece;
      EXPECT_NO_THROW(read(tampered(text, [](Json&) {}))) << "trial " << trial;
      ++read_back;
    }
  }
  EXPECT_EQ(read_back, 96);
  // Spheres.
  System<3> spheres;
  spheres.box = {{{5, 6, 7}}, Boundary::walls};
  for (int k = 0; k < 8; ++k) {
    Particle<3> p;
    p.radius = 0.4;
    p.position = {{1.0 + (k % 2) * 2.5, 1.0 + (k / 2 % 2) * 3.0, 1.0 + (k / 4) * 4.0}};
    p.velocity = {{0.3 * k - 1.0, 0.5, -0.2 * k}};
    spheres.add(p);
  }
  Simulation<3> simulation(spheres, {{Rule::elastic}});
  simulation.run_until(20.0);
  ASSERT_GT(simulation.counts().events, 10u);
  EXPECT_TRUE(std::holds_alternative<Checkpoint<3>>(read(written(simulation.checkpoint("s")))));
}

// A number a run overflowed is never written (JSON would make it null, a checkpoint no reader
// takes back): saving says which one. (Regression: --shear 1e80 --velocity-profile saved null
// kinetic stresses that --resume refused.)
TEST(Checkpoint, ANumberThatOverflowedIsNeverWritten) {
  pcg32 rng(16);
  Simulation<2> simulation(random_gas(rng, 20, 0.3, 0.5, 10, 8), {{Rule::elastic}});
  simulation.run_until(1.0);
  Checkpoint<2> checkpoint = simulation.checkpoint("gas.txt");
  ASSERT_TRUE(checkpoint.counts.fluxes);
  checkpoint.counts.fluxes->kinetic_stress[0] = std::numeric_limits<double>::quiet_NaN();
  try {
    written(checkpoint);
    ADD_FAILURE() << "a NaN was written";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("counts/fluxes/kinetic_stress/0 is not a finite number"),
              std::string::npos)
        << e.what();
  }
}

// Regression: a source whose name is not UTF-8 made write_checkpoint throw (nlohmann's
// "invalid UTF-8 byte"), after the run: nothing was saved. It is written as \udcXX escapes and
// read back as the same bytes, under the same checksum.
TEST(Checkpoint, ASourceNameThatIsNotUtf8IsReadBackAsTheSameBytes) {
  pcg32 rng(16);
  Simulation<2> simulation(random_gas(rng, 20, 0.3, 0.5, 10, 8), {{Rule::elastic}});
  simulation.run_until(2.0);
  const std::string name = "dossier\xe9/caf\xe9\xff.txt";
  const std::string text = written(simulation.checkpoint(name));
  EXPECT_NE(text.find(R"("source": "dossier\udce9/caf\udce9\udcff.txt")"), std::string::npos);
  const AnyCheckpoint back = read(text);
  EXPECT_EQ(std::get<Checkpoint<2>>(back).source, name);
  // Such a name where a number belongs is refused as any other string there (not an exception
  // of the json library's while checking the checksum).
  std::string edited = text;
  const std::size_t first_row =
      edited.find("[", edited.find("[", edited.find("\"particles\"")) + 1);
  edited.replace(first_row + 1, 0, "\"x\\udce9\", ");
  expect_refused(edited, "its checksum does not match");
  const std::size_t checksum = edited.find(",\n \"checksum\"");
  edited.erase(checksum, edited.find('\n', checksum + 2) - checksum);  // to the line's end
  expect_refused(edited, "found [\"x\\udce9\"");
}

// dump_json and parse_json: bytes that are not UTF-8 round-trip, and nothing else changes.
TEST(JsonText, BytesThatAreNotUtf8RoundTripAndValidTextIsUntouched) {
  // Each string, and whether it is UTF-8.
  const std::vector<std::pair<std::string, bool>> strings = {
      {"plain", true},
      {"caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x8e\xb1", true},  // café € and an emoji
      {R"(a backslash \udce9 as text)", true},
      {"\xc6\x80 U+0180, the marks' own range", true},
      {std::string("nul \0 alone", 11), true},
      {"caf\xe9", false},  // Latin-1
      {std::string("nul \0 then \xe9", 13), false},
      {"\xed\xa0\x80", false},  // an encoded surrogate
      {"\xc0\xaf overlong, \xf5 beyond, \xe2\x82 cut", false}};
  for (const auto& [s, utf8] : strings) {
    const nlohmann::json value = {{"name", s}, {s, {s, 1.5}}};
    const std::string text = dump_json(value, 1);
    EXPECT_EQ(parse_json(text), value) << text;
    if (utf8) {
      EXPECT_EQ(text, value.dump(1));  // written as nlohmann writes it
    } else {
      EXPECT_NE(text.find("\\udc"), std::string::npos) << text;
    }
  }
  EXPECT_EQ(dump_json(nlohmann::json("caf\xe9")), R"("caf\udce9")");
  // What Python's json.dumps writes for os.fsdecode(b"caf\xe9") reads as the bytes; a surrogate
  // pair stays the character it encodes.
  EXPECT_EQ(parse_json(R"("caf\udce9")").get<std::string>(), "caf\xe9");
  EXPECT_EQ(parse_json(R"("\ud83c\udfb1")").get<std::string>(), "\xf0\x9f\x8e\xb1");
  EXPECT_THROW(parse_json(R"("\udc41")"), nlohmann::json::parse_error);  // not a byte's escape
}

TEST(Checkpoint, TheChecksumCoversTheValuesNotTheLayout) {
  const std::string text = saved();
  // Reindented by a tool, keys reordered: still the same checkpoint.
  const nlohmann::json sorted = nlohmann::json::parse(text);
  EXPECT_NO_THROW(read(sorted.dump(4)));
  // One bit flipped in a digit of the first particle's position ('3' <-> '2', say): refused,
  // though the result is a plausible state.
  std::string flipped = text;
  const std::size_t row = flipped.find("\"particles\": [\n  [");
  ASSERT_NE(row, std::string::npos);
  std::size_t digit = flipped.find_first_of("123456789", row + 22);
  digit = flipped.find_first_of("123456789", digit + 3);  // a digit well inside the number
  flipped[digit] = static_cast<char>(flipped[digit] ^ 1);
  expect_refused(flipped, "checksum does not match");
  // An unknown kind of checksum is not silently ignored.
  expect_refused(tampered(text, [](Json& j) { j["checksum"] = "crc32:0"; }), "checksum");
}

TEST(Checkpoint, ParticlesAreCheckedAsTheInputReaderChecksThem) {
  const std::string text = saved();
  // Particle 1 moved onto particle 0 (state, velocity and time).
  expect_refused(tampered(text,
                          [](Json& j) {
                            for (int k = 0; k < 5; ++k) j["particles"][1][k] = j["particles"][0][k];
                          }),
                 "overlaps particle 0");
  // Far outside the box.
  expect_refused(tampered(text,
                          [](Json& j) {
                            j["particles"][2][0] = 50.0;
                            j["particles"][2][1] = 5.0;
                          }),
                 "particle 2 at (50, 5) is outside the box [0, 10] x [0, 8]");
  // Inside when stored, but through the right wall by the checkpoint's time.
  expect_refused(tampered(text,
                          [](Json& j) {
                            j["particles"][3][0] = 5.0;
                            j["particles"][3][1] = 4.0;
                            j["particles"][3][2] = 1e3;
                            j["particles"][3][4] = 4.5;
                          }),
                 "at the checkpoint's time t = 5, particle 3");
  // Reaching through a wall where it is stored.
  expect_refused(tampered(text, [](Json& j) { j["particles"][4][0] = 0.01; }),
                 "overlaps the left wall");
  expect_refused(tampered(text, [](Json& j) { j["particles"][4][5] = -0.5; }),
                 "the radius of particle 4 must be greater than 0");
  expect_refused(tampered(text, [](Json& j) { j["particles"][4][6] = 0.0; }),
                 "the mass of particle 4 must be greater than 0");
  expect_refused(tampered(text, [](Json& j) { j["particles"][4][2] = 1e200; }),
                 "the velocity of particle 4 is out of range");
  expect_refused(tampered(text, [](Json& j) { j["particles"][4][2] = "fast"; }),
                 "the velocity of particle 4 must be a number");
  expect_refused(tampered(text, [](Json& j) { j["particles"][4].erase(9); }),
                 "the row of particle 4 does not hold 12 values");
  expect_refused(tampered(text, [](Json& j) { j["particles"] = Json::array(); }), "no particles");
  expect_refused(tampered(text, [](Json& j) { j["box"][0] = -10.0; }),
                 "a box side must be greater than 0");
  // A disk too large for its periodic box.
  expect_refused(tampered(saved(Boundary::periodic), [](Json& j) { j["particles"][0][5] = 2.5; }),
                 "too large for the periodic box");
}

TEST(Checkpoint, TheSettingsAreCheckedAsANewRunsAre) {
  const std::string text = saved();
  expect_refused(tampered(text, [](Json& j) { j["restitution"] = -0.5; }),
                 "the restitution must be in (0, 1], got -0.5");
  expect_refused(tampered(text, [](Json& j) { j["restitution"] = 1.5; }),
                 "the restitution must be in (0, 1], got 1.5");
  expect_refused(tampered(text,
                          [](Json& j) {
                            j["rule"] = "swap";
                            j["restitution"] = 0.5;
                          }),
                 "the swap rule has no restitution");
  expect_refused(tampered(text, [](Json& j) { j["tc"] = -1.0; }),
                 "the TC time must be a number >= 0, got -1");
  expect_refused(tampered(text, [](Json& j) { j["rule"] = "sticky"; }), "unknown rule 'sticky'");
  expect_refused(tampered(text, [](Json& j) { j["carom_checkpoint"] = 7; }), "format 7");
  // Format 3 (carom 1.2 to 1.7: no window records, no seed) is still read.
  EXPECT_NO_THROW(read(tampered(text, [](Json& j) {
    j["carom_checkpoint"] = 3;
    j.erase("window_records");
    j.erase("seed");
  })));
  expect_refused(tampered(text, [](Json& j) { j["carom_checkpoint"] = 2.5; }), "format 2.5");
  expect_refused(tampered(text, [](Json& j) { j["dimension"] = 4; }), "dimension 4");
}

// Resumes `text` and runs 20000 more events checking for overlaps after every one.
void expect_resumes_cleanly(const std::string& text, double time, const std::string& label) {
  Simulation<2> resumed(std::get<Checkpoint<2>>(read(text)));
  ASSERT_EQ(resumed.time(), time) << label;
  resumed.add_observer(std::make_shared<InvariantCheck<2>>(1));
  EXPECT_NO_THROW(resumed.run_until(time + 1e5, 20000)) << label;
  EXPECT_EQ(resumed.counts().events,
            20000u + Json::parse(text)["counts"]["events"].get<std::uint64_t>())
      << label;
}

TEST(Checkpoint, ACheckpointFarInTimeResumesAsPreciselyAsOneNearZero) {
  // Regression: stored times were absolute, and a valid checkpoint with every time shifted by
  // 1e11 overlapped by 2.6e-6 at its second event. Format 3 shifts only its epoch; format 2 (carom
  // 1.1) has absolute stored times, re-based when read.
  const std::string text = saved(Boundary::periodic);
  constexpr double kShift = 1e11;
  const Json original = Json::parse(text);
  const double time = original["time"].get<double>() + kShift;
  expect_resumes_cleanly(tampered(text,
                                  [&](Json& j) {
                                    j["epoch"] = j["epoch"].get<double>() + kShift;
                                    j["time"] = time;
                                    j["measurement"]["start_time"] =
                                        j["measurement"]["start_time"].get<double>() + kShift;
                                  }),
                         time, "its epoch shifted");
  const std::string old = tampered(text, [&](Json& j) {
    const double epoch = j["epoch"].get<double>() + kShift;
    j.erase("epoch");
    j["carom_checkpoint"] = 2;
    j["time"] = time;
    j["measurement"]["start_time"] = j["measurement"]["start_time"].get<double>() + kShift;
    for (Json& row : j["particles"]) {
      row[4] = epoch + row[4].get<double>();
      if (!row[9].is_null()) row[9] = epoch + row[9].get<double>();
      row.erase(11);  // format 2 had no image flags
      row.erase(10);
    }
  });
  const Checkpoint<2> converted = std::get<Checkpoint<2>>(read(old));
  EXPECT_EQ(converted.system.latest_stored(), 0.0);  // re-based to the latest stored time
  expect_resumes_cleanly(old, time, "format 2");
}

TEST(Checkpoint, ImageFlagsAreWholeNumbersInTheInt32Range) {
  const std::string text = saved(Boundary::periodic);
  const Json j = Json::parse(text);
  bool moved = false;  // some disk was wrapped across the box before t = 5
  for (const Json& row : j["particles"]) moved = moved || row[10] != 0 || row[11] != 0;
  EXPECT_TRUE(moved);
  for (const Json& bad : {Json(1.5), Json(2147483648LL), Json(-2147483649LL), Json("1")}) {
    expect_refused(tampered(text, [&](Json& k) { k["particles"][3][11] = bad; }),
                   "the image flag of particle 3 must be a whole number from -2147483648 to "
                   "2147483647");
  }
  EXPECT_NO_THROW(read(tampered(text, [](Json& k) { k["particles"][3][11] = -2147483648LL; })));
}

TEST(Checkpoint, TheEpochIsATimeTheRunHasReached) {
  const std::string text = saved();
  expect_refused(tampered(text, [](Json& j) { j.erase("epoch"); }), "\"epoch\"");
  expect_refused(tampered(text, [](Json& j) { j["epoch"] = "soon"; }), "the epoch");
  expect_refused(tampered(text, [](Json& j) { j["epoch"] = j["time"].get<double>() + 1.0; }),
                 "is after the checkpoint's time");
  expect_refused(tampered(text, [](Json& j) { j["epoch"] = -2e12; }), "the epoch -2000000000000");
}

TEST(Checkpoint, CountsAreWholeNumbersThatAddUp) {
  const std::string text = saved();
  for (const Json& bad : {Json(-5), Json(1.5), Json(1e30), Json("7"), Json(nullptr)}) {
    expect_refused(tampered(text, [&](Json& j) { j["counts"]["events"] = bad; }),
                   "\"events\" in \"counts\" must be a whole number from 0 to "
                   "18446744073709551615");
  }
  // One more than 2^64 - 1 is a json integer no uint64 holds.
  std::string huge = tampered(text, [](Json& j) { j["counts"]["wall_collisions"] = 12345; });
  huge.replace(huge.find("12345"), 5, "18446744073709551616");
  expect_refused(huge, "\"wall_collisions\" in \"counts\" must be a whole number");
  expect_refused(tampered(text, [](Json& j) { j["particles"][0][8] = -1; }),
                 "the pair collision count of particle 0 must be a whole number");
  // Every event is a wall or a pair collision.
  expect_refused(tampered(text,
                          [](Json& j) {
                            j["counts"]["events"] = j["counts"]["events"].get<std::uint64_t>() + 1;
                          }),
                 "the counts in \"counts\" do not add up");
  expect_refused(tampered(text,
                          [](Json& j) {
                            j["counts"]["elastic_by_tc"] =
                                j["counts"]["pair_collisions"].get<std::uint64_t>() + 1;
                          }),
                 "collisions made elastic by TC");
  // The window is part of the run.
  expect_refused(tampered(text,
                          [](Json& j) {
                            j["counts"] = j["measurement"]["counts"];
                            j["counts"]["events"] = 0;
                            j["counts"]["wall_collisions"] = 0;
                            j["counts"]["pair_collisions"] = 0;
                            j["counts"]["elastic_by_tc"] = 0;
                          }),
                 "more than the 0 of the whole run");
  // Each collision is counted by the particles in it.
  expect_refused(tampered(text,
                          [](Json& j) {
                            for (auto& row : j["particles"]) row[8] = 0;
                          }),
                 "the particles' collision counts");
  // Beyond the range of a double (json has no infinity).
  std::string infinite = tampered(text, [](Json& j) { j["counts"]["virial"] = 12345.5; });
  infinite.replace(infinite.find("12345.5"), 7, "1e400");
  expect_refused(infinite, "number overflow parsing '1e400'");
}

// The transport measurement a checkpoint carries: its schedule is checked, and one an older carom
// wrote (without lag_spacing) is read with none (so it continues to its own end only).
TEST(Checkpoint, TheTransportsScheduleIsChecked) {
  const std::string text = saved(Boundary::periodic);
  const auto with_transport = [&](double spacing, std::optional<double> lag) {
    return tampered(text, [&](Json& j) {
      Json t = {{"spacing", spacing},      {"block_samples", 257}, {"samples", Json::array()},
                {"origin", Json::array()}, {"half_msd", 0.0},      {"blocks", Json::array()}};
      if (lag) t["lag_spacing"] = *lag;
      j["transport"] = t;
    });
  };
  const auto lag_read = [&](const std::string& checkpoint) {
    return std::get<Checkpoint<2>>(read(checkpoint)).records.transport.value().lag_spacing;
  };
  EXPECT_EQ(lag_read(with_transport(0.125, 0.25)), 0.25);
  EXPECT_EQ(lag_read(with_transport(0.125, std::nullopt)), 0.0);
  expect_refused(with_transport(0.125, 0.0625),
                 "the transport's lag_spacing (0.0625) is below its spacing (0.125)");
  expect_refused(with_transport(-1.0, 0.25), "are not a schedule");
}

TEST(Checkpoint, TimesAreConsistent) {
  const std::string text = saved();
  // Before a particle's stored time (here, the last event's).
  expect_refused(tampered(text, [](Json& j) { j["time"] = 1.0; }), "after the checkpoint's time 1");
  expect_refused(tampered(text, [](Json& j) { j["particles"][5][9] = 6.0; }),
                 "particle 5 last collided at t = 6, after the checkpoint's time 5");
  expect_refused(tampered(text, [](Json& j) { j["measurement"]["start_time"] = 7.0; }),
                 "the measurement starts at 7, after the checkpoint's time 5");
  expect_refused(tampered(text, [](Json& j) { j["time"] = 1e13; }), "which no run reaches");
  expect_refused(tampered(text, [](Json& j) { j["time"] = "5"; }), "the time must be a number");
  expect_refused(tampered(text, [](Json& j) { j.erase("time"); }), "no \"time\" field");
  expect_refused(tampered(text, [](Json& j) { j["measure_from"] = true; }),
                 "\"measure_from\" must be a number");
}

TEST(Checkpoint, StatesThatPassedThroughEachOtherAreRefused) {
  // Both disks stored at t = 0; at t = 15 they are apart, but disk 0 went through disk 1 at
  // t = 7: no run leaves that collision unprocessed.
  Checkpoint<2> c;
  c.source = "made";
  c.system = carom::testing::boxed({{20, 10}}, {carom::testing::disk({{2, 5}}, {{1, 0}}, 0.5),
                                                carom::testing::disk({{10, 5}}, {{0, 0}}, 0.5)});
  c.settings = {{Rule::elastic}};
  c.time = 15.0;
  c.settled = true;
  expect_refused(written(c), "before the checkpoint's time 15, was never processed");
  // The same two at t = 6, before they meet, are a state a run reaches.
  c.time = 6.0;
  EXPECT_NO_THROW(read(written(c)));
}

TEST(Checkpoint, CarromOnesFormatIsStillReadAndValidated) {
  std::ifstream file(std::string(CAROM_TEST_DATA) + "/checkpoint_v1/v1.ckpt");
  const std::string text((std::istreambuf_iterator<char>(file)), {});
  EXPECT_NO_THROW(read(text));
  expect_refused(tampered(text,
                          [](Json& j) {
                            for (int k = 0; k < 5; ++k) j["particles"][1][k] = j["particles"][0][k];
                          }),
                 "overlaps particle 0");
  expect_refused(tampered(text, [](Json& j) { j["events"] = -1; }),
                 "\"events\" must be a whole number");
}

}  // namespace
}  // namespace carom

// Event-chain Monte Carlo's engine (src/engine/ecmc_engine.hpp), tested alone: its lifts are the
// swap rule's collisions of one moving particle, they never let particles overlap, a run in
// pieces is the run in one, and its pressure is the hard-disk equation of state.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <pcg_random.hpp>
#include <random>
#include <string>
#include <vector>

#include "carom/core/equation_of_state.hpp"
#include "carom/engine/initial.hpp"
#include "carom/engine/overlap.hpp"
#include "engine/ecmc_engine.hpp"
#include "engine/reference_engine.hpp"

namespace carom {
namespace {

// Placed at random where random sequential addition reaches (below its saturation, 0.547 for
// disks and 0.384 for spheres): a lattice's exact symmetries make exact ties, which the chains
// and the reference engine may break differently.
template <std::size_t D>
System<D> periodic_start(std::uint64_t n, double phi, std::uint64_t seed) {
  InitialOptions options;
  options.placement = phi < (D == 2 ? 0.54 : 0.38) ? Placement::random : Placement::lattice;
  options.n = n;
  options.packing_fraction = phi;
  options.boundary = Boundary::periodic;
  options.seed = seed;
  return make_initial<D>(options);
}

TEST(Physics, LiftDistanceIsTheUnitVelocityContactBitForBit) {
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> coordinate(-2.0, 2.0);
  int lifts = 0;
  for (int trial = 0; trial < 100000; ++trial) {
    const Vec<3> r{coordinate(random), coordinate(random), coordinate(random)};
    const std::size_t axis = static_cast<std::size_t>(trial % 3);
    Vec<3> unit{};
    unit[axis] = 1.0;
    const double lift = lift_distance(r, axis, 1.3);
    ASSERT_EQ(lift, earliest_contact(0.0, r, unit, 1.3, kNever)) << trial;
    lifts += lift != kNever;
  }
  EXPECT_GT(lifts, 1000);
  // Near contact the distance keeps its digits: no cancellation.
  const Vec<2> touching{-(1.0 + 1e-12), 0.0};
  EXPECT_NEAR(lift_distance(touching, 0, 1.0), 1e-12, 1e-16);
  EXPECT_EQ(lift_distance(Vec<2>{0.5, 0.0}, 0, 1.0), kNever);   // behind
  EXPECT_EQ(lift_distance(Vec<2>{-0.5, 0.0}, 0, 1.0), 0.0);     // overlapping: at once
  EXPECT_EQ(lift_distance(Vec<2>{-3.0, 1.5}, 0, 1.0), kNever);  // passes beside
}

// Every lift is a contact, and no pair ever overlaps.
TEST(Ecmc, LiftsTouchAndNeverOverlap) {
  for (double phi : {0.3, 0.7}) {
    EcmcEngine<2> engine(periodic_start<2>(200, phi, 3), 5.0, pcg32(11));
    for (int k = 0; k < 20000; ++k) {
      const std::optional<Event> event = engine.step(kNever);
      ASSERT_TRUE(event.has_value());
      ASSERT_FALSE(event->is_wall());
      const double touching = std::sqrt(norm2(Vec<2>{event->contact[0], event->contact[1]}));
      ASSERT_NEAR(touching, 1.0, 1e-9) << "lift " << k << " at phi " << phi;
      if (k % 500 == 0) {
        ASSERT_FALSE(find_pair_overlap(engine.system(), engine.stored_time()).has_value())
            << "after lift " << k << " at phi " << phi;
      }
    }
  }
}

// Lifts of a mover with every other particle at rest are the swap rule's collisions: the
// reference engine, every pair checked after every event, finds the same partners at the same
// times (to round-off: its states move by time, the chain's by distance).
TEST(Ecmc, LiftsAreTheSwapRulesCollisionsOfOneMover) {
  for (int dimension : {2, 3}) {
    const auto check = [&]<std::size_t D>(System<D> start) {
      EcmcEngine<D> chains(start, 1e9, pcg32(5));
      System<D> one_mover = chains.system();
      ReferenceEngine<D> reference(one_mover, {Rule::swap, 1.0, 0.0});
      for (int k = 0; k < 300; ++k) {
        const std::optional<Event> lift = chains.step(kNever);
        const std::optional<Event> collision = reference.step(kNever);
        ASSERT_TRUE(lift && collision);
        ASSERT_EQ(lift->first, collision->first) << "event " << k;
        ASSERT_EQ(lift->partner, collision->partner) << "event " << k;
        ASSERT_NEAR(lift->time, collision->time, 1e-9 * (1.0 + collision->time)) << "event " << k;
      }
    };
    if (dimension == 2) check(periodic_start<2>(64, 0.5, 2));
    if (dimension == 3) check(periodic_start<3>(64, 0.3, 2));
  }
}

// A 64-bit FNV-1a hash of the bits of what a run did: every lift (all its fields) and the state it
// leaves (stored states, records, the chain and its generator, the clock).
struct RunHash {
  std::uint64_t value = 0xcbf29ce484222325ull;
  void add(std::uint64_t word) {
    for (int byte = 0; byte < 8; ++byte) {
      value ^= (word >> (8 * byte)) & 0xFF;
      value *= 0x100000001b3ull;
    }
  }
  void add(double x) { add(std::bit_cast<std::uint64_t>(x)); }
  void add(const Event& e) {
    add(e.time);
    add(std::uint64_t{e.first});
    add(static_cast<std::uint64_t>(static_cast<std::int64_t>(e.partner)));
    add(e.impulse);
    add(std::uint64_t{e.elastic_by_tc});
    for (double m : e.momentum) add(m);
    for (double c : e.contact) add(c);
  }
  template <std::size_t D>
  void add(const EcmcEngine<D>& engine) {
    const System<D>& s = engine.system();
    for (std::size_t i = 0; i < s.size(); ++i) {
      const Particle<D>& p = s.particles[i];
      for (std::size_t k = 0; k < D; ++k) add(p.position[k]);
      for (std::size_t k = 0; k < D; ++k) add(p.velocity[k]);
      add(p.time);
      add(p.radius);
      const ParticleRecord& r = s.records[i];
      add(r.mass);
      add(r.wall_collisions);
      add(r.pair_collisions);
      add(r.last_collision);
      for (std::int32_t flag : r.image)
        add(static_cast<std::uint64_t>(static_cast<std::int64_t>(flag)));
      add(std::uint64_t{r.changes});
    }
    add(s.epoch);
    add(engine.stored_time());
    const ChainState& chain = engine.chain();
    add(std::uint64_t{chain.active});
    add(std::uint64_t{chain.axis});
    add(chain.chain_end);
    pcg32 rng = chain.rng;
    add(std::uint64_t{rng()});
  }
};

template <std::size_t D>
System<D> golden_start(std::uint64_t n, double phi, double polydispersity, double aspect,
                       Placement placement, std::uint64_t seed) {
  InitialOptions options;
  options.placement = placement;
  options.n = n;
  options.packing_fraction = phi;
  options.polydispersity = polydispersity;
  options.aspect = aspect;
  options.boundary = Boundary::periodic;
  options.seed = seed;
  return make_initial<D>(options);
}

// `lifts` lifts in one go; the hash of every event and of the end state.
template <std::size_t D>
std::uint64_t golden_run(System<D> start, double chain_length, std::uint64_t seed, int lifts,
                         ContactKernel kernel) {
  EcmcEngine<D> engine(std::move(start), chain_length, pcg32(seed), kernel);
  RunHash hash;
  try {
    for (int k = 0; k < lifts; ++k) {
      const std::optional<Event> event = engine.step(kNever);
      EXPECT_TRUE(event.has_value());
      if (!event) break;
      hash.add(*event);
    }
  } catch (const JamError&) {  // zero-length lifts around a ring of touching particles
    hash.add(std::uint64_t{0x4a414d});
  }
  hash.add(engine);
  return hash.value;
}

// The same in pieces of stored time, rebased now and then, and continued half way by a new engine
// from the chain state: what a Simulation and a checkpoint do with it.
template <std::size_t D>
std::uint64_t golden_pieces(System<D> start, double chain_length, std::uint64_t seed, double piece,
                            int pieces, ContactKernel kernel) {
  auto engine =
      std::make_unique<EcmcEngine<D>>(std::move(start), chain_length, pcg32(seed), kernel);
  RunHash hash;
  int events = 0;
  for (int k = 1; k <= pieces; ++k) {
    while (const std::optional<Event> event = engine->step(k * piece)) {
      hash.add(*event);
      if (++events % 1000 == 0) engine->rebase();
    }
    if (k == pieces / 2) {
      hash.add(*engine);
      const ChainState chain = engine->chain();
      engine = std::make_unique<EcmcEngine<D>>(engine->system(), chain_length, chain, kernel);
    }
  }
  EXPECT_GT(events, 1000);
  hash.add(*engine);
  return hash.value;
}

std::string hex(std::uint64_t value) {
  char text[24];
  std::snprintf(text, sizeof text, "0x%016llx", static_cast<unsigned long long>(value));
  return text;
}

// Today's lifts, bit for bit: every event's fields and the state left behind hash to what the
// first engine (generic cell lists, the engines' apply()) gave. A faster engine must give them
// too: the same events at the same times, the same impulses, the same final system. Chains stay
// shorter than half a box side where lifts are rare: a flight that long never ends. Both the
// baseline's instructions and the widest this CPU has (AVX2's) give them.
class EcmcGolden : public testing::TestWithParam<ContactKernel> {};

INSTANTIATE_TEST_SUITE_P(Kernels, EcmcGolden,
                         testing::Values(ContactKernel::scalar, widest_contact_kernel()),
                         [](const testing::TestParamInfo<ContactKernel>& info) {
                           return info.index == 0 ? std::string("baseline") : std::string("widest");
                         });

TEST_P(EcmcGolden, RunsAreBitForBitTheSame) {
  const ContactKernel kernel = GetParam();
  const auto expect = [](std::uint64_t got, std::uint64_t want, const char* what) {
    EXPECT_EQ(hex(got), hex(want)) << what;
  };
  const Placement random = Placement::random, lattice = Placement::lattice;
  expect(golden_run(golden_start<2>(300, 0.5, 0.0, 1.0, random, 1), 5.0, 11, 100000, kernel),
         0x1ab55ece1c20497a, "disks 0.5");
  expect(golden_run(golden_start<2>(300, 0.7, 0.0, 1.0, lattice, 2), 12.0, 3, 100000, kernel),
         0xf5f3e3bfd293fce7, "disks 0.7");
  expect(golden_run(golden_start<2>(300, 0.45, 0.25, 1.0, random, 3), 8.0, 5, 100000, kernel),
         0x8f06cf847ef32977, "polydisperse disks 0.45");
  expect(golden_run(golden_start<2>(256, 0.7, 0.05, 1.0, lattice, 4), 8.0, 7, 100000, kernel),
         0x58f8930c62a3a5ae, "polydisperse disks 0.7");
  expect(golden_run(golden_start<2>(200, 0.05, 0.0, 1.0, random, 5), 20.0, 9, 50000, kernel),
         0xce2337692aa9f15c, "sparse disks");
  expect(golden_run(golden_start<2>(32, 0.7, 0.0, 3.0, lattice, 2), 6.0, 2, 50000, kernel),
         0x54aef21e520b9aa2, "disks in a box three cells high");
  expect(golden_run(golden_start<3>(300, 0.3, 0.0, 1.0, random, 7), 5.0, 15, 100000, kernel),
         0x545768e7de56de99, "spheres 0.3");
  expect(golden_run(golden_start<3>(256, 0.45, 0.0, 1.0, lattice, 8), 12.0, 17, 100000, kernel),
         0x3ccd6444b18b7695, "spheres 0.45");
  expect(golden_run(golden_start<3>(300, 0.25, 0.2, 1.0, random, 9), 3.0, 19, 100000, kernel),
         0x813a45a3aaeb08ea, "polydisperse spheres 0.25");
  expect(golden_run(golden_start<3>(200, 0.02, 0.0, 1.0, random, 10), 6.0, 21, 50000, kernel),
         0x7a493ffa498b8567, "sparse spheres");
  expect(golden_run(golden_start<3>(64, 0.45, 0.0, 2.0, lattice, 1), 6.0, 1, 50000, kernel),
         0x30e9f82fe9828a18, "spheres in a box three cells across");
  expect(golden_run(golden_start<3>(64, 0.45, 0.0, 2.0, lattice, 3), 6.0, 3, 50000, kernel),
         0xc6ec40318aa9cd4d, "spheres jammed in a ring");
  expect(
      golden_pieces(golden_start<2>(300, 0.7, 0.0, 1.0, lattice, 12), 10.0, 25, 0.37, 40, kernel),
      0x9cf67b5d139452ae, "disks 0.7 in pieces");
  expect(
      golden_pieces(golden_start<3>(256, 0.45, 0.05, 1.0, lattice, 13), 10.0, 27, 0.37, 40, kernel),
      0x08df2cc5d0221274, "spheres 0.45 in pieces");
}

// Flights of any length, in boxes down to three cells across and in sparse ones where a flight
// goes round the box, some of them in an empty lane for ever: the lifts are the reference
// engine's collisions of one mover, and the two agree when nothing more happens.
TEST(Ecmc, FlightsOfAnyLengthMeetWhatTheReferenceEngineMeets) {
  std::mt19937_64 random(2026);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  int cases = 0, lifts = 0, long_flights = 0, silent = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const auto check = [&]<std::size_t D>(System<D> start) {
      EcmcEngine<D> chains(start, 1e9, pcg32(static_cast<std::uint64_t>(trial)));
      ReferenceEngine<D> reference(chains.system(), {Rule::swap, 1.0, 0.0});
      double shortest = kNever, longest = 0.0;
      for (std::size_t k = 0; k < D; ++k) {
        shortest = std::min(shortest, start.box.size[k]);
        longest = std::max(longest, start.box.size[k]);
      }
      // Long enough for a flight to go round the box twenty times.
      const double end = 20.0 * longest / chains.speed();
      double last = 0.0;
      for (int k = 0; k < 200; ++k) {
        const std::optional<Event> lift = chains.step(end);
        const std::optional<Event> collision = reference.step(end);
        ASSERT_EQ(lift.has_value(), collision.has_value()) << "trial " << trial << " event " << k;
        if (!lift) {
          ++silent;
          break;
        }
        ASSERT_EQ(lift->first, collision->first) << "trial " << trial << " event " << k;
        ASSERT_EQ(lift->partner, collision->partner) << "trial " << trial << " event " << k;
        ASSERT_NEAR(lift->time, collision->time, 1e-9 * (1.0 + collision->time))
            << "trial " << trial << " event " << k;
        ++lifts;
        long_flights += (lift->time - last) * chains.speed() > 0.5 * shortest;
        last = lift->time;
      }
      ASSERT_FALSE(find_pair_overlap(chains.system(), chains.stored_time()).has_value())
          << "trial " << trial;
      ++cases;
    };
    InitialOptions options;
    options.boundary = Boundary::periodic;
    options.seed = static_cast<std::uint64_t>(trial);
    // Packings from 0.003 to 0.3, a handful of particles to a hundred, boxes up to 2:1.
    options.packing_fraction = 0.003 * std::pow(100.0, uniform(random));
    options.n = 4 + static_cast<std::uint64_t>(96.0 * uniform(random) * uniform(random));
    options.aspect = 1.0 + uniform(random);
    options.polydispersity = trial % 3 == 0 ? 0.2 : 0.0;
    try {
      if (trial % 2 == 0) {
        check(make_initial<2>(options));
      } else {
        options.packing_fraction *= 0.7;
        check(make_initial<3>(options));
      }
    } catch (const std::invalid_argument&) {  // a box too narrow for chains: not a case
    }
  }
  EXPECT_GE(cases, 40);
  EXPECT_GE(lifts, 1000);
  EXPECT_GE(long_flights, 20);  // flights of half a box side or more
  EXPECT_GE(silent, 5);         // a flight in an empty lane, or nothing near
}

// `events` lifts of `chains` are the reference engine's collisions of one mover from the same
// system (the same partners at the same times, to round-off), and leave no overlap.
void expect_lifts_of_one_mover(EcmcEngine<2>& chains, int events) {
  ReferenceEngine<2> reference(chains.system(), {Rule::swap, 1.0, 0.0});
  for (int k = 0; k < events; ++k) {
    const std::optional<Event> lift = chains.step(kNever);
    const std::optional<Event> collision = reference.step(kNever);
    ASSERT_TRUE(lift && collision) << "event " << k;
    ASSERT_EQ(lift->first, collision->first) << "event " << k;
    ASSERT_EQ(lift->partner, collision->partner) << "event " << k;
    ASSERT_NEAR(lift->time, collision->time, 1e-9 * (1.0 + collision->time)) << "event " << k;
  }
  EXPECT_FALSE(find_pair_overlap(chains.system(), chains.stored_time()).has_value());
}

// Small disks beside a large one: cells as wide as the large one's diameter hold dozens, more
// than the eight lanes the searches by pairs of lanes take, and are searched one lane at a time.
// The lifts are still the reference engine's collisions of one mover.
TEST(Ecmc, CellsOfManySmallDisksMeetWhatTheReferenceEngineMeets) {
  System<2> start;
  start.box = {{{26.0, 26.0}}, Boundary::periodic};
  Particle<2> large;
  large.position = {{13.0, 13.0}};
  large.radius = 4.0;
  start.add(large);
  for (double x = 0.7; x < 26.0; x += 1.25) {
    for (double y = 0.7; y < 26.0; y += 1.25) {
      Particle<2> small;
      small.position = {{x, y}};
      small.radius = 0.5;
      if (norm2(small.position - large.position) > 4.6 * 4.6) start.add(small);
    }
  }
  EcmcEngine<2> chains(start, 1e9, pcg32(3));
  expect_lifts_of_one_mover(chains, 500);
}

// Four disks of one size in one cell (at its corners: a cell a little over a diameter wide holds
// no more): the blocks take a fourth lane, not six, and the searches still read four lanes at a
// time. The lifts are the reference engine's collisions of one mover.
TEST(Ecmc, AFourthDiskInACellMakesFourLanes) {
  System<2> start;
  start.box = {{{10.5, 10.5}}, Boundary::periodic};  // cells 1.05 wide
  const auto add = [&](double x, double y) {
    Particle<2> disk;
    disk.position = {{x, y}};
    disk.radius = 0.5;
    start.add(disk);
  };
  for (const double x : {0.01, 1.03}) {
    for (const double y : {0.01, 1.03}) add(x + 4.2, y + 4.2);
  }
  for (double x = 0.6; x < 10.0; x += 2.1) {
    for (double y = 0.6; y < 10.0; y += 2.1) {
      if (std::abs(x - 4.7) > 1.6 || std::abs(y - 4.7) > 1.6) add(x, y);
    }
  }
  ASSERT_FALSE(find_pair_overlap(start, 0.0).has_value());
  EcmcEngine<2> chains(start, 1e9, pcg32(8));
  EXPECT_EQ(chains.lanes_per_cell(), 4u);
  expect_lifts_of_one_mover(chains, 500);
}

// A box under three cells across along an axis holds two images of a particle in the columns a
// search reads: chains refuse it, by name.
TEST(Ecmc, ABoxUnderThreeDiametersAcrossIsRefused) {
  InitialOptions options;
  options.boundary = Boundary::periodic;
  options.n = 2;
  options.packing_fraction = 0.3;
  const System<2> narrow = make_initial<2>(options);
  try {
    EcmcEngine<2> engine(narrow, 5.0, pcg32(1));
    FAIL() << "a box " << narrow.box.size[0] << " wide was taken";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("three of the largest diameters"), std::string::npos)
        << e.what();
  }
  options.n = 4;  // 3.2 diameters across: three cells
  EXPECT_NO_THROW(check_chain_start(make_initial<2>(options)));
}

// A sparse system in a long narrow box wider than three diameters is taken, however few its
// particles (its grid has room for three cells across), and its lifts are the reference engine's.
// Regression: a grid of about two cells a particle made 10 disks in an 8 x 200 box one cell wide,
// and the box was refused as under three diameters across.
TEST(Ecmc, ASparseNarrowBoxWiderThanThreeDiametersIsTaken) {
  System<2> start;
  start.box = {{{8.0, 200.0}}, Boundary::periodic};
  for (std::uint32_t i = 0; i < 10; ++i) {
    Particle<2> p;
    p.position = {{1.0 + 0.6 * i, 10.0 + 19.0 * i}};
    p.radius = 0.5;
    start.particles.push_back(p);
  }
  start.records.resize(start.size());
  EcmcEngine<2> chains(start, 1e9, pcg32(4));
  ReferenceEngine<2> reference(chains.system(), {Rule::swap, 1.0, 0.0});
  const double end = 40.0 * 200.0 / chains.speed();
  for (int k = 0; k < 50; ++k) {
    const std::optional<Event> lift = chains.step(end);
    const std::optional<Event> collision = reference.step(end);
    ASSERT_EQ(lift.has_value(), collision.has_value()) << "event " << k;
    if (!lift) break;
    ASSERT_EQ(lift->first, collision->first) << "event " << k;
    ASSERT_EQ(lift->partner, collision->partner) << "event " << k;
    ASSERT_NEAR(lift->time, collision->time, 1e-9 * (1.0 + collision->time)) << "event " << k;
  }
}

// `lifts` lifts of `engine` by lift_quietly, in batches of `batch`: the last one.
template <std::size_t D>
Event lifts_in_batches(EcmcEngine<D>& engine, std::uint64_t lifts, std::uint64_t batch) {
  Counts run, window;
  Event last{};
  for (std::uint64_t done = 0; done < lifts;) {
    const std::uint64_t made =
        engine.lift_quietly(kNever, std::min(batch, lifts - done), run, window, last);
    EXPECT_GT(made, 0u);
    if (made == 0) break;
    done += made;
  }
  return last;
}

// The hash of a run's last lift and of the state it left.
template <std::size_t D>
std::string run_hash(const Event& last, const EcmcEngine<D>& engine) {
  RunHash hash;
  hash.add(last);
  hash.add(engine);
  return hex(hash.value);
}

// Lifts in one go (lift_quietly, as a run that looks at no event alone makes them) are the lifts
// one by one (step()), bit for bit: the same last lift and the same state left behind. In one go
// a lift's mover is put into its block only after the next search (EcmcEngine::landing_).
TEST(Ecmc, LiftsInOneGoAreTheLiftsOneByOne) {
  const auto check = [](auto start, double chain_length, std::uint64_t seed, const char* what) {
    constexpr std::size_t D = decltype(start)::dimension;
    EcmcEngine<D> one_by_one(start, chain_length, pcg32(seed));
    EcmcEngine<D> in_one_go(start, chain_length, pcg32(seed));
    Event last{};
    for (int k = 0; k < 20000; ++k) last = *one_by_one.step(kNever);
    const Event batched = lifts_in_batches(in_one_go, 20000, 7919);
    EXPECT_EQ(run_hash(batched, in_one_go), run_hash(last, one_by_one)) << what;
  };
  const Placement random = Placement::random, lattice = Placement::lattice;
  check(golden_start<2>(300, 0.7, 0.0, 1.0, lattice, 2), 12.0, 3, "disks 0.7");
  check(golden_start<2>(256, 0.7, 0.05, 1.0, lattice, 4), 8.0, 7, "polydisperse disks 0.7");
  check(golden_start<2>(200, 0.05, 0.0, 1.0, random, 5), 20.0, 9, "sparse disks");
  check(golden_start<3>(256, 0.45, 0.0, 1.0, lattice, 8), 12.0, 17, "spheres 0.45");
  check(golden_start<3>(300, 0.25, 0.2, 1.0, random, 9), 3.0, 19, "polydisperse spheres 0.25");
}

// A cell that fills in the middle of a batch lays the blocks out anew with more lanes, the
// search then made again (FlightEnd::relaid): still the lifts one by one. Nine equal disks in a
// box of three cells 1.32 diameters wide a side start with three lanes a cell where no cell holds
// four; in some starts a fourth comes later.
TEST(Ecmc, ACellFilledInOneGoLaysTheBlocksOutAnew) {
  int widened = 0;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    InitialOptions options;
    options.placement = Placement::random;
    options.n = 9;
    options.packing_fraction = 9 * std::numbers::pi / 4.0 / (3.95 * 3.95);  // a side of 3.95
    options.boundary = Boundary::periodic;
    options.seed = seed;
    const System<2> start = make_initial<2>(options);
    EcmcEngine<2> one_by_one(start, 7.0, pcg32(seed));
    if (one_by_one.lanes_per_cell() != 3) continue;
    EcmcEngine<2> in_one_go(start, 7.0, pcg32(seed));
    Event last{};
    for (int k = 0; k < 5000; ++k) last = *one_by_one.step(kNever);
    const Event batched = lifts_in_batches(in_one_go, 5000, 5000);
    ASSERT_EQ(run_hash(batched, in_one_go), run_hash(last, one_by_one)) << "seed " << seed;
    widened += in_one_go.lanes_per_cell() > 3;
  }
  EXPECT_GT(widened, 0);
}

// A lift that grazes its target can stop the mover level with it, or (its distance and the stop
// rounded) an ulp ahead of it: the particle struck then touches the mover at once and lifts it
// back, in one go as one by one. Two disks, one a hair under a diameter across the axis from the
// other, many times over. Regression: in one go, where the mover waits outside its block for
// the next search (EcmcEngine::landing_), that search has to measure it alone.
TEST(Ecmc, AMoverStoppedAheadOfItsTargetIsLiftedBack) {
  std::mt19937_64 random(12);
  std::uniform_real_distribution<double> along(1.5, 6.0), place(0.0, 1.0);
  std::uniform_int_distribution<int> ulps(0, 64);
  int lifted_back = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    System<2> start;
    start.box = {{{12.0, 12.0}}, Boundary::periodic};
    Particle<2> disk;
    disk.radius = 0.5;
    const double x = 0.5 + 3.0 * place(random), y = 3.0 + 3.0 * place(random);
    disk.position = {{x, y}};
    start.add(disk);
    disk.position = {{x + along(random), y + (1.0 - ulps(random) * 0x1p-53)}};
    start.add(disk);
    const auto seed = static_cast<std::uint64_t>(trial);
    EcmcEngine<2> one_by_one(start, 1e6, pcg32(seed));
    EcmcEngine<2> in_one_go(start, 1e6, pcg32(seed));
    Event last{};
    double previous = -1.0;
    for (int k = 0; k < 6; ++k) {
      last = *one_by_one.step(kNever);
      lifted_back += k > 0 && last.time == previous;
      previous = last.time;
    }
    const Event batched = lifts_in_batches(in_one_go, 6, 6);
    ASSERT_EQ(run_hash(batched, in_one_go), run_hash(last, one_by_one)) << "trial " << trial;
  }
  EXPECT_GT(lifted_back, 10);
}

// A slice of a run (Engine::slice_length, between looks at the stop flag) bounds the cell
// crossings of the one particle that moves. Regression: it bounded those of N particles at the
// active one's speed, N times shorter; at N = 10^6 a slice was shorter than a lift, each slice's
// end cost two searches thrown away, and runs there were twice as slow.
TEST(Ecmc, ASliceHoldsTheLiftsOfManyCellCrossings) {
  EcmcEngine<2> engine(periodic_start<2>(1024, 0.7, 1), 5.0, pcg32(1));
  const double slice = engine.slice_length();
  std::uint64_t lifts = 0;
  while (engine.step(slice)) ++lifts;
  EXPECT_GT(lifts, 10000u) << "in a slice of " << slice;
}

// Stopping anywhere and going on gives the same chains, bit for bit.
TEST(Ecmc, AnyPiecesGiveTheSameRun) {
  EcmcEngine<3> whole(periodic_start<3>(100, 0.3, 4), 3.0, pcg32(9));
  EcmcEngine<3> pieces(periodic_start<3>(100, 0.3, 4), 3.0, pcg32(9));
  while (whole.step(2.0)) {
  }
  for (double end = 0.0137; end < 2.0; end += 0.0137) {
    while (pieces.step(end)) {
    }
  }
  while (pieces.step(2.0)) {
  }
  ASSERT_EQ(whole.system().particles.size(), pieces.system().particles.size());
  for (std::size_t i = 0; i < whole.system().size(); ++i) {
    EXPECT_EQ(whole.system().particles[i].position, pieces.system().particles[i].position) << i;
    EXPECT_EQ(whole.system().particles[i].time, pieces.system().particles[i].time) << i;
  }
  EXPECT_EQ(whole.chain().active, pieces.chain().active);
}

// Z = 1 + (sum of the lifts' separations along the move) / (the displacement): from the lifts'
// virials, r . dp = v dx with unit masses, over v^2 t.
TEST(Ecmc, PressureIsTheHardDiskEquationOfState) {
  const double phi = 0.5;
  EcmcEngine<2> engine(periodic_start<2>(400, phi, 6), 10.0, pcg32(1));
  const double equilibrated = 20.0, end = 220.0;
  while (engine.step(equilibrated)) {
  }
  double virial = 0.0;
  while (const std::optional<Event> event = engine.step(end)) virial += event->impulse;
  const double v = engine.speed();
  const double z = 1.0 + virial / (v * v * (end - equilibrated));
  EXPECT_NEAR(z, henderson_z(phi), 0.02 * henderson_z(phi));
}

}  // namespace
}  // namespace carom

// Particle species: carom init's mixtures (--species), their types kept by start files,
// checkpoints, trajectories (GSD, extended XYZ, LAMMPS) and runs, and the partial g_ab(r).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "carom/analysis/analysis.hpp"
#include "carom/core/observables.hpp"
#include "carom/engine/initial.hpp"
#include "carom/engine/simulation.hpp"
#include "carom/engine/validation.hpp"
#include "carom/io/checkpoint.hpp"
#include "carom/io/classic_input.hpp"
#include "carom/io/classic_output.hpp"
#include "carom/io/gsd.hpp"
#include "carom/io/trajectory.hpp"
#include "carom/io/trajectory_reader.hpp"

namespace carom {
namespace {

namespace fs = std::filesystem;

InitialOptions binary(std::uint64_t n, double phi, std::uint64_t seed = 1) {
  InitialOptions o;
  o.n = n;
  o.packing_fraction = phi;
  o.seed = seed;
  o.species = parse_species("A:0.5:1.0,B:0.5:1.4");
  return o;
}

template <std::size_t D>
std::vector<std::uint64_t> counts_of(const System<D>& system) {
  std::vector<std::uint64_t> counts(system.type_names.size());
  for (const ParticleRecord& r : system.records) ++counts.at(r.type);
  return counts;
}

TEST(Species, TheTextIsReadAndCheckedWhole) {
  const std::vector<Species> s = parse_species("A:0.5:1.0,B:0.5:1.4");
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0], (Species{"A", 0.5, 1.0}));
  EXPECT_EQ(s[1], (Species{"B", 0.5, 1.4}));
  EXPECT_EQ(parse_species(species_text(s)), s);
  EXPECT_EQ(parse_species("small:0.2:1,mid:0.3:1.2,large:0.5:1.4").size(), 3u);
  for (const char* bad : {"", "A:0.5:1.0", "A:0.5:1.0,B:0.4:1.4", "A:0.5:1,A:0.5:1",
                          "A:0.5:1.0,B:0.5", "A:0.5:1.0,B:0.5:0", "A:0.5:1.0,B:0.5:x", "A:1:1:1",
                          "A B:1:1", ":1:1", "A:1:1,", "A:-0.5:1,B:1.5:1"}) {
    EXPECT_THROW(parse_species(bad), InitialError) << bad;
  }
  // Within 1e-12 of 1 is 1.
  EXPECT_NO_THROW(parse_species("A:0.1:1,B:0.2:1,C:0.7:1"));
}

TEST(Species, CountsAreByLargestRemainderAndSumToN) {
  const auto halves = parse_species("A:0.5:1,B:0.5:1.4");
  EXPECT_EQ(species_counts(halves, 7), (std::vector<std::uint64_t>{4, 3}));
  EXPECT_EQ(species_counts(halves, 1000), (std::vector<std::uint64_t>{500, 500}));
  const auto thirds = parse_species("A:0.3:1,B:0.3:1,C:0.4:1");
  EXPECT_EQ(species_counts(thirds, 10), (std::vector<std::uint64_t>{3, 3, 4}));
  EXPECT_EQ(species_counts(thirds, 11), (std::vector<std::uint64_t>{3, 3, 5}));  // 3.3 3.3 4.4
  const auto odd = parse_species("A:0.15:1,B:0.85:1");
  EXPECT_EQ(species_counts(odd, 3), (std::vector<std::uint64_t>{0, 3}));  // 0.45, 2.55
  for (std::uint64_t n = 1; n < 200; ++n) {
    std::uint64_t sum = 0;
    for (const auto c : species_counts(thirds, n)) sum += c;
    EXPECT_EQ(sum, n);
  }
}

TEST(Species, InitMakesEachTypeInItsCountAndDiameterReproducibly) {
  InitialOptions o = binary(1001, 0.3);
  o.boundary = Boundary::periodic;
  const System<2> a = make_initial<2>(o);
  EXPECT_EQ(a.type_names, (std::vector<std::string>{"A", "B"}));
  EXPECT_EQ(counts_of(a), (std::vector<std::uint64_t>{501, 500}));
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a.particles[i].radius, a.records[i].type == 0 ? 0.5 : 0.7) << i;
  }
  EXPECT_NEAR(packing_fraction(a), 0.3, 1e-12);
  // The same options and seed: the same particles and types; another seed: other types.
  const System<2> b = make_initial<2>(o);
  EXPECT_EQ(a.particles, b.particles);
  EXPECT_EQ(a.records, b.records);
  o.seed = 2;
  const System<2> c = make_initial<2>(o);
  EXPECT_NE(a.records, c.records);
  // The types are shuffled, not in blocks: both types among the first 20 of the Morton order.
  std::vector<std::uint64_t> first(2);
  for (std::size_t i = 0; i < 20; ++i) ++first[a.records[i].type];
  EXPECT_GT(first[0], 0u);
  EXPECT_GT(first[1], 0u);
  // Spheres and a box too.
  InitialOptions s = binary(300, 0.2, 5);
  s.species = parse_species("A:0.8:1,B:0.2:1.25");
  s.box = {12.0, 12.0, 12.0};
  const System<3> spheres = make_initial<3>(s);
  EXPECT_EQ(counts_of(spheres), (std::vector<std::uint64_t>{240, 60}));
  EXPECT_NEAR(packing_fraction(spheres), 0.2, 1e-12);
}

TEST(Species, TypesAreShuffledByTheSeedNotPlacedInBlocks) {
  // On a lattice the sites do not depend on the seed: only the shuffle spreads the types.
  InitialOptions o = binary(400, 0.6);
  o.species = parse_species("A:0.5:1,B:0.5:1");
  o.boundary = Boundary::periodic;
  o.placement = Placement::lattice;
  const System<2> a = make_initial<2>(o);
  o.seed = 2;
  const System<2> b = make_initial<2>(o);
  std::vector<std::uint32_t> types_a, types_b;
  for (std::size_t i = 0; i < a.size(); ++i) {
    types_a.push_back(a.records[i].type);
    types_b.push_back(b.records[i].type);
  }
  EXPECT_NE(types_a, types_b);
  // As many A in the lower half of the box as chance gives (200 +- 10 sigma), not all or none.
  std::size_t lower_a = 0, lower = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a.particles[i].position[1] < 0.5 * a.box.size[1]) {
      ++lower;
      lower_a += a.records[i].type == 0 ? 1 : 0;
    }
  }
  EXPECT_GT(lower_a, lower / 4);
  EXPECT_LT(lower_a, 3 * lower / 4);
}

// A system a program builds (arrays from Python) is checked as a file's types are: names that
// every file can hold, each once, and every particle's type one of them.
TEST(Species, AStartsTypesAreChecked) {
  System<2> system = make_initial<2>(binary(20, 0.3));
  EXPECT_NO_THROW(check_start(system));
  const auto refused = [&](const System<2>& bad, const std::string& what) {
    try {
      check_start(bad);
      ADD_FAILURE() << "accepted: " << what;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  for (const auto& [names, what] : std::vector<std::pair<std::vector<std::string>, std::string>>{
           {{"A", "A"}, "A appears twice"},
           {{"A", ""}, "\"\" must be letters"},
           {{"A", "B,C"}, "\"B,C\" must be letters"},
           {{}, "at least one type name"}}) {
    System<2> bad = system;
    bad.type_names = names;
    refused(bad, what);
  }
  System<2> beyond = system;
  beyond.records[7].type = 2;
  refused(beyond, "the type 2 of particle 7 is not the index of one of the 2 types (0 to 1)");
}

TEST(Species, ExcludesPolydispersityAndRadius) {
  InitialOptions o = binary(100, 0.3);
  o.polydispersity = 0.1;
  EXPECT_THROW(make_initial<2>(o), InitialError);
  o = binary(100, 0.3);
  o.radius = 0.5;
  EXPECT_THROW(make_initial<2>(o), InitialError);
}

TEST(Species, DenseMixturesArePlacedAtRandomAndCompressedNotOnALattice) {
  InitialOptions o = binary(400, 0.3);
  o.boundary = Boundary::periodic;
  o.placement = Placement::random;
  EXPECT_NO_THROW(make_initial<2>(o));
  // The lattice holds every site for the largest disk: 0.8 of a 1.0/1.4 mixture does not fit.
  o.packing_fraction = 0.8;
  o.placement = Placement::lattice;
  EXPECT_THROW(make_initial<2>(o), InitialError);
}

TEST(Species, AStartFileKeepsTheTypesAndAOneTypeFileIsUnchanged) {
  InitialOptions o = binary(50, 0.3, 4);
  o.boundary = Boundary::periodic;
  const System<2> mixture = make_initial<2>(o);
  std::ostringstream out;
  write_start(out, mixture, Rule::elastic);
  const std::string text = out.str();
  EXPECT_EQ(text.substr(0, text.find('\n')), "# carom: boundary=periodic rule=elastic types=A,B");
  std::istringstream in(text);
  const ClassicInput<2> read = read_classic<2>(in, "mix.txt");
  EXPECT_EQ(read.system.type_names, mixture.type_names);
  EXPECT_EQ(read.system.particles, mixture.particles);
  EXPECT_EQ(read.system.records, mixture.records);
  // One type: the file as before, with no types.
  InitialOptions one = o;
  one.species.clear();
  std::ostringstream plain;
  write_start(plain, make_initial<2>(one), Rule::elastic);
  EXPECT_EQ(plain.str().find("types"), std::string::npos);
  EXPECT_EQ(plain.str().substr(0, plain.str().find('\n')),
            "# carom: boundary=periodic rule=elastic");
  // A type that is not one of the names is refused with its line.
  std::istringstream wrong("# carom: types=A,B\n1\n0.5\n10 10\n5 5 1 0 0.5 1 2\n");
  EXPECT_THROW(read_classic<2>(wrong, "f.txt"), InputError);
  std::istringstream missing("# carom: types=A,B\n1\n0.5\n10 10\n5 5 1 0 0.5 1\n");
  EXPECT_THROW(read_classic<2>(missing, "f.txt"), InputError);
}

Checkpoint<2> checkpoint_of(const std::string& text) {
  std::istringstream in(text);
  return std::get<Checkpoint<2>>(read_checkpoint(in, "ck"));
}

TEST(Species, CheckpointsKeepTheTypesAndResumeBitForBit) {
  InitialOptions o = binary(200, 0.35, 9);
  o.boundary = Boundary::periodic;
  Simulation<2> whole(make_initial<2>(o), {{Rule::elastic}});
  Simulation<2> first(make_initial<2>(o), {{Rule::elastic}});
  first.run_until(2.0);
  std::ostringstream out;
  write_checkpoint(out, first.checkpoint("mix.txt"));
  const std::string text = out.str();
  EXPECT_NE(text.find("\"carom_checkpoint\": 6"), std::string::npos);
  EXPECT_NE(text.find("\"types\""), std::string::npos);
  Simulation<2> resumed(checkpoint_of(text));
  EXPECT_EQ(resumed.state().type_names, first.state().type_names);
  EXPECT_EQ(resumed.state().records, first.state().records);
  whole.run_until(4.0);
  resumed.run_until(4.0);
  EXPECT_EQ(resumed.state().particles, whole.state().particles);
  EXPECT_EQ(resumed.state().records, whole.state().records);
  EXPECT_EQ(resumed.state().type_names, (std::vector<std::string>{"A", "B"}));
  // One type: format 5, as before.
  InitialOptions one = o;
  one.species.clear();
  Simulation<2> plain(make_initial<2>(one), {{Rule::elastic}});
  std::ostringstream plain_out;
  write_checkpoint(plain_out, plain.checkpoint("plain.txt"));
  EXPECT_NE(plain_out.str().find("\"carom_checkpoint\": 5"), std::string::npos);
  EXPECT_EQ(plain_out.str().find("\"types\""), std::string::npos);
  EXPECT_EQ(checkpoint_of(plain_out.str()).system.type_names, (std::vector<std::string>{"A"}));
}

struct TempFile {
  fs::path path;
  explicit TempFile(const std::string& name)
      : path(fs::temp_directory_path() / (std::to_string(::getpid()) + "-" + name)) {}
  ~TempFile() { fs::remove(path); }
};

TEST(Species, TrajectoriesKeepTheTypes) {
  InitialOptions o = binary(60, 0.3, 2);
  o.boundary = Boundary::periodic;
  const System<2> mixture = make_initial<2>(o);
  std::vector<std::uint32_t> types;
  for (const ParticleRecord& r : mixture.records) types.push_back(r.type);
  // GSD: read back as frames and as a start.
  const TempFile gsd("species.gsd");
  {
    std::ofstream file(gsd.path, std::ios::binary);
    auto format = trajectory_format_for<2>(gsd.path.string());
    format->frame(file, 0, 0.0, mixture);
    format->frame(file, 1, 1.0, mixture);
  }
  const std::vector<Frame> frames = read_gsd_frames(gsd.path.string());
  ASSERT_EQ(frames.size(), 2u);
  for (const Frame& f : frames) {
    EXPECT_EQ(f.type_names, mixture.type_names);
    EXPECT_EQ(f.type, types);
  }
  const auto start = std::get<ClassicInput<2>>(read_gsd_start(gsd.path.string(), 0));
  EXPECT_EQ(start.system.type_names, mixture.type_names);
  for (std::size_t i = 0; i < mixture.size(); ++i) {
    EXPECT_EQ(start.system.records[i].type, types[i]) << i;
  }
  EXPECT_EQ(start.record.types, mixture.type_names);
  // Extended XYZ: the species column (H, He) and the type names.
  std::ostringstream xyz;
  trajectory_format_for<2>("m.xyz")->frame(xyz, 0, 0.0, mixture);
  EXPECT_NE(xyz.str().find(":type:S:1"), std::string::npos);
  EXPECT_NE(xyz.str().find("\nHe "), std::string::npos);
  std::istringstream xyz_in(xyz.str());
  const std::vector<Frame> xyz_frames = read_xyz_frames(xyz_in, "m.xyz");
  EXPECT_EQ(xyz_frames.front().type_names, mixture.type_names);
  EXPECT_EQ(xyz_frames.front().type, types);
  // LAMMPS: type index + 1.
  std::ostringstream lammps;
  trajectory_format_for<2>("m.lammpstrj")->frame(lammps, 0, 0.0, mixture);
  std::istringstream lines(lammps.str());
  std::string line;
  while (std::getline(lines, line) && line.rfind("ITEM: ATOMS", 0) != 0) {
  }
  for (std::size_t i = 0; i < mixture.size(); ++i) {
    ASSERT_TRUE(std::getline(lines, line));
    std::istringstream words(line);
    std::size_t id = 0, type = 0;
    words >> id >> type;
    EXPECT_EQ(id, i + 1);
    EXPECT_EQ(type, types[i] + 1);
  }
  // One type: H throughout, no type column, no types on read back.
  InitialOptions one = o;
  one.species.clear();
  std::ostringstream plain;
  trajectory_format_for<2>("m.xyz")->frame(plain, 0, 0.0, make_initial<2>(one));
  EXPECT_EQ(plain.str().find("type"), std::string::npos);
  std::istringstream plain_in(plain.str());
  EXPECT_TRUE(read_xyz_frames(plain_in, "m.xyz").front().type.empty());
}

TEST(Species, PartialPairDistributionsAddUpToTheTotal) {
  InitialOptions o = binary(400, 0.4, 3);
  o.boundary = Boundary::periodic;
  o.placement = Placement::random;
  Simulation<2> simulation(make_initial<2>(o), {{Rule::elastic}});
  std::vector<Frame> frames;
  const TempFile gsd("partial.gsd");
  {
    std::ofstream file(gsd.path, std::ios::binary);
    auto format = trajectory_format_for<2>(gsd.path.string());
    for (int k = 0; k < 4; ++k) {
      simulation.run_until(k);
      format->frame(file, static_cast<std::uint64_t>(k), k, simulation.state());
    }
  }
  const Rdf rdf = radial_distribution(read_gsd_frames(gsd.path.string()));
  ASSERT_EQ(rdf.partial_names, (std::vector<std::string>{"A-A", "A-B", "B-B"}));
  ASSERT_EQ(rdf.partial.size(), 3u);
  const double n = 400.0, a = 200.0, b = 200.0;
  EXPECT_DOUBLE_EQ(rdf.partial_weights[0], a * (a - 1) / (n * (n - 1)));
  EXPECT_DOUBLE_EQ(rdf.partial_weights[1], 2 * a * b / (n * (n - 1)));
  double weights = 0.0;
  for (const double w : rdf.partial_weights) weights += w;
  EXPECT_NEAR(weights, 1.0, 1e-15);
  bool contact_differs = false;
  for (std::size_t bin = 0; bin < rdf.r.size(); ++bin) {
    double sum = 0.0;
    for (std::size_t k = 0; k < 3; ++k) sum += rdf.partial_weights[k] * rdf.partial[k][bin];
    EXPECT_NEAR(sum, rdf.g[bin], 1e-12) << rdf.r[bin];
    // No A-A pair closer than 1.0, no B-B closer than 1.4; A-B from 1.2.
    const double top = rdf.r[bin] + 0.5 * rdf.bin_width;
    for (std::size_t pair = 0; pair < 3; ++pair) {
      if (top < 1.0 + 0.2 * static_cast<double>(pair)) {
        EXPECT_EQ(rdf.partial[pair][bin], 0.0) << pair;
      }
    }
    contact_differs = contact_differs || rdf.partial[0][bin] != rdf.partial[2][bin];
  }
  EXPECT_TRUE(contact_differs);
  // One type: no partials.
  std::vector<Frame> one = read_gsd_frames(gsd.path.string());
  for (Frame& f : one) f.type.clear(), f.type_names.clear();
  EXPECT_TRUE(radial_distribution(one).partial.empty());
}

}  // namespace
}  // namespace carom

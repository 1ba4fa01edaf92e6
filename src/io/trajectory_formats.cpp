// The trajectory formats carom writes (extended XYZ, LAMMPS dumps; GSD in gsd_writer.cpp) and
// trajectory_format_for, the one place that picks among them by a file's name.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "carom/core/physics.hpp"
#include "carom/engine/engine.hpp"
#include "carom/io/trajectory.hpp"
#include "carom/io/trajectory_kind.hpp"
#include "gsd_format.hpp"
#include "whole_lines.hpp"

namespace carom {

namespace {

// x y z of a position or velocity: disks lie in the plane z = 0.
template <std::size_t D>
std::string xyz(const Vec<D>& v) {
  return D == 3 ? fmt::format("{} {} {}", v[0], v[1], v[D - 1])
                : fmt::format("{} {} 0", v[0], v[1]);
}

// The species column of a type in an extended XYZ file: a chemical symbol (ASE and OVITO read
// the column as elements), H for type 0 (as every one-type file has), He for 1, ..., X past the
// list; the type's own name is the `type` column's.
std::string_view element_of(std::uint32_t type) {
  static constexpr std::string_view kElements[] = {
      "H",  "He", "Li", "Be", "B",  "C", "N",  "O",  "F",  "Ne", "Na", "Mg", "Al",
      "Si", "P",  "S",  "Cl", "Ar", "K", "Ca", "Sc", "Ti", "V",  "Cr", "Mn", "Fe"};
  return type < std::size(kElements) ? kElements[type] : std::string_view("X");
}

// A text format: a frame header, then one line a particle.
template <std::size_t D>
class TextFormat : public TrajectoryFormat<D> {
 private:
  using Velocities = typename TrajectoryFormat<D>::Velocities;
  void write_frame(std::ostream& out, std::uint64_t index, double t, const System<D>& system,
                   Velocities velocities) override {
    header(out, index, t, system);
    const double at = system.stored(t);
    const bool typed = has_types(system);
    for (std::size_t i = 0; i < system.size(); ++i) {
      std::array<std::int32_t, 3> image = system.records[i].image;
      Particle<D> now = synchronised(system.particles[i], system.box, at, image);
      if (velocities == Velocities::at_rest) now.velocity = Vec<D>{};
      line(
          out, i, now, system.records[i], image,
          typed ? std::string_view(system.type_names[system.records[i].type]) : std::string_view());
    }
  }

  virtual void header(std::ostream& out, std::uint64_t index, double t,
                      const System<D>& system) = 0;
  // `p` is the particle at the frame's time, wrapped into a periodic box (see synchronised), and
  // `image` its image flags then (see ParticleRecord::image).
  // `type` is the particle's type name in a system with types (has_types), else empty.
  virtual void line(std::ostream& out, std::size_t index, const Particle<D>& p,
                    const ParticleRecord& record, const std::array<std::int32_t, 3>& image,
                    std::string_view type) = 0;
};

// Extended XYZ: the box as a lattice (z of thickness 1 for disks), per-particle species,
// position, velocity, radius and collision count, the periodic axes and the time.
template <std::size_t D>
class ExtendedXyz final : public TextFormat<D> {
 public:
  std::uint64_t whole_frames_before(std::istream& in, double t, bool inclusive, double) override {
    LineReader reader{in, 0, {}};
    std::uint64_t kept = 0;
    try {
      while (reader.next()) {
        const std::uint64_t count = std::stoull(reader.line);
        if (!reader.next()) break;
        const auto at = reader.line.find("Time=");
        if (at == std::string::npos) break;
        const double frame_time = std::stod(reader.line.substr(at + 5));
        if (!reader.skip(count) || !written_before(frame_time, t, inclusive)) break;
        kept = reader.offset;
      }
    } catch (const std::exception&) {
      // A line that does not parse ends the frames worth keeping.
    }
    return kept;
  }

 private:
  // A sheared box's lattice is that of its images at the frame's time: the second vector
  // (shift, Ly, 0), a tilted cell as ASE and OVITO read it.
  void header(std::ostream& out, std::uint64_t, double t, const System<D>& system) override {
    const Vec<D>& L = system.box.size;
    const double lz = D == 3 ? L[D - 1] : 1.0;
    const char* pbc = !system.box.periodic() ? "F F F" : D == 3 ? "T T T" : "T T F";
    out << fmt::format(
        "{}\nLattice=\"{} 0 0 {} {} 0 0 0 {}\" "
        "Properties=species:S:1:pos:R:3:velo:R:3:radius:R:1:collisions:I:1:masses:R:1:"
        "momenta:R:3:image:I:3{} pbc=\"{}\" Time={}{}\n",
        system.size(), L[0], shown_shift(system.box, system.stored(t)), L[1], lz,
        has_types(system) ? ":type:S:1" : "", pbc, t,
        has_types(system) ? fmt::format(" types={}", fmt::join(system.type_names, ","))
                          : std::string());
  }
  // masses and momenta are the columns ASE reads get_masses() and get_velocities() from (velo is
  // OVITO's); image unwraps pos as pos + image . the lattice.
  // A mixture's lines end with the type's name (the species column is its element_of).
  void line(std::ostream& out, std::size_t, const Particle<D>& p, const ParticleRecord& record,
            const std::array<std::int32_t, 3>& image, std::string_view type) override {
    out << fmt::format("{} {} {} {} {} {} {} {} {} {}", element_of(record.type), xyz(p.position),
                       xyz(p.velocity), p.radius, record.wall_collisions + record.pair_collisions,
                       record.mass, xyz(record.mass * p.velocity), image[0], image[1], image[2]);
    if (!type.empty()) out << ' ' << type;
    out << '\n';
  }
};

// LAMMPS text dump: TIMESTEP is the frame number (LAMMPS steps are integers; the time is the
// frame number times the frame interval), ids count from 1 as in LAMMPS; disks span z in
// [-0.5, 0.5].
template <std::size_t D>
class LammpsDump final : public TextFormat<D> {
 public:
  std::uint64_t whole_frames_before(std::istream& in, double t, bool inclusive,
                                    double every) override {
    LineReader reader{in, 0, {}};
    std::uint64_t kept = 0;
    try {
      while (reader.next() && reader.line.rfind("ITEM: TIMESTEP", 0) == 0) {
        if (!reader.next()) break;
        const double frame_time = static_cast<double>(std::stoull(reader.line)) * every;
        if (!reader.skip(1) || !reader.next()) break;
        const std::uint64_t count = std::stoull(reader.line);
        if (!reader.skip(5 + count) || !written_before(frame_time, t, inclusive)) break;
        kept = reader.offset;
      }
    } catch (const std::exception&) {
      // A line that does not parse ends the frames worth keeping.
    }
    return kept;
  }

 private:
  // A sheared box is written as LAMMPS' triclinic one, whose tilt xy is the images' shift: the
  // x bounds are then those of the box that holds the tilted cell, and each bound line ends in
  // a tilt factor (xy, xz = 0, yz = 0).
  void header(std::ostream& out, std::uint64_t index, double t, const System<D>& system) override {
    const Vec<D>& L = system.box.size;
    const char* bounds = system.box.periodic() ? "pp pp pp" : D == 3 ? "ff ff ff" : "ff ff pp";
    const std::string z = D == 3 ? fmt::format("0 {}", L[D - 1]) : std::string("-0.5 0.5");
    out << fmt::format("ITEM: TIMESTEP\n{}\nITEM: NUMBER OF ATOMS\n{}\n", index, system.size());
    if (system.box.sheared()) {
      const double xy = shown_shift(system.box, system.stored(t));
      out << fmt::format("ITEM: BOX BOUNDS xy xz yz {}\n{} {} {}\n0 {} 0\n{} 0\n", bounds,
                         std::min(0.0, xy), L[0] + std::max(0.0, xy), xy, L[1], z);
    } else {
      out << fmt::format("ITEM: BOX BOUNDS {}\n0 {}\n0 {}\n{}\n", bounds, L[0], L[1], z);
    }
    out << "ITEM: ATOMS id type x y z vx vy vz radius mass ix iy iz\n";
  }
  // LAMMPS types count from 1: type index + 1 (the names are not LAMMPS').
  void line(std::ostream& out, std::size_t index, const Particle<D>& p,
            const ParticleRecord& record, const std::array<std::int32_t, 3>& image,
            std::string_view) override {
    out << fmt::format("{} {} {} {} {} {} {} {} {}\n", index + 1, record.type + 1, xyz(p.position),
                       xyz(p.velocity), p.radius, record.mass, image[0], image[1], image[2]);
  }
};

}  // namespace

template <std::size_t D>
std::unique_ptr<TrajectoryFormat<D>> trajectory_format_for(const std::string& path) {
  if (const std::optional<TrajectoryKind> kind = trajectory_kind_of(path)) {
    switch (*kind) {
      case TrajectoryKind::xyz:
        return std::make_unique<ExtendedXyz<D>>();
      case TrajectoryKind::lammpstrj:
        return std::make_unique<LammpsDump<D>>();
      case TrajectoryKind::gsd:
        return std::make_unique<GsdFormat<D>>();
    }
  }
  throw std::invalid_argument(fmt::format(
      "cannot tell the trajectory format of '{}': name it .xyz (extended XYZ), .lammpstrj "
      "(LAMMPS dump) or .gsd (HOOMD-blue's GSD)",
      path));
}

template std::unique_ptr<TrajectoryFormat<2>> trajectory_format_for(const std::string&);
template std::unique_ptr<TrajectoryFormat<3>> trajectory_format_for(const std::string&);

}  // namespace carom

#include "carom/trajectory.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "carom/physics.hpp"

namespace carom {

namespace {

// Extended XYZ: the box as a lattice (z of thickness 1), per-disk species, position, velocity
// and radius, the periodic axes and the time.
class ExtendedXyz final : public TrajectoryWriter {
  void header(std::ostream& out, double t, const System<2>& system) override {
    out << fmt::format(
        "{}\nLattice=\"{} 0 0 0 {} 0 0 0 1\" "
        "Properties=species:S:1:pos:R:3:velo:R:3:radius:R:1:collisions:I:1 pbc=\"{}\" "
        "Time={}\n",
        system.particles.size(), system.box.size[0], system.box.size[1],
        system.box.periodic() ? "T T F" : "F F F", t);
  }
  void line(std::ostream& out, std::size_t, const Vec<2>& at, const Particle<2>& p) override {
    out << fmt::format("H {} {} 0 {} {} 0 {} {}\n", at[0], at[1], p.velocity[0], p.velocity[1],
                       p.radius, p.wall_collisions + p.pair_collisions);
  }
};

// LAMMPS text dump: TIMESTEP is the frame number (LAMMPS steps are integers; the time is the
// frame number times --every), ids count from 1 as in LAMMPS, z spans [-0.5, 0.5].
class LammpsDump final : public TrajectoryWriter {
  void header(std::ostream& out, double, const System<2>& system) override {
    out << fmt::format(
        "ITEM: TIMESTEP\n{}\nITEM: NUMBER OF ATOMS\n{}\nITEM: BOX BOUNDS {}\n0 {}\n0 "
        "{}\n-0.5 0.5\nITEM: ATOMS id type x y z vx vy vz radius\n",
        frames_++, system.particles.size(), system.box.periodic() ? "pp pp pp" : "ff ff pp",
        system.box.size[0], system.box.size[1]);
  }
  void line(std::ostream& out, std::size_t index, const Vec<2>& at, const Particle<2>& p) override {
    out << fmt::format("{} 1 {} {} 0 {} {} 0 {}\n", index + 1, at[0], at[1], p.velocity[0],
                       p.velocity[1], p.radius);
  }

  std::uint64_t frames_ = 0;
};

}  // namespace

void TrajectoryWriter::frame(std::ostream& out, double t, const System<2>& system) {
  header(out, t, system);
  for (std::size_t i = 0; i < system.particles.size(); ++i) {
    const Particle<2>& p = system.particles[i];
    Vec<2> at = position_at(p, t);
    wrap(at, system.box);
    line(out, i, at, p);
  }
}

std::unique_ptr<TrajectoryWriter> trajectory_writer_for(const std::string& path) {
  const auto ends_with = [&](const std::string& suffix) {
    return path.size() >= suffix.size() &&
           path.compare(path.size() - suffix.size(), suffix.size(), suffix) == 0;
  };
  if (ends_with(".xyz")) return std::make_unique<ExtendedXyz>();
  if (ends_with(".lammpstrj")) return std::make_unique<LammpsDump>();
  throw std::invalid_argument(fmt::format(
      "cannot tell the trajectory format of '{}': name it .xyz (extended XYZ) or .lammpstrj "
      "(LAMMPS dump)",
      path));
}

}  // namespace carom

#include "carom/trajectory.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "carom/physics.hpp"

namespace carom {

namespace {

Vec<2> position_in_box(const Particle<2>& p, double t, const Box<2>& box) {
  Vec<2> at = position_at(p, t);
  wrap(at, box);
  return at;
}

// Extended XYZ: the box as a lattice (z of thickness 1), per-disk species, position, velocity
// and radius, the periodic axes and the time.
class ExtendedXyz final : public TrajectoryWriter {
 public:
  void frame(std::ostream& out, double t, const System<2>& system) override {
    const Box<2>& box = system.box;
    const char* pbc = box.periodic() ? "T T F" : "F F F";
    out << fmt::format(
        "{}\nLattice=\"{} 0 0 0 {} 0 0 0 1\" "
        "Properties=species:S:1:pos:R:3:velo:R:3:radius:R:1 pbc=\"{}\" Time={}\n",
        system.particles.size(), box.size[0], box.size[1], pbc, t);
    for (const Particle<2>& p : system.particles) {
      const Vec<2> at = position_in_box(p, t, box);
      out << fmt::format("H {} {} 0 {} {} 0 {}\n", at[0], at[1], p.velocity[0], p.velocity[1],
                         p.radius);
    }
  }
};

// LAMMPS text dump: TIMESTEP is the frame number (LAMMPS steps are integers; the time is the
// frame number times --every), ids count from 1 as in LAMMPS, z spans [-0.5, 0.5].
class LammpsDump final : public TrajectoryWriter {
 public:
  void frame(std::ostream& out, double t, const System<2>& system) override {
    const Box<2>& box = system.box;
    const char* bounds = box.periodic() ? "pp pp pp" : "ff ff pp";
    out << fmt::format(
        "ITEM: TIMESTEP\n{}\nITEM: NUMBER OF ATOMS\n{}\nITEM: BOX BOUNDS {}\n0 {}\n0 "
        "{}\n-0.5 0.5\nITEM: ATOMS id type x y z vx vy vz radius\n",
        frames_++, system.particles.size(), bounds, box.size[0], box.size[1]);
    for (std::size_t i = 0; i < system.particles.size(); ++i) {
      const Particle<2>& p = system.particles[i];
      const Vec<2> at = position_in_box(p, t, box);
      out << fmt::format("{} 1 {} {} 0 {} {} 0 {}\n", i + 1, at[0], at[1], p.velocity[0],
                         p.velocity[1], p.radius);
    }
  }

 private:
  std::uint64_t frames_ = 0;
};

}  // namespace

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

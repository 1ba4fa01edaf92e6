// The trajectory formats carom writes, told apart by a file's name: the one place their endings
// are listed, so that a dump, an end state and a result table agree on what a name means.
#pragma once

#include <optional>
#include <string_view>

namespace carom {

enum class TrajectoryKind {
  xyz,        // extended XYZ (ASE, OVITO)
  lammpstrj,  // LAMMPS text dump
  gsd,        // HOOMD-blue's GSD
};

// The trajectory format a file name ends in, the ending in any case (MOVIE.XYZ is as much
// extended XYZ as movie.xyz); nullopt for any other name.
std::optional<TrajectoryKind> trajectory_kind_of(std::string_view path);

// The format's ending without its dot, lower case: "xyz", "lammpstrj", "gsd".
std::string_view extension_of(TrajectoryKind kind);

}  // namespace carom

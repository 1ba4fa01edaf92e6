#include "carom/io/trajectory_kind.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <utility>

namespace carom {

namespace {

constexpr std::array<std::pair<TrajectoryKind, std::string_view>, 3> kEndings = {{
    {TrajectoryKind::xyz, "xyz"},
    {TrajectoryKind::lammpstrj, "lammpstrj"},
    {TrajectoryKind::gsd, "gsd"},
}};

}  // namespace

std::string_view extension_of(TrajectoryKind kind) {
  return std::ranges::find(kEndings, kind, &std::pair<TrajectoryKind, std::string_view>::first)
      ->second;
}

std::optional<TrajectoryKind> trajectory_kind_of(std::string_view path) {
  for (const auto& [kind, extension] : kEndings) {
    // The dot as well: a file named "xyz" or "movie_xyz" is no extended XYZ.
    if (path.size() <= extension.size() || path[path.size() - extension.size() - 1] != '.') {
      continue;
    }
    const std::string_view end = path.substr(path.size() - extension.size());
    if (std::ranges::equal(end, extension, [](char a, char b) {
          return std::tolower(static_cast<unsigned char>(a)) == b;
        })) {
      return kind;
    }
  }
  return std::nullopt;
}

}  // namespace carom

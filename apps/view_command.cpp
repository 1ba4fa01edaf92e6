#include "view_command.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>

#include "carom/analysis/viewer.hpp"
#include "carom/io/classic_input.hpp"
#include "cli_support.hpp"

namespace carom::cli {

CLI::App* add_view_command(CLI::App& app, ViewArguments& args) {
  CLI::App* view = app.add_subcommand(
      "view",
      "Turn a trajectory (.xyz or .gsd from carom run --dump, disks or spheres) into one HTML page "
      "that animates it.");
  view->footer(
      R"(The page is self-contained (data embedded, no network) and opens from disk in any browser:
play/pause, a time slider, speed, colour by speed or by collision count, and the speed histogram
against the Maxwell-Boltzmann distribution (2D or 3D). Spheres (a trajectory with any nonzero z)
are drawn shaded and depth-sorted in their box, which dragging rotates (double-click resets).

A page above about 50 MB loads slowly in a browser: carom says so and how much --stride would
keep. --frames A:B and --stride K choose what goes in (frames counted from 0, B not included,
either end may be left out).

Examples:
  carom run gas.txt 50 --dump movie.xyz --every 0.25
  carom view movie.xyz -o movie.html
  carom view movie.xyz -o late.html --frames 100: --stride 4)");
  view->add_option("TRAJECTORY", args.trajectory, "An extended XYZ or GSD trajectory")->required();
  view->add_option("-o,--output", args.output, "The HTML file to write")->required();
  add_whole_option(view, "--stride", args.stride, std::uint64_t{1},
                   "Keep every K-th frame of those chosen")
      ->type_name("K")
      ->default_str("1");
  view->add_option("--frames", args.frames, "Keep frames A to B - 1 (A:B, A:, :B)")
      ->type_name("A:B");
  return view;
}

namespace {

// The frames --frames and --stride keep.
FrameSelection chosen(const ViewArguments& args) {
  FrameSelection selection;
  selection.stride = args.stride;
  if (args.frames.empty()) return selection;
  const std::size_t colon = args.frames.find(':');
  const auto bound = [&](const std::string& text) -> std::optional<std::size_t> {
    if (text.empty()) return std::nullopt;
    std::size_t value = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error != std::errc() || end != text.data() + text.size()) {
      throw UsageError(fmt::format("--frames takes A:B (whole numbers), got '{}'", args.frames));
    }
    return value;
  };
  if (colon == std::string::npos) {
    throw UsageError(fmt::format("--frames takes A:B (whole numbers), got '{}'", args.frames));
  }
  selection.first = bound(args.frames.substr(0, colon)).value_or(0);
  selection.last = bound(args.frames.substr(colon + 1));
  return selection;
}

}  // namespace

void view_command(const ViewArguments& args) {
  // The page is created only once the frames are read (a stop meanwhile leaves nothing), but
  // where it goes is checked first.
  if (args.output != "-") check_writable(args.output);
  check_files_apart({{"the input TRAJECTORY", args.trajectory}}, {{"-o", args.output}});
  const std::vector<Frame> frames = read_trajectory_frames(args.trajectory, chosen(args));
  if (frames.empty()) {
    throw UsageError(
        fmt::format("--frames {} keeps none of the frames of {}", args.frames, args.trajectory));
  }
  Output out(args.output);
  write_viewer_html(out.stream(), frames);
  const std::streamoff bytes = out.stream().tellp();
  out.commit();
  constexpr double kSlowPage = 50e6;
  if (bytes > 0 && static_cast<double>(bytes) > kSlowPage) {
    const auto stride =
        static_cast<std::uint64_t>(std::ceil(static_cast<double>(bytes) / kSlowPage));
    std::cerr << fmt::format(
        "carom: note: {} is {:.0f} MB ({} frames of {} particles) and will load slowly in a "
        "browser: --stride {} (one frame in {}) makes it about {:.0f} MB, and --frames A:B keeps "
        "a part\n",
        args.output, static_cast<double>(bytes) / 1e6, frames.size(), frames.front().radius.size(),
        args.stride * stride, args.stride * stride,
        static_cast<double>(bytes) / 1e6 / static_cast<double>(stride));
  }
}

}  // namespace carom::cli

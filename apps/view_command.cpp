#include "view_command.hpp"

#include <fmt/format.h>

#include "carom/classic_input.hpp"
#include "carom/viewer.hpp"
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

Example:
  carom run gas.txt 50 --rule elastic --dump movie.xyz --every 0.25
  carom view movie.xyz -o movie.html)");
  view->add_option("TRAJECTORY", args.trajectory, "An extended XYZ or GSD trajectory")->required();
  view->add_option("-o,--output", args.output, "The HTML file to write")->required();
  return view;
}

void view_command(const ViewArguments& args) {
  // The page is created only once the frames are read (a stop meanwhile leaves nothing), but
  // where it goes is checked first.
  if (args.output != "-") check_writable(args.output);
  const std::vector<Frame> frames = read_trajectory_frames(args.trajectory);
  Output out(args.output);
  write_viewer_html(out.stream(), frames);
  out.commit();
}

}  // namespace carom::cli

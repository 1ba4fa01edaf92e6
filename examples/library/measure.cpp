// measure FILE: the README's library example. Runs the disks of a classic file (periodic box,
// elastic collisions) to t = 100 with a frame every 0.5 in movie.xyz, measures from t = 50 on,
// and prints Z, kT and every disk's final state as csv.
#include <carom/classic_input.hpp>
#include <carom/formats.hpp>
#include <carom/simulation.hpp>
#include <carom/trajectory.hpp>
#include <exception>
#include <fstream>
#include <iostream>
#include <memory>

int main(int argc, char** argv) try {
  const char* path = argc > 1 ? argv[1] : "gas.txt";
  carom::System<2> gas = carom::read_classic_file<2>(path, carom::Boundary::periodic).system;
  carom::Settings settings;  // defaults: swap rule, restitution 1, TC 1e-5, fast engine
  settings.rule.rule = carom::Rule::elastic;
  carom::Simulation<2> sim(std::move(gas), settings);

  std::ofstream movie("movie.xyz");  // a frame every 0.5, written and flushed as the run goes
  sim.add_observer(std::make_shared<carom::FrameWriter<2>>(
      movie, carom::trajectory_format_for<2>("movie.xyz"), 0.5));
  sim.measure_from(50.0);  // equilibrate, then measure
  sim.run_until(100.0);    // any cutting into pieces gives the same run, bit for bit

  const carom::Observables<2> o = sim.observables();
  std::cout << "Z = " << o.compressibility_factor << ", kT = " << o.temperature << '\n';
  carom::write_csv<2>(std::cout, sim.snapshot(), sim.state().records);  // every disk at t = 100
  return 0;
} catch (const std::exception& e) {
  std::cerr << "measure: " << e.what() << '\n';
  return 2;
}

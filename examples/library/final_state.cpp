// final_state FILE END_TIME: runs the disks of a classic input file (the classic assignment's
// rules: walls, disks that swap velocities) up to END_TIME and prints the final state as csv lines
// `x, y, cwall, cpart`, one per disk: what `carom run FILE END_TIME --format csv` prints.
//
// It uses carom through its installed public headers only. Exit codes: 0 done, 1 the output
// could not be written, 2 bad arguments or input (with a message on stderr).
#include <carom/engine/simulation.hpp>  // Simulation, Settings
#include <carom/io/classic_input.hpp>   // read_classic_file, parse_finite_double, InputError
#include <carom/io/classic_output.hpp>  // write_csv
#include <exception>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: final_state FILE END_TIME\n";
    return 2;
  }
  try {
    // The file is read and checked (counts, numbers, disks inside the box and not overlapping);
    // anything wrong throws carom::InputError naming the file and the line.
    const carom::ClassicInput<2> input = carom::read_classic_file<2>(argv[1]);

    // END_TIME as the CLI reads it: a finite number (`20`, `1e2`, `+.5`) and not negative.
    double end_time = 0.0;
    try {
      end_time = carom::parse_finite_double(argv[2]);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("END_TIME: ") + e.what());  // "'x' is not a number"
    }
    if (end_time < 0.0) {
      throw std::invalid_argument("END_TIME must not be negative, got " + std::string(argv[2]));
    }

    // A run from t = 0 with the default settings (the classic assignment's swap rule, the fast
    // engine).
    carom::Simulation<2> simulation(input.system, carom::Settings{});
    // Processes every event up to end_time; throws carom::RunLengthError for a time the run
    // could never reach.
    simulation.run_until(end_time);

    // snapshot(): every disk brought to end_time (the stored states are the lazy ones, at each
    // disk's last collision); the records hold the collision counts, index for index.
    const std::vector<carom::Particle<2>> now = simulation.snapshot();
    carom::write_csv<2>(std::cout, now, simulation.state().records);
  } catch (const carom::InputError& e) {
    std::cerr << "final_state: " << e.what() << '\n';
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "final_state: " << e.what() << '\n';
    return 2;
  }
  if (!std::cout.flush()) {
    std::cerr << "final_state: cannot write the output\n";
    return 1;
  }
  return 0;
}

// Reading back what a run wrote as it went (trajectories, event logs), so that a resumed run
// keeps exactly the whole lines written before its checkpoint.
#pragma once

#include <cstdint>
#include <istream>
#include <string>

namespace carom {

// Reads whole lines, tracking the offset after the last one read; false at the end or at a
// final line without its newline (cut off by a crash).
struct LineReader {
  std::istream& in;
  std::uint64_t offset = 0;
  std::string line;

  bool next() {
    if (!std::getline(in, line) || in.eof()) return false;
    offset += line.size() + 1;
    return true;
  }
  bool skip(std::uint64_t lines) {
    for (std::uint64_t i = 0; i < lines; ++i) {
      if (!next()) return false;
    }
    return true;
  }
};

// Whether something written at `written` belongs before a checkpoint at `t`: earlier, or at `t`
// itself when the checkpoint's run was whole at `t` (Simulation::settled).
inline bool written_before(double written, double t, bool inclusive) {
  return written < t || (inclusive && written == t);
}

}  // namespace carom

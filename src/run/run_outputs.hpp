// The files a run streams as it goes (frames, the event log, the time series): opened, continued
// after a resume, kept open from one run to the next that names them again, flushed and closed.
// Private to the library: Runner (run.hpp) is how a run gets them.
#pragma once

#include <fstream>
#include <functional>
#include <memory>
#include <string>

#include "carom/engine/simulation.hpp"
#include "carom/run/run.hpp"

namespace carom {

template <std::size_t D>
class RunOutputs {
 public:
  // `continued`: files that exist continue (a run continuing a checkpoint), cut to what they hold
  // up to the simulation's time; otherwise they begin anew.
  RunOutputs(Simulation<D>& simulation, bool continued)
      : simulation_(simulation), continued_(continued) {}
  ~RunOutputs();
  RunOutputs(const RunOutputs&) = delete;
  RunOutputs& operator=(const RunOutputs&) = delete;

  // Makes the streamed files those `spec` names: one already open with the same path and
  // cadence stays open (and goes on), the others are closed, and the new ones opened (continued
  // when `continued`). Throws RequestError for a file that cannot be written or continued.
  void update(const RunSpec& spec);
  // Flushes every open file; false if any write failed.
  bool flush();
  void close_all();

 private:
  struct Stream {
    std::string path;
    double every = 0.0;
    std::ofstream file;
    std::shared_ptr<Observer<D>> observer;
    bool open() const { return observer != nullptr; }
  };
  void close(Stream& stream);
  // Opens `path` for `stream`: anew, or (continued and the file exists) cut to the length `keep`
  // finds in it and opened at its end for writing on (and for rewriting in place what a binary
  // format must: a GSD file's index).
  void open(Stream& stream, const std::string& path, double every,
            const std::function<std::uint64_t(std::istream&)>& keep);

  Simulation<D>& simulation_;
  bool continued_;
  Stream frames_, events_, log_;
};

}  // namespace carom

#include "run_outputs.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "carom/io/event_log.hpp"
#include "carom/io/time_series.hpp"
#include "carom/io/trajectory.hpp"
#include "carom/run/request.hpp"

namespace carom {

template <std::size_t D>
RunOutputs<D>::~RunOutputs() {
  close_all();
}

template <std::size_t D>
void RunOutputs<D>::close(Stream& stream) {
  if (!stream.open()) return;
  simulation_.remove_observer(stream.observer.get());
  stream = Stream();
}

template <std::size_t D>
void RunOutputs<D>::close_all() {
  close(frames_);
  close(events_);
  close(log_);
}

template <std::size_t D>
bool RunOutputs<D>::flush() {
  bool ok = true;
  for (Stream* stream : {&frames_, &events_, &log_}) {
    if (stream->open()) ok = static_cast<bool>(stream->file.flush()) && ok;
  }
  return ok;
}

template <std::size_t D>
void RunOutputs<D>::open(Stream& stream, const std::string& path, double every,
                         const std::function<std::uint64_t(std::istream&)>& keep) {
  namespace fs = std::filesystem;
  std::error_code error;
  auto mode = std::ios::binary | std::ios::trunc;
  if (continued_ && fs::is_regular_file(path, error)) {
    std::uint64_t kept = 0;
    {
      std::ifstream in(path, std::ios::binary);
      try {
        kept = keep(in);
      } catch (const std::invalid_argument& e) {  // a file that cannot be continued
        throw RequestError(fmt::format("cannot continue '{}': {}", path, e.what()));
      }
    }
    fs::resize_file(path, kept, error);
    if (error) throw RequestError(fmt::format("cannot continue '{}': {}", path, error.message()));
    mode = std::ios::binary | std::ios::in | std::ios::out;
  }
  stream.file.open(path, mode);
  stream.file.seekp(0, std::ios::end);
  if (!stream.file) {
    throw RequestError(fmt::format("cannot write '{}': {}", path, std::strerror(errno)));
  }
  stream.path = path;
  stream.every = every;
}

template <std::size_t D>
void RunOutputs<D>::update(const RunSpec& spec) {
  const auto stays = [](const Stream& stream, const std::string& path, double every) {
    return stream.open() && stream.path == path && stream.every == every;
  };
  if (!stays(frames_, spec.dump, spec.dump_every)) close(frames_);
  if (!stays(events_, spec.events, 0.0)) close(events_);
  if (!stays(log_, spec.log, spec.log_every)) close(log_);
  for (const std::string* path : {&spec.dump, &spec.events, &spec.log}) {
    if (!path->empty()) check_writable(*path);
  }
  const double t = simulation_.time();
  const bool inclusive = simulation_.settled();
  if (!spec.dump.empty() && !frames_.open()) {
    std::unique_ptr<TrajectoryFormat<D>> format;
    try {
      format = trajectory_format_for<D>(spec.dump);
    } catch (const std::invalid_argument& e) {
      throw RequestError(e.what());
    }
    open(frames_, spec.dump, spec.dump_every, [&](std::istream& in) {
      return format->whole_frames_before(in, t, inclusive, spec.dump_every);
    });
    format->continue_after_cut(frames_.file);
    if (!frames_.file) throw RequestError(fmt::format("cannot continue '{}'", spec.dump));
    // A file that begins here (not one a continued run continues) starts with a frame now, when
    // now is on its grid.
    const bool fresh = frames_.file.tellp() == 0;
    frames_.observer =
        std::make_shared<FrameWriter<D>>(frames_.file, std::move(format), spec.dump_every);
    simulation_.add_observer(
        frames_.observer, fresh ? Simulation<D>::FirstLook::now : Simulation<D>::FirstLook::next);
  }
  if (!spec.events.empty() && !events_.open()) {
    open(events_, spec.events, 0.0,
         [&](std::istream& in) { return EventLogWriter<D>::events_before(in, t, inclusive); });
    if (events_.file.tellp() == 0) events_.file << EventLogWriter<D>::kHeader;
    events_.observer = std::make_shared<EventLogWriter<D>>(events_.file);
    simulation_.add_observer(events_.observer);
  }
  if (!spec.log.empty() && !log_.open()) {
    auto writer = std::make_shared<TimeSeriesWriter<D>>(log_.file, spec.log_every);
    open(log_, spec.log, spec.log_every,
         [&](std::istream& in) { return writer->resume(in, t, inclusive, simulation_); });
    if (log_.file.tellp() == 0) {
      log_.file << TimeSeriesWriter<D>::header(simulation_.settings().sampler.kind);
    }
    log_.observer = std::move(writer);
    simulation_.add_observer(log_.observer);
  }
}

template class RunOutputs<2>;
template class RunOutputs<3>;

}  // namespace carom

#include "carom/time_series.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include "carom/classic_input.hpp"
#include "carom/observables.hpp"
#include "whole_lines.hpp"

namespace carom {

std::pair<double, double> mean_and_variance_of_mean(std::span<const double> values) {
  const auto n = static_cast<double>(values.size());
  double mean = 0.0, squares = 0.0;
  for (const double x : values) mean += x / n;
  for (const double x : values) squares += (x - mean) * (x - mean);
  return {mean, squares / (n - 1.0) / n};
}

void BlockAverage::add(double value) {
  for (std::size_t level = 0;; ++level) {
    if (level == levels_.size()) levels_.emplace_back();
    Level& here = levels_[level];
    here.sum += value;
    here.sum_of_squares += value * value;
    ++here.count;
    if (!here.has_waiting) {
      here.waiting = value;
      here.has_waiting = true;
      return;
    }
    value = 0.5 * (here.waiting + value);  // a block of the next level
    here.has_waiting = false;
  }
}

double BlockAverage::mean() const {
  if (count() == 0) return std::numeric_limits<double>::quiet_NaN();
  return levels_.front().sum / static_cast<double>(levels_.front().count);
}

double BlockAverage::error() const {
  const auto standard_error = [](const Level& level) {
    const auto n = static_cast<double>(level.count);
    const double variance = (level.sum_of_squares - level.sum * level.sum / n) / (n - 1.0);
    return std::sqrt(std::max(variance, 0.0) / n);
  };
  if (count() < 2) return std::numeric_limits<double>::quiet_NaN();
  double largest = standard_error(levels_.front());
  for (const Level& level : levels_) {
    if (level.count >= kLeastBlocks) largest = std::max(largest, standard_error(level));
  }
  return largest;
}

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

Counts difference(const Counts& later, const Counts& earlier) {
  return {later.events - earlier.events,
          later.wall_collisions - earlier.wall_collisions,
          later.pair_collisions - earlier.pair_collisions,
          later.elastic_by_tc - earlier.elastic_by_tc,
          later.virial - earlier.virial,
          later.wall_momentum - earlier.wall_momentum,
          later.fluxes && earlier.fluxes
              ? std::optional<Fluxes>(flux_difference(*later.fluxes, *earlier.fluxes))
              : std::nullopt};
}

// A value in full precision (it reads back as the same double), or an empty field.
std::string field(double value, bool present = true) {
  return present && !std::isnan(value) ? fmt::format("{}", value) : std::string();
}

// When the measurement window opened, or none while equilibration goes on.
template <std::size_t D>
std::optional<double> window(const Simulation<D>& simulation) {
  if (simulation.pending_measurement()) return std::nullopt;
  return simulation.measurement().start_time;
}

}  // namespace

template <std::size_t D>
void TimeSeriesWriter<D>::take(const Row& row, std::optional<double> window_start) {
  if (window_start != window_start_) {  // a new measurement window (or none yet): new averages
    window_start_ = window_start;
    pressure_.clear();
    z_.clear();
  }
  if (row.measured && started_ && window_start_ && last_.time >= *window_start_) {
    pressure_.add(row.pressure);
    z_.add(row.z);
  }
  last_ = row;
  started_ = true;
}

template <std::size_t D>
std::string TimeSeriesWriter<D>::header() {
  std::string text = kHeader;
  text.pop_back();
  for (const char* prefix : {"p", "G"}) {
    for (const std::size_t c : tensor_components<D>()) {
      text += fmt::format(",{}{}", prefix, kTensorComponents[c]);
    }
  }
  return text + "\n";
}

template <std::size_t D>
void TimeSeriesWriter<D>::observe(const Simulation<D>& simulation) {
  const System<D>& system = simulation.state();
  Row row{simulation.time(), simulation.current_counts(), 0.0, 0.0, false};
  double rate = 0.0;
  std::optional<SymmetricTensor> tensor;
  if (started_ && row.time > last_.time) {
    const Measurement interval{last_.time, 0.0, difference(row.totals, last_.totals), std::nullopt};
    const Observables<D> o = measure(system, interval, row.time);
    row.pressure = o.pressure;
    row.z = o.compressibility_factor;
    row.measured = true;
    rate = o.collision_rate;
    if (row.totals.fluxes && last_.totals.fluxes) {
      tensor =
          pressure_tensor_between(*row.totals.fluxes, *last_.totals.fluxes, box_volume(system.box));
    }
  }
  take(row, window(simulation));
  const Counts& c = row.totals;
  std::string line = fmt::format(
      "{},{},{},{},{},{},{},{},{},{},{},{},{}", row.time, c.events, c.pair_collisions,
      field(c.virial), field(c.wall_momentum), field(kinetic_temperature(system)),
      field(row.pressure, row.measured), field(row.z, row.measured), field(rate, row.measured),
      field(pressure_.mean()), field(pressure_.error()), field(z_.mean()), field(z_.error()));
  const SymmetricTensor moment =
      c.fluxes ? c.fluxes->stress_moment() : SymmetricTensor{kNaN, kNaN, kNaN, kNaN, kNaN, kNaN};
  for (const std::size_t k : tensor_components<D>())
    line += "," + field(tensor ? (*tensor)[k] : kNaN);
  for (const std::size_t k : tensor_components<D>()) line += "," + field(moment[k]);
  out_ << line << '\n';
  if (!out_.flush()) throw std::runtime_error("cannot write the time series");
}

template <std::size_t D>
std::uint64_t TimeSeriesWriter<D>::resume(std::istream& in, double t, bool inclusive,
                                          const Simulation<D>& simulation) {
  LineReader reader{in, 0, {}};
  if (!reader.next() || reader.line + "\n" != header()) return 0;
  std::uint64_t kept = reader.offset;
  const std::optional<double> window_start = window(simulation);
  constexpr std::size_t kComponents = tensor_components<D>().size();
  while (reader.next()) {
    // time,events,pair_collisions,virial,wall_momentum,temperature,pressure,Z,...
    std::vector<std::string> fields;
    for (std::size_t from = 0;;) {
      const std::size_t comma = reader.line.find(',', from);
      fields.push_back(reader.line.substr(from, comma - from));
      if (comma == std::string::npos) break;
      from = comma + 1;
    }
    if (fields.size() != 13 + 2 * kComponents) break;
    const auto number = [](const std::string& text, double& value) {
      char* end = nullptr;
      value = std::strtod(text.c_str(), &end);
      return !text.empty() && *end == '\0';
    };
    const auto whole = [](const std::string& text, std::uint64_t& value) {
      char* end = nullptr;
      value = std::strtoull(text.c_str(), &end, 10);
      return !text.empty() && text.front() != '-' && *end == '\0';
    };
    Row row;
    if (!number(fields[0], row.time) || !written_before(row.time, t, inclusive) ||
        !whole(fields[1], row.totals.events) || !whole(fields[2], row.totals.pair_collisions) ||
        !number(fields[3], row.totals.virial) || !number(fields[4], row.totals.wall_momentum)) {
      break;
    }
    row.measured = number(fields[6], row.pressure) && number(fields[7], row.z);
    // The moment's kinetic and collisional parts only matter summed: kept as one.
    Fluxes fluxes;
    fluxes.time = row.time;
    for (std::size_t m = 0; m < kComponents; ++m) {
      if (!number(fields[13 + kComponents + m], fluxes.kinetic_stress[tensor_components<D>()[m]])) {
        return kept;
      }
    }
    row.totals.fluxes = fluxes;
    take(row, window_start);
    kept = reader.offset;
  }
  return kept;
}

template class TimeSeriesWriter<2>;
template class TimeSeriesWriter<3>;

template <std::size_t D>
void ZDrift<D>::observe(const Simulation<D>& simulation) {
  const double now = simulation.time();
  const bool measuring = !simulation.pending_measurement();
  std::optional<double>& last_time = record_.last_time;
  if (last_time && measuring && *last_time >= simulation.measurement().start_time &&
      now > *last_time) {
    const Measurement interval{*last_time, 0.0,
                               difference(simulation.current_counts(), record_.last_totals),
                               std::nullopt};
    const Observables<D> o = measure(simulation.state(), interval, now);
    if (std::isfinite(o.compressibility_factor)) record_.z.push_back(o.compressibility_factor);
    if (o.pressure_tensor) record_.pressure_tensors.push_back(*o.pressure_tensor);
  }
  last_time = now;
  record_.last_totals = simulation.current_counts();
}

template <std::size_t D>
std::optional<DriftVerdict> ZDrift<D>::verdict() const {
  const std::vector<double>& z_ = record_.z;
  const std::size_t half = z_.size() / 2;
  if (half < kLeastPerHalf) return std::nullopt;
  // The halves' means and the squared standard errors of those means; the middle interval of an
  // odd count is in neither half.
  const std::span<const double> z(z_);
  const auto [first, first_variance] = mean_and_variance_of_mean(z.first(half));
  const auto [second, second_variance] = mean_and_variance_of_mean(z.last(half));
  const double error = std::sqrt(first_variance + second_variance);
  const double sigmas = error > 0.0 ? (second - first) / error : 0.0;
  return DriftVerdict{first, second, sigmas, z_.size()};
}

template <std::size_t D>
std::optional<SymmetricTensor> ZDrift<D>::pressure_tensor_error() const {
  const std::vector<SymmetricTensor>& tensors = record_.pressure_tensors;
  if (tensors.size() < 2 * kLeastPerHalf) return std::nullopt;
  SymmetricTensor error{};
  std::vector<double> component(tensors.size());
  for (std::size_t c = 0; c < 6; ++c) {
    for (std::size_t i = 0; i < tensors.size(); ++i) component[i] = tensors[i][c];
    error[c] = std::sqrt(mean_and_variance_of_mean(component).second);
  }
  return error;
}

template class ZDrift<2>;
template class ZDrift<3>;

LogTable read_log_table(const std::string& path) {
  std::ifstream in = open_input(path);
  LogTable table;
  table.file = path;
  const auto fields = [](const std::string& line) {
    std::vector<std::string> out;
    std::stringstream split(line);
    for (std::string field; std::getline(split, field, ',');) out.push_back(field);
    if (!line.empty() && line.back() == ',') out.emplace_back();
    return out;
  };
  std::string line;
  std::size_t number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (number == 1) {
      table.columns = fields(line);
      if (table.columns.empty() || table.columns.front() != "time") {
        throw InputError(path, number, "not a carom log: the header does not start with 'time'");
      }
      continue;
    }
    if (line.empty()) continue;
    const std::vector<std::string> row = fields(line);
    if (row.size() != table.columns.size()) {
      throw InputError(
          path, number,
          fmt::format("expected {} fields, found {}", table.columns.size(), row.size()));
    }
    std::vector<double>& values = table.rows.emplace_back();
    for (std::size_t c = 0; c < row.size(); ++c) {
      if (row[c].empty()) {
        values.push_back(std::numeric_limits<double>::quiet_NaN());
        continue;
      }
      try {
        values.push_back(parse_finite_double(row[c]));
      } catch (const std::invalid_argument& e) {
        throw InputError(path, number, fmt::format("{} (in {})", e.what(), table.columns[c]));
      }
    }
  }
  if (in.bad()) throw InputError(path, number + 1, "read error");
  if (table.columns.empty()) throw InputError(path, 0, "empty: not a carom log");
  return table;
}

}  // namespace carom

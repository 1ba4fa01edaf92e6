#include "carom/io/time_series.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include "carom/core/observables.hpp"
#include "whole_lines.hpp"

namespace carom {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

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
std::string TimeSeriesWriter<D>::header(SamplerKind sampler) {
  std::string text = kHeader;
  text.pop_back();
  const auto columns = [&](const char* prefix, std::span<const std::size_t> components) {
    for (const std::size_t c : components)
      text += fmt::format(",{}{}", prefix, kTensorComponents[c]);
  };
  constexpr auto all = tensor_components<D>();
  columns("p", all);
  if (sampler == SamplerKind::ecmc) {
    columns("K", std::span(all).first(D));
    columns("W", all);
  } else {
    columns("G", all);
  }
  return text + "\n";
}

template <std::size_t D>
void TimeSeriesWriter<D>::observe(const Simulation<D>& simulation) {
  const System<D>& system = simulation.state();
  Row row{simulation.time(), simulation.current_counts(), 0.0, 0.0, false};
  const bool chains = simulation.settings().sampler.kind == SamplerKind::ecmc;
  double rate = 0.0;
  std::optional<SymmetricTensor> tensor;
  if (started_ && row.time > last_.time) {
    const Measurement interval{last_.time, 0.0, difference(row.totals, last_.totals), std::nullopt};
    const Observables<D> o = simulation.observables_over(interval, row.time);
    row.pressure = o.pressure;
    row.z = o.compressibility_factor;
    row.measured = true;
    rate = o.collision_rate;
    if (chains) {
      tensor = o.pressure_tensor;  // beta P_kk from each axis's own moves and lifts
    } else if (row.totals.fluxes && last_.totals.fluxes) {
      tensor =
          pressure_tensor_between(*row.totals.fluxes, *last_.totals.fluxes, box_volume(system.box));
    }
  }
  take(row, window(simulation));
  // Rows a block must hold for its error to count: a turn of event chains (a row each for
  // dynamics). Capped where the count would not fit: no run has that many rows.
  const double turn = chain_turn_duration(simulation.settings().sampler, system.size(), D);
  const auto least_block =
      static_cast<std::uint64_t>(std::max(1.0, std::min(std::ceil(turn / every_), 0x1p62)));
  const Counts& c = row.totals;
  std::string line = fmt::format(
      "{},{},{},{},{},{},{},{},{},{},{},{},{}", row.time, c.events, c.pair_collisions,
      field(c.virial), field(c.wall_momentum), field(simulation.temperature()),
      field(row.pressure, row.measured), field(row.z, row.measured), field(rate, row.measured),
      field(pressure_.mean()), field(pressure_.error(least_block)), field(z_.mean()),
      field(z_.error(least_block)));
  constexpr SymmetricTensor kAbsent{kNaN, kNaN, kNaN, kNaN, kNaN, kNaN};
  for (const std::size_t k : tensor_components<D>())
    line += "," + field(tensor ? (*tensor)[k] : kNaN);
  if (chains) {
    // Both sums, each as it is (the ratio of their differences is a row's P_kk): a log continued
    // from them gives the rows of a run in one piece.
    const SymmetricTensor kinetic = c.fluxes ? c.fluxes->kinetic_stress : kAbsent;
    const SymmetricTensor lifts = c.fluxes ? c.fluxes->collisional_stress : kAbsent;
    for (std::size_t k = 0; k < D; ++k) line += "," + field(kinetic[k]);
    for (const std::size_t k : tensor_components<D>()) line += "," + field(lifts[k]);
  } else {
    const SymmetricTensor moment = c.fluxes ? c.fluxes->stress_moment() : kAbsent;
    for (const std::size_t k : tensor_components<D>()) line += "," + field(moment[k]);
  }
  out_ << line << '\n';
  if (!out_.flush()) throw std::runtime_error("cannot write the time series");
}

template <std::size_t D>
std::uint64_t TimeSeriesWriter<D>::resume(std::istream& in, double t, bool inclusive,
                                          const Simulation<D>& simulation) {
  LineReader reader{in, 0, {}};
  const SamplerKind sampler = simulation.settings().sampler.kind;
  const bool chains = sampler == SamplerKind::ecmc;
  if (!reader.next()) return 0;                 // not even a whole header: written afresh
  if (reader.line + "\n" != header(sampler)) {  // another log's rows, kept rather than lost
    throw std::invalid_argument(
        chains && reader.line + "\n" == header(SamplerKind::md)
            ? "it is an event-chain log of carom before 1.9 (Gxx, ... where chains now write "
              "Kxx, ... and Wxx, ...), which this run cannot continue: continue into a new --log"
            : "its header is not that of this run's log: continue into a new --log");
  }
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
    if (fields.size() != 13 + kComponents + (chains ? D : 0) + kComponents) break;
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
    // Dynamics' moment: its kinetic and collisional parts only matter summed, kept as one.
    // Event chains': each part as written (their moves are along an axis: no kinetic xy).
    Fluxes fluxes;
    fluxes.time = row.time;
    std::size_t column = 13 + kComponents;
    const auto take_column = [&](double& value) { return number(fields[column++], value); };
    for (std::size_t m = 0; m < (chains ? D : kComponents); ++m) {
      if (!take_column(fluxes.kinetic_stress[tensor_components<D>()[m]])) return kept;
    }
    for (std::size_t m = 0; chains && m < kComponents; ++m) {
      if (!take_column(fluxes.collisional_stress[tensor_components<D>()[m]])) return kept;
    }
    row.totals.fluxes = fluxes;
    take(row, window_start);
    kept = reader.offset;
  }
  return kept;
}

template class TimeSeriesWriter<2>;
template class TimeSeriesWriter<3>;

}  // namespace carom

#include "carom/engine/simulation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "carom/engine/checkpoint_state.hpp"
#include "carom/engine/initial.hpp"
#include "ecmc_engine.hpp"
#include "run_engine.hpp"

namespace carom {

void check_settings(const Settings& settings) {
  const CollisionRule& rule = settings.rule;
  if (!(rule.restitution > 0.0 && rule.restitution <= 1.0)) {
    throw std::invalid_argument(
        fmt::format("the restitution must be in (0, 1], got {}", rule.restitution));
  }
  if (rule.restitution < 1.0 && rule.rule != Rule::elastic) {
    throw std::invalid_argument(
        "a restitution below 1 needs the elastic rule (the swap rule has no restitution)");
  }
  if (!(rule.elastic_within >= 0.0) || !std::isfinite(rule.elastic_within)) {
    throw std::invalid_argument(
        fmt::format("the TC time must be a number >= 0, got {}", rule.elastic_within));
  }
  check_thermostat(settings.thermostat);
  if (settings.sampler.kind == SamplerKind::ecmc) {
    if (settings.thermostat.kind != ThermostatKind::none) {
      throw std::invalid_argument("event chains sample at kT = 1 and take no thermostat");
    }
    if (rule.restitution != 1.0) {
      throw std::invalid_argument("event chains sample hard particles: the restitution must be 1");
    }
    if (settings.engine == EngineKind::reference) {
      throw std::invalid_argument("event chains have one engine: the reference engine is dynamics'");
    }
    const double length = settings.sampler.chain_length;
    if (!(length >= 0.0) || !std::isfinite(length)) {
      throw std::invalid_argument(
          fmt::format("a chain length must be a number above 0, got {}", length));
    }
  }
}

namespace {

// The engine for a new run, its settings checked first.
template <std::size_t D>
std::unique_ptr<Engine<D>> checked_engine(System<D> system, const Settings& settings) {
  check_settings(settings);
  return make_run_engine(settings, std::move(system), std::nullopt);
}

// `settings` with an event chain's default length resolved for `system`.
template <std::size_t D>
Settings resolved(Settings settings, const System<D>& system) {
  Sampler& sampler = settings.sampler;
  if (sampler.kind == SamplerKind::ecmc && sampler.chain_length == 0.0) {
    sampler.chain_length = default_chain_length(system, mean_diameter(system));
  }
  return settings;
}

}  // namespace

template <std::size_t D>
Simulation<D>::Simulation(System<D> system, const Settings& settings)
    : settings_(resolved(settings, system)),
      chains_(settings_.sampler.kind == SamplerKind::ecmc),
      engine_(checked_engine(std::move(system), settings_)),
      chains_kinetic_temperature_(chains_ ? carom::kinetic_temperature(state()) : 0.0),
      time_(engine_->time()),
      slice_(engine_->slice_length()),
      rebase_period_(rebase_period(state().size())),
      events_to_rebase_(rebase_period_ - counts_.events % rebase_period_) {
  // Stored times far from zero (a system handed over mid-run) are made small before any event.
  engine_->rebase();
  stored_time_ = engine_->stored_time();
  measurement_ = {time_, kinetic_energy(state()), {}, std::nullopt};
  track_fluxes();
  thermostat_rng_.seed(settings_.thermostat.seed);
  if (resets_as_events(settings_.thermostat)) {
    thermostat_next_ =
        time_ + next_reset_delay(settings_.thermostat, state().size(), thermostat_rng_);
  } else if (settings_.thermostat.kind != ThermostatKind::none) {
    thermostat_instants_ =
        static_cast<std::uint64_t>(std::floor(time_ / settings_.thermostat.every));
  }
}

template <std::size_t D>
Simulation<D>::Simulation(const Checkpoint<D>& checkpoint)
    : settings_(checkpoint.settings),
      chains_(settings_.sampler.kind == SamplerKind::ecmc),
      engine_(make_run_engine(checkpoint.settings, checkpoint.system, checkpoint.chain)),
      chains_kinetic_temperature_(chains_ ? carom::kinetic_temperature(state()) : 0.0),
      time_(checkpoint.time),
      settled_(checkpoint.settled),
      counts_(checkpoint.counts),
      measurement_(checkpoint.measurement),
      measure_from_(checkpoint.measure_from),
      slice_(engine_->slice_length()),
      rebase_period_(rebase_period(state().size())),
      events_to_rebase_(rebase_period_ - counts_.events % rebase_period_) {
  if (!(time_ >= engine_->time())) {
    throw std::invalid_argument("a checkpoint's time precedes a particle's stored time");
  }
  // Saved just after an event, at that event's stored time; saved whole, at its own.
  stored_time_ = settled_ ? state().stored(time_) : engine_->stored_time();
  track_fluxes();  // a checkpoint of carom before 1.6 kept none
  thermostat_instants_ = checkpoint.thermostat_instants;
  thermostat_rng_ = checkpoint.thermostat_rng;
  thermostat_next_ = checkpoint.thermostat_next;
}

template <std::size_t D>
Simulation<D>::~Simulation() = default;
template <std::size_t D>
Simulation<D>::Simulation(Simulation&&) noexcept = default;
template <std::size_t D>
Simulation<D>& Simulation<D>::operator=(Simulation&&) noexcept = default;

void check_latest_time(double t) {
  constexpr double latest = Simulation<2>::kLatestTime;
  static_assert(latest == Simulation<3>::kLatestTime);
  if (t > latest) {
    throw RunLengthError(fmt::format(
        "{} is beyond {}, where a double resolves time too coarsely; rescale the time unit", t,
        latest));
  }
}

template <std::size_t D>
void Simulation<D>::check_target(double t) const {
  if (!(t >= time_)) {
    throw RunLengthError(fmt::format("{} is before the run's current time {}", t, time_));
  }
  check_latest_time(t);
  engine_->check_target(t);
  const double crossings = most_crossings(state(), t - time_);
  if (crossings > kMostCrossings) {
    throw RunLengthError(fmt::format(
        "a particle could cross the box about {:.3g} times before {} (at the highest speed its "
        "energy allows), more than the {:.0e} carom can process: check the velocities, masses, "
        "box and time unit",
        crossings, t, kMostCrossings));
  }
  // A thermostat's work grows with how often it acts, whatever the particles do: each instant
  // touches every particle, and Andersen's resets come N NU a unit of time.
  const Thermostat& thermostat = settings_.thermostat;
  if (thermostat.kind == ThermostatKind::none) return;
  const auto n = static_cast<double>(state().size());
  const bool resets = resets_as_events(thermostat);
  const double touches =
      resets ? n * thermostat.rate * (t - time_) : n * (t - time_) / thermostat.every;
  if (touches > kMostCrossings) {
    throw RunLengthError(fmt::format(
        "the thermostat would act on a particle about {:.3g} times before {}, more than the {:.0e} "
        "carom can process: check {}",
        touches, t, kMostCrossings, resets ? "--thermostat-rate" : "--thermostat-every"));
  }
}

template <std::size_t D>
RunStatus Simulation<D>::run_until(double t, std::uint64_t max_events) {
  check_target(t);
  std::uint64_t processed = 0;
  while (true) {
    // Long stretches without events (a few particles crossing cells for a long time) are cut
    // into slices of bounded work, so that the stop flag is looked at even then. A slice end
    // is an instant the run is whole at, like any target: the events are the same.
    const double slice_end = time_ + slice_;
    const double stop_at = std::min({t, next_due_time(), slice_end > time_ ? slice_end : t});
    if (chains_ && !watch_events_) {
      if (const std::optional<RunStatus> status = lift_quietly(stop_at, max_events, processed)) {
        return *status;
      }
    }
    while (const std::optional<Event> event = next_event(stop_at)) {
      record(*event);
      ++processed;
      const bool stop = stop_ != nullptr && stop_->load(std::memory_order_relaxed) != 0;
      if (stop || processed >= max_events) {
        complete_instant();
        return stop ? RunStatus::stopped : RunStatus::event_limit;
      }
      // The same events follow as if the run had stopped here and gone on: any division of a
      // run gives the same run.
      if (instant_awaited_) complete_instant();
    }
    settle_at(stop_at);
    if (stop_at == t) return RunStatus::reached;
    if (stop_ != nullptr && stop_->load(std::memory_order_relaxed) != 0) return RunStatus::stopped;
  }
}

template <std::size_t D>
std::optional<RunStatus> Simulation<D>::lift_quietly(double stop_at, std::uint64_t max_events,
                                                     std::uint64_t& processed) {
  // Lifts between looks at the stop flag: a few milliseconds' worth.
  constexpr std::uint64_t kBatch = 1 << 16;
  auto& chains = static_cast<EcmcEngine<D>&>(*engine_);
  while (true) {
    // Never past a rebase: it comes after the same lift as when lifts are recorded one by one.
    const std::uint64_t most = std::min({events_to_rebase_, max_events - processed, kBatch});
    Event last;
    const std::uint64_t done =
        chains.lift_quietly(stop_at, most, counts_, measurement_.counts, last);
    take_velocity_changes();
    if (done == 0) return std::nullopt;
    processed += done;
    after_events(last, done);
    const bool stop = stop_ != nullptr && stop_->load(std::memory_order_relaxed) != 0;
    if (stop || processed >= max_events) {
      complete_instant();
      return stop ? RunStatus::stopped : RunStatus::event_limit;
    }
    if (done < most) return std::nullopt;
  }
}

template <std::size_t D>
void Simulation<D>::take_velocity_changes() {
  engine_->take_velocity_changes([this](const typename Engine<D>::VelocityChange& change) {
    if (!counts_.fluxes) return;
    const System<D>& system = state();
    const std::uint32_t i = change.particle;
    counts_.fluxes->change_velocity<D>(system.absolute(change.at), change.at,
                                       system.records[i].mass, change.before, change.after);
  });
}

template <std::size_t D>
std::optional<Event> Simulation<D>::next_event(double end_time) {
  std::optional<Event> event = engine_->step(end_time);
  take_velocity_changes();
  return event;
}

template <std::size_t D>
void Simulation<D>::record(const Event& event) {
  if (chains_) {
    count_lift<D>(counts_, measurement_.counts, event);
  } else {
    counts_.add(event);
    measurement_.counts.add(event);
    if (counts_.fluxes) {
      const System<D>& system = state();
      const auto partner =
          event.is_wall() ? event.first : static_cast<std::uint32_t>(event.partner);
      Fluxes& fluxes = *counts_.fluxes;
      if (fluxes.shear_rate != 0.0) [[unlikely]] {
        fluxes.add_event_as<D, true>(event, engine_->stored_time(),
                                     system.records[event.first].mass,
                                     flux_velocity(system.particles[event.first], system.box),
                                     system.records[partner].mass,
                                     flux_velocity(system.particles[partner], system.box));
      } else {
        fluxes.add_event_as<D, false>(event, engine_->stored_time(),
                                      system.records[event.first].mass,
                                      system.particles[event.first].velocity,
                                      system.records[partner].mass,
                                      system.particles[partner].velocity);
      }
    }
  }
  after_events(event, 1);
  if (!watch_events_) return;
  for (Scheduled& entry : observers_) {
    Observer<D>& observer = *entry.observer;
    switch (observer.trigger().kind) {
      case Trigger::Kind::each_event:
        observer.observe(*this);
        break;
      case Trigger::Kind::events:
        if (!entry.due && counts_.events >= entry.next_event) call_or_await(entry);
        break;
      case Trigger::Kind::seconds:
        if (!entry.due && counts_.events % 1024 == 0 &&
            std::chrono::steady_clock::now() >= entry.next_clock) {
          call_or_await(entry);
        }
        break;
      case Trigger::Kind::time:
        break;
    }
  }
}

template <std::size_t D>
void Simulation<D>::after_events(const Event& last, std::uint64_t count) {
  last_event_ = last;
  time_ = last.time;
  settled_ = false;
  events_to_rebase_ -= count;
  if (events_to_rebase_ == 0) {  // counts_.events is a multiple of rebase_period_
    // Lifts leave the kinetic integrals behind (Fluxes::add_lift): brought to the epoch's new
    // origin first.
    if (chains_ && counts_.fluxes) counts_.fluxes->integrate_to(engine_->stored_time());
    engine_->rebase();
    events_to_rebase_ = rebase_period_;
    if (counts_.fluxes) {
      counts_.fluxes->stored = engine_->stored_time();  // the same instant in the new epoch
      renew_flux_rates();
    }
  }
  stored_time_ = engine_->stored_time();
}

template <std::size_t D>
void Simulation<D>::call_or_await(Scheduled& entry) {
  if (entry.observer->trigger().whole_instant) {
    entry.due = true;
    instant_awaited_ = true;
    return;
  }
  entry.observer->observe(*this);
  schedule(entry);
}

template <std::size_t D>
void Simulation<D>::complete_instant() {
  const double now = time_;
  while (const std::optional<Event> event = next_event(now)) record(*event);
  settle_at(now);
  if (!instant_awaited_) return;
  instant_awaited_ = false;
  for (Scheduled& entry : observers_) {
    if (entry.due) {
      entry.due = false;
      entry.observer->observe(*this);
      schedule(entry);
    }
  }
}

template <std::size_t D>
void Simulation<D>::settle_at(double t) {
  time_ = t;
  stored_time_ = state().stored(t);
  settled_ = true;
  if (measure_from_ && *measure_from_ <= t) reset_measurement();
  try {
    for (Scheduled& entry : observers_) {
      if (entry.observer->trigger().kind == Trigger::Kind::time && entry.next_time <= t) {
        entry.observer->observe(*this);
        schedule(entry);
      }
    }
  } catch (...) {
    // An observer that failed (a write to a full disk) leaves the instant incomplete: the
    // observers after it and the thermostat have not acted at t. A checkpoint saved now says so,
    // and the run resumed from it completes the instant: the time observers look at t again
    // (what they wrote at t is cut off first; the drift's record takes an instant once).
    settled_ = false;
    throw;
  }
  // After the observers: they see the state the dynamics reached.
  if (t >= next_thermostat_time()) apply_thermostat();
}

template <std::size_t D>
double Simulation<D>::next_thermostat_time() const {
  const Thermostat& thermostat = settings_.thermostat;
  if (thermostat.kind == ThermostatKind::none) return kNever;
  if (resets_as_events(thermostat)) return thermostat_next_;
  return thermostat.every * static_cast<double>(thermostat_instants_ + 1);
}

template <std::size_t D>
void Simulation<D>::reset_one_velocity() {
  const Thermostat& thermostat = settings_.thermostat;
  const System<D>& system = state();
  const auto i =
      static_cast<std::uint32_t>(thermostat_rng_(static_cast<std::uint32_t>(system.size())));
  Particle<D> reset = system.particles[i];
  advance(reset, stored_time_);
  // Drawn relative to the streaming profile where the particle is, in a sheared box.
  const Vec<D> velocity = streaming_velocity(
      maxwell_velocity<D>(thermostat.kT, system.records[i].mass, thermostat_rng_), reset,
      system.box);
  const Vec<D> before = flux_velocity(system.particles[i], system.box);
  engine_->reset_velocity(i, stored_time_, velocity);
  if (counts_.fluxes) {
    counts_.fluxes->change_velocity<D>(time_, stored_time_, system.records[i].mass, before,
                                       flux_velocity(state().particles[i], system.box));
  }
  ++thermostat_instants_;
  thermostat_next_ += next_reset_delay(thermostat, system.size(), thermostat_rng_);
}

template <std::size_t D>
void Simulation<D>::apply_thermostat() {
  const Thermostat& thermostat = settings_.thermostat;
  if (resets_as_events(thermostat)) {
    reset_one_velocity();
    return;
  }
  if (counts_.fluxes) *counts_.fluxes = counts_.fluxes->advanced(time_, stored_time_);
  engine_->intervene(stored_time_, [&](System<D>& system) {
    if (thermostat.kind == ThermostatKind::rescale) {
      rescale_velocities(system, thermostat.kT);
    } else {
      andersen_resets(system, thermostat, thermostat_rng_);
    }
  });
  stored_time_ = engine_->stored_time();  // the epoch is now: 0
  if (counts_.fluxes) {
    counts_.fluxes->stored = stored_time_;
    renew_flux_rates();
  }
  slice_ = engine_->slice_length();  // speeds changed
  ++thermostat_instants_;
}

template <std::size_t D>
double Simulation<D>::next_due_time() const {
  double due = std::min(measure_from_.value_or(kNever), next_thermostat_time());
  for (const Scheduled& entry : observers_) {
    if (entry.observer->trigger().kind == Trigger::Kind::time) due = std::min(due, entry.next_time);
  }
  return due;
}

template <std::size_t D>
void Simulation<D>::schedule(Scheduled& entry) const {
  const Trigger& trigger = entry.observer->trigger();
  switch (trigger.kind) {
    case Trigger::Kind::time: {
      // The first multiple of the period not yet observed: from time_ on in a run that is not
      // yet whole at time_, after it otherwise.
      double k = std::ceil(time_ / trigger.period);
      if (settled_ && k * trigger.period <= time_) k += 1.0;
      entry.next_time = k * trigger.period;
      break;
    }
    case Trigger::Kind::events: {
      const auto n = static_cast<std::uint64_t>(trigger.period);
      entry.next_event = (counts_.events / n + 1) * n;
      break;
    }
    case Trigger::Kind::seconds:
      entry.next_clock = std::chrono::steady_clock::now() +
                         std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                             std::chrono::duration<double>(trigger.period));
      break;
    case Trigger::Kind::each_event:
      break;
  }
}

template <std::size_t D>
void Simulation<D>::add_observer(std::shared_ptr<Observer<D>> observer, FirstLook first) {
  const Trigger& trigger = observer->trigger();
  const bool positive = trigger.period > 0.0 && std::isfinite(trigger.period);
  if (trigger.kind == Trigger::Kind::events && !(positive && trigger.period >= 1.0)) {
    throw std::invalid_argument("an event trigger needs a period of at least one event");
  }
  if (trigger.kind != Trigger::Kind::each_event && !positive) {
    throw std::invalid_argument("a trigger's period must be positive and finite");
  }
  Scheduled entry{std::move(observer), 0.0, 0, {}};
  schedule(entry);
  if (first == FirstLook::now && settled_ && trigger.kind == Trigger::Kind::time &&
      std::ceil(time_ / trigger.period) * trigger.period == time_) {
    entry.observer->observe(*this);
  }
  watch_events_ = watch_events_ || trigger.kind != Trigger::Kind::time;
  observers_.push_back(std::move(entry));
}

template <std::size_t D>
void Simulation<D>::remove_observer(const Observer<D>* observer) {
  std::erase_if(observers_,
                [&](const Scheduled& entry) { return entry.observer.get() == observer; });
  watch_events_ = std::any_of(observers_.begin(), observers_.end(), [](const Scheduled& entry) {
    return entry.observer->trigger().kind != Trigger::Kind::time;
  });
}

template <std::size_t D>
void Simulation<D>::reset_measurement() {
  measurement_ = {time_, kinetic_energy(state()), {}, current_counts().fluxes};
  measure_from_.reset();
}

template <std::size_t D>
Counts Simulation<D>::current_counts() const {
  Counts counts = counts_;
  if (counts.fluxes) counts.fluxes = counts.fluxes->advanced(time_, stored_time_);
  return counts;
}

template <std::size_t D>
Measurement Simulation<D>::measurement() const {
  Measurement m = measurement_;
  if (counts_.fluxes && m.flux_origin) {
    m.counts.fluxes = flux_difference(*current_counts().fluxes, *m.flux_origin);
  }
  return m;
}

template <std::size_t D>
void Simulation<D>::track_fluxes() {
  if (counts_.fluxes) return;
  counts_.fluxes = fluxes_of(state(), time_, stored_time_, false);
  if (!measurement_.flux_origin) measurement_.flux_origin = counts_.fluxes;
}

template <std::size_t D>
void Simulation<D>::renew_flux_rates() {
  const Fluxes exact = fluxes_of(state(), time_, stored_time_, counts_.fluxes->heat);
  counts_.fluxes->stress_rate = exact.stress_rate;
  counts_.fluxes->heat_rate = exact.heat_rate;
}

template <std::size_t D>
void Simulation<D>::keep_heat_flux() {
  if (!counts_.fluxes || counts_.fluxes->heat) return;
  *counts_.fluxes = counts_.fluxes->advanced(time_, stored_time_);
  counts_.fluxes->heat = true;
  renew_flux_rates();
}

template <std::size_t D>
void Simulation<D>::measure_from(double t) {
  if (std::isnan(t)) throw std::invalid_argument("a measurement cannot start at NaN");
  if (t <= time_) {
    reset_measurement();
  } else {
    measure_from_ = t;
  }
}

template <std::size_t D>
Checkpoint<D> Simulation<D>::checkpoint(const std::string& source) const {
  return {source,          state(),          settings_,     time_, settled_,
          counts_,         measurement_,     measure_from_, {},    thermostat_instants_,
          thermostat_rng_, thermostat_next_, std::nullopt,  chain()};
}

template <std::size_t D>
std::optional<ChainState> Simulation<D>::chain() const {
  const auto* chains = dynamic_cast<const EcmcEngine<D>*>(engine_.get());
  if (chains == nullptr) return std::nullopt;
  return chains->chain();
}

template <std::size_t D>
double Simulation<D>::temperature() const {
  return chains_ ? 1.0 : kinetic_temperature();
}

template <std::size_t D>
double Simulation<D>::kinetic_temperature() const {
  return chains_ ? chains_kinetic_temperature_ : carom::kinetic_temperature(state());
}

template <std::size_t D>
Observables<D> Simulation<D>::observables_over(const Measurement& stretch, double now) const {
  Observables<D> o = measure(state(), stretch, now);
  if (chains_) {
    return at_unit_temperature(
        o, stretch, static_cast<double>(state().size()) / box_volume(state().box));
  }
  return o;
}

template class Simulation<2>;
template class Simulation<3>;

}  // namespace carom

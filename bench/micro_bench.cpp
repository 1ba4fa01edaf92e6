// Google Benchmark microbenchmarks of the pieces every event uses: the prediction functions and
// the event queue. `make bench` runs them before the whole-program benchmark.
#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <memory>
#include <pcg_random.hpp>
#include <vector>

#include "carom/core/physics.hpp"
#include "carom/engine/initial.hpp"
#include "engine/ecmc_engine.hpp"
#include "engine/event_calendar.hpp"
#include "event_queue.hpp"

namespace carom {
namespace {

double uniform(pcg32& rng) {
  return static_cast<double>(rng()) / 4294967296.0;
}

std::vector<Particle<2>> particles(std::size_t n) {
  pcg32 rng(1);
  std::vector<Particle<2>> out(n);
  for (Particle<2>& p : out) {
    p.position = {{10 * uniform(rng), 10 * uniform(rng)}};
    p.velocity = {{uniform(rng) - 0.5, uniform(rng) - 0.5}};
    p.radius = 0.5;
    p.time = uniform(rng);
  }
  return out;
}

void BM_ContactTime(benchmark::State& state) {
  const auto p = particles(1024);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(contact_time(p[i % 1024], p[(i * 7 + 1) % 1024]));
    ++i;
  }
}
BENCHMARK(BM_ContactTime);

void BM_ContactTimePeriodicImage(benchmark::State& state) {
  const auto p = particles(1024);
  const Box<2> box{Vec2{{10, 10}}, Boundary::periodic};
  std::size_t i = 0;
  for (auto _ : state) {
    const Particle<2>& a = p[i % 1024];
    const Particle<2>& b = p[(i * 7 + 1) % 1024];
    const Vec2 offset = image_offset(position_at(a, 1.0) - position_at(b, 1.0), box);
    benchmark::DoNotOptimize(contact_time(a, b, offset));
    ++i;
  }
}
BENCHMARK(BM_ContactTimePeriodicImage);

void BM_NextWallHit(benchmark::State& state) {
  const auto p = particles(1024);
  const Box<2> box{Vec2{{10, 10}}};
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(next_wall_hit(p[i++ % 1024], box));
}
BENCHMARK(BM_NextWallHit);

void BM_ElasticCollision(benchmark::State& state) {
  auto p = particles(2);
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        collide(p[0], p[1], p[0].position - p[1].position, Rule::elastic, 1.0, 1.0, 1.0));
  }
}
BENCHMARK(BM_ElasticCollision);

// One event's queue work: replace the earliest event by one a random time later (as an event and
// its new prediction do). The heap is the baseline the calendar replaced.
template <class Queue>
void BM_QueueUpdate(benchmark::State& state) {
  const auto n = static_cast<std::uint32_t>(state.range(0));
  Queue queue(n);
  pcg32 rng(2);
  for (std::uint32_t i = 0; i < n; ++i) queue.update(i, {uniform(rng), i});
  for (auto _ : state) {
    const std::uint32_t top = queue.top();
    const double now = queue.top_key().time;
    queue.update(top, {now + uniform(rng), top});
    benchmark::DoNotOptimize(top);
  }
}
BENCHMARK(BM_QueueUpdate<EventQueue>)->Name("BM_HeapUpdate")->Range(1 << 10, 1 << 20);
BENCHMARK(BM_QueueUpdate<EventCalendar>)->Name("BM_CalendarUpdate")->Range(1 << 10, 1 << 20);

// Event-chain Monte Carlo's lifts a second (items/s), the engine alone: N disks at packing 0.70
// or spheres at 0.45 from a lattice, chains of sqrt(N) mean diameters, a few lifts a particle
// first to leave the lattice. One engine per size, kept from run to run.
template <std::size_t D>
void BM_EcmcLifts(benchmark::State& state) {
  static std::map<std::int64_t, std::unique_ptr<EcmcEngine<D>>> engines;
  std::unique_ptr<EcmcEngine<D>>& engine = engines[state.range(0)];
  if (!engine) {
    InitialOptions options;
    options.n = static_cast<std::uint64_t>(state.range(0));
    options.packing_fraction = D == 2 ? 0.70 : 0.45;
    options.boundary = Boundary::periodic;
    options.placement = Placement::lattice;
    engine = std::make_unique<EcmcEngine<D>>(make_initial<D>(options),
                                             std::sqrt(static_cast<double>(options.n)), pcg32(1));
    for (std::uint64_t k = 0; k < 4 * options.n; ++k) engine->step(kNever);
  }
  for (auto _ : state) benchmark::DoNotOptimize(engine->step(kNever));
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_EcmcLifts<2>)->Name("BM_EcmcLiftsDisks070")->Arg(4096)->Arg(65536)->Arg(1 << 20);
BENCHMARK(BM_EcmcLifts<3>)->Name("BM_EcmcLiftsSpheres045")->Arg(4096)->Arg(65536);

}  // namespace
}  // namespace carom

BENCHMARK_MAIN();

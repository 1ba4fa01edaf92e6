#include "ecmc_engine.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <new>
#include <stdexcept>

#include "carom/engine/initial.hpp"
#include "large_pages.hpp"

namespace carom {

namespace {

// The grid the chains search: cells one largest diameter wide or more, with room for three along
// every axis even with a handful of particles (a grid allows about two cells a particle).
template <std::size_t D>
CellGrid<D> chain_grid(const System<D>& system) {
  return CellGrid<D>(system.box, 2.0 * largest_radius(system),
                     std::max<std::size_t>(system.size(), 6));
}

// A system as chains start in it: every particle at rest at the latest stored time (the engine
// checks that chains can run in it).
template <std::size_t D>
System<D> at_rest(System<D> system) {
  double latest = 0.0;
  for (const Particle<D>& p : system.particles) latest = std::max(latest, p.time);
  if (system.records.empty()) system.records.resize(system.size());
  for (std::size_t i = 0; i < system.size(); ++i) {
    Particle<D>& p = system.particles[i];
    p.position = position_at(p, latest);
    p.time = latest;
    p.velocity = Vec<D>{};
    wrap(p, system.box, system.records[i].image);
  }
  return system;
}

template <std::size_t D>
Vec<D> along(std::size_t axis, double speed) {
  Vec<D> v{};
  v[axis] = speed;
  return v;
}

}  // namespace

namespace {

// check_chain_start with the grid the chains would search in `system`.
template <std::size_t D>
void check_chain_start(const System<D>& system, const CellGrid<D>& grid) {
  if (!system.box.periodic() || system.box.sheared()) {
    throw std::invalid_argument("event-chain Monte Carlo needs a periodic box that is not sheared");
  }
  for (const ParticleRecord& r : system.records) {
    if (r.mass != 1.0) {
      throw std::invalid_argument(
          "event-chain Monte Carlo samples positions only: every mass must be 1");
    }
  }
  for (std::size_t k = 0; k < D; ++k) {
    if (grid.cells_along(k) < 3) {
      throw std::invalid_argument(fmt::format(
          "event-chain Monte Carlo needs a box three of the largest diameters wide or more along "
          "every axis; this one is {} wide along axis {}, and the largest diameter is {}",
          system.box.size[k], "xyz"[k], 2.0 * largest_radius(system)));
    }
  }
}

}  // namespace

template <std::size_t D>
void check_chain_start(const System<D>& system) {
  check_chain_start(system, chain_grid(system));
}

template <std::size_t D>
EcmcEngine<D>::EcmcEngine(System<D> system, double chain_length, const ChainState& chain)
    : Engine<D>(std::move(system), {Rule::swap, 1.0, 0.0}, {}),
      chain_(chain),
      grid_(chain_grid(this->system_)) {
  check_chain_start(this->system_, grid_);
  if (!(chain_length > 0.0)) {
    throw std::invalid_argument(
        fmt::format("a chain length must be above 0, not {}", chain_length));
  }
  const std::size_t n = this->system_.size();
  if (chain_.active >= n) {
    throw std::invalid_argument(
        fmt::format("the active particle {} is not one of the {}", chain_.active, n));
  }
  const double diameter = mean_diameter(this->system_);
  speed_ = static_cast<double>(n) * diameter;
  chain_duration_ = chain_length * diameter / speed_;
  for (std::size_t k = 0; k < D; ++k) {
    half_box_[k] = 0.5 * this->system_.box.size[k];
    cells_along_[k] = grid_.cells_along(k);
    strides_[k] = k == 0 ? 1 : strides_[k - 1] * cells_along_[k - 1];
    widths_[k] = grid_.width(k);
  }
  // The lists, as long as the fullest cell's.
  std::vector<std::uint32_t> cell_of(n);
  fill_.assign(grid_.cell_count(), 0);
  for (std::uint32_t i = 0; i < n; ++i) {
    cell_of[i] = grid_.locate(this->system_.particles[i].position);
    capacity_ = std::max(capacity_, ++fill_[cell_of[i]]);
  }
  std::fill(fill_.begin(), fill_.end(), 0u);
  resting_.resize(grid_.cell_count() * capacity_);
  prefetch_cells_ = resting_.size() * sizeof(Resting) > kCacheBytes;
  gathered_.resize(CellGrid<D>::kBlock * std::max(capacity_, 8u) + 8);
  touching_.resize(gathered_.size());
  for (std::uint32_t i = 0; i < n; ++i) rest(i, cell_of[i]);
  plain_grid_ = true;
  for (std::size_t k = 0; k < D; ++k) plain_grid_ = plain_grid_ && cells_along_[k] >= 5;
  // The cells ahead of a cell one from every edge, relative to it.
  std::uint32_t inner = 0;
  for (std::size_t k = 0; k < D; ++k) inner += strides_[k];
  for (std::size_t axis = 0; axis < D; ++axis) {
    std::array<std::uint32_t, CellGrid<D>::kBlock> cells;
    if (grid_.cells_ahead(inner, axis, cells) != kAhead) {
      throw std::logic_error("event chains: the cells ahead are not the two columns of three");
    }
    std::size_t lead = 0;
    for (std::size_t c = 0; c < kAhead; ++c) {
      inner_offsets_[axis][c] = static_cast<std::int64_t>(cells[c]) - inner;
      // The next column's cells, moved on to the one kLead ahead.
      if (grid_.coordinates_of(cells[c])[axis] == 2) {
        lead_offsets_[axis][lead++] =
            inner_offsets_[axis][c] + static_cast<std::int64_t>((kLead - 1) * strides_[axis]);
      }
    }
  }
  prefer_large_pages(this->system_);
  set_moving(chain_.active);
}

template <std::size_t D>
EcmcEngine<D>::EcmcEngine(System<D> system, double chain_length, pcg32 rng)
    : EcmcEngine(at_rest(std::move(system)), chain_length, ChainState{0, 0, 0.0, rng}) {
  rest(0, locate(this->system_.particles[0].position));
  start_moving_at(this->now_);
}

template <std::size_t D>
[[gnu::always_inline]] inline std::uint32_t EcmcEngine<D>::locate(const Vec<D>& position) const {
  std::uint32_t cell = 0;
  for (std::size_t k = 0; k < D; ++k) {
    const double x = position[k];
    // Inside the box wrap() leaves x alone, and floor(x / width) >= 0 is its truncation.
    if (!(x > 0.0 && x < this->system_.box.size[k])) [[unlikely]]
      return grid_.locate(position);
    const auto at = static_cast<std::uint32_t>(x / widths_[k]);
    cell += strides_[k] * std::min(at, cells_along_[k] - 1);
  }
  return cell;
}

template <std::size_t D>
[[gnu::always_inline]] inline std::uint32_t EcmcEngine<D>::locate_moved(
    const Vec<D>& position) const {
  const std::size_t axis = chain_.axis;
  const double x = position[axis];
  if (!(x > 0.0 && x < this->system_.box.size[axis])) [[unlikely]]
    return grid_.locate(position);
  const auto along = static_cast<std::uint32_t>(x / widths_[axis]);
  std::uint32_t cell = strides_[axis] * std::min(along, cells_along_[axis] - 1);
  for (std::size_t k = 0; k < D; ++k) {
    if (k != axis) cell += strides_[k] * at_[k];
  }
  return cell;
}

template <std::size_t D>
[[gnu::always_inline]] inline void EcmcEngine<D>::wrap_into_box(
    Vec<D>& position, std::array<std::int32_t, 3>& image) const {
  for (std::size_t k = 0; k < D; ++k) {
    const double side = this->system_.box.size[k];
    if (position[k] > 0.0 && position[k] < side) [[likely]]
      continue;
    const double sides = std::floor(position[k] / side);
    position[k] -= side * sides;
    if (sides != 0.0) add_sides(image[k], sides);
  }
}

template <std::size_t D>
[[gnu::always_inline]] inline void EcmcEngine<D>::rest(std::uint32_t i, std::uint32_t cell,
                                                       const Vec<D>& position, double radius) {
  if (fill_[cell] == capacity_) [[unlikely]]
    widen_cells();
  resting_[cell * capacity_ + fill_[cell]++] = {position, radius, i, cell};
}

template <std::size_t D>
void EcmcEngine<D>::rest(std::uint32_t i, std::uint32_t cell) {
  const Particle<D>& p = this->system_.particles[i];
  rest(i, cell, p.position, p.radius);
}

template <std::size_t D>
[[gnu::always_inline]] inline void EcmcEngine<D>::take_out(std::uint32_t slot, std::uint32_t cell) {
  resting_[slot] = resting_[cell * capacity_ + --fill_[cell]];
}

template <std::size_t D>
template <class T>
T* EcmcEngine<D>::LargePages<T>::allocate(std::size_t n) {
  constexpr std::size_t kPage = std::size_t{1} << 21;
  const std::size_t bytes = n * sizeof(T);
  if (bytes < kPage) {
    if (void* p = std::malloc(bytes)) return static_cast<T*>(p);
    throw std::bad_alloc();
  }
  const std::size_t rounded = (bytes + kPage - 1) / kPage * kPage;
  void* p = std::aligned_alloc(kPage, rounded);
  if (!p) throw std::bad_alloc();
  prefer_large_pages(p, rounded);
  return static_cast<T*>(p);
}

template <std::size_t D>
void EcmcEngine<D>::widen_cells() {
  const std::uint32_t wider = capacity_ + 1 + capacity_ / 4;
  std::vector<Resting, LargePages<Resting>> resting(fill_.size() * wider);
  for (std::size_t cell = 0; cell < fill_.size(); ++cell) {
    std::copy_n(resting_.begin() + static_cast<std::ptrdiff_t>(cell * capacity_), fill_[cell],
                resting.begin() + static_cast<std::ptrdiff_t>(cell * wider));
  }
  resting_ = std::move(resting);
  capacity_ = wider;
  prefetch_cells_ = resting_.size() * sizeof(Resting) > kCacheBytes;
  gathered_.resize(CellGrid<D>::kBlock * std::max(capacity_, 8u) + 8);
  touching_.resize(gathered_.size());
}

template <std::size_t D>
void EcmcEngine<D>::set_moving(std::uint32_t i) {
  // Where it rests: its stored position located as when it came to rest.
  const Particle<D>& p = this->system_.particles[i];
  flight_ = {p.position, p.time, p.radius};
  const std::uint32_t cell = locate(p.position);
  std::uint32_t slot = cell * capacity_;
  while (resting_[slot].id != i) ++slot;
  take_out(slot, cell);
  cell_ = cell;
  at_ = grid_.coordinates_of(cell);
  start_flight();
}

template <std::size_t D>
[[gnu::always_inline]] inline void EcmcEngine<D>::start_flight() {
  start_column_ = at_[chain_.axis];
  columns_crossed_ = 0;
}

// x less the nearest whole number of sides: image_separation's component when x is more than
// half a side (rare: out of line).
[[gnu::noinline]] static double nearest_image(double x, double side) {
  return x - side * std::nearbyint(x / side);
}

template <std::size_t D>
template <std::size_t Axis>
typename EcmcEngine<D>::Lift EcmcEngine<D>::nearest_lift(double ahead) const {
  const Vec<D> p = flight_.from, half = half_box_, side = this->system_.box.size;
  const double radius = flight_.radius;
  const Resting* const resting = resting_.data();
  const std::uint32_t* const fill = fill_.data();
  const std::uint32_t capacity = capacity_;
  Lift best{kNever, chain_.active, 0, 0};
  // First the cells' slots in use, gathered into one list without a branch on how many each
  // has (eight at a time, the count added after), then the particles in them: one loop.
  std::uint32_t* const gathered = gathered_.data();
  std::size_t count = 0;
  // Room for 4 x Fours slots a cell: all of them written, the count of those in use added.
  const auto visit_fours = [&]<int Fours>(std::integral_constant<int, Fours>, std::uint32_t cell) {
    using Four = std::uint32_t __attribute__((vector_size(16)));
    Four slots = Four{0, 1, 2, 3} + cell * capacity;
    for (int k = 0; k < Fours; ++k, slots += 4) std::memcpy(gathered + count + 4 * k, &slots, 16);
    count += fill[cell];
  };
  const auto visit = [&](std::uint32_t cell) {
    if (capacity <= 8) [[likely]] {
      visit_fours(std::integral_constant<int, 2>{}, cell);
      return;
    }
    for (std::uint32_t k = 0; k < fill[cell]; ++k) gathered[count + k] = cell * capacity + k;
    count += fill[cell];
  };
  // The cells CellGrid::for_each_ahead visits: the cell's and the next along Axis, each with its
  // neighbours across (wrapping around the box).
  bool inner = at_[Axis] + 1 < cells_along_[Axis];
  for (std::size_t k = 0; k < D; ++k) {
    if (k != Axis) inner = inner && at_[k] - 1 < cells_along_[k] - 2;  // 1 <= at <= n - 2
  }
  if (inner) [[likely]] {  // no wrapping: fixed offsets
    const std::array<std::int64_t, kAhead>& offsets = inner_offsets_[Axis];
    const auto ahead_cell = [&](std::size_t c) {
      return static_cast<std::uint32_t>(cell_ + offsets[c]);
    };
    if (capacity <= 4) [[likely]] {
      for (std::size_t c = 0; c < kAhead; ++c) {
        visit_fours(std::integral_constant<int, 1>{}, ahead_cell(c));
      }
    } else if (capacity <= 8) {
      for (std::size_t c = 0; c < kAhead; ++c) {
        visit_fours(std::integral_constant<int, 2>{}, ahead_cell(c));
      }
    } else {
      for (std::size_t c = 0; c < kAhead; ++c) visit(ahead_cell(c));
    }
  } else {
    std::array<std::array<std::uint32_t, 3>, D> along;  // per axis, place x stride
    for (std::size_t k = 0; k < D; ++k) {
      const std::uint32_t at = at_[k], n = cells_along_[k], stride = strides_[k];
      const std::uint32_t up = (at + 1 == n ? 0 : at + 1) * stride;
      if (k == Axis) {
        along[k] = {at * stride, up, 0};
      } else {
        along[k] = {(at == 0 ? n - 1 : at - 1) * stride, at * stride, up};
      }
    }
    static_assert(D == 2 || D == 3);
    if constexpr (D == 2) {
      constexpr std::size_t kX = Axis == 0 ? 2 : 3, kY = Axis == 1 ? 2 : 3;
      for (std::size_t y = 0; y < kY; ++y) {
        for (std::size_t x = 0; x < kX; ++x) visit(along[1][y] + along[0][x]);
      }
    } else {
      constexpr std::size_t kX = Axis == 0 ? 2 : 3, kY = Axis == 1 ? 2 : 3, kZ = Axis == 2 ? 2 : 3;
      for (std::size_t z = 0; z < kZ; ++z) {
        for (std::size_t y = 0; y < kY; ++y) {
          const std::uint32_t row = along[2][z] + along[1][y];
          for (std::size_t x = 0; x < kX; ++x) visit(row + along[0][x]);
        }
      }
    }
  }
  // lift_distance(r, Axis, sigma) with no limit, r = p - b through b's image in the two columns
  // searched: the axis first (half are behind), and no bound to cut candidates short, which
  // changes no nearest lift (the nearest is never cut). The two columns lie within a cell width
  // of their middle, p + ahead, less than half a side: the image is the one within half a side
  // of it, and the separation is image_separation's wherever that is the nearest image.
  // Plain: a flight that has not wrapped round the box, among cells that do not wrap either, in
  // a grid five cells across or more: every separation is the plain difference (the checks below
  // would change none), and none is checked.
  const auto scan = [&]<bool Plain>(std::bool_constant<Plain>) {
    const double centre = -ahead, low = centre - half[Axis], high = centre + half[Axis];
    const auto separation_along = [&](const Resting& b) {
      double along = p[Axis] - b.position[Axis];
      if (!Plain && !(along >= low && along <= high)) [[unlikely]]
        along -= side[Axis] * std::nearbyint((along - centre) / side[Axis]);
      return along;
    };
    // A particle's separation from the active one and the quadratic's coefficients.
    const auto coefficients = [&](std::uint32_t slot) {
      const Resting& b = resting[slot];
      Vec<D> r;
      for (std::size_t k = 0; k < D; ++k) {
        if (k == Axis) {
          r[k] = separation_along(b);
          continue;
        }
        r[k] = p[k] - b.position[k];
        if (!Plain && !(std::abs(r[k]) <= half[k])) [[unlikely]]
          r[k] = nearest_image(r[k], side[k]);
      }
      const double sigma = radius + b.radius;
      const double c2 = norm2(r) - sigma * sigma;
      const double along = r[Axis];
      return Touching{along, c2, along * along - c2, slot};  // discriminant >= 0 if c2 <= 0
    };
    const auto touches = [](const Touching& t) { return t.along < 0.0 && t.discriminant >= 0.0; };
    // Where the active particle touches one (ahead of it, in its lane).
    const auto consider = [&](const Touching& t) {
      const double s = t.c2 <= 0.0 ? 0.0 : t.c2 / (-t.along + std::sqrt(t.discriminant));
      const Resting* const b = resting + t.slot;
      if (s < best.distance || (s == best.distance && b->id < best.target)) {
        best = {s, b->id, t.slot, b->cell};
      }
    };
    if constexpr (D == 2) {
      for (std::size_t c = 0; c < count; ++c) {
        const Touching t = coefficients(gathered[c]);
        if (touches(t)) consider(t);
      }
    } else {
      // Spheres: the ones touched first, kept without a branch on which (about half are behind
      // and some beside the lane; with eighteen cells' worth the branches' misses cost more than
      // the extra pass), then their roots.
      Touching* const touching = touching_.data();
      std::size_t kept = 0;
      for (std::size_t c = 0; c < count; ++c) {
        touching[kept] = coefficients(gathered[c]);
        kept += touches(touching[kept]);
      }
      for (std::size_t c = 0; c < kept; ++c) consider(touching[c]);
    }
  };
  if (inner && plain_grid_ && start_column_ + columns_crossed_ < cells_along_[Axis]) [[likely]] {
    scan(std::true_type{});
  } else {
    scan(std::false_type{});
  }
  return best;
}

template <std::size_t D>
typename EcmcEngine<D>::Lift EcmcEngine<D>::nearest_lift(double ahead) const {
  static_assert(D == 2 || D == 3);
  if constexpr (D == 3) {
    if (chain_.axis == 2) return nearest_lift<2>(ahead);
  }
  return chain_.axis == 0 ? nearest_lift<0>(ahead) : nearest_lift<1>(ahead);
}

template <std::size_t D>
double EcmcEngine<D>::distance_to_next_column() const {
  const std::size_t k = chain_.axis;
  // The box sides the flight has wrapped round since it started (in the box, at column
  // start_column_).
  const std::uint32_t column = start_column_ + columns_crossed_;
  const double next_column = static_cast<double>(at_[k] + 1) * widths_[k];
  if (column < cells_along_[k]) [[likely]]
    return next_column - flight_.from[k];
  const std::uint32_t laps = column / cells_along_[k];
  return (next_column + laps * this->system_.box.size[k]) - flight_.from[k];
}

template <std::size_t D>
std::optional<Event> EcmcEngine<D>::step(double end_time) {
  std::optional<Event> lift(std::in_place);
  if (!next_lift(end_time, *lift)) lift.reset();
  write_struck();
  return lift;
}

template <std::size_t D>
void EcmcEngine<D>::write_struck() {
  if (!struck_unwritten_) return;
  struck_unwritten_ = false;
  const std::uint32_t i = chain_.active;
  Particle<D>& p = this->system_.particles[i];
  p.velocity[chain_.axis] = speed_;
  p.time = flight_.time;
  this->system_.records[i].count_pair_collision(flight_.time);
}

template <std::size_t D>
bool EcmcEngine<D>::next_lift(double end_time, Event& event) {
  while (true) {
    // A whole lap without a lift (from the start column's cells through to their next image,
    // where the lap ends): nothing lies in the lane, and the flight goes on to the chain's end.
    if (columns_crossed_ > cells_along_[chain_.axis]) [[unlikely]] {
      if (!this->due_by(chain_.chain_end, end_time)) return false;
      start_next_chain();
      continue;
    }
    const double ahead = distance_to_next_column();
    const Lift lift = nearest_lift(ahead);
    // A lift no farther than the crossing comes no later (the flight's time + x / v rounds
    // monotonically in x): then only its time is needed.
    if (lift.distance <= ahead && lift.distance != kNever) [[likely]] {
      const double lift_time = flight_.time + lift.distance / speed_;
      if (chain_.chain_end <= lift_time) {
        if (!this->due_by(chain_.chain_end, end_time)) return false;
        start_next_chain();
        continue;
      }
      if (!this->due_by(lift_time, end_time)) return false;
      this->lift(lift, lift_time, event);
      return true;
    }
    const double crossing_time = flight_.time + std::max(ahead / speed_, 0.0);
    if (chain_.chain_end <= crossing_time) {
      if (!this->due_by(chain_.chain_end, end_time)) return false;
      start_next_chain();
      continue;
    }
    if (!this->due_by(crossing_time, end_time)) return false;
    const std::size_t axis = chain_.axis;
    cell_ = grid_.adjacent(cell_, axis, true);
    at_[axis] = at_[axis] + 1 == cells_along_[axis] ? 0 : at_[axis] + 1;
    ++columns_crossed_;
  }
}

template <std::size_t D>
std::uint64_t EcmcEngine<D>::lift_quietly(double end_time, std::uint64_t most, Counts& run,
                                          Counts& window, Event& last) {
  std::uint64_t done = 0;
  while (done < most && next_lift(end_time, last)) {
    count_lift<D>(run, window, last);
    ++done;
  }
  write_struck();
  return done;
}

// Engine::apply's swap-rule collision of the pair, bit for bit, with what it does written out for
// one particle moving along the axis at speed_ and one at rest (unit masses): the mover brought
// to t along the axis (the one at rest stays where it is, inside the box), r = first - partner
// through the nearest image, the velocities exchanged, r . dp, the mover wrapped into the box.
// The terms that are zeros in apply() add nothing, signed zeros included.
template <std::size_t D>
void EcmcEngine<D>::lift(const Lift& lift, double t, Event& event) {
  const std::uint32_t moving = chain_.active, target = lift.target;
  const std::size_t axis = chain_.axis;
  System<D>& system = this->system_;
  event.first = std::min(moving, target);
  event.partner = static_cast<std::int32_t>(std::max(moving, target));
  this->events_at_now_ = t == this->now_ ? this->events_at_now_ + 1 : 0;
  if (this->events_at_now_ > 64 * system.particles.size() + 1000) [[unlikely]] {
    write_struck();
    event.time = t;
    this->throw_stuck(event);
  }
  this->now_ = t;
  // The particle struck is the next one ahead, about a diameter on: a chain's front moves on by
  // a cell or so a lift, and each search reads cells the ones before did not. The column of
  // cells kLead ahead of the target's is asked for now, a lift or two before a search reads it,
  // where the lists do not fit in a core's cache (at an edge of the grid some of these are other
  // cells: no harm). So are the target's System entries, written at its own lift.
  if (prefetch_cells_) {
    for (const std::int64_t offset : lead_offsets_[axis]) {
      const auto cell = static_cast<std::uint64_t>(lift.cell + offset);
      if (cell < fill_.size()) {
        __builtin_prefetch(resting_.data() + cell * capacity_);
        __builtin_prefetch(fill_.data() + cell);
      }
    }
    __builtin_prefetch(system.particles.data() + target, 1);
    __builtin_prefetch(system.records.data() + target, 1);
  }
  const Resting& struck = resting_[lift.slot];
  Vec<D> xm = flight_.from;
  xm[axis] += speed_ * (t - flight_.time);
  const bool moving_first = moving < target;
  Vec<D> r = moving_first ? xm - struck.position : struck.position - xm;
  for (std::size_t k = 0; k < D; ++k) {
    if (!(std::abs(r[k]) <= half_box_[k])) [[unlikely]]
      r[k] = nearest_image(r[k], system.box.size[k]);
  }
  // The first one's velocity after less before: -speed_ or speed_ along the axis.
  const double change = moving_first ? -speed_ : speed_;
  event.impulse = 0.0 + r[axis] * change;
  event.elastic_by_tc = false;
  event.momentum = {};
  event.momentum[axis] = change;
  for (std::size_t k = 0; k < D; ++k) event.contact[k] = r[k];
  event.time = system.absolute(t);
  // The mover's entries as Engine::apply leaves them; its being struck (moving since then) is
  // counted now if it was not written then (write_struck()).
  ParticleRecord& rm = system.records[moving];
  wrap_into_box(xm, rm.image);
  Particle<D>& pm = system.particles[moving];
  pm.position = xm;
  pm.velocity[axis] = 0.0;
  pm.time = t;
  const std::uint32_t counted = struck_unwritten_ ? 2 : 1;
  rm.pair_collisions += counted;
  rm.changes += counted;
  rm.last_collision = t;
  struck_unwritten_ = true;
  flight_ = {struck.position, t, struck.radius};
  // The one that stopped rests where it is; the one struck moves on from its cell.
  take_out(lift.slot, lift.cell);
  rest(moving, locate_moved(xm), xm, pm.radius);
  chain_.active = target;
  cell_ = lift.cell;
  at_ = grid_.coordinates_of(cell_);
  start_flight();
}

template <std::size_t D>
void EcmcEngine<D>::start_next_chain() {
  write_struck();
  Particle<D>& a = this->system_.particles[chain_.active];
  ParticleRecord& record = this->system_.records[chain_.active];
  const double t = chain_.chain_end;
  advance(a, t);
  this->velocity_changes_.push_back({chain_.active, t, a.velocity, Vec<D>{}});
  a.velocity = Vec<D>{};
  wrap(a, this->system_.box, record.image);
  rest(chain_.active, locate_moved(a.position));
  chain_.axis = static_cast<std::uint8_t>((chain_.axis + 1) % D);
  start_moving_at(t);
  this->velocity_changes_.push_back({chain_.active, t, Vec<D>{}, along<D>(chain_.axis, speed_)});
}

template <std::size_t D>
void EcmcEngine<D>::start_moving_at(double t) {
  chain_.active =
      static_cast<std::uint32_t>(chain_.rng(static_cast<std::uint32_t>(this->system_.size())));
  Particle<D>& next = this->system_.particles[chain_.active];
  next.time = t;
  next.velocity = along<D>(chain_.axis, speed_);
  chain_.chain_end = t + chain_duration_;
  set_moving(chain_.active);
}

template <std::size_t D>
void EcmcEngine<D>::velocity_reset(std::uint32_t) {
  throw std::logic_error("event-chain Monte Carlo has no velocities to reset");
}

template void check_chain_start(const System<2>&);
template void check_chain_start(const System<3>&);
template class EcmcEngine<2>;
template class EcmcEngine<3>;

}  // namespace carom

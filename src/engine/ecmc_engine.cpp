#include "ecmc_engine.hpp"

#include <fmt/format.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <new>
#include <stdexcept>

#include "carom/engine/initial.hpp"
#include "carom/engine/simulation.hpp"
#include "large_pages.hpp"

namespace carom {

namespace {

// The grid the chains search: cells one largest diameter wide or more, and three or more along
// every axis wherever the box is wider than three diameters, however sparse the system (a
// search looks at a cell and its neighbours, which must be distinct cells); about two cells a
// particle otherwise, so a sparse box with one narrow side costs no more than a cubic one.
template <std::size_t D>
CellGrid<D> chain_grid(const System<D>& system) {
  return CellGrid<D>(system.box, 2.0 * largest_radius(system), system.size(), 3);
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
          "event-chain Monte Carlo needs a box more than three of the largest diameters wide along "
          "every axis (by a part in a million: three cells, each a hair wider than a diameter); "
          "this one is {} wide along axis {}, and the largest diameter is {}",
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
EcmcEngine<D>::EcmcEngine(System<D> system, double chain_length, const ChainState& chain,
                          ContactKernel kernel)
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
  chain_length_ = chain_length;
  chain_duration_ = chain_length * diameter / speed_;
  for (std::size_t k = 0; k < D; ++k) {
    half_box_[k] = 0.5 * this->system_.box.size[k];
    cells_along_[k] = grid_.cells_along(k);
    strides_[k] = k == 0 ? 1 : strides_[k - 1] * cells_along_[k - 1];
    widths_[k] = grid_.width(k);
  }
  // The blocks, with room for the fullest cell's particles.
  std::vector<std::uint32_t> cell_of(n);
  std::vector<std::uint32_t> in_cell(grid_.cell_count(), 0);
  std::uint32_t fullest = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    cell_of[i] = grid_.locate(this->system_.particles[i].position);
    fullest = std::max(fullest, ++in_cell[cell_of[i]]);
  }
  cells_ = grid_.cell_count();
  radius_ = this->system_.particles[0].radius;
  radii_kept_ = std::any_of(this->system_.particles.begin(), this->system_.particles.end(),
                            [&](const Particle<D>& p) { return p.radius != radius_; });
  std::uint32_t capacity = D == 2 && !radii_kept_ ? 3 : 4;
  while (capacity < fullest) capacity = more_lanes(capacity);
  lay_out(capacity);
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
    std::size_t wide = 0;
    for (std::size_t across = 0; across < D; ++across) {
      if (across == axis) continue;
      for (const std::int64_t columns : {kLead - 1, kLead}) {
        for (const std::int64_t rows : {-2, 2}) {
          wide_offsets_[axis][wide++] = columns * strides_[axis] + rows * strides_[across];
        }
      }
    }
  }
  prefer_large_pages(this->system_);
  stops_held_ = (sizeof(Particle<D>) + sizeof(ParticleRecord)) * n > kHeldAbove;
  if (stops_held_) stops_.reserve(kStopsHeld);
  set_moving(chain_.active);
#ifdef CAROM_HAVE_AVX2_KERNEL
  avx2_ = kernel != ContactKernel::scalar && cpu_has_avx2();
#else
  static_cast<void>(kernel);
#endif
}

template <std::size_t D>
EcmcEngine<D>::EcmcEngine(System<D> system, double chain_length, pcg32 rng, ContactKernel kernel)
    : EcmcEngine(at_rest(std::move(system)), chain_length, ChainState{0, 0, 0.0, rng}, kernel) {
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
[[gnu::always_inline]] inline std::uint32_t EcmcEngine<D>::locate_moved(const Vec<D>& position,
                                                                        std::size_t axis) const {
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
[[gnu::always_inline]] inline void EcmcEngine<D>::wrap_into_box(Vec<D>& position, std::uint32_t i) {
  for (std::size_t k = 0; k < D; ++k) {
    const double side = this->system_.box.size[k];
    if (position[k] > 0.0 && position[k] < side) [[likely]]
      continue;
    const double sides = std::floor(position[k] / side);
    position[k] -= side * sides;
    if (sides != 0.0) add_sides(this->system_.records[i].image[k], sides);
  }
}

namespace {
// The index in a lane of a block whose indices begin `offset` doubles in (see
// EcmcEngine::lanes_).
[[gnu::always_inline]] inline std::uint32_t id_at(const double* block, std::size_t offset,
                                                  std::uint32_t lane) {
  std::uint32_t id;
  const auto* ids = reinterpret_cast<const unsigned char*>(block + offset);
  std::memcpy(&id, ids + sizeof(id) * lane, sizeof(id));
  return id;
}
}  // namespace

template <std::size_t D>
template <class S>
[[gnu::always_inline]] inline Vec<D> EcmcEngine<D>::position_in(const S& shape, const double* b,
                                                                std::uint32_t lane) {
  Vec<D> position;
  for (std::size_t k = 0; k < D; ++k) position[k] = b[k * shape.capacity + lane];
  return position;
}

template <std::size_t D>
template <class S>
[[gnu::always_inline]] inline double EcmcEngine<D>::radius_in(const S& shape, const double* b,
                                                              std::uint32_t lane) const {
  return shape.radii ? b[D * shape.capacity + lane] : radius_;
}

template <std::size_t D>
template <class S>
[[gnu::always_inline]] inline std::uint32_t EcmcEngine<D>::id_in(const S& shape, const double* b,
                                                                 std::uint32_t lane) {
  return id_at(b, shape.ids, lane);
}

template <std::size_t D>
template <class S>
[[gnu::always_inline]] inline std::uint32_t EcmcEngine<D>::fill(const S& shape, const double* b) {
  return id_at(b, shape.ids, shape.capacity);
}

template <std::size_t D>
template <class S>
[[gnu::always_inline]] inline void EcmcEngine<D>::set_fill(const S& shape, double* b,
                                                           std::uint32_t lanes) {
  auto* ids = reinterpret_cast<unsigned char*>(b + shape.ids);
  std::memcpy(ids + sizeof(lanes) * shape.capacity, &lanes, sizeof(lanes));
}

template <std::size_t D>
template <class S>
[[gnu::always_inline]] inline void EcmcEngine<D>::put(const S& shape, double* b, std::uint32_t lane,
                                                      const Vec<D>& position, double radius,
                                                      std::uint32_t id) {
  for (std::size_t k = 0; k < D; ++k) b[k * shape.capacity + lane] = position[k];
  if (shape.radii) b[D * shape.capacity + lane] = radius;
  auto* ids = reinterpret_cast<unsigned char*>(b + shape.ids);
  std::memcpy(ids + sizeof(id) * lane, &id, sizeof(id));
}

template <std::size_t D>
template <class S>
[[gnu::always_inline]] inline bool EcmcEngine<D>::rest_in(const S& shape, double* b,
                                                          std::uint32_t i, const Vec<D>& position,
                                                          double radius) {
  const std::uint32_t lanes = fill(shape, b);
  if (lanes == shape.capacity) [[unlikely]]
    return false;
  put(shape, b, lanes, position, radius, i);
  set_fill(shape, b, lanes + 1);
  return true;
}

template <std::size_t D>
void EcmcEngine<D>::rest(std::uint32_t i, std::uint32_t cell, const Vec<D>& position,
                         double radius) {
  if (!rest_in(shape(), block(cell), i, position, radius)) {
    lay_out(more_lanes(capacity_));
    rest_in(shape(), block(cell), i, position, radius);
  }
}

template <std::size_t D>
void EcmcEngine<D>::rest(std::uint32_t i, std::uint32_t cell) {
  const Particle<D>& p = this->system_.particles[i];
  rest(i, cell, p.position, p.radius);
}

template <std::size_t D>
template <class S>
[[gnu::always_inline]] inline void EcmcEngine<D>::take_out(const S& shape, double* b,
                                                           std::uint32_t lane) {
  const std::uint32_t last = fill(shape, b) - 1;
  set_fill(shape, b, last);
  put(shape, b, lane, position_in(shape, b, last), radius_in(shape, b, last),
      id_in(shape, b, last));
  // A NaN first coordinate is enough: the lane's distance, discriminant and every test on them
  // are NaN or false.
  b[last] = std::numeric_limits<double>::quiet_NaN();
}

template <std::size_t D>
template <class F>
[[gnu::always_inline]] inline decltype(auto) EcmcEngine<D>::with_shape(F&& f) const {
  if (!radii_kept_) {
    if (capacity_ == 3) return f(FixedShape<3, false>{});
    if (capacity_ == 4) return f(FixedShape<4, false>{});
    if (capacity_ == 8) return f(FixedShape<8, false>{});
  } else {
    if (capacity_ == 4) return f(FixedShape<4, true>{});
    if (capacity_ == 8) return f(FixedShape<8, true>{});
  }
  return f(shape());
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
void EcmcEngine<D>::lay_out(std::uint32_t capacity) {
  struct Held {
    Vec<D> position;
    double radius;
    std::uint32_t id;
    std::uint32_t cell;
  };
  std::vector<Held> held;
  const Shape before = shape();
  for (std::uint32_t cell = 0; cell < (lanes_.empty() ? 0 : cells_); ++cell) {
    const double* const b = block(cell);
    for (std::uint32_t lane = 0; lane < fill(before, b); ++lane) {
      held.push_back(
          {position_in(before, b, lane), radius_in(before, b, lane), id_in(before, b, lane), cell});
    }
  }
  capacity_ = capacity;
  ids_offset_ = (D + (radii_kept_ ? 1 : 0)) * capacity;
  block_ = block_doubles(capacity, radii_kept_);
  lanes_.assign(std::size_t{cells_} * block_, 0.0);      // no lane in use
  for (std::uint32_t cell = 0; cell < cells_; ++cell) {  // every lane empty (take_out)
    std::fill_n(block(cell), capacity, std::numeric_limits<double>::quiet_NaN());
  }
  for (const Held& h : held) rest_in(shape(), block(h.cell), h.id, h.position, h.radius);
  prefetch_cells_ = lanes_.size() * sizeof(double) > kCacheBytes;
  prefetch_wide_ = lanes_.size() * sizeof(double) > kWideAbove;
}

template <std::size_t D>
void EcmcEngine<D>::set_moving(std::uint32_t i) {
  // Where it rests: its stored position located as when it came to rest.
  const Particle<D>& p = this->system_.particles[i];
  flight_ = {p.position, p.time, p.radius};
  const std::uint32_t cell = locate(p.position);
  double* const b = block(cell);
  std::uint32_t lane = 0;
  while (id_in(shape(), b, lane) != i) ++lane;
  take_out(shape(), b, lane);
  cell_ = cell;
  at_ = grid_.coordinates_of(cell);
  start_flight(chain_.axis);
}

template <std::size_t D>
[[gnu::always_inline]] inline void EcmcEngine<D>::start_flight(std::size_t axis) {
  start_column_ = at_[axis];
  columns_crossed_ = 0;
}

// lift_distance(r, Axis, sigma) with no limit, r = p - b, in two steps: whether the active
// particle touches b at all (ahead of it, in its lane: the axis first, since half are behind),
// then where. No bound cuts candidates short, which changes no nearest lift (the nearest is
// never cut).
template <std::size_t D, std::size_t Axis>
struct Approach {
  double along;         // r's component along the axis (< 0: b is ahead)
  double c2;            // |r|^2 - sigma^2
  double discriminant;  // along^2 - c2, >= 0 where the lane meets b
  Approach(const Vec<D>& r, double sigma)
      : along(r[Axis]), c2(norm2(r) - sigma * sigma), discriminant(along * along - c2) {}
  bool touches() const { return along < 0.0 && discriminant >= 0.0; }
  // How far the active particle moves to touch b, given touches(), from the terms.
  static double distance(double c2, double along, double discriminant) {
    return c2 <= 0.0 ? 0.0 : c2 / (-along + std::sqrt(discriminant));
  }
  double distance() const { return distance(c2, along, discriminant); }
};

// x less the nearest whole number of sides: image_separation's component when x is more than
// half a side (rare: out of line).
[[gnu::noinline]] static double nearest_image(double x, double side) {
  return x - side * std::nearbyint(x / side);
}

template <std::size_t D>
template <std::size_t Axis, class S>
[[gnu::always_inline]] inline typename EcmcEngine<D>::Lift EcmcEngine<D>::nearest_lift(
    const S& shape, double ahead) const {
  bool inner = at_[Axis] + 1 < cells_along_[Axis];
  for (std::size_t k = 0; k < D; ++k) {
    if (k != Axis) inner = inner && at_[k] - 1 < cells_along_[k] - 2;  // 1 <= at <= n - 2
  }
  // Plain: no separation needs an image (cells that do not wrap, a flight that has not wrapped
  // round the box, a grid five cells across or more).
  const bool plain = inner && plain_grid_ && start_column_ + columns_crossed_ < cells_along_[Axis];
  Cells cells;
  if (inner) [[likely]] {
    for (std::size_t c = 0; c < kAhead; ++c) {
      cells[c] = static_cast<std::uint32_t>(cell_ + inner_offsets_[Axis][c]);
    }
  } else {
    cells_ahead<Axis>(cells);
  }
  Lift nearest;
#if defined(__SSE2__)
  if constexpr (!std::is_same_v<S, Shape>) {
    nearest = nearest_lift_in_lanes<Axis, S::capacity, S::radii>(cells, ahead, !plain);
  } else {
    nearest = nearest_lift_one_by_one<Axis>(cells, ahead);
  }
#else
  nearest = nearest_lift_one_by_one<Axis>(cells, ahead);
#endif
  if (landing_) [[likely]]
    measure_landing<Axis>(shape, ahead, plain, nearest);
  return nearest;
}

// The last lift's mover, not yet in its block (see landing_), measured as if it were, in the
// lane it will take (the first free one). It touches the particle moving now, if at all, where
// its stop rounded it level with or ahead of it, in contact: in the column searched or the
// next, a row aside at most, in a block searched.
// Out of line: inlined, the searches of spheres held fewer of their terms in registers (4000
// spheres at 0.45, 1627 -> 1804 instructions a lift).
template <std::size_t D>
template <std::size_t Axis, class S>
[[gnu::noinline]] void EcmcEngine<D>::measure_landing(const S& shape, double ahead, bool plain,
                                                      Lift& nearest) const {
  Vec<D> r;
  if (plain) {
    for (std::size_t k = 0; k < D; ++k) r[k] = flight_.from[k] - landing_at_.position[k];
  } else {
    r = separation<Axis>(landing_at_.position, ahead);
  }
  const Approach<D, Axis> approach(r, flight_.radius + landing_at_.radius);
  if (approach.touches()) [[unlikely]] {
    nearest.keep_nearer({approach.distance(), landing_at_.id, fill(shape, block(landing_at_.cell)),
                         landing_at_.cell});
  }
}

template <std::size_t D>
template <std::size_t Axis>
void EcmcEngine<D>::cells_ahead(Cells& cells) const {
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
  std::size_t c = 0;
  if constexpr (D == 2) {
    constexpr std::size_t kX = Axis == 0 ? 2 : 3, kY = Axis == 1 ? 2 : 3;
    for (std::size_t y = 0; y < kY; ++y) {
      for (std::size_t x = 0; x < kX; ++x) cells[c++] = along[1][y] + along[0][x];
    }
  } else {
    constexpr std::size_t kX = Axis == 0 ? 2 : 3, kY = Axis == 1 ? 2 : 3, kZ = Axis == 2 ? 2 : 3;
    for (std::size_t z = 0; z < kZ; ++z) {
      for (std::size_t y = 0; y < kY; ++y) {
        for (std::size_t x = 0; x < kX; ++x) cells[c++] = along[2][z] + along[1][y] + along[0][x];
      }
    }
  }
}

// The image of b the search sees: the one in the two columns of cells being searched. They lie
// within a cell width of their middle, p + ahead, less than half a side, so the image is the one
// within half a side of it; across the axis it is image_separation's nearest image.
template <std::size_t D>
template <std::size_t Axis>
[[gnu::always_inline]] inline Vec<D> EcmcEngine<D>::separation(const Vec<D>& b,
                                                               double ahead) const {
  const Vec<D>& half = half_box_;
  const Vec<D>& side = this->system_.box.size;
  const double centre = -ahead;
  Vec<D> r;
  for (std::size_t k = 0; k < D; ++k) {
    r[k] = flight_.from[k] - b[k];
    if (k == Axis) {
      if (!(r[k] >= centre - half[k] && r[k] <= centre + half[k])) {
        r[k] -= side[k] * std::nearbyint((r[k] - centre) / side[k]);
      }
    } else if (!(std::abs(r[k]) <= half[k])) {
      r[k] = nearest_image(r[k], side[k]);
    }
  }
  return r;
}

#if defined(__SSE2__)
namespace {
// Four doubles (or their comparisons) at a time, through GCC's vector extensions: compiled into
// lifts_avx2 they are one AVX register each, into the baseline loop two SSE2 registers. (Passed
// by value only to and from functions that are always inlined, so the calling convention GCC
// warns of, which differs with and without AVX, is never used; GCC reports it at the file's end,
// so it is silenced from here on.)
#pragma GCC diagnostic ignored "-Wpsabi"
using Quad = double __attribute__((vector_size(32)));
using QuadMask = std::int64_t __attribute__((vector_size(32)));

[[gnu::always_inline]] inline Quad load_quad(const double* at) {
  Quad q;
  std::memcpy(&q, at, sizeof(q));
  return q;
}
[[gnu::always_inline]] inline Quad broadcast(double x) { return Quad{x, x, x, x}; }
// A bit for each element of `mask` that is set: the high halves of its four words (which hold
// their signs) gathered into one register and their signs read at once (one shuffle and one
// movmskps; the two movmskpd of the register's halves cost 16 instructions more a lift at 4096
// disks, 576 -> 560).
[[gnu::always_inline]] inline unsigned bits_of(QuadMask mask) {
  using Octet = std::int32_t __attribute__((vector_size(32)));
  const auto words = reinterpret_cast<Octet>(mask);
  const auto signs = reinterpret_cast<__m128>(__builtin_shufflevector(words, words, 1, 3, 5, 7));
  return static_cast<unsigned>(_mm_movemask_ps(signs));
}
// std::nearbyint, element by element, in the default rounding mode, for |x| < 2^51: x plus
// 1.5 x 2^52 is rounded to a whole number (ties to even) and the addend taken off exactly. (Only
// the sign of a zero may differ, and x - side * n is the same for either.)
[[gnu::always_inline]] inline Quad nearbyint4(Quad x) {
  const Quad shift = broadcast(0x1.8p52);
  return (x + shift) - shift;
}
}  // namespace

// The lanes of the cells' blocks are tested four at a time, without a branch, for whether the
// active particle touches the particle in each (Approach::touches(), term by term, through the
// image separation() takes where Images: a lane not in use has a NaN first coordinate, so a NaN
// squared distance, and every comparison with NaN is false), and the terms of Approach kept;
// then the few lanes that touch are measured one by one from those terms, as
// nearest_lift_one_by_one measures them (where Images, through separation() again).
template <std::size_t D>
template <std::size_t Axis, std::uint32_t Capacity, bool Radii>
[[gnu::always_inline]] inline typename EcmcEngine<D>::Lift EcmcEngine<D>::nearest_lift_in_lanes(
    const Cells& cells, double ahead, bool images) const {
  return images ? nearest_lift_in_lanes<Axis, Capacity, Radii, true>(cells, ahead)
                : nearest_lift_in_lanes<Axis, Capacity, Radii, false>(cells, ahead);
}

template <std::size_t D>
template <std::size_t Axis, std::uint32_t Capacity, bool Radii, bool Images>
[[gnu::always_inline]] inline typename EcmcEngine<D>::Lift EcmcEngine<D>::nearest_lift_in_lanes(
    const Cells& cells, double ahead) const {
  constexpr std::size_t kIds = FixedShape<Capacity, Radii>::ids;
  constexpr std::size_t kBlock = FixedShape<Capacity, Radii>::doubles;
  const double* const lanes = lanes_.data();
  Quad from[D], half[D], side[D], per_side[D];
  for (std::size_t k = 0; k < D; ++k) {
    from[k] = broadcast(flight_.from[k]);
    half[k] = broadcast(half_box_[k]);
    side[k] = broadcast(this->system_.box.size[k]);
    per_side[k] = broadcast(1.0 / this->system_.box.size[k]);
  }
  const Quad radius = broadcast(flight_.radius), zero{};
  const Quad both_radii = broadcast(flight_.radius + radius_);
  const Quad centre = broadcast(-ahead);
  const Quad low = centre - half[Axis], high = centre + half[Axis];
  const QuadMask magnitude = QuadMask{} + 0x7fffffffffffffff;
  // A slot for each lane, kStride a cell (a power of two, four or more, so that a slot's cell
  // and lane are a shift and a mask away): a bit in `touching` for each lane that touches, and
  // its Approach's terms.
  constexpr std::size_t kStride = std::bit_ceil(std::max<std::size_t>(Capacity, 4));
  constexpr std::size_t kSlots = kAhead * kStride;
  std::array<std::uint64_t, (kSlots + 63) / 64> touching{};
  alignas(32) double alongs[kSlots], c2s[kSlots], discriminants[kSlots];
  for (std::size_t c = 0; c < kAhead; ++c) {
    const double* const b = lanes + std::size_t{cells[c]} * kBlock;
    for (std::uint32_t lane = 0; lane < Capacity; lane += 4) {
      // Lanes are used from the first on: a NaN here is the end of those in use.
      if (lane > 0 && std::isnan(b[lane])) break;
      Quad r[D];
      for (std::size_t k = 0; k < D; ++k) {
        r[k] = from[k] - load_quad(b + k * Capacity + lane);
        // separation(), term by term, but for whole sides counted with 1 / side for / side:
        // the two differ only for a quotient within a rounding of a half, a particle half a side
        // from the columns searched, which touches through neither image (a lane that touches
        // is measured again through separation()).
        if constexpr (Images) {
          if (k == Axis) {
            const QuadMask inside = r[k] >= low && r[k] <= high;
            r[k] = inside ? r[k] : r[k] - side[k] * nearbyint4((r[k] - centre) * per_side[k]);
          } else {
            const QuadMask inside = reinterpret_cast<Quad>(reinterpret_cast<QuadMask>(r[k]) &
                                                           magnitude) <= half[k];
            r[k] = inside ? r[k] : r[k] - side[k] * nearbyint4(r[k] * per_side[k]);
          }
        }
      }
      Quad norm = r[0] * r[0];
      for (std::size_t k = 1; k < D; ++k) norm += r[k] * r[k];
      const Quad sigma = Radii ? radius + load_quad(b + D * Capacity + lane) : both_radii;
      const Quad c2 = norm - sigma * sigma;
      const Quad along = r[Axis];
      const Quad discriminant = along * along - c2;
      // Of fewer than four lanes left, the doubles after the last are the next run's, or
      // indices: their bits are dropped.
      constexpr unsigned kInUse = Capacity < 4 ? (1u << Capacity) - 1 : 15u;
      const std::uint64_t hits = bits_of(along < zero && discriminant >= zero) & kInUse;
      const std::size_t at = c * kStride + lane;
      touching[at / 64] |= hits << (at % 64);
      if constexpr (!Images) {
        std::memcpy(alongs + at, &along, sizeof(along));
        std::memcpy(c2s + at, &c2, sizeof(c2));
        std::memcpy(discriminants + at, &discriminant, sizeof(discriminant));
      }
    }
  }
  // The nearest, ties to the lower index (keep_nearer). The distances are independent of each
  // other, and which is the nearest is a coin toss: chosen without a branch, they are measured
  // side by side, not one after another behind a mispredicted branch that waits on a square
  // root and a division. The indices are read only where two lie at the same distance (tied),
  // and then every lane that touches is taken again, one by one.
  const auto id_of = [&](std::size_t at) __attribute__((always_inline)) {
    return id_at(lanes + std::size_t{cells[at / kStride]} * kBlock, kIds,
                 static_cast<std::uint32_t>(at % kStride));
  };
  const auto distance_at = [&](std::size_t at) __attribute__((always_inline)) {
    if constexpr (Images) {
      const std::uint32_t lane = at % kStride;
      const double* const b = lanes + std::size_t{cells[at / kStride]} * kBlock;
      Vec<D> position;
      for (std::size_t k = 0; k < D; ++k) position[k] = b[k * Capacity + lane];
      return Approach<D, Axis>(separation<Axis>(position, ahead),
                               flight_.radius + (Radii ? b[D * Capacity + lane] : radius_))
          .distance();
    } else {
      return Approach<D, Axis>::distance(c2s[at], alongs[at], discriminants[at]);
    }
  };
  double nearest = kNever;
  std::size_t nearest_at = 0;
  bool tied = false;
  for (std::size_t word = 0; word < touching.size(); ++word) {
    for (std::uint64_t hits = touching[word]; hits != 0; hits &= hits - 1) {
      const std::size_t at = 64 * word + static_cast<std::size_t>(std::countr_zero(hits));
      const double s = distance_at(at);
      tied |= s == nearest;
      const bool nearer = s < nearest;
      nearest_at = nearer ? at : nearest_at;
      nearest = nearer ? s : nearest;
    }
  }
  const auto lift_at = [&](std::size_t at, double distance) __attribute__((always_inline)) {
    return Lift{distance, id_of(at), static_cast<std::uint32_t>(at % kStride),
                cells[at / kStride]};
  };
  if (tied) [[unlikely]] {
    Lift best{kNever, chain_.active, 0, 0};
    for (std::size_t word = 0; word < touching.size(); ++word) {
      for (std::uint64_t hits = touching[word]; hits != 0; hits &= hits - 1) {
        const std::size_t at = 64 * word + static_cast<std::size_t>(std::countr_zero(hits));
        best.keep_nearer(lift_at(at, distance_at(at)));
      }
    }
    return best;
  }
  if (nearest == kNever) return {kNever, chain_.active, 0, 0};
  return lift_at(nearest_at, nearest);
}
#endif

template <std::size_t D>
template <std::size_t Axis>
typename EcmcEngine<D>::Lift EcmcEngine<D>::nearest_lift_one_by_one(const Cells& cells,
                                                                    double ahead) const {
  Lift best{kNever, chain_.active, 0, 0};
  const Shape now = shape();
  for (const std::uint32_t cell : cells) {
    const double* const b = block(cell);
    for (std::uint32_t lane = 0, lanes = fill(now, b); lane < lanes; ++lane) {
      const Approach<D, Axis> approach(separation<Axis>(position_in(now, b, lane), ahead),
                                       flight_.radius + radius_in(now, b, lane));
      if (!approach.touches()) continue;
      best.keep_nearer({approach.distance(), id_in(now, b, lane), lane, cell});
    }
  }
  return best;
}

template <std::size_t D>
[[gnu::always_inline]] inline double EcmcEngine<D>::distance_to_next_column() const {
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
  write_back();
  return lift;
}

template <std::size_t D>
void EcmcEngine<D>::write_stops() {
  constexpr std::size_t kAheadOfWrite = 8;
  for (std::size_t s = 0; s < stops_.size(); ++s) {
    if (s + kAheadOfWrite < stops_.size()) {
      prefetch_entries(stops_[s + kAheadOfWrite].id);
    }
    write_stop(stops_[s], chain_.axis);
    this->system_.records[stops_[s].id].add_pair_collisions(stops_[s].counted);
  }
  stops_.clear();
}

template <std::size_t D>
[[gnu::always_inline]] inline void EcmcEngine<D>::prefetch_entries(std::uint32_t i) const {
  const auto whole = [](const auto* entry) __attribute__((always_inline)) {
    const auto* const first = reinterpret_cast<const char*>(entry);
    __builtin_prefetch(first, 1);
    __builtin_prefetch(first + sizeof(*entry) - 1, 1);
  };
  whole(this->system_.particles.data() + i);
  whole(this->system_.records.data() + i);
}

template <std::size_t D>
[[gnu::always_inline]] inline void EcmcEngine<D>::write_stop(const Stop& stop, std::size_t axis) {
  Particle<D>& p = this->system_.particles[stop.id];
  p.position = stop.position;
  p.velocity[axis] = 0.0;
  p.time = stop.time;
  this->system_.records[stop.id].last_collision = stop.time;
}

template <std::size_t D>
[[gnu::always_inline]] inline void EcmcEngine<D>::count_lifts(std::uint32_t i,
                                                              std::uint32_t lifts) {
  Count& oldest = counts_lagging_[next_count_];
  this->system_.records[oldest.id].add_pair_collisions(oldest.lifts);  // {0, 0} where none lags
  oldest = {i, lifts};
  next_count_ = (next_count_ + 1) % kCountsLag;
}

template <std::size_t D>
void EcmcEngine<D>::write_counts() {
  for (std::size_t c = 0; c < kCountsLag; ++c) count_lifts(0, 0);
}

template <std::size_t D>
void EcmcEngine<D>::write_back() {
  if (landing_) {
    landing_ = false;
    rest(landing_at_.id, landing_at_.cell, landing_at_.position, landing_at_.radius);
  }
  write_stops();
  write_counts();
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
  return lifts(end_time, 1, event, [](const Event&) {}) == 1;
}

template <std::size_t D>
template <class OnLift>
std::uint64_t EcmcEngine<D>::lifts(double end_time, std::uint64_t most, Event& last,
                                   OnLift&& on_lift) {
#ifdef CAROM_HAVE_AVX2_KERNEL
  if (avx2_) return lifts_avx2(end_time, most, last, on_lift);
#endif
  return lifts_loop(end_time, most, last, on_lift);
}

#ifdef CAROM_HAVE_AVX2_KERNEL
template <std::size_t D>
template <class OnLift>
[[gnu::target("avx2")]] std::uint64_t EcmcEngine<D>::lifts_avx2(double end_time, std::uint64_t most,
                                                                Event& last, OnLift&& on_lift) {
  return lifts_loop(end_time, most, last, on_lift);
}
#endif

// Everything a lift runs is inlined here (always_inline), so that lifts_avx2 compiles it anew.
template <std::size_t D>
template <class OnLift>
[[gnu::always_inline]] inline std::uint64_t EcmcEngine<D>::lifts_loop(double end_time,
                                                                      std::uint64_t most,
                                                                      Event& last,
                                                                      OnLift&& on_lift) {
  std::uint64_t done = 0;
  // Lifts along one axis in blocks of one layout, in a loop compiled for them, until the chain
  // turns or the blocks are laid out anew (a full cell): then the next axis and layout.
  bool due = true;
  while (due && done < most) {
    due = with_axis([&]<std::size_t Axis>() __attribute__((always_inline)) {
      return with_shape([&](const auto& shape) __attribute__((always_inline)) {
        while (true) {
          const FlightEnd end = fly_to_next_lift<Axis>(shape, end_time, last);
          if (end != FlightEnd::lifted) return end != FlightEnd::not_due;
          on_lift(last);
          if (++done == most || capacity_ != shape.capacity) return true;
        }
      });
    });
  }
  return done;
}

template <std::size_t D>
template <class F>
[[gnu::always_inline]] inline decltype(auto) EcmcEngine<D>::with_axis(F&& f) const {
  static_assert(D == 2 || D == 3);
  if constexpr (D == 3) {
    if (chain_.axis == 2) return f.template operator()<2>();
  }
  return chain_.axis == 0 ? f.template operator()<0>() : f.template operator()<1>();
}

template <std::size_t D>
template <std::size_t Axis, class S>
[[gnu::always_inline]] inline typename EcmcEngine<D>::FlightEnd EcmcEngine<D>::fly_to_next_lift(
    const S& shape, double end_time, Event& event) {
  while (true) {
    // A whole lap without a lift (from the start column's cells through to their next image,
    // where the lap ends): nothing lies in the lane, and the flight goes on to the chain's end.
    if (columns_crossed_ > cells_along_[Axis]) [[unlikely]] {
      if (!this->due_by(chain_.chain_end, end_time)) return FlightEnd::not_due;
      start_next_chain();
      return FlightEnd::turned;
    }
    const double ahead = distance_to_next_column();
    const Lift lift = nearest_lift<Axis>(shape, ahead);
    if (landing_) [[likely]] {
      landing_ = false;
      const Landing& l = landing_at_;
      if (!rest_in(shape, block(l.cell), l.id, l.position, l.radius)) [[unlikely]] {
        rest(l.id, l.cell, l.position, l.radius);  // the blocks laid out anew: search again
        return FlightEnd::relaid;
      }
    }
    // A lift no farther than the crossing comes no later (the flight's time + x / v rounds
    // monotonically in x): then only its time is needed.
    if (lift.distance <= ahead && lift.distance != kNever) [[likely]] {
      const double lift_time = flight_.time + lift.distance / speed_;
      if (chain_.chain_end <= lift_time) {
        if (!this->due_by(chain_.chain_end, end_time)) return FlightEnd::not_due;
        start_next_chain();
        return FlightEnd::turned;
      }
      if (!this->due_by(lift_time, end_time)) return FlightEnd::not_due;
      this->lift<Axis>(shape, lift, lift_time, event);
      return FlightEnd::lifted;
    }
    const double crossing_time = flight_.time + std::max(ahead / speed_, 0.0);
    if (chain_.chain_end <= crossing_time) {
      if (!this->due_by(chain_.chain_end, end_time)) return FlightEnd::not_due;
      start_next_chain();
      return FlightEnd::turned;
    }
    if (!this->due_by(crossing_time, end_time)) return FlightEnd::not_due;
    cell_ = grid_.adjacent(cell_, Axis, true);
    at_[Axis] = at_[Axis] + 1 == cells_along_[Axis] ? 0 : at_[Axis] + 1;
    ++columns_crossed_;
  }
}

template <std::size_t D>
std::uint64_t EcmcEngine<D>::lift_quietly(double end_time, std::uint64_t most, Counts& run,
                                          Counts& window, Event& last) {
  std::uint64_t done = 0;
  LiftTally<D> tally(run, window);
  try {
    done = lifts(end_time, most, last, [&](const Event& lift) { tally.add(lift); });
  } catch (...) {  // a jam: the lifts made before it are counted, as one by one
    tally.commit(run, window);
    throw;
  }
  tally.commit(run, window);
  write_back();
  return done;
}

// Engine::apply's swap-rule collision of the pair, bit for bit, with what it does written out for
// one particle moving along the axis at speed_ and one at rest (unit masses): the mover brought
// to t along the axis (the one at rest stays where it is, inside the box), r = first - partner
// through the nearest image, the velocities exchanged, r . dp, the mover wrapped into the box.
// The terms that are zeros in apply() add nothing, signed zeros included.
template <std::size_t D>
template <std::size_t Axis, class S>
[[gnu::always_inline]] inline void EcmcEngine<D>::lift(const S& shape, const Lift& lift, double t,
                                                       Event& event) {
  const std::uint32_t moving = chain_.active, target = lift.target;
  constexpr std::size_t axis = Axis;
  System<D>& system = this->system_;
  event.first = std::min(moving, target);
  event.partner = static_cast<std::int32_t>(std::max(moving, target));
  // A jam: lifts that move the clock on by nothing a double resolves, counted from where it last
  // moved on by 2^-40 of itself or more (a ring of particles in contact around the box, which
  // rounding never lets go, has the clock creep by an ulp now and then: counting lifts at one
  // unchanged time missed it, and such a run lifted for ever at one instant, Z without bound).
  if (t - stall_since_ > std::abs(t) * 0x1p-40) {
    stall_since_ = t;
    this->events_at_now_ = 0;
  } else if (++this->events_at_now_ > 64 * system.particles.size() + 1000) [[unlikely]] {
    write_back();
    event.time = t;
    throw_ring(event);
  }
  this->now_ = t;
  // The particle struck is the next one ahead, about a diameter on: a chain's front moves on by
  // a cell or so a lift, and each search reads cells the ones before did not. The column of
  // cells kLead ahead of the target's is asked for now, a lift or two before a search reads it,
  // where the blocks do not fit in a core's cache (at an edge of the grid some of these are other
  // cells: no harm): the lines of their coordinates (and radii), which every search reads (not
  // the indices' beyond them: 3D spheres at N = 32768 were 5 % slower with them), and where
  // they fit in no cache at all the cells two rows aside (wide_offsets_). So are the target's
  // System entries where a lift writes its stop itself (not stops_held_).
  if (prefetch_cells_) {
    const std::size_t read = shape.ids * sizeof(double);
    const auto fetch = [&](const std::int64_t offset) __attribute__((always_inline)) {
      const auto cell = static_cast<std::uint64_t>(lift.cell + offset);
      if (cell < cells_) {
        const auto* const b =
            reinterpret_cast<const char*>(block(static_cast<std::uint32_t>(cell)));
        for (std::size_t line = 0; line < read; line += 64) {
          __builtin_prefetch(b + line);
        }
      }
    };
    for (const std::int64_t offset : lead_offsets_[axis]) fetch(offset);
    if (prefetch_wide_) {
      for (const std::int64_t offset : wide_offsets_[axis]) fetch(offset);
    }
    if (!stops_held_) {
      prefetch_entries(target);
    }
  }
  double* const lanes = lanes_.data();
  double* const struck_block = lanes + std::size_t{lift.cell} * shape.doubles;
  const Vec<D> struck = position_in(shape, struck_block, lift.lane);
  Vec<D> xm = flight_.from;
  xm[axis] += speed_ * (t - flight_.time);
  const bool moving_first = moving < target;
  Vec<D> r = moving_first ? xm - struck : struck - xm;
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
  // The mover's entries as Engine::apply leaves them, now or with the chain's other stops
  // (stops_held_) but for its image flags, which change only here; its being struck (moving
  // since then) is counted now if it was not written then (write_back()).
  wrap_into_box(xm, moving);
  const Stop stop{xm, t, moving, struck_unwritten_ ? 2u : 1u};
  if (stops_held_) {
    if (stops_.size() == kStopsHeld) [[unlikely]]
      write_stops();
    stops_.push_back(stop);
  } else {
    write_stop(stop, axis);
    count_lifts(moving, stop.counted);
  }
  struck_unwritten_ = true;
  const double mover_radius = flight_.radius;
  flight_ = {struck, t, radius_in(shape, struck_block, lift.lane)};
  // The one struck moves on from its cell; the one that stopped rests where it is, put into its
  // block after the next search (landing_).
  take_out(shape, struck_block, lift.lane);
  landing_at_ = {xm, mover_radius, moving, locate_moved(xm, axis)};
  landing_ = true;
  chain_.active = target;
  cell_ = lift.cell;
  at_ = grid_.coordinates_of(cell_);
  start_flight(axis);
}

template <std::size_t D>
void EcmcEngine<D>::throw_ring(const Event& event) const {
  const char axis = "xyz"[chain_.axis];
  throw JamError(fmt::format(
      "the {0} are jammed for event chains: {1}: the chain goes round a ring of {0} in contact "
      "across the box along {2}, which no move along {2} can open. A perfect lattice (carom "
      "init's) can close such a ring in a small box; start the chains from a state dynamics has "
      "disordered, such as `carom run START 1 --final START2 -o /dev/null` leaves (one unit of "
      "molecular dynamics)",
      kParticlesName<D>, this->describe_stall(event, "lifts"), axis));
}

template <std::size_t D>
void EcmcEngine<D>::start_next_chain() {
  write_back();
  Particle<D>& a = this->system_.particles[chain_.active];
  ParticleRecord& record = this->system_.records[chain_.active];
  const double t = chain_.chain_end;
  advance(a, t);
  this->velocity_changes_.push_back({chain_.active, t, a.velocity, Vec<D>{}});
  a.velocity = Vec<D>{};
  wrap(a, this->system_.box, record.image);
  rest(chain_.active, locate_moved(a.position, chain_.axis));
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
double EcmcEngine<D>::slice_length() const {
  return std::min(Engine<D>::slice_length(), kChainsPerSlice * chain_duration_);
}

void check_chain_clock(double end_time, double chain_length, double chain_duration) {
  // A chain's end is its start plus chain_duration, in stored times no later than end_time:
  // resolved to a millionth of a chain at least.
  if (!(chain_duration >= std::abs(end_time) * 0x1p-32)) {
    throw RunLengthError(fmt::format(
        "{} is too late for event chains of {:.3g} mean diameters: each lasts {:.3g} time units, "
        "and a chain must last a million times what a double resolves at that time ({:.3g}); use a "
        "longer chain length or a shorter run",
        end_time, chain_length, chain_duration, std::abs(end_time) * 0x1p-52));
  }
}

template <std::size_t D>
void EcmcEngine<D>::check_target(double t) const {
  check_chain_clock(t, chain_length_, chain_duration_);
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

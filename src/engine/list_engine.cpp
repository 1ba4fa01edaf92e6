#include "list_engine.hpp"
#include "large_pages.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <limits>
#include <new>

#include "carom/core/observables.hpp"

namespace carom {

namespace {

// Shells' centres may be this much (relatively) further apart than the reach and still be
// neighbours: far more than the round-off in the positions and times that place a particle in
// its shell.
constexpr double kReachMargin = 1e-8;

// Where `j` is in a list that holds it, padded to a multiple of eight by entries other than j.
std::uint32_t position_in(const std::uint32_t* list, std::uint32_t j, const NarrowContacts&) {
  std::uint32_t k = 0;
  while (list[k] != j) ++k;
  return k;
}

#ifdef CAROM_HAVE_AVX2_KERNEL
// Eight entries a comparison.
[[gnu::target("avx2")]] std::uint32_t position_in_eights(const std::uint32_t* list,
                                                         std::uint32_t j) {
  const __m256i wanted = _mm256_set1_epi32(static_cast<int>(j));
  for (std::uint32_t k = 0;; k += 8) {
    const __m256i eight = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(list + k));
    const auto equal = static_cast<unsigned>(
        _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(eight, wanted))));
    if (equal != 0) return k + static_cast<std::uint32_t>(std::countr_zero(equal));
  }
}

[[gnu::target("avx2")]] std::uint32_t position_in(const std::uint32_t* list, std::uint32_t j,
                                                  const WideContacts&) {
  return position_in_eights(list, j);
}

[[gnu::target("avx512f")]] std::uint32_t position_in(const std::uint32_t* list, std::uint32_t j,
                                                     const WiderContacts&) {
  return position_in_eights(list, j);
}
#endif

// A neighbour's name in a list (see ListEngine::slots_).
template <std::size_t D>
std::uint32_t name_of(std::uint32_t index) {
  return ByOffset::name<D>(index);
}

}  // namespace

template <std::size_t D>
bool ListEngine<D>::suits(const System<D>& system, const Growth& growth) {
  // Nor sheared boxes: a list's neighbours across the sheared boundary slide away (the cells
  // follow them).
  if (growth.rate != 0.0 || system.size() == 0 || system.box.sheared()) return false;
  // Lists name particles by offsets of 32 bits (see slots_).
  if (system.size() > std::numeric_limits<std::uint32_t>::max() / kStride<D>) return false;
  double smallest = kNever;
  for (const Particle<D>& p : system.particles) smallest = std::min(smallest, p.radius);
  const double largest = largest_radius(system);
  if (!(smallest > 0.0) || largest > 2.0 * smallest) return false;
  // In a dilute system the cells hold few candidates and a list would be made again after every
  // few collisions: cells serve it better.
  const double packing = packing_fraction(system);
  if (!(packing >= kLeastPacking)) return false;
  if (system.box.periodic()) {
    // Neighbours are at most 2 R (1 + 2 skin) apart: within half a box, one image of each.
    const double apart = 2.0 * largest * (1.0 + 2.0 * skin(packing)) * (1.0 + kReachMargin);
    for (std::size_t k = 0; k < D; ++k) {
      if (!(system.box.size[k] > 2.0 * apart)) return false;
    }
  }
  return true;
}

template <std::size_t D>
ListEngine<D>::ListEngine(System<D> system, const CollisionRule& rule, ContactKernel kernel)
    : Engine<D>(std::move(system), rule, Growth{}),
      shell_(skin(packing_fraction(this->system_)) * largest_radius(this->system_)),
      reach_(2.0 * (largest_radius(this->system_) + shell_) * (1.0 + kReachMargin)),
      grid_(this->system_.box, reach_, this->system_.size()),
      queue_(static_cast<std::uint32_t>(this->system_.size())),
      centre_(this->system_.size() + 1),  // one more, which near_points may read
      size_(this->system_.size(), 0),
      kernel_(std::min(kernel, widest_contact_kernel())) {
  const auto n = static_cast<std::uint32_t>(this->system_.size());
  for (std::uint32_t i = 0; i < n; ++i) {
    grid_.insert(i, grid_.locate(position_at(this->system_.particles[i], this->now_)));
  }
  make_all_lists();
  // What an event reads and writes, in large pages (large_pages.hpp).
  prefer_large_pages(this->system_);
  grid_.prefer_large_pages();
  queue_.prefer_large_pages();
  prefer_large_pages(centre_);
  prefer_large_pages(slots_.get(), this->system_.size() * capacity_ * sizeof(std::uint32_t));
}

template <std::size_t D>
std::vector<std::uint32_t> ListEngine<D>::neighbours(std::uint32_t i) const {
  std::vector<std::uint32_t> indices;
  for (std::uint32_t k = 0; k < size_[i]; ++k) {
    indices.push_back(ByOffset::index<D>(slots_[slot(i) + k]));
  }
  return indices;
}

template <std::size_t D>
void ListEngine<D>::rebased(double) {
  queue_ = EventCalendar(static_cast<std::uint32_t>(this->system_.size()));
  make_all_lists();
}

template <std::size_t D>
void ListEngine<D>::make_all_lists() {
  const auto& particles = this->system_.particles;
  const auto n = static_cast<std::uint32_t>(particles.size());
  clock_ = this->now_;
  for (std::uint32_t i = 0; i < n; ++i) {
    centre_[i] = position_at(particles[i], clock_);
    const std::uint32_t cell = grid_.locate(centre_[i]);
    if (cell != grid_.cell_of(i)) grid_.move(i, cell);
  }
  const Box<D>& box = this->system_.box;
  const auto for_each_pair = [&](auto&& pair) {
    for (std::uint32_t i = 0; i < n; ++i) {
      grid_.for_each_within(centre_[i], reach_, [&](std::uint32_t j) {
        if (j > i && near_points_scalar(centre_[i], centre_.data(), &j, 1, box, reach_) != 0) {
          pair(i, j);
        }
      });
    }
  };
  // The lists' lengths first, so that their slots are allocated once, as many as the longest
  // needs (later growth widens them), the old ones freed before.
  std::fill(size_.begin(), size_.end(), 0);
  for_each_pair([&](std::uint32_t i, std::uint32_t j) {
    ++size_[i];
    ++size_[j];
  });
  const std::uint32_t longest = n == 0 ? 0 : *std::max_element(size_.begin(), size_.end());
  const std::size_t capacity =
      std::max<std::size_t>(8, (std::size_t{longest} + 7) & ~std::size_t{7});
  if (!slots_ || capacity > capacity_) {
    slots_.reset();
    capacity_ = capacity;
    reserve_slots(slot(n));
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    std::fill_n(&slots_[slot(i)], capacity_, name_of<D>(i));
    size_[i] = 0;
  }
  for_each_pair([&](std::uint32_t i, std::uint32_t j) {
    add(i, j);
    add(j, i);
  });
  // The scalar kernel's times are the wide kernels' (contact_batch.hpp): it serves here, once.
  for (std::uint32_t i = 0; i < n; ++i) predict_with(i, NarrowContacts{});
}

template <std::size_t D>
template <class Contacts>
void ListEngine<D>::make_list_with(std::uint32_t i, const Contacts& contacts) {
  // The old neighbours, told apart from the new ones: most are neighbours again, and their lists
  // keep i where it is; only the lists of those that leave or come change.
  const std::uint32_t old_count = size_[i];
  // Room for the list, a sentinel and the rest of its eight.
  if (former_.size() < old_count + 8) former_.resize(old_count + 8);
  std::uint32_t* old = former_.data();
  std::copy_n(&slots_[slot(i)], old_count, old);
  std::uint32_t left = old_count;  // old neighbours not found again yet: old[0 .. left)
  size_[i] = 0;
  const Vec<D> centre = position_at(this->system_.particles[i], clock_);
  centre_[i] = centre;
  // The candidates in batches, padded by the particle itself, which is no neighbour of its own.
  const Box<D>& box = this->system_.box;
  std::array<std::uint32_t, kMostContacts> batch;
  std::size_t size = 0;
  const auto flush = [&] {
    while (size % Contacts::kLanes != 0) batch[size++] = i;
    for (std::uint64_t near =
             contacts.near_points(centre, centre_.data(), batch.data(), size, box, reach_);
         near != 0; near &= near - 1) {
      const std::uint32_t j = batch[static_cast<std::size_t>(std::countr_zero(near))];
      if (j == i) continue;
      add(i, j);
      old[left] = name_of<D>(j);  // a sentinel: the search stops at `left` if j is new
      const std::uint32_t k = position_in(old, name_of<D>(j), contacts);
      if (k < left) {
        old[k] = old[--left];
      } else {
        add(j, i);
      }
    }
    size = 0;
  };
  const std::uint32_t cell = grid_.for_each_within(centre, reach_, [&](std::uint32_t j) {
    batch[size++] = j;
    if (size == kMostContacts) flush();
  });
  if (size > 0) flush();
  for (std::uint32_t k = 0; k < left; ++k) remove(ByOffset::index<D>(old[k]), i, contacts);
  // Slots the shorter list no longer holds are padding again.
  if (size_[i] < old_count) {
    std::fill(&slots_[slot(i) + size_[i]], &slots_[slot(i) + old_count], name_of<D>(i));
  }
  if (cell != grid_.cell_of(i)) grid_.move(i, cell);
}

template <std::size_t D>
void ListEngine<D>::add(std::uint32_t i, std::uint32_t j) {
  if (size_[i] == capacity_) widen();
  slots_[slot(i) + size_[i]++] = name_of<D>(j);
}

template <std::size_t D>
template <class Contacts>
void ListEngine<D>::remove(std::uint32_t i, std::uint32_t j, const Contacts& contacts) {
  std::uint32_t* list = &slots_[slot(i)];
  const std::uint32_t last = --size_[i];
  const std::uint32_t k = position_in(list, name_of<D>(j), contacts);
  list[k] = list[last];
  list[last] = name_of<D>(i);
}

template <std::size_t D>
void ListEngine<D>::widen() {
  // Eight more, not half as many again: lists grow by a few neighbours as a lattice melts or a
  // fluctuation crowds one, and every particle pays for the longest. Each widening moves every
  // list once; there are a handful in a run.
  const std::size_t capacity = capacity_ + 8;
  const auto n = static_cast<std::uint32_t>(size_.size());
  reserve_slots(std::size_t{n} * capacity);
  // Each list moves up to its wider slots, the last first: no list is overwritten before it moves.
  for (std::uint32_t i = n; i-- > 0;) {
    std::uint32_t* from = &slots_[std::size_t{i} * capacity_];
    std::uint32_t* to = &slots_[std::size_t{i} * capacity];
    std::copy_backward(from, from + size_[i], to + size_[i]);
    std::fill(to + size_[i], to + capacity, name_of<D>(i));
  }
  capacity_ = capacity;
}

template <std::size_t D>
void ListEngine<D>::reserve_slots(std::size_t count) {
  void* grown = std::realloc(slots_.get(), count * sizeof(std::uint32_t));
  if (grown == nullptr) throw std::bad_alloc();
  (void)slots_.release();
  slots_.reset(static_cast<std::uint32_t*>(grown));
}

template <std::size_t D>
template <class Contacts>
void ListEngine<D>::predict_with(std::uint32_t i, const Contacts& contacts) {
  const auto& particles = this->system_.particles;
  const Particle<D>& p = particles[i];
  const Box<D>& box = this->system_.box;
  const Vec<D> here = position_at(p, clock_);
  EarliestEvent<D> earliest;
  earliest.start_with_wall(contacts, p, box, i, clock_);
  // Leaving its shell first: nothing after it matters (the list is made again then, and with it
  // the prediction), so it bounds the contacts worth looking at. A collision at the same instant
  // still comes first (after_collisions).
  const double exit = shell_exit_delay(here - centre_[i], p.velocity, shell_);
  if (exit != kNever) {
    const EventKey renewal{clock_ + exit, after_collisions(i)};
    // A renewal the time cannot resolve would come again at the same instant forever.
    if (renewal.time == clock_ && exit > 0.0) this->throw_too_fast(clock_);
    if (renewal < earliest.key) earliest.key = renewal;
  }
  // The list in the kernel's widths: its own padding is the particle itself, never a contact of
  // its own.
  const std::uint32_t* list = &slots_[slot(i)];
  constexpr std::size_t lanes = Contacts::kLanes;
  const std::size_t count = (std::size_t{size_[i]} + lanes - 1) / lanes * lanes;
  for (std::size_t from = 0; from < count; from += kMostContacts) {
    earliest.try_batch(contacts, p, here, clock_, box, particles.data(), i, list + from,
                       std::min(count - from, kMostContacts), ByOffset{});
  }
  earliest.read_partner_version(this->system_.records);
  // The version fits the tag: it counts in 32 bits (ParticleRecord::changes).
  queue_.update(i, earliest.key, static_cast<std::uint32_t>(earliest.pending.partner_version));
}

template <std::size_t D>
std::optional<Event> ListEngine<D>::step(double end_time) {
  switch (kernel_) {
    case ContactKernel::avx512:
      return step_avx512(end_time);
    case ContactKernel::avx2:
      return step_avx2(end_time);
    default:
      return step_scalar(end_time);
  }
}

// The event loop compiled for each kernel's instructions, everything it calls in this file inlined.
template <std::size_t D>
[[gnu::flatten]] std::optional<Event> ListEngine<D>::step_scalar(double end_time) {
  return step_with(end_time, NarrowContacts{});
}

#ifdef CAROM_HAVE_AVX2_KERNEL
template <std::size_t D>
[[gnu::flatten, gnu::target("avx2")]] std::optional<Event> ListEngine<D>::step_avx2(
    double end_time) {
  return step_with(end_time, WideContacts{});
}

template <std::size_t D>
[[gnu::flatten, gnu::target("avx512f")]] std::optional<Event> ListEngine<D>::step_avx512(
    double end_time) {
  return step_with(end_time, WiderContacts{});
}
#else
template <std::size_t D>
std::optional<Event> ListEngine<D>::step_avx2(double end_time) {
  return step_scalar(end_time);
}

template <std::size_t D>
std::optional<Event> ListEngine<D>::step_avx512(double end_time) {
  return step_scalar(end_time);
}
#endif

template <std::size_t D>
template <class Contacts>
std::optional<Event> ListEngine<D>::step_with(double end_time, const Contacts& contacts) {
  const auto& records = this->system_.records;
  while (true) {
    // Events a few steps away are known: what they will read is fetched while these are handled.
    const std::uint32_t i = queue_.top([&](std::uint32_t slot, int) { prefetch_entry(slot); });
    const EventKey key = queue_.top_key();
    const double t = key.time;
    if (t == kNever || !this->due_by(t, end_time)) return std::nullopt;  // kNever: none queued
    const KeyedEntry entry = keyed_entry<D>(i, key);
    switch (entry.kind) {
      case EntryKind::crossing:  // leaving its shell
        clock_ = t;
        make_list_with(i, contacts);
        predict_with(i, contacts);
        continue;
      case EntryKind::wall: {
        clock_ = t;
        const Event event = this->apply({t, i, entry.partner});
        predict_with(i, contacts);
        return event;
      }
      case EntryKind::pair: {
        const auto j = static_cast<std::uint32_t>(entry.partner);
        if (records[j].version() != queue_.tag(i)) {
          predict_with(i, contacts);  // the partner has collided since: this event will not happen
          continue;
        }
        clock_ = t;
        const Event event = this->apply(pair_event(t, i, j));
        predict_with(i, contacts);
        predict_with(j, contacts);
        return event;
      }
      case EntryKind::renewal:  // only the cell engine has one
        __builtin_unreachable();
    }
  }
}

// Every kernel predicts the same times bit for bit: the scalar one serves this rare event.
template <std::size_t D>
void ListEngine<D>::velocity_reset(std::uint32_t i) {
  clock_ = this->now_;
  predict_with(i, NarrowContacts{});
}

template class ListEngine<2>;
template class ListEngine<3>;

}  // namespace carom

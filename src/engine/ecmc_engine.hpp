// Straight event-chain Monte Carlo (Bernard, Krauth and Wilson, Phys. Rev. E 80, 056704 (2009)) as
// an engine: one particle, the active one, moves along +x (then +y, then +z in 3D, in turn) at
// constant speed while every other rests; when it touches another it stops and hands its velocity
// on (a lift), and the one struck carries the rest of the displacement. After a chain of
// `chain_length` mean diameters of displacement the direction turns and a new active particle is
// drawn uniformly at random. No move is ever rejected, and the moves sample the equilibrium of
// hard particles at any temperature.
//
// A lift is the swap rule's collision of a moving particle with one at rest, so the engine speaks
// the engines' language: stored (lazy) states with times, lifts as pair events with the momentum
// they carry (unit masses), the epoch and its rebasing. The active particle moves at N times the
// mean diameter per unit time, so that a unit of time moves every particle one diameter on
// average. With it the virial and the kinetic temperature (m v^2 / (D N), the one moving
// particle's) give ECMC's pressure exactly: Z = 1 + (sum over lifts of the separation along the
// move) / (the displacement) (Michel, Kapfer and Krauth, J. Chem. Phys. 140, 054116 (2014)).
//
// Candidates come from a cell grid: a particle the active one touches while inside its cell lies
// in the block of cells around it, and not in the layer behind (CellGrid::for_each_ahead), so the
// nearest lift there is the next event if it comes before the active particle leaves its cell;
// otherwise the cell changes and the cells are searched again. No calendar: the next event is
// always the active particle's. The particles at rest are kept in a block per cell, coordinate by
// coordinate in lanes, so that a search reads a few runs of contiguous memory, never the System,
// and tests four particles at a time without a branch on which it touches; the System's stored
// states are brought up to date as Engine::apply would (the lifts are its swap-rule collisions
// bit for bit), at every lift or, in large systems, a chain's stops in bulk, before the engine
// returns.
//
// Lifts are measured from where the active particle's flight began (its stored state), through
// the image of each candidate that lies in the two columns of cells being searched: the flight
// knows how many columns it has crossed, so it can be any length, several box sides included.
// After a whole lap without a lift nothing lies in its lane, and it flies on to the chain's end.
// That needs three cells or more along every axis (a box three of the largest diameters wide):
// with fewer, one column's window would hold two images of a particle.
#pragma once

#include <array>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <pcg_random.hpp>
#include <vector>

#include "carom/core/measurement.hpp"
#include "carom/engine/engine.hpp"
#include "carom/engine/sampler.hpp"
#include "cell_grid.hpp"
#include "contact_batch.hpp"

namespace carom {

template <std::size_t D>
class EcmcEngine final : public Engine<D> {
 public:
  // Starts chains in `system` (a periodic box; velocities are ignored and masses taken as 1): the
  // first active particle is drawn from `rng`, moving along x. `chain_length` in mean diameters.
  // The lifts are computed with `kernel`'s instructions (the same lifts, bit for bit: see lifts()).
  EcmcEngine(System<D> system, double chain_length, pcg32 rng,
             ContactKernel kernel = widest_contact_kernel());
  // Continues from `chain`, with `system`'s stored states as an EcmcEngine left them.
  EcmcEngine(System<D> system, double chain_length, const ChainState& chain,
             ContactKernel kernel = widest_contact_kernel());

  std::optional<Event> step(double end_time) override;
  // step() in a loop without leaving the engine, for a run that looks at no event alone: the
  // lifts due by the absolute `end_time`, at most `most`, each counted into `run` and `window` as
  // Simulation::record counts one (count_lift), the last one left in `last`. Returns how many.
  std::uint64_t lift_quietly(double end_time, std::uint64_t most, Counts& run, Counts& window,
                             Event& last);

  const ChainState& chain() const { return chain_; }
  // A slice also bounds the chains begun in it (kChainsPerSlice): chains far shorter than the
  // space between particles end by the thousand without a lift, each a velocity change the
  // Simulation takes only after the engine returns.
  double slice_length() const override;
  // Chains too short for the clock to resolve by t (a chain's end no later than its start, or
  // hardly): RunLengthError.
  void check_target(double t) const override;
  // The active particle's speed: N mean diameters per unit time.
  double speed() const { return speed_; }
  // The lanes a cell's block has room for (see lanes_).
  std::uint32_t lanes_per_cell() const { return capacity_; }

 private:
  // Only times move: the flight's start and the columns it crossed stay as they were (no stop is
  // held: the engine has returned, write_back() done).
  void rebased(double shift) override {
    chain_.chain_end -= shift;
    stall_since_ -= shift;
    flight_.time = this->system_.particles[chain_.active].time;
  }
  void velocity_reset(std::uint32_t) override;
  // One particle moves (at speed_, N mean diameters a unit of time): a slice of a run bounds its
  // cell crossings, not those of N particles at that speed (with which a slice at N = 10^6 was
  // shorter than a lift, and each of its ends cost searches thrown away).
  double moving_particles() const override { return 1.0; }

  // The nearest lift found: how far from the active particle's stored position (kNever if none),
  // the partner, and where it rests (its cell and its lane there).
  struct Lift {
    double distance;
    std::uint32_t target;
    std::uint32_t lane;
    std::uint32_t cell;
    // Becomes `other` if other is nearer; of two as near, the one with the lower index.
    void keep_nearer(const Lift& other) {
      if (other.distance < distance || (other.distance == distance && other.target < target)) {
        *this = other;
      }
    }
  };
  // Memory for the blocks: large ones in 2 MiB pages where the system offers them (a search reads
  // rows of cells a box side apart, each on a page of its own otherwise).
  template <class T>
  struct LargePages {
    using value_type = T;
    LargePages() = default;
    template <class U>
    LargePages(const LargePages<U>&) {}
    T* allocate(std::size_t n);
    void deallocate(T* p, std::size_t) { std::free(p); }
    friend bool operator==(const LargePages&, const LargePages&) { return true; }
  };

  // Stops the active particle at the chain's end and starts the next chain.
  void start_next_chain();
  // JamError for lifts that no longer move the clock on: in a periodic box, a ring of particles
  // in contact all round it along the chain's axis, round which a chain lifts for ever with no
  // displacement (exactly, not by rounding: a perfect lattice gives rows whose particles, each
  // pushed across the axis into contact with both neighbours ahead of it, close one).
  [[noreturn]] void throw_ring(const Event& event) const;
  // The nearest lift of the active particle among the particles around its cell (the cells
  // CellGrid::for_each_ahead visits), measured from its stored position: ties go to the lower
  // index. `ahead` is distance_to_next_column(); the blocks' layout is `shape`'s.
  template <std::size_t Axis, class S>
  Lift nearest_lift(const S& shape, double ahead) const;
  // nearest_lift's measure of the last lift's mover, not yet in its block (see landing_): kept
  // in `nearest` if nearer; `plain` as nearest_lift found it.
  template <std::size_t Axis, class S>
  void measure_landing(const S& shape, double ahead, bool plain, Lift& nearest) const;
  // The cells a search reads (CellGrid::for_each_ahead's), wrapping round the box.
  static constexpr std::size_t kAhead = D == 2 ? 6 : 18;
  using Cells = std::array<std::uint32_t, kAhead>;
  template <std::size_t Axis>
  void cells_ahead(Cells& cells) const;
  // The separation from b (a particle's stored position) to the active particle's stored
  // position, through the image of b a search of the cells ahead sees; `ahead` as in
  // nearest_lift.
  template <std::size_t Axis>
  Vec<D> separation(const Vec<D>& b, double ahead) const;
  // nearest_lift among `cells`, for blocks of Capacity lanes with the radii in them where Radii
  // (else every radius is radius_): the lanes four at a time, through images where Images (else
  // the plain differences, which nearest_lift has checked are theirs).
  template <std::size_t Axis, std::uint32_t Capacity, bool Radii, bool Images>
  Lift nearest_lift_in_lanes(const Cells& cells, double ahead) const;
  template <std::size_t Axis, std::uint32_t Capacity, bool Radii>
  Lift nearest_lift_in_lanes(const Cells& cells, double ahead, bool images) const;
  // nearest_lift among `cells` for any capacity: the lanes in use one by one.
  template <std::size_t Axis>
  Lift nearest_lift_one_by_one(const Cells& cells, double ahead) const;
  // Engine::apply for the lift of the active particle onto lift.target at stored time t, bit for
  // bit; then the target moves on. Every field of `event` is written (a run that counts lifts
  // quietly reuses one).
  // The blocks' layout is `shape`'s (see with_shape()).
  template <std::size_t Axis, class S>
  void lift(const S& shape, const Lift& lift, double t, Event& event);
  // step() into `event`: false, and `event` as it was, if no lift is due by `end_time`.
  bool next_lift(double end_time, Event& event);
  // The lifts due by `end_time`, at most `most`, each left in `last` and handed to on_lift:
  // how many. next_lift() and lift_quietly() are this loop (lifts_loop, everything a lift runs
  // inlined into it), compiled with AVX2's instructions where the CPU has them (lifts_avx2:
  // their three-operand forms spare the search's register copies; 4096 disks at 0.70, 662
  // instructions a lift before, 637 baseline and 550 AVX2 after; 4000 spheres 1811 -> 1475),
  // else for the baseline. The arithmetic is the same (no fused multiply-add: the library is
  // built with -ffp-contract=off), so the lifts are the same bit for bit.
  template <class OnLift>
  std::uint64_t lifts(double end_time, std::uint64_t most, Event& last, OnLift&& on_lift);
  template <class OnLift>
  std::uint64_t lifts_loop(double end_time, std::uint64_t most, Event& last, OnLift&& on_lift);
#ifdef CAROM_HAVE_AVX2_KERNEL
  template <class OnLift>
  [[gnu::target("avx2")]] std::uint64_t lifts_avx2(double end_time, std::uint64_t most, Event& last,
                                                   OnLift&& on_lift);
#endif
  // How a flight along one axis ended: in a lift, in nothing due by the end time, in a turn
  // to the next chain (whose axis, and the blocks' layout, may differ), or in the blocks laid
  // out anew before its search was done (the search is made again).
  enum class FlightEnd { lifted, not_due, turned, relaid };
  // next_lift() while the chain's axis is Axis and the blocks' layout `shape`'s.
  template <std::size_t Axis, class S>
  FlightEnd fly_to_next_lift(const S& shape, double end_time, Event& event);
  // f.template operator()<Axis>() for the chain's axis.
  template <class F>
  decltype(auto) with_axis(F&& f) const;
  // The System's entries of the particles lifts stopped (write_stops()), then those of the
  // particle struck last, as Engine::apply leaves them (moving at speed_ since its lift, which
  // counted): a lift writes them a lift later, with the struck particle's own stop, where they
  // are written anyway. Done before the engine returns, and before anything reads them.
  void write_back();
  // The stops held (stops_) written into the System, in the order of the lifts.
  void write_stops();
  // Where the column after cell_'s begins along the axis, as the flight has unwrapped it, less
  // the active particle's stored position: how far it is from leaving cell_, and the middle of
  // the two columns of cells a search reads.
  double distance_to_next_column() const;
  // The active particle's flight starts afresh from its stored state, in cell_.
  void start_flight(std::size_t axis);
  // Draws the next chain's active particle, at rest until now, and sets it moving along the
  // chain's axis from stored time t.
  void start_moving_at(double t);
  // Puts particle i at rest into cell `cell`'s block (its position and radius as given, or the
  // System's), the blocks laid out anew with more lanes if the cell is full.
  void rest(std::uint32_t i, std::uint32_t cell, const Vec<D>& position, double radius);
  void rest(std::uint32_t i, std::uint32_t cell);
  // A cell's block, and what a lane of block b (of layout `shape`) holds.
  double* block(std::uint32_t cell) { return lanes_.data() + std::size_t{cell} * block_; }
  const double* block(std::uint32_t cell) const {
    return lanes_.data() + std::size_t{cell} * block_;
  }
  template <class S>
  static Vec<D> position_in(const S& shape, const double* b, std::uint32_t lane);
  template <class S>
  double radius_in(const S& shape, const double* b, std::uint32_t lane) const;
  template <class S>
  static std::uint32_t id_in(const S& shape, const double* b, std::uint32_t lane);
  // How many of a block's lanes are in use (the first ones), and setting it.
  template <class S>
  static std::uint32_t fill(const S& shape, const double* b);
  template <class S>
  static void set_fill(const S& shape, double* b, std::uint32_t lanes);
  template <class S>
  static void put(const S& shape, double* b, std::uint32_t lane, const Vec<D>& position,
                  double radius, std::uint32_t id);
  // Puts particle i at rest in block b: false, and nothing done, if every lane is in use.
  template <class S>
  static bool rest_in(const S& shape, double* b, std::uint32_t i, const Vec<D>& position,
                      double radius);
  // Takes the particle in `lane` out of block b (the last lane in use moves into it).
  template <class S>
  void take_out(const S& shape, double* b, std::uint32_t lane);
  // Every cell's lanes laid out for `capacity` a cell, those in use kept.
  void lay_out(std::uint32_t capacity);
  // The capacity after `capacity` when a cell is full: four after three (the fourth lane of
  // equal disks' cells, whose searches then still read four lanes at a time), else twice as
  // many (capacities the searches by fours of lanes take: 3, 4, 8, 16, ...).
  static constexpr std::uint32_t more_lanes(std::uint32_t capacity) {
    return capacity == 3 ? 4 : 2 * capacity;
  }
  // The doubles a block of `capacity` lanes takes: coordinates, radii if kept, indices and the
  // count, in whole 64-byte lines.
  static constexpr std::size_t block_doubles(std::uint32_t capacity, bool radii) {
    return ((D + (radii ? 1 : 0)) * capacity + (capacity + 2) / 2 + 7) / 8 * 8;
  }
  // The blocks' layout (see lanes_): how many lanes a block has, where its indices begin and how
  // many doubles it takes, and whether it keeps radii. As the engine has it now (Shape), or fixed
  // when compiled (FixedShape), so that a lift's stores into blocks make it read none of these
  // again. Both have the same members.
  struct Shape {
    std::uint32_t capacity;
    std::size_t ids;
    std::size_t doubles;
    bool radii;
  };
  template <std::uint32_t Capacity, bool Radii>
  struct FixedShape {
    static constexpr std::uint32_t capacity = Capacity;
    static constexpr std::size_t ids = (D + (Radii ? 1 : 0)) * Capacity;
    static constexpr std::size_t doubles = block_doubles(Capacity, Radii);
    static constexpr bool radii = Radii;
  };
  Shape shape() const { return {capacity_, ids_offset_, block_, radii_kept_}; }
  // f(the blocks' layout): a FixedShape where one is compiled (the capacities a search takes by
  // fours of lanes), else shape().
  template <class F>
  decltype(auto) with_shape(F&& f) const;
  // Takes the particle i, at rest, out of its cell's block to move: the active one.
  void set_moving(std::uint32_t i);
  // The active particle's stored state, as the System has it, kept here for the next search: the
  // System's copy is written at every lift but read by none (a lift's next search starts from
  // what the last one read, without waiting for the struck particle's state in the System).
  struct Flight {
    Vec<D> from;        // stored position
    double time = 0.0;  // stored time
    double radius = 0.0;
  };
  // grid_.locate(position), bit for bit: inside the box without libm's floor.
  std::uint32_t locate(const Vec<D>& position) const;
  // locate(position) for the active particle moved along the axis from where its flight began
  // (across the axis it is where cell_ is), bit for bit.
  std::uint32_t locate_moved(const Vec<D>& position, std::size_t axis) const;
  // wrap(position, box, particle i's image flags), bit for bit, inline: its record is touched
  // only where a flag changes.
  void wrap_into_box(Vec<D>& position, std::uint32_t i);

  static constexpr double kChainsPerSlice = 4096;
  bool avx2_ = false;  // lifts() runs lifts_avx2
  // The stored time the clock last moved on from by a step a double resolves (see lift()).
  double stall_since_ = 0.0;
  double chain_length_ = 0.0;    // in mean diameters
  double chain_duration_ = 0.0;  // stored time a chain lasts
  double speed_ = 0.0;
  ChainState chain_;
  Flight flight_;
  // The grid's geometry only: which cells are searched, and when the active particle leaves
  // its cell. The particles at rest are kept here instead, cell by cell in blocks of block_
  // doubles (whole 64-byte lines): a block holds, for each of its capacity_ lanes, one run of
  // coordinates per axis, then the radii unless every particle has the same (radius_), then the
  // indices and after them the count of lanes in use (uint32s, two in a double's room, read and
  // written through memcpy). Equal disks start with three lanes a cell, which fill one line
  // (cells a diameter wide hold four only at their corners), so that a search reads one line a
  // cell; others with four (or as many as the fullest cell needs: lanes are added when a cell
  // is full, more_lanes()). Lanes below the count (fill()) are in use; the others have a NaN
  // first coordinate, which touches nothing, so that a search tests lanes four at a time,
  // whether in use or not, and reads no count (it stops at a four that begins with a NaN). The
  // active particle is in no block.
  CellGrid<D> grid_;
  std::vector<double, LargePages<double>> lanes_;
  std::uint32_t cells_ = 0;  // in the grid
  std::uint32_t capacity_ = 0;
  std::size_t block_ = 0;
  std::size_t ids_offset_ = 0;  // (D + radii_kept_) x capacity_
  bool radii_kept_ = true;      // in the blocks; else every particle's radius is radius_
  double radius_ = 0.0;
  std::uint32_t cell_ = 0;             // the cell the active particle is in now
  std::array<std::uint32_t, D> at_{};  // cell_'s place along each axis
  std::array<std::uint32_t, D> cells_along_{};
  std::array<std::uint32_t, D> strides_{};
  Vec<D> widths_;
  // The cells ahead of a cell one from every edge, relative to it, per axis (the search finds
  // the cells ahead itself).
  std::array<std::array<std::int64_t, kAhead>, D> inner_offsets_{};
  // The column of cells kLead ahead of a cell, relative to it, per axis: fetched ahead (lift()).
  static constexpr std::uint32_t kLead = 2;
  std::array<std::array<std::int64_t, kAhead / 2>, D> lead_offsets_{};
  // Where the blocks are larger than kWideAbove (beyond any cache's reach, so that a search
  // waits on memory for any block not asked for), also the cells two rows off either way along
  // each axis across, in the column kLead ahead and the one before: those the search after next
  // reads when the chain turns a row aside, which it does about every other lift (paired runs
  // at 10^6 disks, 7.73 -> 8.17 M lifts/s, medians of three; at 65536, whose blocks a lift finds
  // in the last-level cache, the fetches cost more than they spared).
  static constexpr std::size_t kWideAbove = std::size_t{32} << 20;
  std::array<std::array<std::int64_t, 4 * (D - 1)>, D> wide_offsets_{};
  bool prefetch_wide_ = false;
  // Blocks larger than this in all are fetched ahead of a search (see lift()).
  static constexpr std::size_t kCacheBytes = std::size_t{1} << 20;
  bool prefetch_cells_ = false;
  // Five cells or more along every axis: two cells either way are less than half a side.
  bool plain_grid_ = false;
  // The column along the axis the flight started in, and how many it has crossed since: after
  // more than cells_along_[axis] of them, the whole lane was searched (see step()).
  std::uint32_t start_column_ = 0;
  std::uint32_t columns_crossed_ = 0;
  bool struck_unwritten_ = false;  // see write_back()
  // A lift's mover is put into its block after the next search, not by the lift: the search
  // cannot touch it (it lies behind the particle struck, which moves away from it) unless its
  // stop rounded it level with or ahead of that one, and nearest_lift() measures it alone for
  // that. The search's loads from the blocks wait on no store whose address the lift's square
  // root and division decide (the mover's cell), and the next search starts as soon as its
  // particle is known: 4096 disks at 0.70, 0.99 -> 0.91 s, medians of ten paired runs; 4000
  // spheres at 0.45 level (docs/performance.md).
  struct Landing {
    Vec<D> position;
    double radius;
    std::uint32_t id;
    std::uint32_t cell;
  };
  Landing landing_at_{};
  bool landing_ = false;  // landing_at_ waits to be put into its block
  // Each lift's mover as Engine::apply leaves it: where and when it stopped, and the lifts it
  // counted there (2 where its being struck was not written).
  struct Stop {
    Vec<D> position;
    double time;
    std::uint32_t id;
    std::uint32_t counted;
  };
  // Writes one into the System, but for its counts: added with the held stop
  // (write_stops()), else by count_lifts().
  void write_stop(const Stop& stop, std::size_t axis);
  // Where a lift writes its own stop (not stops_held_), the lifts it counted are added to the
  // mover's ParticleRecord kCountsLag lifts later (counts_lagging_, the oldest at next_count_),
  // and those still lagging when the engine returns by write_counts(). Its record is asked for
  // when it is struck (prefetch_entries()), a lift before its stop: added at the stop itself
  // (read, then written) the counts waited on the line (a tenth of the samples of perf at 65536
  // disks; paired runs, 10.1 -> 11.1 M lifts/s, medians of five).
  struct Count {
    std::uint32_t id;
    std::uint32_t lifts;
  };
  static constexpr std::size_t kCountsLag = 4;
  std::array<Count, kCountsLag> counts_lagging_{};
  std::size_t next_count_ = 0;
  void count_lifts(std::uint32_t i, std::uint32_t lifts);
  void write_counts();
  // Asks for the lines of particle i's System entries (its Particle and its ParticleRecord, each
  // of which may straddle two lines), to be written.
  void prefetch_entries(std::uint32_t i) const;
  // Where the System's entries are more than kHeldAbove bytes (stops_held_), the stops are held
  // in stops_ and written in bulk (write_stops(): each a line or two of its own, asked for a few
  // stops ahead) at a chain's end, when kStopsHeld are held, and before the engine returns:
  // paired runs, 10^6 disks 6.1 -> 6.7 M lifts/s, 262144 7.8 -> 8.4; but 65536 11.6 -> 11.2
  // and 4096 13.9 -> 13.3, whose System a lift finds in a cache, so there each lift writes its
  // own.
  static constexpr std::size_t kHeldAbove = std::size_t{16} << 20;
  static constexpr std::size_t kStopsHeld = 4096;
  bool stops_held_ = false;
  std::vector<Stop> stops_;
  Vec<D> half_box_;  // 0.5 x each side, as image_offset computes it
};

}  // namespace carom

// Checkpoints: a Simulation serialised, from which it continues exactly as if never
// interrupted. Every particle's stored (lazy) state and record are kept as they are, double for
// double: predictions are functions of the stored states alone, so the resumed run finds the
// same events at the same times, bit for bit.
#pragma once

#include <functional>
#include <istream>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <variant>

#include "carom/engine/checkpoint_state.hpp"
#include "carom/engine/simulation.hpp"

namespace carom {

// Format 5 (carom 1.9) adds the sampler ("sampler": md or ecmc) and event chains' chain in
// flight ("chains"), so that a carom without them refuses such a checkpoint rather than continue
// it as dynamics. Format 4
// (carom 1.8) adds what the summary needs of the measurement window (its records: the
// drift verdict's intervals, the pressure tensor's, transport's blocks, with the window and end
// they measure) and the velocities' seed, so that a run resumed at any instant, its end included,
// reports the uninterrupted run's summary; a carom that knows only format 3 refuses it rather
// than report a summary without them. Format 3 (carom 1.2 to 1.7) records the epoch the stored
// times count from (System::epoch) and every particle's image flags (ParticleRecord::image), and
// is still read (a run resumed from it starts its window's records afresh). Format 2 (carom 1.1:
// the dimension, the TC model's last-collision times, the run's counts apart from the measurement
// window's, whether the run is whole at its time; absolute stored times) and format 1 (carom
// 1.0) are still read, their stored times re-based at once to the latest of them.
// Format 6 adds the particles' types ("types", the names, in the head and each row's last column
// its index): written only for a system with types (has_types), so that a one-type checkpoint
// stays format 5, which older carom reads. The drift verdict's record (formats 4 and up) holds
// blocks that double (block_length, boundaries, totals, temperatures) since carom 1.9's
// 2026-11-27 change, intervals of a twentieth of the window ("every") before: a carom that
// knows only intervals refuses the new record for its missing "every"; this one reads the old
// and measures the errors afresh from the resumed instant.
inline constexpr int kCheckpointFormat = 6;

// json, numbers in shortest round-trip form; written through AtomicFile by the caller.
template <std::size_t D>
void write_checkpoint(std::ostream& out, const Checkpoint<D>& checkpoint);

// Throws InputError naming `name` for anything that is not a complete, consistent checkpoint.
AnyCheckpoint read_checkpoint(std::istream& in, const std::string& name);

// Writes `checkpoint` to `path` atomically (a temporary file, then a rename): a crash never
// leaves half a checkpoint. Throws std::runtime_error when it cannot.
template <std::size_t D>
void save_checkpoint(const std::string& path, const Checkpoint<D>& checkpoint);

// Saves a checkpoint whenever its trigger fires (every so many events or seconds), once the run
// is whole at that instant (Trigger::whole_instant): a checkpoint never splits the events of one
// time, so that files written up to it are cut at its time exactly. `make` gives what to save:
// the simulation's checkpoint with what its run keeps beyond it (Simulation::checkpoint, the
// window's records). `before_save` (optional) flushes what else the run writes, so that a run
// killed after a checkpoint has on disk everything the checkpoint counts.
template <std::size_t D>
class CheckpointWriter final : public Observer<D> {
 public:
  CheckpointWriter(std::string path, Trigger trigger, std::function<Checkpoint<D>()> make,
                   std::function<void()> before_save = {})
      : Observer<D>(trigger.at_whole_instants()),
        path_(std::move(path)),
        make_(std::move(make)),
        before_save_(std::move(before_save)) {}
  void observe(const Simulation<D>&) override {
    if (before_save_) before_save_();
    save_checkpoint(path_, make_());
  }

 private:
  std::string path_;
  std::function<Checkpoint<D>()> make_;
  std::function<void()> before_save_;
};

}  // namespace carom

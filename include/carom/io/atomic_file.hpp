// An output file that appears whole or not at all: written to a temporary file beside the
// target, then renamed over it. A failed or stopped run (its AtomicFile destroyed uncommitted)
// leaves neither a partial file nor a clobbered one; a crash or SIGKILL can leave the temporary
// file, never a partial target. A symbolic link is written through; a device or pipe is written
// directly. No signal handlers: stopping on a signal is the caller's (see Simulation).
#pragma once

#include <fstream>
#include <string>
#include <string_view>

namespace carom {

class AtomicFile {
 public:
  // Creates the temporary file; throws std::runtime_error if the directory is not writable.
  explicit AtomicFile(std::string path);
  ~AtomicFile();  // removes the temporary file unless committed
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ostream& stream() { return stream_; }
  // Flushes, syncs and renames the file into place; throws std::runtime_error on failure.
  void commit();

  // Whether `name` is the name of a temporary file an AtomicFile of `target` (a file name, no
  // folder) made: TARGET.tmp.XXXXXX, the X's mkstemp's letters and digits. Only such a file may
  // be deleted as a leftover of a killed write: a user's "run.tmp.xyz" is not one.
  static bool is_temporary_of(std::string_view name, std::string_view target);

 private:
  std::string path_;
  std::string temporary_;
  std::ofstream stream_;
  bool committed_ = false;
};

}  // namespace carom

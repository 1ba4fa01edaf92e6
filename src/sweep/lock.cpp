// The sweep's locks: an open file description lock (fcntl F_OFD_SETLK) on a lock file, held by
// the open file, not the process, so that two threads of one process exclude each other as two
// processes do, and released by the OS with the last descriptor, however the process ends. Not
// flock: the Linux NFS client emulates it with POSIX record locks, which belong to the process
// (two descriptors of one process do not exclude each other, and closing any one drops the
// lock); open file description locks behave alike locally and over NFS.
#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <utility>

#include "carom/sweep/sweep.hpp"

namespace carom {

std::optional<HeldLock> HeldLock::try_take(const std::string& path) {
  // O_CLOEXEC: a child process (a shell a user's code starts) must not keep the lock alive.
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
  if (fd < 0) {
    throw RequestError(fmt::format("cannot make the lock file {}: {}", path, std::strerror(errno)));
  }
  struct flock whole_file {};
  whole_file.l_type = F_WRLCK;
  whole_file.l_whence = SEEK_SET;  // l_start = l_len = 0: the whole file; l_pid = 0, as OFD needs
  if (::fcntl(fd, F_OFD_SETLK, &whole_file) != 0) {
    const int why = errno;
    ::close(fd);
    if (why == EAGAIN || why == EACCES) return std::nullopt;
    throw RequestError(fmt::format(
        "cannot lock {}: {}: its file system keeps no file locks, without which two sweeps (or "
        "a sweep and a Dask worker left running) could write one task together; use a folder on "
        "a file system with locks (on Lustre, mounted with -o flock)",
        path, std::strerror(why)));
  }
  HeldLock lock(fd);
  std::array<char, 256> host{};
  if (::gethostname(host.data(), host.size() - 1) != 0) host[0] = '\0';
  const std::string who = fmt::format("pid {} on {}\n", ::getpid(), host.data());
  // Who holds it, for others' messages only: a failed write leaves the lock as good.
  const bool named = ::ftruncate(fd, 0) == 0 &&
                     ::pwrite(fd, who.data(), who.size(), 0) == static_cast<ssize_t>(who.size());
  static_cast<void>(named);
  return lock;
}

std::string HeldLock::holder(const std::string& path) {
  std::ifstream in(path);
  std::string who;
  std::getline(in, who);
  return who;
}

HeldLock::HeldLock(HeldLock&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}

HeldLock& HeldLock::operator=(HeldLock&& other) noexcept {
  if (this != &other) {
    release();
    fd_ = std::exchange(other.fd_, -1);
  }
  return *this;
}

HeldLock::~HeldLock() {
  release();
}

void HeldLock::release() {
  if (fd_ < 0) return;
  // No longer anyone's: a later reader finds no holder named (if this fails, closing releases
  // the lock all the same).
  const bool cleared = ::ftruncate(fd_, 0) == 0;
  static_cast<void>(cleared);
  ::close(std::exchange(fd_, -1));
}

HeldLock lock_sweep_folder(const std::string& out_dir) {
  const std::string path = (std::filesystem::path(out_dir) / kSweepLock).string();
  std::optional<HeldLock> lock = HeldLock::try_take(path);
  if (!lock) {
    const std::string who = HeldLock::holder(path);
    throw RequestError(fmt::format(
        "another sweep is running in {} ({}{}): wait for it to end, or stop it, then run this "
        "again",
        out_dir, who.empty() ? "" : who + ", ", "it holds " + path));
  }
  return std::move(*lock);
}

}  // namespace carom

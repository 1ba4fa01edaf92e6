#include "carom/io/atomic_file.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <vector>

namespace carom {

namespace {

namespace fs = std::filesystem;

// What mkstemp replaces with six letters or digits: the temporary is TARGET + this.
constexpr std::string_view kTemporarySuffix = ".tmp.XXXXXX";
constexpr std::size_t kRandomLetters = 6;

[[noreturn]] void fail(const std::string& what, const std::string& path) {
  throw std::runtime_error(fmt::format("{} '{}': {}", what, path, std::strerror(errno)));
}

}  // namespace

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
  std::error_code error;
  // Write through a link to the file it names, so the link stays a link.
  if (fs::is_symlink(path_, error)) path_ = fs::weakly_canonical(path_, error).string();
  const fs::file_status status = fs::status(path_, error);
  if (fs::is_directory(status)) {
    throw std::runtime_error(fmt::format("cannot write '{}': it is a directory", path_));
  }
  // A device or pipe (/dev/stdout, a FIFO) cannot be replaced by renaming: write to it directly.
  if (fs::exists(status) && !fs::is_regular_file(status)) {
    stream_.open(path_, std::ios::binary);
    if (!stream_) fail("cannot open", path_);
    return;
  }
  std::string pattern = path_ + std::string(kTemporarySuffix);
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  const int fd = ::mkstemp(name.data());
  if (fd < 0) fail("cannot create a file beside", path_);
  // mkstemp makes the file private; keep an existing file's permissions, or give a new one those
  // a plainly created file would have.
  struct stat existing {};
  if (::stat(path_.c_str(), &existing) == 0) {
    ::fchmod(fd, existing.st_mode & 07777);
  } else {
    const mode_t mask = ::umask(0);
    ::umask(mask);
    ::fchmod(fd, 0666 & ~mask);
  }
  ::close(fd);
  temporary_.assign(name.data());
  stream_.open(temporary_, std::ios::binary | std::ios::trunc);
  if (!stream_) fail("cannot open", temporary_);
}

AtomicFile::~AtomicFile() {
  if (!committed_ && !temporary_.empty()) {
    stream_.close();
    std::remove(temporary_.c_str());
  }
}

bool AtomicFile::is_temporary_of(std::string_view name, std::string_view target) {
  const std::string_view marker =
      kTemporarySuffix.substr(0, kTemporarySuffix.size() - kRandomLetters);
  if (name.size() != target.size() + kTemporarySuffix.size() || !name.starts_with(target) ||
      name.substr(target.size(), marker.size()) != marker) {
    return false;
  }
  const std::string_view letters = name.substr(name.size() - kRandomLetters);
  return std::all_of(letters.begin(), letters.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9');
  });
}

void AtomicFile::commit() {
  stream_.flush();
  if (!stream_) fail("cannot write", temporary_.empty() ? path_ : temporary_);
  stream_.close();
  if (!stream_) fail("cannot write", temporary_.empty() ? path_ : temporary_);
  committed_ = true;
  if (temporary_.empty()) return;
  const int fd = ::open(temporary_.c_str(), O_RDONLY);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
  if (std::rename(temporary_.c_str(), path_.c_str()) != 0) {
    committed_ = false;
    fail("cannot rename into", path_);
  }
}

}  // namespace carom

#include "carom/run/request.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

namespace carom {

void check_writable(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (fs::is_directory(path, error)) {
    throw RequestError(fmt::format("cannot write '{}': it is a directory", path));
  }
  fs::path folder = fs::path(path).parent_path();
  if (folder.empty()) folder = ".";
  if (!fs::is_directory(folder, error)) {
    throw RequestError(fmt::format("cannot write '{}': no folder {}", path, folder.string()));
  }
  if (::access(folder.c_str(), W_OK) != 0) {
    throw RequestError(fmt::format("cannot write '{}': {}", path, std::strerror(errno)));
  }
}

bool same_file(const std::string& a, const std::string& b) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (fs::exists(a, error) && fs::exists(b, error)) return fs::equivalent(a, b, error);
  const fs::path pa = fs::weakly_canonical(fs::absolute(a, error), error);
  const fs::path pb = fs::weakly_canonical(fs::absolute(b, error), error);
  return pa == pb;
}

void check_files_apart(const std::vector<NamedFile>& inputs,
                       const std::vector<NamedFile>& outputs) {
  const auto names_a_file = [](const NamedFile& f) { return !f.path.empty() && f.path != "-"; };
  for (const NamedFile& input : inputs) {
    if (!names_a_file(input)) continue;
    for (const NamedFile& output : outputs) {
      if (names_a_file(output) && output.option != input.saved_over_by &&
          same_file(input.path, output.path)) {
        throw RequestError(fmt::format(
            "{} and {} name the same file ({} and {}): writing it would destroy what is read",
            input.option, output.option, input.path, output.path));
      }
    }
  }
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    for (std::size_t j = i + 1; j < outputs.size(); ++j) {
      if (names_a_file(outputs[i]) && names_a_file(outputs[j]) &&
          same_file(outputs[i].path, outputs[j].path)) {
        throw RequestError(
            fmt::format("{} and {} name the same file ({} and {}): one would overwrite the other",
                        outputs[i].option, outputs[j].option, outputs[i].path, outputs[j].path));
      }
    }
  }
}

}  // namespace carom

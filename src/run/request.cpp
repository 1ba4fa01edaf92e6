#include "carom/run/request.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <utility>

namespace carom {

MessagePiece option(std::string key, std::string value) {
  MessagePiece piece(std::move(key));
  piece.is_option = true;
  piece.value = std::move(value);
  return piece;
}

std::string command_line_option(std::string_view key) {
  // The keys whose option is not "--" and the key with '-' for '_'.
  static constexpr std::array<std::pair<std::string_view, std::string_view>, 4> kRenamed{{
      {"temperature", "--kT"},
      {"dump_every", "--every"},
      {"measure_from", "--equilibrate"},
      {"end_time", "END_TIME"},
  }};
  for (const auto& [renamed, spelled] : kRenamed) {
    if (renamed == key) return std::string(spelled);
  }
  std::string spelled = "--";
  for (const char c : key) spelled += c == '_' ? '-' : c;
  return spelled;
}

namespace {

std::string joined(const std::vector<MessagePiece>& pieces, const RequestError::Spelling& spell) {
  std::string message;
  for (const MessagePiece& piece : pieces) {
    message += piece.is_option ? spell(piece.text, piece.value) : piece.text;
  }
  return message;
}

std::string command_line_spelling(std::string_view key, std::string_view value) {
  return value.empty() ? command_line_option(key)
                       : fmt::format("{} {}", command_line_option(key), value);
}

}  // namespace

RequestError::RequestError(const std::string& message)
    : std::invalid_argument(message), pieces_{MessagePiece(message)} {}

RequestError::RequestError(std::vector<MessagePiece> pieces)
    : std::invalid_argument(joined(pieces, command_line_spelling)), pieces_(std::move(pieces)) {}

std::string RequestError::worded(const Spelling& spell) const {
  return joined(pieces_, spell);
}

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
      if (names_a_file(output) && output.option.text != input.saved_over_by &&
          same_file(input.path, output.path)) {
        throw RequestError({input.option, " and ", output.option,
                            fmt::format(" name the same file ({} and {}): writing it would "
                                        "destroy what is read",
                                        input.path, output.path)});
      }
    }
  }
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    for (std::size_t j = i + 1; j < outputs.size(); ++j) {
      if (names_a_file(outputs[i]) && names_a_file(outputs[j]) &&
          same_file(outputs[i].path, outputs[j].path)) {
        throw RequestError({outputs[i].option, " and ", outputs[j].option,
                            fmt::format(" name the same file ({} and {}): one would overwrite "
                                        "the other",
                                        outputs[i].path, outputs[j].path)});
      }
    }
  }
}

}  // namespace carom

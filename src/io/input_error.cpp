#include "carom/io/input_error.hpp"

#include <fmt/format.h>

#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "carom/engine/validation.hpp"

namespace carom {

namespace {

std::string location(const std::string& file, std::size_t line) {
  return line == 0 ? file : fmt::format("{}:{}", file, line);
}

}  // namespace

InputError::InputError(const std::string& file, std::size_t line, const std::string& message)
    : std::runtime_error(location(file, line) + ": " + message), file_(file), line_(line) {}

std::string quoted_token(std::string_view token) {
  std::string out;
  for (char ch : token.substr(0, 24))
    out += std::isprint(static_cast<unsigned char>(ch)) ? ch : '?';
  if (token.size() > 24) out += "...";
  return "'" + out + "'";
}

double parse_finite_double(std::string_view token) {
  // from_chars takes no '+' sign; strtod, which users' files were written for, does.
  std::string_view digits = token;
  if (digits.size() > 1 && digits[0] == '+' && digits[1] != '-' && digits[1] != '+') {
    digits.remove_prefix(1);
  }
  double value = 0.0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (error == std::errc::result_out_of_range) {
    throw std::invalid_argument(
        fmt::format("{} is out of range: carom takes magnitudes from {} to {}", quoted_token(token),
                    kSmallestMagnitude, kLargestMagnitude));
  }
  if (error != std::errc() || end != digits.data() + digits.size() || digits.empty()) {
    throw std::invalid_argument(quoted_token(token) + " is not a number");
  }
  if (!std::isfinite(value))
    throw std::invalid_argument(quoted_token(token) + " is not a finite number");
  if (!within_magnitudes(value)) {
    throw std::invalid_argument(
        fmt::format("{} is out of range: carom takes magnitudes from {} to {}", quoted_token(token),
                    kSmallestMagnitude, kLargestMagnitude));
  }
  return value;
}

std::ifstream open_input(const std::string& path) {
  if (std::filesystem::is_directory(path)) throw InputError(path, 0, "is a directory, not a file");
  std::ifstream file(path, std::ios::binary);
  if (!file) throw InputError(path, 0, fmt::format("cannot open: {}", std::strerror(errno)));
  return file;
}

}  // namespace carom

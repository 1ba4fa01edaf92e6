#include "cli_support.hpp"

#include <algorithm>
#include <charconv>
#include <system_error>

namespace carom::cli {

double parse_number(const std::string& text, const std::string& what) {
  try {
    return parse_finite_double(text);
  } catch (const std::invalid_argument& e) {
    throw UsageError(what + ": " + e.what());
  }
}

std::uint64_t parse_whole(const std::string& text, const std::string& option, std::uint64_t least,
                          std::uint64_t most, bool bounded) {
  std::uint64_t value = 0;
  const bool digits_only = !text.empty() && std::all_of(text.begin(), text.end(), [](char c) {
    return c >= '0' && c <= '9';
  });
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (digits_only && error == std::errc() && value >= least && value <= most) return value;
  const bool too_large = digits_only && (error == std::errc::result_out_of_range || value > most);
  const std::string range = bounded     ? fmt::format("from {} to {}", least, most)
                            : too_large ? fmt::format("of at most {}", most)
                                        : fmt::format("of at least {}", least);
  throw CLI::ValidationError(
      fmt::format("{} must be a whole number {}, got '{}'", option, range, text));
}

}  // namespace carom::cli

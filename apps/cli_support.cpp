#include "cli_support.hpp"

namespace carom::cli {

double parse_number(const std::string& text, const std::string& what) {
  try {
    return parse_finite_double(text);
  } catch (const std::invalid_argument& e) {
    throw UsageError(what + ": " + e.what());
  }
}

}  // namespace carom::cli

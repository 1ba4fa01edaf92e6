#include "carom/io/log_table.hpp"

#include <fmt/format.h>

#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include "carom/io/input_error.hpp"

namespace carom {

LogTable read_log_table(const std::string& path) {
  std::ifstream in = open_input(path);
  LogTable table;
  table.file = path;
  const auto fields = [](const std::string& line) {
    std::vector<std::string> out;
    std::stringstream split(line);
    for (std::string field; std::getline(split, field, ',');) out.push_back(field);
    if (!line.empty() && line.back() == ',') out.emplace_back();
    return out;
  };
  std::string line;
  std::size_t number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (number == 1) {
      table.columns = fields(line);
      if (table.columns.empty() || table.columns.front() != "time") {
        throw InputError(path, number, "not a carom log: the header does not start with 'time'");
      }
      continue;
    }
    if (line.empty()) continue;
    const std::vector<std::string> row = fields(line);
    if (row.size() != table.columns.size()) {
      throw InputError(
          path, number,
          fmt::format("expected {} fields, found {}", table.columns.size(), row.size()));
    }
    std::vector<double>& values = table.rows.emplace_back();
    for (std::size_t c = 0; c < row.size(); ++c) {
      if (row[c].empty()) {
        values.push_back(std::numeric_limits<double>::quiet_NaN());
        continue;
      }
      try {
        values.push_back(parse_finite_double(row[c]));
      } catch (const std::invalid_argument& e) {
        throw InputError(path, number, fmt::format("{} (in {})", e.what(), table.columns[c]));
      }
    }
  }
  if (in.bad()) throw InputError(path, number + 1, "read error");
  if (table.columns.empty()) throw InputError(path, 0, "empty: not a carom log");
  return table;
}

}  // namespace carom

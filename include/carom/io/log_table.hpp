// A time-series log (time_series.hpp) read back, for carom analyze.
#pragma once

#include <string>
#include <vector>

namespace carom {

// A time-series log (carom run --log FILE.csv) as read back: its columns, and rows of numbers
// (NaN where a field is empty: not measured yet).
struct LogTable {
  std::string file;
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
};
// Throws InputError naming the file and line for anything that is not such a table.
LogTable read_log_table(const std::string& path);

}  // namespace carom

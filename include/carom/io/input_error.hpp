// What every reader of carom's files throws and uses: an error naming the file and line, opening
// a file to read, and numbers parsed whole.
#pragma once

#include <cstddef>
#include <fstream>
#include <stdexcept>
#include <string>
#include <string_view>

namespace carom {

// A problem with an input file, located at a line (0 when it concerns the file as a whole).
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& file, std::size_t line, const std::string& message);
  const std::string& file() const { return file_; }
  std::size_t line() const { return line_; }

 private:
  std::string file_;
  std::size_t line_;
};

// Opens an input file (classic, checkpoint, trajectory) for reading; throws InputError naming it
// when it is a directory or cannot be opened.
std::ifstream open_input(const std::string& path);

// Parses a whole token as a finite double (`-.5`, `+1`, `1e-3`); throws std::invalid_argument
// with a message saying what is wrong ("is not a number", "is not finite", "is out of range").
double parse_finite_double(std::string_view token);

// A token as a message shows it: quoted, its first 24 characters, non-printable ones as '?'.
std::string quoted_token(std::string_view token);

}  // namespace carom

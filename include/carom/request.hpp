// What the library refuses before it does any work: a request (a run's outputs and cadences, a
// path, a start's options) that cannot be carried out. The message names the command line's
// option, the words the Python module's documentation uses too; the command line reports it as a
// usage error (exit 2), Python as ValueError.
#pragma once

#include <stdexcept>
#include <string>

namespace carom {

class RequestError : public std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// Throws RequestError for a path that cannot be written, before anything is created: its folder
// is missing or not writable, or it is a folder itself.
void check_writable(const std::string& path);

// Whether two paths name one file: the same file if both exist (hard links, symlinks and other
// spellings included), else the same absolute path once symbolic links are resolved.
bool same_file(const std::string& a, const std::string& b);

}  // namespace carom

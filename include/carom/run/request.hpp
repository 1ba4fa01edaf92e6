// What the library refuses before it does any work: a request (a run's outputs and cadences, a
// path, a start's options) that cannot be carried out. The message names the command line's
// option, the words the Python module's documentation uses too; the command line reports it as a
// usage error (exit 2), Python as ValueError.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

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

// A file a command reads or writes, with what names it in messages: the option ("-o", "--html")
// or the argument ("the input FILE").
struct NamedFile {
  std::string option;
  std::string path;
  // For an input, the one output option allowed to save over it ("" for none): a resumed run's
  // checkpoint, saved again by --checkpoint.
  std::string saved_over_by = {};
};

// Throws RequestError, naming both options and paths, when an output is one of the inputs (it
// would be overwritten before or while it is read) or two outputs are one file (one would
// overwrite the other), however the paths are spelled (same_file). Empty paths and "-" (the
// standard streams) are left out. Every front end checks its files with this, before any work.
void check_files_apart(const std::vector<NamedFile>& inputs, const std::vector<NamedFile>& outputs);

}  // namespace carom

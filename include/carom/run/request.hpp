// What the library refuses before it does any work: a request (a run's outputs and cadences, a
// path, a start's options) that cannot be carried out. The command line reports it as a usage
// error (exit 2), Python as ValueError. A message names the options it is about by their keys
// (the fields of RunSpec and StartSpec: "temperature", "dump_every"), which each front end spells
// its own way: `--kT` on the command line, `kT=` in Python.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace carom {

// A piece of a RequestError's message: text, or the option a key names (option("temperature")),
// perhaps set to a value (option("rule", "elastic")).
struct MessagePiece {
  MessagePiece(std::string text) : text(std::move(text)) {}  // NOLINT: pieces read as text
  MessagePiece(const char* text) : text(text) {}             // NOLINT
  std::string text;
  bool is_option = false;  // text is the option's key
  std::string value;       // the option's value, if the piece names one
};

// The piece that names the option `key`, or the option set to `value`.
MessagePiece option(std::string key, std::string value = {});

// The command line's name of the option `key`: "--kT" for "temperature", "--every" for
// "dump_every".
std::string command_line_option(std::string_view key);

class RequestError : public std::invalid_argument {
 public:
  // How a front end spells the option `key`, set to `value` when that is not empty.
  using Spelling = std::function<std::string(std::string_view key, std::string_view value)>;
  // A message that names no option.
  explicit RequestError(const std::string& message);
  // A message whose option pieces are spelled, in what(), as the command line spells them.
  explicit RequestError(std::vector<MessagePiece> pieces);
  // The message with each option spelled by `spell` (what() spells them "--rule elastic").
  std::string worded(const Spelling& spell) const;

 private:
  std::vector<MessagePiece> pieces_;
};

// Throws RequestError for a path that cannot be written, before anything is created: its folder
// is missing or not writable, or it is a folder itself.
void check_writable(const std::string& path);

// Whether two paths name one file: the same file if both exist (hard links, symlinks and other
// spellings included), else the same absolute path once symbolic links are resolved.
bool same_file(const std::string& a, const std::string& b);

// A file a command reads or writes, with what names it in messages: the option ("-o", "--html",
// or a key: option("dump")) or the argument ("the input FILE").
struct NamedFile {
  MessagePiece option;
  std::string path;
  // For an input, the one output option allowed to save over it, as `option` names it ("" for
  // none): a resumed run's checkpoint, saved again by --checkpoint.
  std::string saved_over_by = {};
};

// Throws RequestError, naming both options and paths, when an output is one of the inputs (it
// would be overwritten before or while it is read) or two outputs are one file (one would
// overwrite the other), however the paths are spelled (same_file). Empty paths and "-" (the
// standard streams) are left out. Every front end checks its files with this, before any work.
void check_files_apart(const std::vector<NamedFile>& inputs, const std::vector<NamedFile>& outputs);

}  // namespace carom

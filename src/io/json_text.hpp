// JSON text for strings that are bytes. A file name on Linux is any bytes, UTF-8 or not
// ("caf\xe9.txt" from a Latin-1 system), and carom writes names into its summaries,
// checkpoints and pages; nlohmann::json refuses to write such a string. Here a byte that is not
// part of valid UTF-8 is written as the escape \udcXX (XX its value, 80 to ff): the lone low
// surrogate that Python's "surrogateescape" (PEP 383) gives it. Python's json.load then reads the
// name that os.fsencode turns back into the file's bytes, a browser shows U+FFFD, and parse_json
// reads the bytes themselves: the name survives a round trip.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace carom {

// value.dump(indent), writing strings that are not UTF-8 as described above; the same text as
// dump() for a value whose strings are all UTF-8.
template <class Json>
std::string dump_json(const Json& value, int indent = -1);

// nlohmann::json::parse(text), reading the escapes dump_json writes back into the bytes they
// stand for. Throws what parse throws.
nlohmann::json parse_json(std::string_view text);

}  // namespace carom

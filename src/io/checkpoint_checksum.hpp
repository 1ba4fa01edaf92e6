// The checksum of a checkpoint: FNV-1a over what it holds, the same for the writer and the
// reader.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string_view>

#include "json_text.hpp"

namespace carom {

// FNV-1a, 64 bits: the checksum of what a checkpoint holds.
class Fnv1a {
 public:
  void add(std::string_view bytes) {
    for (const unsigned char byte : bytes) {
      hash_ ^= byte;
      hash_ *= 0x100000001b3ULL;
    }
  }
  std::string text() const { return fmt::format("fnv1a64:{:016x}", hash_); }

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ULL;
};

// The checksum covers the values, not their layout: the head (every field but the particles and
// the checksum, keys sorted, compact) and each particle row, compact, each followed by a newline.
// Numbers are written in shortest round-trip form, so reading and writing again gives the same
// bytes; reindenting or reordering the file keeps it, changing any value does not.
inline void add_head(Fnv1a& hash, const nlohmann::json& head) {
  hash.add(dump_json(head));
  hash.add("\n");
}

}  // namespace carom

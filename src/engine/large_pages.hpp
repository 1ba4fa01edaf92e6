// Large (2 MiB) pages for an engine's arrays. An event reads and writes the entries of particles
// anywhere in the System and in the engine's arrays: with a million particles those span more
// small pages than the TLB holds, and a miss there costs as much as one in the cache. Advice
// only: where the system does not take it nothing changes, and no result depends on it.
#pragma once

#include <cstddef>
#include <vector>

#include "carom/core/system.hpp"

namespace carom {

// The whole 2 MiB pages of [data, data + bytes), in large pages: at once where the system can
// (MADV_COLLAPSE, Linux 6.1, for memory in use already), else as it finds time. True if they
// are large pages now (false also when the range holds no whole one).
bool prefer_large_pages(const void* data, std::size_t bytes);

template <class T>
bool prefer_large_pages(const std::vector<T>& entries) {
  return prefer_large_pages(entries.data(), entries.size() * sizeof(T));
}

template <std::size_t D>
void prefer_large_pages(const System<D>& system) {
  prefer_large_pages(system.particles);
  prefer_large_pages(system.records);
}

}  // namespace carom

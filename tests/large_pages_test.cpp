#include "engine/large_pages.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace carom {
namespace {

// The kB of large pages /proc/self/smaps counts in the mapping that holds `address` (-1 if none
// is found there: not Linux).
long large_page_kb_at(const void* address) {
  std::ifstream smaps("/proc/self/smaps");
  const auto at = reinterpret_cast<std::uintptr_t>(address);
  std::string line;
  bool inside = false;
  while (std::getline(smaps, line)) {
    std::uintptr_t low = 0, high = 0;
    char dash = 0;
    std::istringstream range(line);
    if (range >> std::hex >> low >> dash >> high && dash == '-') {
      inside = low <= at && at < high;
      continue;
    }
    if (inside && line.rfind("AnonHugePages:", 0) == 0) {
      return std::stol(line.substr(14));
    }
  }
  return -1;
}

TEST(LargePages, AVectorInUseIsMovedIntoThemWhereTheSystemOffersThem) {
  std::vector<double> entries(std::size_t{1} << 20, 1.0);  // 8 MiB, written: in small pages
  if (!prefer_large_pages(entries)) GTEST_SKIP() << "this system gives no large pages at once";
  EXPECT_GE(large_page_kb_at(entries.data() + entries.size() / 2), 2048);
  EXPECT_EQ(entries[12345], 1.0);  // nothing in it changed
}

TEST(LargePages, ARangeWithNoWholeLargePageIsLeftAlone) {
  std::vector<double> entries(1000, 1.0);
  EXPECT_FALSE(prefer_large_pages(entries));
  EXPECT_FALSE(prefer_large_pages(nullptr, 0));
}

}  // namespace
}  // namespace carom

#include "carom/analysis/viewer.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string_view>
#include <utility>

#include "carom/io/input_error.hpp"
#include "carom/viewer_html.hpp"

namespace carom {

namespace {

std::string base64(const void* data, std::size_t size) {
  static constexpr char kDigits[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* bytes = static_cast<const unsigned char*>(data);
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  for (std::size_t i = 0; i < size; i += 3) {
    const unsigned v =
        bytes[i] << 16 | (i + 1 < size ? bytes[i + 1] << 8 : 0) | (i + 2 < size ? bytes[i + 2] : 0);
    out += kDigits[v >> 18 & 63];
    out += kDigits[v >> 12 & 63];
    out += i + 1 < size ? kDigits[v >> 6 & 63] : '=';
    out += i + 2 < size ? kDigits[v & 63] : '=';
  }
  return out;
}

}  // namespace

void write_viewer_html(std::ostream& out, const std::vector<Frame>& frames) {
  const Frame& first = frames.front();
  const std::size_t n = first.radius.size();
  const auto d = static_cast<std::size_t>(first.dimension == 3 ? 3 : 2);
  std::vector<float> radius(first.radius.begin(), first.radius.end());
  std::vector<float> state;  // per frame and particle: d position components, d velocity ones
  std::vector<std::uint32_t> collisions;
  std::vector<double> times;
  state.reserve(frames.size() * n * 2 * d);
  for (const Frame& f : frames) {
    times.push_back(f.time);
    for (std::size_t i = 0; i < n; ++i) {
      for (const Vec<3>* v : {&f.position[i], &f.velocity[i]}) {
        for (std::size_t k = 0; k < d; ++k) state.push_back(static_cast<float>((*v)[k]));
      }
      collisions.push_back(f.collisions[i]);
    }
  }
  nlohmann::json box = {first.box[0], first.box[1]};
  if (d == 3) box.push_back(first.box[2]);
  const nlohmann::json data = {
      {"n", n},
      {"dimension", d},
      {"box", box},
      {"periodic", first.periodic},
      {"times", times},
      {"radius", base64(radius.data(), radius.size() * sizeof(float))},
      {"state", base64(state.data(), state.size() * sizeof(float))},
      {"collisions", base64(collisions.data(), collisions.size() * sizeof(std::uint32_t))},
  };
  constexpr std::string_view kSlot = "/*CAROM_DATA*/";
  const std::size_t slot = kViewerHtml.find(kSlot);
  out << kViewerHtml.substr(0, slot) << data.dump() << kViewerHtml.substr(slot + kSlot.size());
}

}  // namespace carom

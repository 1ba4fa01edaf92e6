#include "json_text.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cstdint>
#include <system_error>

namespace carom {

namespace {

// Inside nlohmann's strings, between marking and the text, a byte that is not UTF-8 is held as
// U+0000 followed by the character U+0100 + byte (U+0180 to U+01FF), and a real U+0000 as two:
// valid UTF-8 that nlohmann writes, and that no other string can be mistaken for.
constexpr char kMark = '\0';
constexpr unsigned kMarkedBase = 0x100;
// The escapes of lone low surrogates that stand for bytes 0x80 to 0xff.
constexpr unsigned kByteEscapeBase = 0xDC00;

// The length of the valid UTF-8 sequence at text[i], or 0 if there is none (RFC 3629: no
// overlong forms, surrogates or code points beyond U+10FFFF).
std::size_t utf8_sequence(std::string_view text, std::size_t i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned lead = byte(i);
  if (lead < 0x80) return 1;
  std::size_t length = 0;
  unsigned low = 0x80, high = 0xBF;  // the second byte's range
  if (lead >= 0xC2 && lead <= 0xDF) {
    length = 2;
  } else if (lead >= 0xE0 && lead <= 0xEF) {
    length = 3;
    if (lead == 0xE0) low = 0xA0;
    if (lead == 0xED) high = 0x9F;
  } else if (lead >= 0xF0 && lead <= 0xF4) {
    length = 4;
    if (lead == 0xF0) low = 0x90;
    if (lead == 0xF4) high = 0x8F;
  } else {
    return 0;
  }
  if (i + length > text.size() || byte(i + 1) < low || byte(i + 1) > high) return 0;
  for (std::size_t k = 2; k < length; ++k) {
    if (byte(i + k) < 0x80 || byte(i + k) > 0xBF) return 0;
  }
  return length;
}

bool is_utf8(std::string_view text) {
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t length = utf8_sequence(text, i);
    if (length == 0) return false;
    i += length;
  }
  return true;
}

void append_utf8(std::string& out, unsigned code_point) {  // below U+0800
  out += static_cast<char>(0xC0 | (code_point >> 6));
  out += static_cast<char>(0x80 | (code_point & 0x3F));
}

// `bytes` in the marked form above.
std::string marked(std::string_view bytes) {
  std::string out;
  out.reserve(bytes.size() + 8);
  for (std::size_t i = 0; i < bytes.size();) {
    const std::size_t length = utf8_sequence(bytes, i);
    if (length == 0) {
      out += kMark;
      append_utf8(out, kMarkedBase + static_cast<unsigned char>(bytes[i]));
      i += 1;
      continue;
    }
    if (bytes[i] == kMark) out += kMark;
    out.append(bytes.substr(i, length));
    i += length;
  }
  return out;
}

// The byte a marked character, U+0100 + byte in UTF-8 (`lead` and `trail`), stands for.
unsigned char marked_byte(char lead, char trail) {
  const unsigned code_point =
      (static_cast<unsigned char>(lead) & 0x1Fu) << 6 | (static_cast<unsigned char>(trail) & 0x3Fu);
  return static_cast<unsigned char>(code_point - kMarkedBase);
}

// The bytes a marked string stands for.
std::string unmarked(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == kMark && i + 1 < text.size() && text[i + 1] == kMark) {
      out += kMark;
      ++i;
    } else if (text[i] == kMark && i + 2 < text.size() && utf8_sequence(text, i + 1) == 2) {
      out += static_cast<char>(marked_byte(text[i + 1], text[i + 2]));
      i += 2;
    } else {
      out += text[i];
    }
  }
  return out;
}

// Applies `change` to every string of `value`, keys included.
template <class Json, class Change>
void rewrite_strings(Json& value, const Change& change) {
  if (value.is_string()) {
    std::string& text = value.template get_ref<std::string&>();
    text = change(text);
  } else if (value.is_array()) {
    for (auto& element : value) rewrite_strings(element, change);
  } else if (value.is_object()) {
    Json rebuilt = Json::object();
    for (auto&& [key, element] : value.items()) {
      rewrite_strings(element, change);
      rebuilt[change(key)] = std::move(element);
    }
    value = std::move(rebuilt);
  }
}

template <class Json>
bool has_non_utf8(const Json& value) {
  if (value.is_string()) return !is_utf8(value.template get_ref<const std::string&>());
  if (value.is_array()) {
    for (const auto& element : value) {
      if (has_non_utf8(element)) return true;
    }
  }
  if (value.is_object()) {
    for (const auto& [key, element] : value.items()) {
      if (!is_utf8(key) || has_non_utf8(element)) return true;
    }
  }
  return false;
}

// Calls on_escape(code, at) for each \uXXXX escape of JSON text (code its value, at the offset of
// its backslash), skipping the others, so that an escaped backslash is never taken for the
// start of an escape.
template <class OnEscape>
void for_each_unicode_escape(std::string_view text, const OnEscape& on_escape) {
  for (std::size_t i = 0; i + 1 < text.size(); ++i) {
    if (text[i] != '\\') continue;
    if (text[i + 1] == 'u' && i + 6 <= text.size()) {
      unsigned code = 0;
      const auto [end, error] = std::from_chars(text.data() + i + 2, text.data() + i + 6, code, 16);
      if (error == std::errc() && end == text.data() + i + 6) on_escape(code, i);
    }
    ++i;  // the escaped character
  }
}

}  // namespace

template <class Json>
std::string dump_json(const Json& value, int indent) {
  if (!has_non_utf8(value)) return value.dump(indent);
  Json copy = value;
  rewrite_strings(copy, [](const std::string& text) { return marked(text); });
  const std::string text = copy.dump(indent);
  // Every mark reaches the text as the escape \u0000, followed by what it marks.
  constexpr std::string_view kEscapedMark = "\\u0000";
  std::string out;
  out.reserve(text.size());
  std::size_t copied = 0;
  for_each_unicode_escape(text, [&](unsigned code, std::size_t at) {
    if (code != 0 || at < copied) return;
    out.append(text, copied, at - copied);
    const std::size_t after = at + kEscapedMark.size();
    if (text.compare(after, kEscapedMark.size(), kEscapedMark) == 0) {
      out += kEscapedMark;  // a real U+0000
      copied = after + kEscapedMark.size();
    } else {
      out += fmt::format("\\u{:04x}", kByteEscapeBase + marked_byte(text[after], text[after + 1]));
      copied = after + 2;
    }
  });
  out.append(text, copied);
  return out;
}

nlohmann::json parse_json(std::string_view text) {
  // Byte escapes are rare: text without them is parsed as it is.
  std::string prepared;
  std::size_t copied = 0;
  std::size_t after_high_surrogate = std::string_view::npos;  // where a pair may continue
  for_each_unicode_escape(text, [&](unsigned code, std::size_t at) {
    const bool paired = at == after_high_surrogate;
    after_high_surrogate = code >= 0xD800 && code <= 0xDBFF ? at + 6 : std::string_view::npos;
    const bool byte = !paired && code >= kByteEscapeBase + 0x80 && code <= kByteEscapeBase + 0xFF;
    if (code != 0 && !byte) return;
    prepared.append(text.substr(copied, at - copied));
    prepared += "\\u0000";
    prepared += fmt::format("\\u{:04x}", byte ? code - kByteEscapeBase + kMarkedBase : 0);
    copied = at + 6;
  });
  if (copied == 0) return nlohmann::json::parse(text);
  prepared.append(text.substr(copied));
  nlohmann::json value = nlohmann::json::parse(prepared);
  rewrite_strings(value, [](const std::string& s) { return unmarked(s); });
  return value;
}

template std::string dump_json(const nlohmann::json&, int);
template std::string dump_json(const nlohmann::ordered_json&, int);

}  // namespace carom

#include "server/wire_text.h"

#include <cstdint>

namespace incise::server {

namespace {

constexpr std::string_view kReplacement = "\xEF\xBF\xBD";  // U+FFFD

// The length of the well-formed UTF-8 sequence at text[at], or 0 when it is ill-formed; then
// `subpart` is the length of its maximal subpart (at least 1), the bytes one U+FFFD replaces.
std::size_t sequence_at(std::string_view text, std::size_t at, std::size_t& subpart) {
  const auto byte = [&](std::size_t i) { return static_cast<std::uint8_t>(text[at + i]); };
  const std::uint8_t lead = byte(0);
  subpart = 1;
  if (lead < 0x80) return 1;
  // Table 3-7: the lead byte fixes the length and the range of the second byte; every later
  // byte is 80..BF. C0, C1 and F5..FF never occur, nor does a continuation byte as a lead.
  std::size_t length = 0;
  std::uint8_t low = 0x80, high = 0xBF;
  if (lead >= 0xC2 && lead <= 0xDF) {
    length = 2;
  } else if (lead >= 0xE0 && lead <= 0xEF) {
    length = 3;
    if (lead == 0xE0) low = 0xA0;   // overlong below U+0800
    if (lead == 0xED) high = 0x9F;  // surrogates U+D800..U+DFFF
  } else if (lead >= 0xF0 && lead <= 0xF4) {
    length = 4;
    if (lead == 0xF0) low = 0x90;   // overlong below U+10000
    if (lead == 0xF4) high = 0x8F;  // past U+10FFFF
  } else {
    return 0;
  }
  for (std::size_t i = 1; i < length; ++i) {
    if (at + i >= text.size()) return 0;
    const std::uint8_t b = byte(i);
    const bool ok = i == 1 ? (b >= low && b <= high) : (b >= 0x80 && b <= 0xBF);
    if (!ok) return 0;
    subpart = i + 1;
  }
  return length;
}

}  // namespace

bool is_valid_utf8(std::string_view text) {
  std::size_t subpart = 0;
  for (std::size_t at = 0; at < text.size();) {
    const std::size_t length = sequence_at(text, at, subpart);
    if (length == 0) return false;
    at += length;
  }
  return true;
}

std::string valid_utf8(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  std::size_t subpart = 0;
  for (std::size_t at = 0; at < text.size();) {
    const std::size_t length = sequence_at(text, at, subpart);
    if (length == 0) {
      out += kReplacement;
      at += subpart;
    } else {
      out.append(text.substr(at, length));
      at += length;
    }
  }
  return out;
}

std::string clip_utf8(std::string_view text, std::size_t max_bytes) {
  std::string out = valid_utf8(text);
  if (out.size() <= max_bytes) return out;
  constexpr std::string_view kEllipsis = "...";
  const bool ellipsis = max_bytes >= 2 * kEllipsis.size();
  std::size_t end = ellipsis ? max_bytes - kEllipsis.size() : max_bytes;
  // out is valid UTF-8, so backing up over continuation bytes (10xxxxxx) reaches a lead byte.
  while (end > 0 && (static_cast<std::uint8_t>(out[end]) & 0xC0) == 0x80)
    --end;
  out.resize(end);
  if (ellipsis) out += kEllipsis;
  return out;
}

bool is_plain_text(std::string_view text, bool multiline) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto byte = static_cast<unsigned char>(text[i]);
    const auto next = i + 1 < text.size() ? static_cast<unsigned char>(text[i + 1]) : 0u;
    const auto third = i + 2 < text.size() ? static_cast<unsigned char>(text[i + 2]) : 0u;
    if (byte < 0x20 && !(multiline && (byte == '\n' || byte == '\t'))) return false;
    if (byte == 0x7F) return false;
    if (byte == 0xC2 && next >= 0x80 && next <= 0x9F) return false;  // C1: U+0080..U+009F
    if (byte == 0xE2 && next == 0x80 && third >= 0xAA && third <= 0xAE) return false;  // 202A..E
    if (byte == 0xE2 && next == 0x81 && third >= 0xA6 && third <= 0xA9) return false;  // 2066..9
  }
  return true;
}

std::string dump_json(const nlohmann::json& value) {
  return value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::optional<std::string_view> query_value(std::string_view query, std::string_view key) {
  std::size_t at = 0;
  while (at < query.size()) {
    auto end = query.find('&', at);
    if (end == std::string_view::npos) end = query.size();
    const auto pair = query.substr(at, end - at);
    const auto eq = pair.find('=');
    if (eq != std::string_view::npos && pair.substr(0, eq) == key) return pair.substr(eq + 1);
    at = end + 1;
  }
  return std::nullopt;
}

std::optional<std::string> percent_decoded(std::string_view text) {
  const auto hex = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  };
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '%') {
      out += text[i] == '+' ? ' ' : text[i];
      continue;
    }
    const int high = i + 2 < text.size() ? hex(text[i + 1]) : -1;
    const int low = i + 2 < text.size() ? hex(text[i + 2]) : -1;
    if (high < 0 || low < 0) return std::nullopt;
    out += static_cast<char>(high * 16 + low);
    i += 2;
  }
  return out;
}

}  // namespace incise::server

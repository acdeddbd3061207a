#pragma once
// Text that leaves the server: every JSON body, WebSocket text message and close reason must be
// valid UTF-8 (RFC 8259 section 8.1, RFC 6455 sections 5.6 and 7.1.6), whatever bytes a client
// sent that ended up in it (an echoed path, nlohmann's "last read: ..." excerpt of a bad body).
// None of these functions throws on any input (only std::bad_alloc can escape).
#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

namespace incise::server {

// Whether `text` is well-formed UTF-8 (Unicode 15, table 3-7): no stray continuation bytes, no
// truncated or overlong sequences, no UTF-16 surrogates (U+D800..U+DFFF), nothing past U+10FFFF.
bool is_valid_utf8(std::string_view text);

// `text` with each ill-formed part replaced by U+FFFD: one replacement per maximal subpart of an
// ill-formed sequence (the Unicode standard's recommended practice, section 3.9), so "\xE2\x82"
// at the end becomes one U+FFFD and "\xC0\xAF" (an overlong '/') becomes two. Valid text comes
// back unchanged.
std::string valid_utf8(std::string_view text);

// At most `max_bytes` of valid_utf8(text), cut before a whole code point, with "..." in place of
// what was cut (when max_bytes leaves room for it).
std::string clip_utf8(std::string_view text, std::size_t max_bytes);

// A WebSocket close reason: valid UTF-8 of at most 123 bytes (a control frame's payload is at most
// 125 bytes, two of which are the close code).
inline constexpr std::size_t kMaxCloseReasonBytes = 123;
inline std::string close_reason_text(std::string_view text) {
  return clip_utf8(text, kMaxCloseReasonBytes);
}

// Whether `text` (valid UTF-8) is fit to show as a name or a note: no control characters (C0,
// DEL, C1; a note may hold line breaks and tabs when `multiline`), and none of the bidirectional
// embeddings, overrides and isolates (U+202A..U+202E, U+2066..U+2069) that make text read other
// than it is stored ("exe.txt" shown for "txt.exe").
bool is_plain_text(std::string_view text, bool multiline);

// value.dump(), with any invalid UTF-8 inside strings replaced by U+FFFD instead of nlohmann's
// type_error 316.
std::string dump_json(const nlohmann::json& value);

// The value of the first key=value pair with this key in a URL's query (the part after '?'),
// as it is written (still percent-encoded), if any.
std::optional<std::string_view> query_value(std::string_view query, std::string_view key);

// The text a query value percent-encodes ("scenes%2Fcube.json" is "scenes/cube.json", '+' a
// space), or nullopt for a '%' not followed by two hex digits.
std::optional<std::string> percent_decoded(std::string_view text);

}  // namespace incise::server

#include "server/json_input.h"

#include "server/wire_text.h"

namespace incise::server {

namespace {

// Room for nlohmann's longest messages with a short excerpt of the input; a WebSocket close
// reason cuts it further (close_reason_text).
constexpr std::size_t kMaxMessageBytes = 160;

// Whether arrays and objects in `bytes` nest deeper than `limit`, counted outside strings.
// Brackets need not balance: the parser judges that.
bool nested_deeper_than(std::string_view bytes, int limit) {
  int depth = 0;
  bool in_string = false, escaped = false;
  for (const char c : bytes) {
    if (in_string) {
      if (escaped) {
        escaped = false;
      } else if (c == '\\') {
        escaped = true;
      } else if (c == '"') {
        in_string = false;
      }
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > limit) return true;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return false;
}

// nlohmann's what() without its "[json.exception.parse_error.101] " prefix, as valid UTF-8: its
// "last read" excerpt holds the client's raw bytes.
std::string describe(const nlohmann::json::exception& e) {
  std::string_view what = e.what();
  if (const auto cut = what.find("] "); cut != std::string_view::npos) what.remove_prefix(cut + 2);
  return clip_utf8(what, kMaxMessageBytes);
}

JsonInput failure(JsonInputError error, std::string message) {
  JsonInput out;
  out.value = nlohmann::json(nlohmann::json::value_t::discarded);
  out.error = error;
  out.message = std::move(message);
  return out;
}

}  // namespace

JsonInput parse_json_input(std::string_view bytes, int max_depth) {
  if (nested_deeper_than(bytes, max_depth)) {
    return failure(JsonInputError::too_deep,
                   "nested deeper than " + std::to_string(max_depth) + " levels");
  }
  try {
    JsonInput out;
    out.value = nlohmann::json::parse(bytes);
    return out;
  } catch (const nlohmann::json::parse_error& e) {
    return failure(JsonInputError::syntax, describe(e));
  } catch (const nlohmann::json::out_of_range& e) {
    return failure(JsonInputError::out_of_range, describe(e));
  } catch (const nlohmann::json::exception& e) {
    // The parser raises nothing else today; a later version's new error is still not a crash.
    return failure(JsonInputError::syntax, describe(e));
  }
}

}  // namespace incise::server

#include "sim/mesh/mesh_text_reader.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <utility>

namespace incise::sim {
namespace {

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

// from_chars does not accept a leading '+', which C's strtod (and so some writers' readers) do.
std::string_view without_plus(std::string_view field) {
  if (field.size() > 1 && field[0] == '+') field.remove_prefix(1);
  return field;
}

std::string quoted(std::string_view field) {
  constexpr std::size_t kMaxShown = 40;
  std::string text(1, '\'');
  text.append(field.substr(0, kMaxShown));
  if (field.size() > kMaxShown) text.append("...");
  text.push_back('\'');
  return text;
}

}  // namespace

std::string FieldName::str() const {
  std::string text(prefix_);
  if (has_id_) text.append(std::to_string(id_));
  text.append(suffix_);
  return text;
}

MeshTextReader::MeshTextReader(std::string_view text, std::string name, char comment)
    : text_(text), name_(std::move(name)), comment_(comment) {}

bool MeshTextReader::next_line() {
  while (position_ < text_.size()) {
    std::size_t end = text_.find('\n', position_);
    if (end == std::string_view::npos) end = text_.size();
    std::string_view line = text_.substr(position_, end - position_);
    position_ = end + 1;
    line_number_ = next_line_number_++;
    if (comment_ != '\0') line = line.substr(0, line.find(comment_));
    tokens_.clear();
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && is_space(line[i]))
        ++i;
      const std::size_t start = i;
      while (i < line.size() && !is_space(line[i]))
        ++i;
      if (i > start) tokens_.push_back(line.substr(start, i - start));
    }
    if (!tokens_.empty()) return true;
  }
  tokens_.clear();
  return false;
}

void MeshTextReader::expect_line(std::string_view what) {
  if (!next_line()) fail_truncated(what);
}

void MeshTextReader::fail_truncated(std::string_view what) const {
  // Report at the last line of the file: that is where the reader ran out.
  fail_at(std::max(1, next_line_number_ - 1), "truncated file: expected " + std::string(what));
}

void MeshTextReader::expect_at_least(std::size_t count, const FieldName& what) const {
  if (tokens_.size() < count) {
    fail(what.str() + ": expected at least " + std::to_string(count) + " fields, found " +
         std::to_string(tokens_.size()));
  }
}

void MeshTextReader::expect_exactly(std::size_t count, const FieldName& what) const {
  if (tokens_.size() != count) {
    fail(what.str() + ": expected " + std::to_string(count) + " fields, found " +
         std::to_string(tokens_.size()));
  }
}

long long MeshTextReader::integer(std::size_t i, const FieldName& what) const {
  if (i >= tokens_.size()) fail(what.str() + ": missing");
  const std::string_view field = without_plus(tokens_[i]);
  long long value = 0;
  const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (error != std::errc() || end != field.data() + field.size()) {
    fail(what.str() + ": expected an integer, found " + quoted(tokens_[i]));
  }
  return value;
}

double MeshTextReader::real(std::size_t i, const FieldName& what) const {
  if (i >= tokens_.size()) fail(what.str() + ": missing");
  const std::string_view field = without_plus(tokens_[i]);
  double value = 0;
  const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (error != std::errc() || end != field.data() + field.size()) {
    fail(what.str() + ": expected a number, found " + quoted(tokens_[i]));
  }
  if (!std::isfinite(value)) fail(what.str() + ": not finite (" + quoted(tokens_[i]) + ")");
  return value;
}

int MeshTextReader::count(std::size_t i, const FieldName& what) const {
  const long long value = integer(i, what);
  if (value < 0 || value > 2'000'000'000) {
    fail("bad count: " + what.str() + " is " + std::to_string(value));
  }
  return static_cast<int>(value);
}

void MeshTextReader::fail(const std::string& problem) const {
  fail_at(line_number_, problem);
}

void MeshTextReader::fail_at(int line, const std::string& problem) const {
  throw MeshFileError(name_, line, problem);
}

std::string read_mesh_text(const std::string& path) {
  std::ifstream stream(path, std::ios::binary);
  if (!stream) {
    throw MeshFileError(path, 0, std::string("cannot open file (") + std::strerror(errno) + ")");
  }
  std::ostringstream text;
  text << stream.rdbuf();
  if (stream.bad()) throw MeshFileError(path, 0, "cannot read file");
  return std::move(text).str();
}

}  // namespace incise::sim

#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "sim/mesh/mesh_file_error.h"

namespace incise::sim {

// The name of a field for error messages, e.g. "node 30 y": a prefix, then an id if given, then
// a suffix. Assembled only when there is an error, so that naming each field of each record of
// a large file costs nothing.
class FieldName {
 public:
  FieldName(const char* text) : prefix_(text) {}         // NOLINT: implicit, like string_view
  FieldName(std::string_view text) : prefix_(text) {}    // NOLINT
  FieldName(const std::string& text) : prefix_(text) {}  // NOLINT
  FieldName(std::string_view prefix, long long id, std::string_view suffix)
      : prefix_(prefix), suffix_(suffix), id_(id), has_id_(true) {}

  std::string str() const;

 private:
  std::string_view prefix_;
  std::string_view suffix_;
  long long id_ = 0;
  bool has_id_ = false;
};

// Line-by-line reading of a text mesh file (gmsh .msh, TetGen .node/.ele) with errors that name
// the file and the line. Both formats put one record per line, so a record is read as one line
// split at whitespace: a record with too few fields is reported on its own line instead of
// silently swallowing the next one.
class MeshTextReader {
 public:
  //   text     the whole file
  //   name     the file name for error messages
  //   comment  a character that starts a comment running to the end of the line ('#' for
  //            TetGen), or '\0' for none
  MeshTextReader(std::string_view text, std::string name, char comment = '\0');

  // Moves to the next line that has at least one field; false (and no current line) at the end.
  bool next_line();
  // next_line, but the end of the text is an error "truncated file: expected <what>" reported
  // at the last line (fail_truncated).
  void expect_line(std::string_view what);
  [[noreturn]] void fail_truncated(std::string_view what) const;

  int line_number() const { return line_number_; }
  // Bytes after the current line: an upper bound on what the remaining records can hold, to
  // check a declared count before allocating for it.
  std::size_t remaining_bytes() const {
    return position_ < text_.size() ? text_.size() - position_ : 0;
  }
  std::size_t size() const { return tokens_.size(); }
  std::string_view token(std::size_t i) const { return tokens_[i]; }
  const std::string& name() const { return name_; }

  // Throws unless the current line has at least (or exactly) count fields.
  void expect_at_least(std::size_t count, const FieldName& what) const;
  void expect_exactly(std::size_t count, const FieldName& what) const;

  // Field i of the current line as an integer or a finite real; throws naming what it is
  // ("node 3 x coordinate") if it is not one.
  long long integer(std::size_t i, const FieldName& what) const;
  double real(std::size_t i, const FieldName& what) const;
  // Field i as a count: an integer in [0, 2e9] (so that it fits an int index), else "bad count".
  int count(std::size_t i, const FieldName& what) const;

  // Throws MeshFileError at the current line (or at line) with the problem.
  [[noreturn]] void fail(const std::string& problem) const;
  [[noreturn]] void fail_at(int line, const std::string& problem) const;

 private:
  std::string_view text_;
  std::string name_;
  char comment_;
  std::size_t position_ = 0;  // start of the next unread line in text_
  int next_line_number_ = 1;
  int line_number_ = 0;  // of the current line; 0 before the first
  std::vector<std::string_view> tokens_;
};

// The whole content of path; throws MeshFileError (no line) if it cannot be opened or read.
std::string read_mesh_text(const std::string& path);

}  // namespace incise::sim

// Private helper of the text readers: the whole file in memory, split into tokens or into lines of tokens, with the
// 1-based line number of the current position, and number parsing that reports errors as InputError naming the
// file and line. Comments ('#' to the end of the line) are skipped when the format has them.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "qualmesh/error.h"
#include "qualmesh/types.h"

namespace qualmesh::plc_io {

// Reads a whole file; throws InputError(Io) when it is missing or unreadable.
std::string read_whole_file(const std::string& path);

class TextScanner {
 public:
  // `text` is the file content; `path` is used in messages. With `hash_comments`, '#' starts a comment.
  TextScanner(std::string text, std::string path, bool hash_comments);

  // Next whitespace-separated token; an empty view at the end of the file. line() is then the token's line.
  std::string_view next_token();
  // Next line holding at least one token (comments and blank lines skipped), split into tokens; false at the end.
  bool next_line(std::vector<std::string_view>& tokens);
  // Skips the rest of the current line (token mode).
  void skip_rest_of_line();

  long line() const { return line_; }
  const std::string& path() const { return path_; }
  std::size_t size() const { return text_.size(); }
  std::size_t remaining_bytes() const { return text_.size() - pos_; }
  bool at_end();  // only whitespace and comments left

  // Errors at the current line.
  [[noreturn]] void fail(ErrorCode code, const std::string& message, ElementIds ids = {}) const;

  // Number parsing; `what` names the field in messages ("x coordinate of vertex 3").
  double to_double(std::string_view token, const std::string& what) const;  // finite, else NonFinite / Parse
  long long to_integer(std::string_view token, const std::string& what) const;
  // A count of records, each taking at least `min_bytes_per_record` bytes of what is left of the file; an absurd
  // or negative count is a Parse error (so no allocation ever follows from a corrupt count).
  std::size_t to_count(std::string_view token, const std::string& what, std::size_t min_bytes_per_record) const;

 private:
  void skip_blanks_and_comments();

  std::string text_;
  std::string path_;
  bool hash_comments_;
  std::size_t pos_ = 0;
  long line_ = 1;
};

// "1.5e3" -> true and the value (locale independent); false when the token is not entirely a number.
bool parse_double(std::string_view token, double& value);
bool parse_integer(std::string_view token, long long& value);

// A token as messages show it: in single quotes, at most 40 bytes (then "..."), every byte that is not printable
// ASCII written as \xNN.
std::string quoted(std::string_view token);

// Lower-case copy (ASCII).
std::string to_lower(std::string_view text);

}  // namespace qualmesh::plc_io

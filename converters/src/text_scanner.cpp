// Tokenizer with line numbers for the text PLC readers. See text_scanner.h.
#include "text_scanner.h"

#include "file_read.h"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <utility>

namespace qualmesh::plc_io {

// Regular files only, at most their size (file_read.h: FIFOs, directories, /dev/zero refused).
std::string read_whole_file(const std::string& path) { return io_detail::read_regular_file(path); }

TextScanner::TextScanner(std::string text, std::string path, bool hash_comments)
    : text_(io_detail::as_text(std::move(text))), path_(std::move(path)), hash_comments_(hash_comments) {}

namespace {
bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v' || c == '\0'; }
}  // namespace

void TextScanner::skip_blanks_and_comments() {
  while (pos_ < text_.size()) {
    const char c = text_[pos_];
    if (c == '\n') {
      ++line_;
      ++pos_;
    } else if (is_blank(c)) {
      ++pos_;
    } else if (hash_comments_ && c == '#') {
      while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    } else {
      return;
    }
  }
}

bool TextScanner::at_end() {
  skip_blanks_and_comments();
  return pos_ >= text_.size();
}

std::string_view TextScanner::next_token() {
  skip_blanks_and_comments();
  const std::size_t start = pos_;
  while (pos_ < text_.size() && !is_blank(text_[pos_]) && text_[pos_] != '\n' &&
         !(hash_comments_ && text_[pos_] == '#')) {
    ++pos_;
  }
  return std::string_view(text_).substr(start, pos_ - start);
}

void TextScanner::skip_rest_of_line() {
  while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
}

bool TextScanner::next_line(std::vector<std::string_view>& tokens) {
  tokens.clear();
  skip_blanks_and_comments();  // lands on the first token of a non-empty line
  if (pos_ >= text_.size()) return false;
  while (pos_ < text_.size() && text_[pos_] != '\n') {
    if (hash_comments_ && text_[pos_] == '#') {
      skip_rest_of_line();
      break;
    }
    if (is_blank(text_[pos_])) {
      ++pos_;
      continue;
    }
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !is_blank(text_[pos_]) && text_[pos_] != '\n' &&
           !(hash_comments_ && text_[pos_] == '#')) {
      ++pos_;
    }
    tokens.push_back(std::string_view(text_).substr(start, pos_ - start));
  }
  return true;  // the newline itself is consumed by the next call (which counts it)
}

void TextScanner::fail(ErrorCode code, const std::string& message, ElementIds ids) const {
  throw InputError(code, message, path_, line_, std::move(ids));
}

namespace {
}  // namespace

std::string quoted(std::string_view token) {
  std::string shown;
  for (char c : token.substr(0, 40)) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= 32 && byte < 127) {
      shown += c;
    } else {  // control and non-ASCII bytes as \xNN: a binary file's bytes never reach the terminal raw
      static const char* hex = "0123456789abcdef";
      shown += "\\x";
      shown += hex[byte >> 4];
      shown += hex[byte & 15];
    }
  }
  if (token.size() > 40) shown += "...";
  return "'" + shown + "'";
}

bool parse_double(std::string_view token, double& value) {
  if (token.empty()) return false;
  const char* first = token.data();
  const char* last = first + token.size();
  if (*first == '+') ++first;  // from_chars rejects a leading '+'
  if (first == last) return false;
  // from_chars does not read "nan"/"inf" in every spelling; do it here so that they are reported as non-finite.
  const std::string lower = to_lower(std::string_view(first, last - first));
  const std::string_view bare = (lower[0] == '-') ? std::string_view(lower).substr(1) : std::string_view(lower);
  if (bare == "nan" || bare.rfind("nan(", 0) == 0 || bare == "-nan") {
    value = std::nan("");
    return true;
  }
  if (bare == "inf" || bare == "infinity") {
    value = (lower[0] == '-') ? -HUGE_VAL : HUGE_VAL;
    return true;
  }
  auto [ptr, ec] = std::from_chars(first, last, value);
  if (ec == std::errc::result_out_of_range) {
    // Overflow: report as infinite (non-finite); underflow to 0 is harmless.
    double probe = std::strtod(std::string(first, last).c_str(), nullptr);
    value = probe;
    return ptr == last;
  }
  return ec == std::errc() && ptr == last;
}

bool parse_integer(std::string_view token, long long& value) {
  if (token.empty()) return false;
  const char* first = token.data();
  const char* last = first + token.size();
  if (*first == '+') ++first;
  auto [ptr, ec] = std::from_chars(first, last, value);
  return ec == std::errc() && ptr == last;
}

std::string to_lower(std::string_view text) {
  std::string lower(text);
  for (char& c : lower) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return lower;
}

double TextScanner::to_double(std::string_view token, const std::string& what) const {
  if (token.empty()) fail(ErrorCode::Parse, "unexpected end of file: expected the " + what);
  double value = 0;
  if (!parse_double(token, value)) fail(ErrorCode::Parse, "expected a number for the " + what + ", got " + quoted(token));
  if (!std::isfinite(value)) fail(ErrorCode::NonFinite, "the " + what + " is not finite (" + quoted(token) + ")");
  return value;
}

long long TextScanner::to_integer(std::string_view token, const std::string& what) const {
  if (token.empty()) fail(ErrorCode::Parse, "unexpected end of file: expected the " + what);
  long long value = 0;
  if (!parse_integer(token, value)) {
    fail(ErrorCode::Parse, "expected an integer for the " + what + ", got " + quoted(token));
  }
  return value;
}

std::size_t TextScanner::to_count(std::string_view token, const std::string& what,
                                  std::size_t min_bytes_per_record) const {
  const long long count = to_integer(token, what);
  if (count < 0) fail(ErrorCode::Parse, "the " + what + " is negative (" + std::to_string(count) + ")");
  const std::size_t left = remaining_bytes();
  if (min_bytes_per_record > 0 && static_cast<unsigned long long>(count) > left / min_bytes_per_record + 1) {
    fail(ErrorCode::Parse, "the " + what + " (" + std::to_string(count) + ") is absurd: only " +
                               std::to_string(left) + " bytes of the file are left");
  }
  return static_cast<std::size_t>(count);
}

}  // namespace qualmesh::plc_io

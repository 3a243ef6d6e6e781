// Private helpers of the mesh readers and writers (mesh_read_*.cpp, mesh_write_*.cpp): exact number formatting,
// the group label of a boundary face, and a whitespace tokenizer that keeps line numbers for error messages.
#pragma once

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <map>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "qualmesh/error.h"
#include "qualmesh/tet_mesh.h"

namespace qualmesh::io {

// Writes `value` in the shortest form that reads back to the same double (std::to_chars); "nan", "inf", "-inf"
// for non-finite values.
inline void put_double(std::ostream& out, double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.write(buffer, result.ptr - buffer);
}

// The comment line that opens a TetGen .node file whose first vertex attribute is the weight (squared radius).
inline constexpr const char* kWeightAttributeComment = "# QualMesh: vertex attribute 1 is the weight (squared radius)";

// Region attribute of tetrahedron t (0 when the mesh has none).
inline int tet_region_of(const TetMesh& mesh, std::size_t t) {
  return mesh.tet_region.empty() ? 0 : mesh.tet_region[t];
}

// Splits a text file into whitespace-separated tokens, skipping comments from `comment` to the end of the line
// (comment = 0: none), and knows the line of each token. Quoted strings ("a b") are one token, quotes removed.
class Tokenizer {
 public:
  Tokenizer(std::string text, std::string file, char comment)
      : text_(std::move(text)), file_(std::move(file)), comment_(comment) {}

  const std::string& file() const { return file_; }
  long line() const { return line_; }

  // True when another token follows (skips whitespace and comments).
  bool has_more() {
    skip_blank();
    return pos_ < text_.size();
  }

  // The next token, or throws Parse ("unexpected end of file, expected WHAT").
  std::string_view next(const char* what) {
    if (!has_more()) fail(ErrorCode::Parse, std::string("unexpected end of file, expected ") + what);
    if (text_[pos_] == '"') {
      const std::size_t start = ++pos_;
      while (pos_ < text_.size() && text_[pos_] != '"' && text_[pos_] != '\n') ++pos_;
      if (pos_ >= text_.size() || text_[pos_] != '"') fail(ErrorCode::Parse, "unterminated quoted string");
      return std::string_view(text_).substr(start, pos_++ - start);
    }
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_]) && !(comment_ && text_[pos_] == comment_)) ++pos_;
    return std::string_view(text_).substr(start, pos_ - start);
  }

  double next_double(const char* what) {
    const std::string token(next(what));
    char* end = nullptr;
    const double value = std::strtod(token.c_str(), &end);
    if (end == token.c_str() || *end != '\0') fail(ErrorCode::Parse, std::string("expected ") + what + ", got '" + token + "'");
    if (!std::isfinite(value)) fail(ErrorCode::NonFinite, std::string(what) + " is not finite: '" + token + "'");
    return value;
  }

  long long next_integer(const char* what) {
    const std::string token(next(what));
    char* end = nullptr;
    const long long value = std::strtoll(token.c_str(), &end, 10);
    if (end == token.c_str() || *end != '\0') {
      // TetGen writes attributes as reals ("1" or "1.0"); accept an integral real.
      const double real = std::strtod(token.c_str(), &end);
      if (end != token.c_str() && *end == '\0' && std::isfinite(real) && real == std::floor(real) &&
          std::fabs(real) < 9e15) {
        return static_cast<long long>(real);
      }
      fail(ErrorCode::Parse, std::string("expected ") + what + " (an integer), got '" + token + "'");
    }
    return value;
  }

  // A count: a non-negative integer below a sanity bound.
  std::size_t next_count(const char* what) {
    const long long value = next_integer(what);
    if (value < 0 || value > 2000000000LL) fail(ErrorCode::Parse, std::string("absurd ") + what + ": " + std::to_string(value));
    // Whatever is counted takes at least a token and a blank each: a count beyond that is absurd, and allocating
    // for it would blow up (a Medit "Vertices 999999999" asked for 24 GB; found by fuzzing).
    const std::size_t left = text_.size() - pos_;
    if (static_cast<std::size_t>(value) > left / 2 + 1) {
      fail(ErrorCode::Parse, std::string("absurd ") + what + ": " + std::to_string(value) + ", but only " +
                                 std::to_string(left) + " bytes of the file are left");
    }
    return static_cast<std::size_t>(value);
  }

  // Skips the rest of the current line.
  void skip_line() {
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
  }

  [[noreturn]] void fail(ErrorCode code, const std::string& message, ElementIds ids = {}) const {
    throw InputError(code, message, file_, line_, std::move(ids));
  }

 private:
  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v'; }
  void skip_blank() {
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (c == '\n') {
        ++line_;
        ++pos_;
      } else if (is_space(c)) {
        ++pos_;
      } else if (comment_ && c == comment_) {
        skip_line();
      } else {
        break;
      }
    }
  }

  std::string text_;
  std::string file_;
  char comment_;
  std::size_t pos_ = 0;
  long line_ = 1;
};

// Whole file as a string; throws InputError(Io) when it cannot be read.
std::string read_whole_file(const std::string& path);

// Checks that every vertex index of the tetrahedra and faces is in range and every coordinate finite.
void check_mesh_indices(const TetMesh& mesh, const std::string& file);

// The per-format writers and readers behind write_tet_mesh / read_tet_mesh.
void write_vtu(const TetMesh& mesh, const std::string& path);
void write_tetgen(const TetMesh& mesh, const std::string& base);
void write_gmsh41(const TetMesh& mesh, const std::string& path);
void write_medit(const TetMesh& mesh, const std::string& path);
void write_abaqus(const TetMesh& mesh, const std::string& path);
void write_unv(const TetMesh& mesh, const std::string& path);
void write_elmer(const TetMesh& mesh, const std::string& path);
TetMesh read_tetgen(const std::string& base);
TetMesh read_gmsh(const std::string& path);
TetMesh read_medit(const std::string& path);
TetMesh read_vtu(const std::string& path);
TetMesh read_abaqus(const std::string& path);
TetMesh read_unv(const std::string& path);

// "dir/name.ext" -> "dir/name"; "dir/name" unchanged.
std::string strip_extension(const std::string& path);

}  // namespace qualmesh::io

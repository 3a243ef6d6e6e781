// Helpers shared by the GoogleTest suites: where the shared test data lives, and skipping (never passing) a test
// whose input or tool is missing.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace qualmesh::test {

inline std::string source_path(const std::string& relative) {
  return std::string(QUALMESH_SOURCE_DIR) + "/" + relative;
}

// Path of a file under ../shared (e.g. "data/plc/fandisk.off").
inline std::string shared_path(const std::string& relative) {
  return std::string(QUALMESH_SHARED_DIR) + "/" + relative;
}

inline std::string qualmesh_exe() { return QUALMESH_EXE; }

// A fresh, empty temporary folder for one test.
inline std::filesystem::path temp_dir(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() / ("qualmesh-test-" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// The whole file as a string ("" when it cannot be read), and a file written with exactly `text`.
inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

inline void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

}  // namespace qualmesh::test

// Skips the current test (reported as skipped by CTest) when a shared data file is absent.
#define QM_REQUIRE_FILE(path)                                                   \
  do {                                                                          \
    if (!std::filesystem::exists(path)) GTEST_SKIP() << "missing input " << (path); \
  } while (0)

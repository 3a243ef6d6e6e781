// The malformed-input corpus (tests/data/malformed, written by make_corpus.py; EXPECTED.tsv says, per file, the
// ErrorCode name, a substring of the message and the 1-based line, 0 when unchecked). read_plc() must throw
// InputError with that code, message and line for every file; the CLI (`qualmesh info FILE`) must exit with 2 and
// print the same message on stderr.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <sys/wait.h>

#include "qualmesh/error.h"
#include "qualmesh/plc_io.h"
#include "test_support.h"

namespace qualmesh {
namespace {

struct Expectation {
  std::string file;
  std::string code;
  std::string substring;
  long line = 0;
};

std::string corpus_path(const std::string& file) { return test::source_path("tests/data/malformed/" + file); }

std::vector<Expectation> load_expectations() {
  std::vector<Expectation> rows;
  std::ifstream in(corpus_path("EXPECTED.tsv"));
  std::string text;
  while (std::getline(in, text)) {
    if (text.empty() || text[0] == '#') continue;
    std::vector<std::string> columns;
    std::stringstream stream(text);
    std::string column;
    while (std::getline(stream, column, '\t')) columns.push_back(column);
    Expectation row;
    row.file = columns.at(0);
    row.code = columns.at(1);
    row.substring = columns.at(2);
    if (columns.size() > 3) row.line = std::stol(columns[3]);
    rows.push_back(row);
  }
  return rows;
}

TEST(MalformedCorpus, HasEnoughFilesAcrossFormats) {
  const auto rows = load_expectations();
  EXPECT_GE(rows.size(), 24u);
  for (const char* ext : {".off", ".stl", ".obj", ".mesh", ".poly", ".smesh", ".node"}) {
    std::size_t n = 0;
    for (const auto& row : rows) n += row.file.size() > 5 && row.file.find(ext) == row.file.size() - std::string(ext).size();
    EXPECT_GE(n, 1u) << ext;
  }
}

TEST(MalformedCorpus, ReadPlcThrowsTheExpectedError) {
  const auto rows = load_expectations();
  ASSERT_FALSE(rows.empty()) << "EXPECTED.tsv not found or empty";
  for (const auto& row : rows) {
    SCOPED_TRACE(row.file);
    const std::string path = corpus_path(row.file);
    ASSERT_TRUE(std::filesystem::exists(path));
    for (bool merge : {true, false}) {
      ReadOptions options;
      options.merge_coplanar = merge;
      try {
        read_plc(path, options);
        ADD_FAILURE() << "no error for " << row.file;
      } catch (const InputError& e) {
        EXPECT_EQ(to_string(e.code()), row.code) << e.what();
        EXPECT_NE(e.message().find(row.substring), std::string::npos) << e.what();
        EXPECT_EQ(e.file(), path);
        if (row.line > 0) EXPECT_EQ(e.line(), row.line) << e.what();
        // what() is "FILE[:LINE]: error[CODE]: MESSAGE".
        EXPECT_NE(std::string(e.what()).find("error[" + row.code + "]"), std::string::npos);
      } catch (const std::exception& e) {
        ADD_FAILURE() << "not an InputError: " << e.what();
      }
    }
  }
}

TEST(MalformedCorpus, CliInfoExitsWithTwoAndNamesTheProblem) {
  const std::string exe = test::qualmesh_exe();
  if (!std::filesystem::exists(exe)) GTEST_SKIP() << "the qualmesh executable is not built: " << exe;
  const auto rows = load_expectations();
  ASSERT_FALSE(rows.empty());
  const auto dir = test::temp_dir("malformed-cli");
  const std::string stderr_path = (dir / "stderr.txt").string();
  for (const auto& row : rows) {
    SCOPED_TRACE(row.file);
    const std::string command =
        "'" + exe + "' info '" + corpus_path(row.file) + "' >/dev/null 2>'" + stderr_path + "'";
    const int status = std::system(command.c_str());
    ASSERT_TRUE(WIFEXITED(status)) << "killed by a signal: " << command;
    EXPECT_EQ(WEXITSTATUS(status), 2) << command;
    std::ifstream in(stderr_path);
    const std::string err((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(err.find(row.substring), std::string::npos) << "stderr: " << err;
  }
}

// Every prefix of a valid binary STL and of a valid OFF is either read or rejected with an InputError: never a
// crash, never another exception (truncation at every byte).
TEST(MalformedCorpus, EveryTruncationOfValidFilesIsAnInputError) {
  const auto dir = test::temp_dir("malformed-truncation");
  for (const char* name : {"box_binary.stl", "box_hole.off", "box.obj", "box.mesh", "box.poly", "box.stl"}) {
    std::ifstream in(test::source_path(std::string("tests/data/small/") + name), std::ios::binary);
    const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_FALSE(data.empty()) << name;
    const std::string path = (dir / name).string();
    std::size_t rejected = 0;
    for (std::size_t size = 0; size < data.size(); ++size) {
      std::ofstream(path, std::ios::binary | std::ios::trunc).write(data.data(), static_cast<std::streamsize>(size));
      try {
        read_plc(path);
      } catch (const InputError&) {
        ++rejected;
      }
    }
    EXPECT_GT(rejected, data.size() / 2) << name;
  }
}

}  // namespace
}  // namespace qualmesh

// Issue 18 item 4: a multi-file output (OutputSet, atomic_file.h) lands whole or not at all, and leaves no
// temporary behind either way; the text readers' view of a file (io_detail::as_text: byte order mark, CR line ends).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "atomic_file.h"
#include "file_read.h"
#include "qualmesh/error.h"

namespace fs = std::filesystem;
using qualmesh::InputError;
using qualmesh::io::OutputSet;

namespace {

struct TempFolder {
  fs::path path;
  TempFolder() {
    path = fs::temp_directory_path() / ("qualmesh-output-set-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
                                        "-" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempFolder() { fs::remove_all(path); }
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void put(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

std::size_t count_temporaries(const fs::path& folder) {
  std::size_t n = 0;
  for (const auto& e : fs::recursive_directory_iterator(folder)) n += e.path().filename().string().find(".tmp-") != std::string::npos;
  return n;
}

}  // namespace

TEST(OutputSet, CommitsEveryFileAndReplacesTheOldOnes) {
  TempFolder dir;
  put(dir.path / "m.node", "old node");
  OutputSet out;
  out.write_file((dir.path / "m.node").string(), [](std::ostream& s) { s << "new node"; });
  out.write_file((dir.path / "m.ele").string(), [](std::ostream& s) { s << "new ele"; });
  EXPECT_EQ(slurp(dir.path / "m.node"), "old node");  // nothing in place before commit
  EXPECT_FALSE(fs::exists(dir.path / "m.ele"));
  out.commit();
  EXPECT_EQ(slurp(dir.path / "m.node"), "new node");
  EXPECT_EQ(slurp(dir.path / "m.ele"), "new ele");
  EXPECT_EQ(count_temporaries(dir.path), 0u);
}

TEST(OutputSet, AFillThatThrowsLeavesTheOldSetAndNoTemporary) {
  TempFolder dir;
  put(dir.path / "m.node", "old node");
  put(dir.path / "m.ele", "old ele");
  try {
    OutputSet out;
    out.write_file((dir.path / "m.node").string(), [](std::ostream& s) { s << "new node"; });
    out.write_file((dir.path / "m.ele").string(), [](std::ostream&) { throw std::runtime_error("writer failed"); });
    out.commit();
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "writer failed");
  }
  EXPECT_EQ(slurp(dir.path / "m.node"), "old node");
  EXPECT_EQ(slurp(dir.path / "m.ele"), "old ele");
  EXPECT_EQ(count_temporaries(dir.path), 0u);
}

TEST(OutputSet, ATargetThatIsADirectoryRefusesTheWholeSetBeforeAnyRename) {
  TempFolder dir;
  put(dir.path / "m.node", "old node");
  fs::create_directory(dir.path / "m.face");
  OutputSet out;
  out.write_file((dir.path / "m.node").string(), [](std::ostream& s) { s << "new node"; });
  out.write_file((dir.path / "m.face").string(), [](std::ostream& s) { s << "new face"; });
  try {
    out.commit();
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_EQ(e.code(), qualmesh::ErrorCode::Io);
    EXPECT_NE(e.message().find("is a directory"), std::string::npos) << e.message();
  }
  EXPECT_EQ(slurp(dir.path / "m.node"), "old node");
  EXPECT_TRUE(fs::is_directory(dir.path / "m.face"));
  EXPECT_EQ(count_temporaries(dir.path), 0u);
}

TEST(OutputSet, ADirectoryOutputReplacesTheOldDirectoryWhole) {
  TempFolder dir;
  fs::create_directory(dir.path / "m.elmer");
  put(dir.path / "m.elmer" / "stale", "from the old mesh");
  OutputSet out;
  const std::string temp = out.write_directory((dir.path / "m.elmer").string());
  out.write_inside(temp, "mesh.header", (dir.path / "m.elmer").string(), [](std::ostream& s) { s << "1 1 1"; });
  out.commit();
  EXPECT_EQ(slurp(dir.path / "m.elmer" / "mesh.header"), "1 1 1");
  EXPECT_FALSE(fs::exists(dir.path / "m.elmer" / "stale"));
  EXPECT_EQ(count_temporaries(dir.path), 0u);
}

TEST(AsText, DropsAByteOrderMarkAndTurnsLoneCarriageReturnsIntoLineFeeds) {
  using qualmesh::io_detail::as_text;
  EXPECT_EQ(as_text("\xEF\xBB\xBFOFF\r8 6 0\r"), "OFF\n8 6 0\n");
  EXPECT_EQ(as_text("a\r\nb\r"), "a\r\nb\n");  // CR LF kept (readers take the CR as a blank)
  EXPECT_EQ(as_text("\xEF\xBB"), "\xEF\xBB");   // half a mark is data
  EXPECT_EQ(as_text(""), "");
}

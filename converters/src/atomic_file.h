// Private helper of the writers (issue 18 item 4): outputs land whole or not at all.
//
// Every output file is first written to a temporary sibling "<path>.tmp-XXXXXXXX" (a directory output, the Elmer
// mesh, to a temporary sibling directory), and only when every file of the output is complete are they renamed into
// place, together. A failure (an exception from a writer, a full disk, the file size limit, a rename that fails)
// removes every temporary and leaves the files already at those paths exactly as they were: a TetGen set never ends
// as a new .node beside an old .ele and .face. Each temporary is registered, from before it is created until it is
// renamed or removed, with the signal cleanup of qualmesh/temporary_files.h, so that SIGINT, SIGTERM or SIGHUP during
// a write leave no "*.tmp-*" behind.
#pragma once

#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

namespace qualmesh::io {

// One output made of one or more files or directories, committed together.
//
//   OutputSet out;
//   out.write_file(base + ".node", fill_node);   // to a temporary; nothing at base.node changes yet
//   out.write_file(base + ".ele", fill_ele);
//   out.commit();                                // all renamed into place, or none (InputError(Io))
//
// Destroying a set that was not committed removes its temporaries (so an exception thrown between the writes
// cleans up by itself). Not thread-safe; one set per output.
class OutputSet {
 public:
  OutputSet();
  ~OutputSet();
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;

  // Writes `fill`'s bytes (binary mode) to a temporary sibling of `path`, flushes and checks the stream. Throws
  // InputError(Io) naming `path` when the folder is missing, the file cannot be created or a write fails ("the
  // file size limit (ulimit -f) was reached" when SIGXFSZ was the cause); the exception `fill` throws propagates.
  void write_file(const std::string& path, const std::function<void(std::ostream&)>& fill);

  // Creates a temporary sibling directory of `path` (which must not exist as a non-directory) and returns its
  // path; fill it with write_inside(). At commit it replaces `path` (an existing directory there is moved aside
  // first and removed once the new one is in place).
  std::string write_directory(const std::string& path);
  // Writes a file `name` inside the temporary directory `temp_dir` returned by write_directory(); errors name
  // `target` (the directory the user asked for) and the file.
  void write_inside(const std::string& temp_dir, const std::string& name, const std::string& target,
                    const std::function<void(std::ostream&)>& fill);

  // Renames every temporary into place, with SIGINT, SIGTERM and SIGHUP held back meanwhile. The targets that
  // existed are first kept aside (a hard link, or a rename for a directory); if any rename fails, the ones done are
  // undone, the old files put back, the temporaries removed, and InputError(Io) is thrown.
  void commit();

 private:
  struct Entry;
  std::vector<std::unique_ptr<Entry>> entries_;
  bool committed_ = false;
  void discard() noexcept;
};

// One file: OutputSet with a single write_file and commit.
void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& fill);

}  // namespace qualmesh::io

// Reading an input file whole, safely (issue 18 item 3): only regular files, and no more bytes than the file's size
// says. A FIFO without a writer used to block forever, a symbolic link to /dev/zero read until 4.2 GB, and a
// directory was reported as "the file is empty"; each is now refused at once with what it is.
#pragma once

#include <string>

namespace qualmesh::io_detail {

// The bytes of the regular file at `path` (symbolic links followed). Throws InputError(Io) naming the file when it
// cannot be opened ("cannot open file: <reason>"), is not a regular file ("is a directory", "is a FIFO (named
// pipe)", "is a character device (such as /dev/zero)", ..., plus "(a symbolic link to T)" when it is one), or a
// read fails. Reads at most the size fstat reports, so a file that grows while being read cannot run away.
std::string read_regular_file(const std::string& path);

}  // namespace qualmesh::io_detail

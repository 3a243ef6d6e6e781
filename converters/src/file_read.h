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

// Text as every text reader sees it (issue 18 item 7): a leading UTF-8 byte order mark (EF BB BF, as Windows editors
// write it) is dropped, and a carriage return not followed by a line feed (classic Mac OS line ends) becomes a line
// feed, so that a CR-only file has its lines and its line numbers. CR LF is left as it is (readers take CR as a
// blank). Offsets do not move except by the 3 bytes of the mark.
std::string as_text(std::string bytes);

// Throws InputError(Io) naming `path`, as read_regular_file does, unless it is a regular file (symbolic links
// followed). Opens nothing that could block (O_NONBLOCK) and reads nothing.
void require_regular_file(const std::string& path);

}  // namespace qualmesh::io_detail

// Private helper of the writers: write a file through a temporary sibling and rename it into place, so that a
// failure (exception, full disk) never leaves a half-written file and never clobbers an existing one.
#pragma once

#include <functional>
#include <iosfwd>
#include <string>

namespace qualmesh::io {

// Calls `fill` with a stream open on "<path>.tmp-XXXXXX" in the same folder (binary mode), flushes, checks the
// stream, then renames over `path`. On any failure the temporary is removed and InputError(ErrorCode::Io) or the
// exception `fill` threw propagates; `path` is untouched.
void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& fill);

}  // namespace qualmesh::io

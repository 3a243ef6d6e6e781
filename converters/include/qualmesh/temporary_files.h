// Temporary files of the writers and signals (issue 18 item 4).
//
// The writers create their output under temporary names ("<path>.tmp-XXXXXXXX") and rename it into place when it is
// complete. While a temporary exists its path is held in a fixed table that a signal handler may read, so that a
// program stopped by a signal during a write can remove them. The library installs no handler by itself (signal
// dispositions belong to the program); `qualmesh` calls install_temporary_cleanup_handlers() first thing in main().
// A program with handlers of its own calls remove_registered_temporaries() from them.
#pragma once

namespace qualmesh {

// Installs, for SIGINT, SIGTERM and SIGHUP, a handler that removes every registered temporary
// (remove_registered_temporaries) and re-raises the signal with its default action, so that the process ends as
// the signal asked (a shell sees 130 for SIGINT, 143 for SIGTERM). SIGXFSZ (the file size limit, `ulimit -f`) no
// longer kills the process: the write that passes the limit fails with EFBIG, the writer removes its temporaries and
// throws InputError(Io) "the file size limit (ulimit -f) was reached", and file_size_limit_reached() says so.
// Idempotent.
void install_temporary_cleanup_handlers();

// Unlinks every registered temporary file, then removes every registered temporary directory (after its registered
// files). Async-signal-safe: only unlink(2) and rmdir(2) on paths held in static storage.
void remove_registered_temporaries() noexcept;

// True once a SIGXFSZ was received since install_temporary_cleanup_handlers() (a write passed the file size limit).
bool file_size_limit_reached() noexcept;

}  // namespace qualmesh

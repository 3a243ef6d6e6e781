// `qualmesh`: the command-line front end. Subcommands live one per file (cmd_*.cpp) and register here.
// Library code never prints; this is where errors become messages on stderr and exit codes (see cli_common.h).
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>

#include "cli_common.h"
#include "mesh_limits.h"
#include "qualmesh/error.h"
#include "qualmesh/temporary_files.h"

namespace {

// A message as it may reach a terminal (issue 18 item 7): readers quote what they found, and a binary or random file
// would otherwise put raw bytes (escape sequences included) on the user's screen. Printable ASCII, line feeds and
// well-formed UTF-8 (a file name with accents) pass; every other byte is written \xNN. At most kMaxBytes of the
// message are shown.
std::string printable(const std::string& message) {
  constexpr std::size_t kMaxBytes = 2000;
  static const char* hex = "0123456789abcdef";
  std::string out;
  const std::size_t n = message.size();
  for (std::size_t i = 0; i < n && out.size() < kMaxBytes;) {
    const auto byte = static_cast<unsigned char>(message[i]);
    std::size_t length = 0;  // of a well-formed UTF-8 sequence starting here
    if (byte >= 0xC2 && byte <= 0xDF) length = 2;
    else if (byte >= 0xE0 && byte <= 0xEF) length = 3;
    else if (byte >= 0xF0 && byte <= 0xF4) length = 4;
    bool well_formed = length > 0 && i + length <= n;
    for (std::size_t k = 1; well_formed && k < length; ++k)
      well_formed = (static_cast<unsigned char>(message[i + k]) & 0xC0) == 0x80;
    if (well_formed && length > 2) {
      // Strict UTF-8 (RFC 3629): no overlong form (E0 80..9F, F0 80..8F), no surrogate (ED A0..BF), nothing above
      // U+10FFFF (F4 90..BF). A terminal shows such bytes as replacement characters (fuzzing corpus, stl).
      const auto second = static_cast<unsigned char>(message[i + 1]);
      well_formed = !(byte == 0xE0 && second < 0xA0) && !(byte == 0xED && second > 0x9F) &&
                    !(byte == 0xF0 && second < 0x90) && !(byte == 0xF4 && second > 0x8F);
    }
    if (well_formed) {
      out.append(message, i, length);
      i += length;
      continue;
    }
    if ((byte >= 32 && byte < 127) || byte == '\n') {
      out += message[i];
    } else {
      out += "\\x";
      out += hex[byte >> 4];
      out += hex[byte & 15];
    }
    ++i;
  }
  if (out.size() >= kMaxBytes) out += "... (message cut)";
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace qualmesh::cli;
  // SIGINT, SIGTERM, SIGHUP during a write remove the temporaries and end the run as the signal asks; SIGXFSZ makes
  // the write fail instead (issue 18 item 4, qualmesh/temporary_files.h).
  qualmesh::install_temporary_cleanup_handlers();
  CLI::App app{
      "QualMesh: quality tetrahedral meshing by weighted Delaunay refinement (Cheng & Dey).\n"
      "Exit codes: 0 ok, 1 internal error, 2 bad input or usage, 3 `check` found defects, 4 a resource limit "
      "(time, memory, vertices) stopped the run."};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("qualmesh 0.1.0"));

  int exit_code = kExitOk;
  register_info_command(app, exit_code);
  register_check_command(app, exit_code);
  register_convert_command(app, exit_code);
  register_mesh_command(app, exit_code);

  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);  // --help, --version
  } catch (const CLI::ParseError& e) {
    app.exit(e);  // prints the usage error
    return kExitBadInput;
  } catch (const qualmesh::InputError& e) {
    std::cerr << "qualmesh: " << printable(e.what()) << "\n";
    // A write that passed `ulimit -f` is a resource limit (exit 4), not bad input; its temporaries are gone.
    if (qualmesh::file_size_limit_reached()) return kExitResource;
    return kExitBadInput;
  } catch (const std::bad_alloc&) {
    // A resource limit, not a bug (issue 18): the machine or the address-space limit ran out.
    std::cerr << "qualmesh: error[resource]: out of memory (lower the size field, or raise the memory limit): "
                 "nothing written\n";
    return kExitResource;
  } catch (const std::exception& e) {
    std::cerr << "qualmesh: internal error: " << printable(e.what()) << "\n";
    return kExitInternal;
  }
  std::cout.flush();
  return exit_code;
}

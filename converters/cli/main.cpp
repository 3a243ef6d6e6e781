// `qualmesh`: the command-line front end. Subcommands live one per file (cmd_*.cpp) and register here.
// Library code never prints; this is where errors become messages on stderr and exit codes (see cli_common.h).
#include <cstdio>
#include <exception>
#include <iostream>

#include "cli_common.h"
#include "mesh_limits.h"
#include "qualmesh/error.h"

int main(int argc, char** argv) {
  using namespace qualmesh::cli;
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
    std::cerr << "qualmesh: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const std::bad_alloc&) {
    // A resource limit, not a bug (issue 18): the machine or the address-space limit ran out.
    std::cerr << "qualmesh: error[resource]: out of memory (lower the size field, or raise the memory limit): "
                 "nothing written\n";
    return kExitResource;
  } catch (const std::exception& e) {
    std::cerr << "qualmesh: internal error: " << e.what() << "\n";
    return kExitInternal;
  }
  std::cout.flush();
  return exit_code;
}

// libFuzzer harness for QualMesh's readers (issue 18, "Fuzzing"). One source, one executable per reader: the
// reader is chosen at compile time by QUALMESH_FUZZ_READER (tests/fuzz/CMakeLists.txt builds fuzz_<reader> for
// each). Every reader takes a path, so each input is written to a file in a private folder (under /dev/shm when it
// exists) with the reader's extension, then read through the public entry point the CLI uses:
//   PLC readers (mesh, info, convert, check --ref): read_plc   poly smesh node off stl obj medit
//   check's mesh readers: read_tet_mesh                         vtu msh inp unv mesh_medit mesh_tetgen
// Multi-file formats take several files from one input, split at the line "@@" ("\n@@\n"): mesh_tetgen reads
// parts 1-3 as BASE.node, BASE.ele, BASE.face; poly and smesh read part 2 as the sibling .node file (read when the
// .poly's node count is 0).
//
// A finding is anything but a clean return or qualmesh::InputError (bad input, exit 2 in the CLI): a crash, a
// sanitizer report, another exception (the CLI's "internal error", exit 1), a hang (-timeout) or a blow-up
// (-rss_limit_mb). scripts/fuzz.sh runs one reader; each finding becomes a regression test in tests/fuzz/regressions/.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

#include "qualmesh/error.h"
#include "qualmesh/mesh_io.h"
#include "qualmesh/plc_io.h"

#ifndef QUALMESH_FUZZ_READER
#error "define QUALMESH_FUZZ_READER (poly, smesh, node, off, stl, obj, medit, vtu, msh, inp, unv, mesh_medit, mesh_tetgen)"
#endif

namespace {

const std::string kReader = QUALMESH_FUZZ_READER;
std::string g_folder;  // private folder of this process, made once

enum class Entry { Plc, Mesh };

struct ReaderSpec {
  Entry entry;
  std::vector<std::string> extensions;  // one file per part, in split order
};

ReaderSpec spec_of(const std::string& reader) {
  if (reader == "poly") return {Entry::Plc, {".poly", ".node"}};
  if (reader == "smesh") return {Entry::Plc, {".smesh", ".node"}};
  if (reader == "node") return {Entry::Plc, {".node"}};
  if (reader == "off") return {Entry::Plc, {".off"}};
  if (reader == "stl") return {Entry::Plc, {".stl"}};
  if (reader == "obj") return {Entry::Plc, {".obj"}};
  if (reader == "medit") return {Entry::Plc, {".mesh"}};
  if (reader == "vtu") return {Entry::Mesh, {".vtu"}};
  if (reader == "msh") return {Entry::Mesh, {".msh"}};
  if (reader == "inp") return {Entry::Mesh, {".inp"}};
  if (reader == "unv") return {Entry::Mesh, {".unv"}};
  if (reader == "mesh_medit") return {Entry::Mesh, {".mesh"}};
  if (reader == "mesh_tetgen") return {Entry::Mesh, {".node", ".ele", ".face"}};
  std::fprintf(stderr, "fuzz_reader: unknown reader '%s'\n", reader.c_str());
  std::abort();
}

const ReaderSpec kSpec = spec_of(kReader);

// The input cut at "\n@@\n" into at most `max_parts` parts (the last part keeps any further separators).
std::vector<std::string_view> split_parts(std::string_view data, std::size_t max_parts) {
  static constexpr std::string_view kSeparator = "\n@@\n";
  std::vector<std::string_view> parts;
  while (parts.size() + 1 < max_parts) {
    const std::size_t at = data.find(kSeparator);
    if (at == std::string_view::npos) break;
    parts.push_back(data.substr(0, at + 1));  // the part keeps its last newline
    data.remove_prefix(at + kSeparator.size());
  }
  parts.push_back(data);
  return parts;
}

void write_file(const std::string& path, std::string_view bytes) {
  FILE* file = std::fopen(path.c_str(), "wb");
  if (!file) {
    std::perror(path.c_str());
    std::abort();
  }
  if (!bytes.empty() && std::fwrite(bytes.data(), 1, bytes.size(), file) != bytes.size()) std::abort();
  std::fclose(file);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  const char* base = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : (std::getenv("TMPDIR") ? std::getenv("TMPDIR") : "/tmp");
  std::string pattern = std::string(base) + "/qualmesh-fuzz-" + kReader + "-XXXXXX";
  if (!mkdtemp(pattern.data())) {
    std::perror("mkdtemp");
    std::abort();
  }
  g_folder = pattern;
  // The folder goes when the process ends normally; a crash leaves it (a few small files) for inspection.
  std::atexit([] {
    for (const std::string& ext : kSpec.extensions) unlink((g_folder + "/input" + ext).c_str());
    rmdir(g_folder.c_str());
  });
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  const std::string base = g_folder + "/input";
  const std::vector<std::string_view> parts =
      split_parts(std::string_view(reinterpret_cast<const char*>(data), size), kSpec.extensions.size());
  for (std::size_t i = 0; i < kSpec.extensions.size(); ++i) {
    const std::string path = base + kSpec.extensions[i];
    if (i < parts.size()) {
      write_file(path, parts[i]);
    } else {
      unlink(path.c_str());  // an optional sibling (.face, .node) absent this time
    }
  }
  const std::string main_path = base + kSpec.extensions[0];
  try {
    if (kSpec.entry == Entry::Plc) {
      (void)qualmesh::read_plc(main_path);
    } else {
      (void)qualmesh::read_tet_mesh(main_path);
    }
  } catch (const qualmesh::InputError&) {
    // bad input, reported cleanly: what a reader must do
  }
  return 0;
}

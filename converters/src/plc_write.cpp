// PLC writers: TetGen .poly (1-based, facets with polygons and facet holes, volume holes, regions), TetGen .smesh
// (single-polygon facets) and OFF (single-polygon facets, 0-based). Coordinates are written in the shortest form
// that reads back to the same double, so write -> read is exact. Files go through write_file_atomically, and
// everything a format cannot hold is rejected before the file is opened.
#include <charconv>
#include <ostream>
#include <set>
#include <string>
#include <utility>

#include "atomic_file.h"
#include "plc_read_formats.h"
#include "qualmesh/error.h"
#include "qualmesh/plc_io.h"

namespace qualmesh {

namespace {

enum class PlcFormat { Poly, Smesh, Off };

std::string format_double(double value) {
  char buffer[64];
  auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  return ec == std::errc() ? std::string(buffer, end) : std::string("0");
}

void write_point(std::ostream& out, const Point3& p) {
  out << format_double(p[0]) << ' ' << format_double(p[1]) << ' ' << format_double(p[2]);
}

// Throws InputError(Unsupported) for what `format` cannot hold.
void check_representable(const Plc& plc, PlcFormat format, const std::string& path) {
  const char* name = format == PlcFormat::Poly ? ".poly" : format == PlcFormat::Smesh ? ".smesh" : ".off";
  const std::size_t nv = plc.vertices.size();
  for (std::size_t f = 0; f < plc.facets.size(); ++f) {
    const Facet& facet = plc.facets[f];
    const ElementIds ids{{}, {}, {static_cast<Index>(f)}, {}};
    if (facet.polygons.empty()) {
      throw InputError(ErrorCode::Unsupported, "facet " + std::to_string(f) + " has no polygon", path, 0, ids);
    }
    for (const auto& loop : facet.polygons) {
      if (loop.empty()) {
        throw InputError(ErrorCode::Unsupported, "facet " + std::to_string(f) + " has an empty polygon", path, 0, ids);
      }
      for (Index v : loop) {
        if (v >= nv) {
          throw InputError(ErrorCode::IndexOutOfRange,
                           "facet " + std::to_string(f) + " refers to vertex " + std::to_string(v) +
                               ", but there are " + std::to_string(nv) + " vertices",
                           path, 0, ids);
        }
      }
    }
    if (format != PlcFormat::Poly && (facet.polygons.size() > 1 || !facet.holes.empty())) {
      throw InputError(ErrorCode::Unsupported,
                       "facet " + std::to_string(f) + " has " + std::to_string(facet.polygons.size()) +
                           " polygons and " + std::to_string(facet.holes.size()) + " hole points; the " + name +
                           " format holds one polygon per facet (write .poly instead)",
                       path, 0, ids);
    }
    if (format == PlcFormat::Off && facet.polygons[0].size() < 3) {
      throw InputError(ErrorCode::Unsupported,
                       "facet " + std::to_string(f) + " is a polygon of " + std::to_string(facet.polygons[0].size()) +
                           " vertices; OFF faces need at least 3",
                       path, 0, ids);
    }
  }
  if (format == PlcFormat::Off && !plc.holes.empty()) {
    throw InputError(ErrorCode::Unsupported,
                     std::to_string(plc.holes.size()) + " volume hole points cannot be written to OFF (write .poly)",
                     path);
  }
  if (format == PlcFormat::Off && !plc.regions.empty()) {
    throw InputError(ErrorCode::Unsupported,
                     std::to_string(plc.regions.size()) + " region seeds cannot be written to OFF (write .poly)", path);
  }
  // Explicit segments: TetGen 3D files and OFF hold only those that are facet edges (which are implied).
  if (!plc.segments.empty()) {
    std::set<std::pair<Index, Index>> edges;
    for (const Facet& facet : plc.facets) {
      for (const auto& loop : facet.polygons) {
        if (loop.size() < 2) continue;
        for (std::size_t i = 0; i < loop.size(); ++i) {
          Index a = loop[i], b = loop[(i + 1) % loop.size()];
          if (a > b) std::swap(a, b);
          edges.insert({a, b});
        }
      }
    }
    for (std::size_t s = 0; s < plc.segments.size(); ++s) {
      Index a = plc.segments[s].a, b = plc.segments[s].b;
      if (a > b) std::swap(a, b);
      if (!edges.count({a, b})) {
        throw InputError(ErrorCode::Unsupported,
                         "segment " + std::to_string(s) + " (" + std::to_string(plc.segments[s].a) + ", " +
                             std::to_string(plc.segments[s].b) + ") is no facet edge; the " + name +
                             " format cannot hold a free segment",
                         path, 0, ElementIds{{}, {static_cast<Index>(s)}, {}, {}});
      }
    }
  }
}

void write_tetgen(std::ostream& out, const Plc& plc, bool smesh) {
  out << "# " << (smesh ? "TetGen .smesh" : "TetGen .poly") << " written by QualMesh";
  if (!plc.name.empty()) out << " from " << plc.name;
  out << "\n# part 1: nodes (1-based)\n" << plc.vertices.size() << " 3 0 0\n";
  for (std::size_t i = 0; i < plc.vertices.size(); ++i) {
    out << i + 1 << ' ';
    write_point(out, plc.vertices[i]);
    out << '\n';
  }
  out << "# part 2: facets\n" << plc.facets.size() << " 1\n";
  for (const Facet& facet : plc.facets) {
    if (smesh) {
      const auto& loop = facet.polygons[0];
      out << loop.size();
      for (Index v : loop) out << ' ' << v + 1;
      out << ' ' << facet.marker << '\n';
      continue;
    }
    out << facet.polygons.size() << ' ' << facet.holes.size() << ' ' << facet.marker << '\n';
    for (const auto& loop : facet.polygons) {
      out << loop.size();
      for (Index v : loop) out << ' ' << v + 1;
      out << '\n';
    }
    for (std::size_t h = 0; h < facet.holes.size(); ++h) {
      out << h + 1 << ' ';
      write_point(out, facet.holes[h]);
      out << '\n';
    }
  }
  out << "# part 3: volume holes\n" << plc.holes.size() << '\n';
  for (std::size_t h = 0; h < plc.holes.size(); ++h) {
    out << h + 1 << ' ';
    write_point(out, plc.holes[h]);
    out << '\n';
  }
  out << "# part 4: regions\n" << plc.regions.size() << '\n';
  for (std::size_t r = 0; r < plc.regions.size(); ++r) {
    out << r + 1 << ' ';
    write_point(out, plc.regions[r].point);
    out << ' ' << plc.regions[r].attribute;
    if (plc.regions[r].max_volume > 0) out << ' ' << format_double(plc.regions[r].max_volume);
    out << '\n';
  }
}

void write_off(std::ostream& out, const Plc& plc) {
  out << "OFF\n" << plc.vertices.size() << ' ' << plc.facets.size() << " 0\n";
  for (const Point3& p : plc.vertices) {
    write_point(out, p);
    out << '\n';
  }
  for (const Facet& facet : plc.facets) {
    const auto& loop = facet.polygons[0];
    out << loop.size();
    for (Index v : loop) out << ' ' << v;
    out << '\n';
  }
}

}  // namespace

void write_plc(const Plc& plc, const std::string& path) {
  const std::string ext = plc_io::lower_extension(path);
  PlcFormat format;
  if (ext == ".poly") {
    format = PlcFormat::Poly;
  } else if (ext == ".smesh") {
    format = PlcFormat::Smesh;
  } else if (ext == ".off") {
    format = PlcFormat::Off;
  } else {
    throw InputError(ErrorCode::Unsupported, "cannot write a PLC as '" + ext + "' (write .poly, .smesh or .off)", path);
  }
  check_representable(plc, format, path);
  io::write_file_atomically(path, [&](std::ostream& out) {
    if (format == PlcFormat::Off) {
      write_off(out, plc);
    } else {
      write_tetgen(out, plc, format == PlcFormat::Smesh);
    }
  });
}

}  // namespace qualmesh

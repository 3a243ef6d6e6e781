// Text and JSON renderings of a CheckReport. JSON keys are the CheckReport field names (stable); numbers are printed
// with %.17g so that a reader gets the exact double back; NaN and infinity become null.
#include <cmath>
#include <cstdio>
#include <sstream>

#include "qualmesh/mesh_check.h"

namespace qualmesh {
namespace {

std::string json_number(double value) {
  if (!std::isfinite(value)) return "null";
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.17g", value);
  return buffer;
}

std::string json_string(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buffer[8];
          std::snprintf(buffer, sizeof buffer, "\\u%04x", c);
          out += buffer;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

std::string short_number(double value) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.6g", value);
  return buffer;
}

// Writes "key": value pairs separated by commas.
class JsonObject {
 public:
  explicit JsonObject(std::ostringstream& out, const char* indent) : out_(out), indent_(indent) { out_ << "{"; }
  void raw(const char* key, const std::string& value) {
    out_ << (first_ ? "\n" : ",\n") << indent_ << "  " << json_string(key) << ": " << value;
    first_ = false;
  }
  void number(const char* key, double value) { raw(key, json_number(value)); }
  void count(const char* key, std::size_t value) { raw(key, std::to_string(value)); }
  void boolean(const char* key, bool value) { raw(key, value ? "true" : "false"); }
  void close() { out_ << "\n" << indent_ << "}"; }

 private:
  std::ostringstream& out_;
  std::string indent_;
  bool first_ = true;
};

std::string json_counts(const std::vector<std::size_t>& counts) {
  std::string out = "[";
  for (std::size_t i = 0; i < counts.size(); ++i) out += (i ? ", " : "") + std::to_string(counts[i]);
  return out + "]";
}

}  // namespace

std::string to_json(const CheckReport& r) {
  std::ostringstream out;
  JsonObject o(out, "");
  o.boolean("ok", r.ok);
  o.count("num_points", r.num_points);
  o.count("num_tets", r.num_tets);
  o.count("num_unused_points", r.num_unused_points);
  o.count("num_faces", r.num_faces);
  o.count("num_boundary_faces", r.num_boundary_faces);
  o.count("num_hull_faces", r.num_hull_faces);
  o.count("num_region_interface_faces", r.num_region_interface_faces);
  o.count("num_regions", r.num_regions);
  o.count("num_nonpositive_tets", r.num_nonpositive_tets);
  o.count("num_duplicate_tets", r.num_duplicate_tets);
  o.count("num_overshared_faces", r.num_overshared_faces);
  o.count("num_folded_faces", r.num_folded_faces);
  o.count("num_bad_indices", r.num_bad_indices);
  o.number("mesh_volume", r.mesh_volume);
  o.boolean("has_reference", r.has_reference);
  if (r.has_reference) {
    o.number("reference_volume", r.reference_volume);
    o.raw("reference_volume_method", json_string(r.reference_volume_method));
    o.number("volume_relative_error", r.volume_relative_error);
    o.count("num_faces_off_input", r.num_faces_off_input);
    o.count("num_interior_faces_on_input", r.num_interior_faces_on_input);
    o.count("num_faces_given", r.num_faces_given);
    o.number("facet_area", r.facet_area);
    o.number("covered_area", r.covered_area);
    o.number("max_facet_area_relative_error", r.max_facet_area_relative_error);
    o.count("num_miscovered_facets", r.num_miscovered_facets);
    std::string facets = "[";
    for (std::size_t i = 0; i < r.facets.size(); ++i) {
      const FacetCoverage& f = r.facets[i];
      facets += std::string(i ? ",\n    " : "\n    ") + "{\"facet\": " + std::to_string(f.facet) +
                ", \"marker\": " + std::to_string(f.marker) +
                ", \"bounds_domain\": " + (f.bounds_domain ? "true" : "false") + ", \"area\": " + json_number(f.area) +
                ", \"covered_area\": " + json_number(f.covered_area) +
                ", \"relative_error\": " + json_number(f.relative_error) + "}";
    }
    o.raw("facets", facets + (r.facets.empty() ? "]" : "\n  ]"));
  }
  o.boolean("weighted_delaunay_checked", r.weighted_delaunay_checked);
  o.count("num_weighted_points", r.num_weighted_points);
  o.number("max_weight", r.max_weight);
  o.count("num_regularity_tested_faces", r.num_regularity_tested_faces);
  o.count("num_non_regular_faces", r.num_non_regular_faces);
  o.number("min_dihedral_deg", r.min_dihedral_deg);
  o.number("max_dihedral_deg", r.max_dihedral_deg);
  o.number("dihedral_histogram_bin_deg", r.dihedral_histogram_bin_deg);
  o.raw("dihedral_histogram", json_counts(r.dihedral_histogram));
  o.raw("min_dihedral_histogram", json_counts(r.min_dihedral_histogram));
  o.number("max_radius_edge", r.max_radius_edge);
  o.number("min_sigma", r.min_sigma);
  o.number("min_volume", r.min_volume);
  o.count("num_tets_min_dihedral_below_5", r.num_tets_min_dihedral_below_5);
  o.count("num_tets_min_dihedral_below_10", r.num_tets_min_dihedral_below_10);
  o.count("num_tets_min_dihedral_below_15", r.num_tets_min_dihedral_below_15);
  o.boolean("protection_checked", r.protection_checked);
  if (r.protection_checked) {
    o.raw("protection_zone", r.protection_zone == CheckReport::ProtectionZone::Balls ? "\"protecting_balls\""
                                                                                       : "\"cad_feature_balls\"");
    if (r.protection_zone == CheckReport::ProtectionZone::CadFeatureBalls)
      o.number("protection_radius", r.protection_radius);
    o.number("protection_angle_deg", r.protection_angle_deg);
    o.count("num_sharp_vertices", r.num_sharp_vertices);
    o.count("num_sharp_segments", r.num_sharp_segments);
    o.count("num_tets_in_protection_zone", r.num_tets_in_protection_zone);
    o.number("min_dihedral_outside_protection_deg", r.min_dihedral_outside_protection_deg);
    o.count("num_tets_outside_protection_below_10", r.num_tets_outside_protection_below_10);
    o.count("num_tets_outside_protection_below_15", r.num_tets_outside_protection_below_15);
  }
  o.count("num_problems", r.num_problems);
  std::string problems = "[";
  for (std::size_t i = 0; i < r.problems.size(); ++i) problems += (i ? ", " : "") + json_string(r.problems[i]);
  o.raw("problems", problems + "]");
  o.close();
  out << "\n";
  return out.str();
}

std::string to_text(const CheckReport& r) {
  std::ostringstream out;
  out << "mesh: " << r.num_points << " points, " << r.num_tets << " tets, " << r.num_faces << " faces ("
      << r.num_boundary_faces << " boundary: " << r.num_hull_faces << " hull, " << r.num_region_interface_faces
      << " between regions), " << r.num_regions << " region(s)";
  if (r.num_unused_points) out << ", " << r.num_unused_points << " unused points";
  out << "\n";
  out << "structure: " << r.num_nonpositive_tets << " non-positive tets, " << r.num_duplicate_tets
      << " duplicate tets, " << r.num_overshared_faces << " faces shared by > 2 tets, " << r.num_folded_faces
      << " folded faces, " << r.num_bad_indices << " tets with bad indices\n";
  out << "volume: " << short_number(r.mesh_volume);
  if (r.has_reference) {
    out << ", input encloses " << short_number(r.reference_volume) << " (" << r.reference_volume_method
        << "), relative error " << short_number(r.volume_relative_error);
  }
  out << "\n";
  if (r.has_reference) {
    out << "conformity: " << r.num_faces_off_input << " boundary faces on no input facet, "
        << r.num_interior_faces_on_input << " interior faces on an internal facet; facet area "
        << short_number(r.facet_area) << ", covered " << short_number(r.covered_area) << "; "
        << r.num_miscovered_facets << " of " << r.facets.size()
        << " facets miscovered (max relative error " << short_number(r.max_facet_area_relative_error) << ")\n";
  }
  if (r.weighted_delaunay_checked) {
    out << (r.num_weighted_points ? "weighted Delaunay (regular): " : "Delaunay (all weights zero): ")
        << r.num_non_regular_faces << " of " << r.num_regularity_tested_faces
        << " faces of two tets locally non-regular";
    if (r.num_weighted_points) {
      out << "; " << r.num_weighted_points << " weighted points, max weight " << short_number(r.max_weight);
    }
    out << "\n";
  } else {
    out << "weighted Delaunay: not checked\n";
  }
  out << "quality: dihedral " << short_number(r.min_dihedral_deg) << " .. " << short_number(r.max_dihedral_deg)
      << " deg, max radius-edge " << short_number(r.max_radius_edge) << ", min sigma " << short_number(r.min_sigma)
      << "; tets with min dihedral < 5/10/15 deg: " << r.num_tets_min_dihedral_below_5 << "/"
      << r.num_tets_min_dihedral_below_10 << "/" << r.num_tets_min_dihedral_below_15 << "\n";
  if (r.protection_checked && r.protection_zone == CheckReport::ProtectionZone::CadFeatureBalls) {
    out << "farther than " << short_number(r.protection_radius) << " from sharp CAD features (angles < "
        << short_number(r.protection_angle_deg) << " deg: " << r.num_sharp_vertices << " sharp vertices, "
        << r.num_sharp_segments << " sharp edges; " << r.num_tets_in_protection_zone << " of " << r.num_tets
        << " tets inside): min dihedral " << short_number(r.min_dihedral_outside_protection_deg)
        << " deg, tets with min dihedral < 10/15 deg: " << r.num_tets_outside_protection_below_10 << "/"
        << r.num_tets_outside_protection_below_15 << "\n";
  } else if (r.protection_checked) {
    out << "outside the protection zones of input angles < " << short_number(r.protection_angle_deg) << " deg ("
        << r.num_sharp_vertices << " sharp vertices, " << r.num_sharp_segments << " sharp segments; "
        << r.num_tets_in_protection_zone << " of " << r.num_tets << " tets inside): min dihedral "
        << short_number(r.min_dihedral_outside_protection_deg) << " deg, tets with min dihedral < 10/15 deg: "
        << r.num_tets_outside_protection_below_10 << "/" << r.num_tets_outside_protection_below_15 << "\n";
  }
  out << "min dihedral histogram (" << short_number(r.dihedral_histogram_bin_deg) << " deg bins):";
  for (std::size_t i = 0; i < r.min_dihedral_histogram.size(); ++i) {
    if (r.min_dihedral_histogram[i]) {
      out << " [" << short_number(i * r.dihedral_histogram_bin_deg) << ", "
          << short_number((i + 1) * r.dihedral_histogram_bin_deg) << "): " << r.min_dihedral_histogram[i];
    }
  }
  out << "\n";
  for (const std::string& p : r.problems) out << "problem: " << p << "\n";
  if (r.num_problems > r.problems.size()) out << "... and " << r.num_problems - r.problems.size() << " more problems\n";
  out << (r.ok ? "OK" : "FAILED: " + std::to_string(r.num_problems) + " problem(s)") << "\n";
  return out.str();
}

}  // namespace qualmesh

// Basic value types shared by every stage of QualMesh: indices, points, boxes.
// Coordinates are in the units of the input model (for CAD: millimetres as stored in the file).
#pragma once

#include <array>
#include <cstdint>
#include <limits>

namespace qualmesh {

// Index of a vertex, segment, facet or element. 0-based everywhere inside the library; file formats that count
// from 1 are converted by their readers and writers.
using Index = std::uint32_t;
constexpr Index kNoIndex = std::numeric_limits<Index>::max();

// A point or vector in R^3: {x, y, z}.
using Point3 = std::array<double, 3>;

// Axis-aligned bounding box. An empty box has min > max.
struct BoundingBox {
  Point3 min{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
             std::numeric_limits<double>::infinity()};
  Point3 max{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
             -std::numeric_limits<double>::infinity()};

  bool empty() const { return min[0] > max[0]; }
  void add(const Point3& p) {
    for (int i = 0; i < 3; ++i) {
      if (p[i] < min[i]) min[i] = p[i];
      if (p[i] > max[i]) max[i] = p[i];
    }
  }
  // Length of the box diagonal; 0 for an empty box.
  double diagonal() const;
};

}  // namespace qualmesh

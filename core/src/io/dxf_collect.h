// DXF entities as dxflib reports them: shapes in their block's coordinates, blocks and layers.
#pragma once

#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "io/dxf_scan.h"
#include "popcut/geometry.h"

namespace popcut::dxf {

struct Style {
  std::string layer = "0";
  int colour = 256;  // AutoCAD colour index: 0 by block, 256 by layer
  std::string linetype = "BYLAYER";
};

struct Vertex {
  Point2 p;
  double bulge = 0;
};

// An entity as drawn, in its block's (or the model's) coordinates; flattened only once the
// transform of every insert above it is known, so the chord tolerance holds on the sheet.
struct Shape {
  enum class Type { path, ellipse, spline, insert } type = Type::path;
  Style style;
  std::string where;
  bool mirrored = false;  // drawn with extrusion (0, 0, −1)
  bool ocs = false;       // coordinates in the entity's own system, which mirroring turns over
  std::vector<Vertex> vertices;
  bool closed = false;
  Point2 centre, major;  // ellipses, circles and arcs
  double ratio = 1, t0 = 0, t1 = 2 * std::numbers::pi;
  int degree = 0;  // splines
  std::vector<double> knots, weights;
  std::vector<Point2> control;
  std::size_t fit_points = 0;
  std::string block;  // inserts
  Point2 at;
  double sx = 1, sy = 1, angle_deg = 0, column_mm = 0, row_mm = 0;
  int columns = 1, rows = 1;
};

struct Block {
  Point2 base;
  std::vector<Shape> shapes;
};

struct Layer {
  int colour = 7;
  std::string linetype = "CONTINUOUS";
  bool hidden = false;  // switched off or frozen
};

struct Collected {
  std::map<std::string, Layer> layers;
  std::map<std::string, Block> blocks;
  std::vector<Shape> model;
};

// Parses the scan's kept text with dxflib; throws popcut::Error for entities popcut cannot
// lay flat (meshes, curves out of the sheet's plane), naming their line.
Collected collect(const Scan& scan, const std::string& source);

}  // namespace popcut::dxf

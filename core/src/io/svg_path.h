// SVG geometry for the drawing reader: affine transforms, the path data grammar, curves flattened to chords.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "popcut/geometry.h"

namespace popcut::svg {

// x' = a x + c y + e, y' = b x + d y + f (SVG's matrix(a b c d e f)).
struct Affine {
  double a = 1, b = 0, c = 0, d = 1, e = 0, f = 0;
  Point2 apply(Point2 p) const { return {a * p.x_mm + c * p.v_mm + e, b * p.x_mm + d * p.v_mm + f}; }
  Affine then(const Affine& outer) const;  // this first, then outer
  double max_scale() const;                // the largest stretch of any direction, for tolerances
};

// Parses a transform attribute ("translate(1 2) rotate(30) ..."); throws std::invalid_argument
// with what was expected where the text is malformed.
Affine parse_transform(const std::string& text);

struct Subpath {
  std::vector<Point2> points;  // user units, y down
  bool closed = false;
};

// Parses path data, flattening curves and arcs so no chord strays more than `tolerance` (user
// units) from the curve; throws std::invalid_argument naming the offending command or number.
// `max_points` bounds the output (std::length_error past it).
std::vector<Subpath> parse_path_data(const std::string& d, double tolerance, std::size_t max_points);

// The points of a cubic Bézier after its start p[0], so no chord strays more than `tolerance`
// from the curve.
std::vector<Point2> cubic_points(const std::array<Point2, 4>& p, double tolerance);
// The same for a quadratic Bézier from p0 through control q to p2 (as the cubic it is).
std::vector<Point2> quadratic_points(Point2 p0, Point2 q, Point2 p2, double tolerance);

// A numbers list as in points="…" or stroke-dasharray (commas or spaces); throws std::invalid_argument.
std::vector<double> parse_number_list(const std::string& text);

// An ellipse (centre, radii, rotation in degrees) as a closed polygon within `tolerance`.
std::vector<Point2> ellipse_points(Point2 centre, double rx, double ry, double tolerance);

}  // namespace popcut::svg

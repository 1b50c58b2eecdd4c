// DXF's curves as chords: bulged polyline segments, elliptic arcs (circles and arcs too) and NURBS splines.
#pragma once

#include <vector>

#include "popcut/geometry.h"

namespace popcut::dxf {

// The points after `a` up to and including `b` along the segment a→b with DXF's bulge (the
// tangent of a quarter of the included angle; positive turns counter-clockwise), each chord
// within `tolerance` of the arc.
std::vector<Point2> bulge_points(Point2 a, Point2 b, double bulge, double tolerance);

// Points c + cos t·major + sin t·ratio·perp(major) for t from t0 to t1 (radians, t1 > t0), both
// ends included; perp turns major a quarter counter-clockwise, or clockwise when `clockwise`.
std::vector<Point2> ellipse_points(Point2 centre, Point2 major, double ratio, double t0, double t1, bool clockwise,
                                   double tolerance);

// A NURBS curve of `degree` over `knots` (control.size() + degree + 1 of them) with `weights`
// (empty: all 1), flattened adaptively so no chord strays more than `tolerance`; throws
// std::invalid_argument saying what is inconsistent.
std::vector<Point2> spline_points(int degree, const std::vector<double>& knots, const std::vector<Point2>& control,
                                  const std::vector<double>& weights, double tolerance);

}  // namespace popcut::dxf

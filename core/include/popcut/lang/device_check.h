// Patterns and maths that check a cutter: the square-in-triangle test cut, the calibration frame and its correction.
#pragma once

#include "popcut/geometry.h"
#include "popcut/lang/plotter_frame.h"
#include "popcut/pattern/pattern.h"

namespace popcut {

// The test cut: a square cut through inside an equilateral triangle that is scored (or
// kiss-cut), with the same gap between the square and each side of the triangle.
struct TestCutShape {
  double square_mm = 10;
  double triangle_mm = 28;  // the triangle's side: 2.8 squares, so the gap is about a fifth of a square
  double gap_mm = 0;        // from the square to each side of the triangle
  double width_mm() const { return triangle_mm; }
  double height_mm() const;  // the triangle's height
};

// The shape for a square of `square_mm`; the triangle is 2.8 times as wide.
TestCutShape test_cut_shape(double square_mm);

// The test with its bounding box's min corner at `offset` (pattern mm), on a sheet from (0, 0)
// reaching `edge_mm` past the box: the square as cut lines, the triangle's base along x and its
// apex up, as lines of `triangle_kind`.
Pattern test_cut_pattern(const TestCutShape& shape, Point2 offset, double edge_mm, LineKind triangle_kind);

// The calibration frame's sides along pattern x (its width) and v (its height).
struct FrameSize {
  double width_mm = 100;
  double height_mm = 150;
  double diagonal_mm() const;
};

// The frame as cut lines on a sheet `edge_mm` larger on every side: the rectangle, its diagonal
// from the min corner to the max corner, and a 5 mm tick into the frame from the middle of the
// width side, which tells that side from the other when the frame is square.
Pattern calibration_frame_pattern(const FrameSize& size, double edge_mm);

// What the user measured on the cut frame: the width side (the one with the tick), the height
// side and the diagonal.
struct FrameMeasurement {
  double width_mm = 0;
  double height_mm = 0;
  double diagonal_mm = 0;
};

// A correction of the plotter's axes as a profile's [device] scale_x, scale_y and skew_deg hold it
// (PlotterFrame applies them: units_per_mm times the scale, skew_deg as its shear).
struct AxisCorrection {
  double scale_x = 1;
  double scale_y = 1;
  double skew_deg = 0;
};

// How far off the device was, along its own axes, in the frame that was cut.
struct AxisError {
  double side_x_mm = 0, side_y_mm = 0;  // the frame's sides that ran along the plotter's x and y, as meant
  double ratio_x = 1, ratio_y = 1;      // cut / meant
  double off_x_mm = 0, off_y_mm = 0;    // cut − meant over those sides
  double skew_deg = 0;                  // the y axis leaned toward +x by this: the corner was 90° − this
  double skew_mm = 0;                   // how far the side along y leaned over its length
};

struct AxisCalibration {
  AxisError error;            // of the cut frame (with `in_effect` applied)
  AxisCorrection correction;  // what makes the next cut right: `in_effect` composed with the error's inverse
};

// Limits of a plausible measurement and correction: the profile's ranges for scale_x, scale_y,
// skew_deg. A side outside kMinRatio..kMaxRatio of its length was measured wrong, not cut wrong.
inline constexpr double kMinCalibrationRatio = 0.9, kMaxCalibrationRatio = 1.1;
inline constexpr double kMaxSkewDeg = 5;

// The correction from a frame of `size` cut with `in_effect` on a device of `frame` (its swap and
// flips say which side ran along which plotter axis, and which way the diagonal ran). Throws
// popcut::Error(invalid_input) at location "measured width", "measured height", "measured diagonal"
// or "correction" for a length that is not positive, a ratio outside 0.9–1.1, a diagonal no frame
// with those sides can have, a skew over 5°, or a composed correction outside the profile's ranges.
AxisCalibration calibrate_axes(const FrameSize& size, const FrameMeasurement& measured, const PlotterFrame& frame,
                               const AxisCorrection& in_effect);

}  // namespace popcut

// Independent checks of a pattern from its emitted geometry alone (polygons and lines), for tests.
#pragma once

#include <string>
#include <vector>

#include "popcut/pattern/pattern.h"

namespace popcut::testing {

// Even-odd point-in-polygon over the outer ring and holes; p must not lie on a boundary.
bool face_contains(const PatternFace& face, Point2 p);

// Index of the one face containing p, -1 if none; -2 if more than one (overlap).
int face_at(const Pattern& pattern, Point2 p);

// Checks on a pattern whose vertices lie on a grid of `step_mm`; each returns a list of
// human-readable problems (empty = fine).
std::vector<std::string> check_tiling(const Pattern& pattern, double step_mm);
std::vector<std::string> check_lines(const Pattern& pattern, double step_mm);
std::vector<std::string> check_folds(const Pattern& pattern);

}  // namespace popcut::testing

// Tool paths: what the knife does along one chained, ordered path (perforation, passes, overcut,
// precut, drag-knife blade offset), in mm.
#pragma once

#include <vector>

#include "popcut/pattern/pattern.h"

namespace popcut {

double path_length_mm(const std::vector<Point2>& path);

// Pieces of `path` that the knife cuts when perforating: dashes of on_mm with gaps of about
// off_mm, the gaps stretched evenly so both ends are uncut. A path shorter than one dash and its
// gaps still gets one shorter dash. Empty for a path of no length.
std::vector<std::vector<Point2>> perforate(const std::vector<Point2>& path, double on_mm, double off_mm);
// The path without the vertices it runs straight through (a junction where another line ends):
// the same cut, but the cutter need not stop there. Ends stay.
std::vector<Point2> without_straight_vertices(const std::vector<Point2>& path);
// `passes` times along the path, turning back at each end, knife down throughout.
std::vector<Point2> with_passes(const std::vector<Point2>& path, int passes);
// The same passes as paths of their own (each to be cut as a stroke): the path, then reversed,
// and so on, so each starts where the one before ended.
std::vector<std::vector<Point2>> separate_passes(const std::vector<Point2>& path, int passes);

// The tool axis path that makes a drag knife's tip follow `tip_path` (see PlanOptions).
std::vector<Point2> blade_offset_path(const std::vector<Point2>& tip_path, double offset_mm, double swivel_step_deg);
// The tip path of a precut before `tip_path`: its first min(precut_mm, first segment) mm;
// empty when precut_mm is 0.
std::vector<Point2> precut_path(const std::vector<Point2>& tip_path, double precut_mm);
// A closed loop continued past its start by `overcut_mm` along itself; open paths unchanged.
std::vector<Point2> with_overcut(const std::vector<Point2>& path, double overcut_mm);

}  // namespace popcut

// DXF group pairs checked line by line, and the subset of the file the DXF library is given to parse.
#pragma once

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace popcut::dxf {

// Where an entity the reader reads starts, in the order the library will report them.
struct EntityPlace {
  std::string type;  // LINE, LWPOLYLINE, POLYLINE, ARC, CIRCLE, ELLIPSE, SPLINE, INSERT
  std::size_t line = 0;
  std::string handle;  // group 5, where the file has one
};

struct Scan {
  // HEADER, the LAYER table, BLOCKS and ENTITIES holding only the entities popcut reads: the
  // library then never sees counts it would allocate from (HATCH, LEADER, LTYPE) or data popcut
  // does not use.
  std::string kept;
  std::vector<EntityPlace> entities;
  std::optional<int> insunits;                 // $INSUNITS, where the header has it
  std::map<std::string, std::size_t> skipped;  // entity types not read (TEXT, HATCH, ...) and how many
  std::size_t paper_space = 0;                 // entities on a layout (group 67 = 1), not the model
};

// Checks every group code and value (integers where DXF wants integers, finite numbers where it
// wants reals), the counts the library allocates from (vertices, knots, control points) against
// what follows and against `max_points`, and the end of file; throws popcut::Error naming the
// line. Binary DXF is refused by name.
Scan scan(const std::string& text, const std::string& source, std::size_t max_points);

}  // namespace popcut::dxf

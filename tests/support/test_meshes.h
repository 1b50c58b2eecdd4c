// Small meshes the tests and benchmarks build themselves (house, arch, tower) and writers for every mesh format read.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "popcut/mesh/mesh_import.h"

namespace popcut::testing {

// A point in the (x, z) plane of the mesh (+Z up, -Y towards the viewer).
using XZ = std::array<double, 2>;

// Adds a convex polygon (counter-clockwise seen from the front) extruded from y0 (front) to y1.
void add_prism(TriangleSoup& soup, const std::vector<XZ>& outline, double y0, double y1);
void add_box(TriangleSoup& soup, double x0, double y0, double z0, double x1, double y1, double z1);

// A house with its gable towards the viewer: walls `wall` high, a pitched roof rising `roof`
// more to a ridge that runs front to back, and a porch box in front of the door.
TriangleSoup house_mesh(double width = 40, double depth = 30, double wall = 20, double roof = 14);
// A free-standing arch: two piers and a semicircular opening of `segments` facets, `depth` deep.
TriangleSoup arch_mesh(double width = 40, double height = 30, double depth = 20, int segments = 16);
// A tower of `tiers` boxes, each narrower, shallower and set back from the one below.
TriangleSoup tower_mesh(int tiers = 4, double base = 40, double tier_height = 12);
// A street front 80 wide, 80 deep and 40 high (the voxel paper's size at 80 voxels across and
// half the depth kept): gabled houses, arcades, balconies and a tower, `houses` across, for
// benchmarks and examples; every feature the import pipeline treats differently appears.
TriangleSoup street_mesh(int houses = 5);
// A grid of `n` × `n` city blocks of random heights: many triangles and steps, for benchmarks.
TriangleSoup city_mesh(int n, unsigned seed);

std::string to_obj(const TriangleSoup& soup);
std::string to_off(const TriangleSoup& soup);
std::string to_ply(const TriangleSoup& soup);  // ASCII
std::string to_stl_ascii(const TriangleSoup& soup);
std::string to_stl_binary(const TriangleSoup& soup);

// Writes `text` to a file in this process's folder under the system temporary directory (removed
// when the process ends); returns its path.
std::string write_temp(const std::string& name, const std::string& text);

}  // namespace popcut::testing

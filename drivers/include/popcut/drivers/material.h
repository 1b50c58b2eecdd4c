// Materials (configs/materials/*.toml): force, speed, passes and fold treatment per device family, applied to a
// profile.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "popcut/drivers/profile.h"
#include "popcut/lang/encoder.h"
#include "popcut/plan/plan.h"

namespace popcut::drivers {

// How one line kind is cut in one material on one device family. Forces are in grams, like
// [tool.KIND] force_g: each profile's own factor turns them into its device's units.
struct MaterialKind {
  ToolMode mode = ToolMode::cut;  // folds: score or perforate; cut and outline: cut
  ToolSetting tool;               // force, speed and per-pass lists; the pen stays the profile's
  int passes = 1;
  double perforate_on_mm = 1, perforate_off_mm = 1;  // mode perforate only
};

struct Material {
  std::string name;  // the file's stem: what --material and the API's `material` take
  std::string source;
  std::string description;
  std::vector<std::string> sources;  // where the numbers come from
  // Per family (indexed by DeviceFamily), per kind (index_of(PlanKind)); nullopt: no values.
  std::array<std::optional<std::array<MaterialKind, 4>>, kDeviceFamilyNames.entries.size()> families{};
  // The families it has values for, comma-separated in kDeviceFamilyNames order.
  std::string family_list() const;
};

// Reads a material; wrong types, out-of-range values, unknown sections or keys and missing kinds
// throw popcut::Error(invalid_input) naming the file, "[section] key" and what was expected.
Material parse_material(const std::string& text, const std::string& source, const std::string& name);
Material load_material(const std::string& path);  // named by the file's stem

// The materials in `dir` (its *.toml files' stems), sorted.
std::vector<std::string> material_names(const std::string& dir);
// The material `name` in `dir`; an unknown name throws Error(invalid_input, dir, "material", ...)
// listing the known ones (a caller names its own flag or field instead of "material").
Material find_material(const std::string& dir, const std::string& name);

// The profile with the material's values for its family: each kind's force, speed, passes and
// (folds) score or perforate with its dash lengths. The pen, and a kind the profile skips, stay
// the profile's. A material without values for the family throws Error(invalid_input) naming the
// families it has.
void apply_material(DeviceProfile& profile, const Material& material);

}  // namespace popcut::drivers

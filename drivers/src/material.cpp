// Material loader: [material] and one table per device family with the four line kinds, strictly read; applied to a
// profile.
#include "popcut/drivers/material.h"

#include <algorithm>
#include <filesystem>
#include <system_error>
#include <toml++/toml.h>

#include "popcut/drivers/language.h"
#include "popcut/drivers/toml_section.h"
#include "popcut/error.h"
#include "popcut/io/files.h"
#include "tool_keys.h"

namespace popcut::drivers {
namespace {

namespace fs = std::filesystem;

bool is_fold(PlanKind kind) { return kind == PlanKind::valley || kind == PlanKind::mountain; }

std::size_t family_index(DeviceFamily f) { return static_cast<std::size_t>(f); }

// [FAMILY.KIND] (or KIND = { ... } inside [FAMILY]): force, speed, passes; folds also a mode.
MaterialKind read_kind(TomlSection& s, PlanKind kind) {
  MaterialKind m;
  KindPlan plan;
  read_passes(s, m.tool, plan);
  m.passes = plan.passes;
  // With a list per pass the single value is optional: it is then the last (full) pass's.
  const auto required = [&](const std::string& key, const std::vector<double>& per_pass, double lo, double hi) {
    if (!s.node(key) && per_pass.empty())
      s.fail(key, "missing: every kind of a material gives it (or " + key.substr(0, key.find('_')) + " per pass)");
    return s.number(key, per_pass.empty() ? 0 : per_pass.back(), lo, hi);
  };
  m.tool.force_g = required("force_g", m.tool.pass_force_g, kMinForceG, kMaxForceG);
  m.tool.speed_cm_s = required("speed_cm_s", m.tool.pass_speed_cm_s, kMinSpeedCmS, kMaxSpeedCmS);
  if (!is_fold(kind)) return m;
  if (!s.node("mode")) s.fail("mode", "missing: a fold is \"score\" or \"perforate\"");
  m.mode = s.choice("mode", ToolMode::score, kToolModeNames);
  if (m.mode != ToolMode::score && m.mode != ToolMode::perforate)
    s.fail("mode", "a fold is \"score\" or \"perforate\", not \"" + std::string(kToolModeNames.name(m.mode)) + "\"");
  const bool perforate = m.mode == ToolMode::perforate;
  for (const char* key : {"perforate_on_mm", "perforate_off_mm"}) {
    if (!perforate && s.node(key)) s.fail(key, "only with mode = \"perforate\"");
  }
  m.perforate_on_mm = s.number("perforate_on_mm", 1, 0.1, 100);
  m.perforate_off_mm = s.number("perforate_off_mm", 1, 0.1, 100);
  return m;
}

// One family's table: each of the four kinds, nothing else.
std::array<MaterialKind, 4> read_family(const toml::table& table, const std::string& family,
                                        const std::string& source) {
  std::array<MaterialKind, 4> kinds{};
  TomlSection fam(&table, family, source);
  for (const PlanKind kind : kAllPlanKinds) {
    const std::string kind_name(kPlanKindNames.name(kind));
    const toml::node* n = fam.node(kind_name);
    if (!n) fam.fail(kind_name, "missing: a material gives every line kind (" + kPlanKindNames.list(", ") + ")");
    if (!n->is_table()) fam.fail(kind_name, "expected a table (force_g, speed_cm_s, ...)");
    TomlSection s(n->as_table(), family + "." + kind_name, source);
    kinds[index_of(kind)] = read_kind(s, kind);
    s.reject_unknown();
  }
  fam.reject_unknown();
  return kinds;
}

void read_header(TomlSection& s, bool present, Material& m) {
  if (!present) s.fail("description", "missing: every material says what it is");
  m.description = s.text("description", "", 512);
  if (m.description.empty()) s.fail("description", "must not be empty");
  const toml::array* sources = s.array("sources");
  if (!sources || sources->empty()) s.fail("sources", "missing: say where the numbers come from (a list of strings)");
  for (const toml::node& n : *sources) {
    if (!n.is_string() || n.value<std::string>().value_or("").empty()) s.fail("sources", "expected non-empty strings");
    m.sources.push_back(*n.value<std::string>());
  }
}

// The language's own checks on the profile with the material in it: a value the material file's
// ranges allow may still be out of this device's (a force above its FX maximum), and is then named
// as the material's ([FAMILY.KIND] KEY in its file) since the profile alone was fine.
void check_applied(const DeviceProfile& profile, const Material& material, const std::string& family) {
  const LanguageUnit& language = language_unit(profile.language);
  if (!language.check_profile) return;
  try {
    language.check_profile(profile);
  } catch (const Error& e) {
    std::string where = e.location();
    const std::string tool = "[tool.";
    if (where.rfind(tool, 0) == 0) where = "[" + family + "." + where.substr(tool.size());
    throw Error(e.code(), material.source, where,
                e.message() + " for " + profile.name + " (" + profile.source + "): material \"" + material.name +
                    "\" does not suit this device");
  }
}

}  // namespace

std::string Material::family_list() const {
  std::string out;
  for (const auto& [family, family_name] : kDeviceFamilyNames.entries) {
    if (families[family_index(family)]) out += (out.empty() ? "" : ", ") + std::string(family_name);
  }
  return out.empty() ? "none" : out;
}

Material parse_material(const std::string& text, const std::string& source, const std::string& name) {
  const toml::table root = parse_toml(text, source);
  Material m;
  m.name = name;
  m.source = source;
  for (const auto& [k, v] : root) {
    const std::string key(k.str());
    if (key == "material") continue;
    const std::optional<DeviceFamily> family = kDeviceFamilyNames.find(key);
    if (!family) {
      throw Error(ErrorCode::invalid_input, source, "[" + key + "]",
                  "unknown section (expected material or a device family: " + kDeviceFamilyNames.list(", ") + ")");
    }
    if (!v.is_table()) throw Error(ErrorCode::invalid_input, source, "[" + key + "]", "expected a table");
    m.families[family_index(*family)] = read_family(*v.as_table(), key, source);
  }
  const toml::node* header = root.get("material");
  if (header && !header->is_table()) throw Error(ErrorCode::invalid_input, source, "[material]", "expected a table");
  TomlSection s(header ? header->as_table() : nullptr, "material", source);
  read_header(s, header != nullptr, m);
  s.reject_unknown();
  if (m.family_list() == "none") {
    throw Error(ErrorCode::invalid_input, source, "[FAMILY]",
                "no device family has values (expected tables for some of " + kDeviceFamilyNames.list(", ") + ")");
  }
  return m;
}

Material load_material(const std::string& path) {
  return parse_material(read_text_file(path, 1 << 20), path, fs::path(path).stem().string());
}

std::vector<std::string> material_names(const std::string& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    if (e.is_regular_file(ec) && e.path().extension() == ".toml") names.push_back(e.path().stem().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

Material find_material(const std::string& dir, const std::string& name) {
  const std::vector<std::string> names = material_names(dir);
  // Only a listed name is opened: a name is never a path.
  if (std::find(names.begin(), names.end(), name) == names.end()) {
    std::string known;
    for (const std::string& n : names) known += (known.empty() ? "" : ", ") + n;
    throw Error(ErrorCode::invalid_input, dir, "material",
                "unknown material \"" + name + "\" (known: " + (known.empty() ? "none" : known) + ")");
  }
  return load_material((fs::path(dir) / (name + ".toml")).string());
}

void apply_material(DeviceProfile& profile, const Material& material) {
  const std::string family(kDeviceFamilyNames.name(profile.family));
  const auto& kinds = material.families[family_index(profile.family)];
  if (!kinds) {
    throw Error(ErrorCode::invalid_input, material.source, "[" + family + "]",
                "material \"" + material.name + "\" has no values for the " + family + " family of " + profile.name +
                    " ([device] family in " + profile.source + "); it has values for " + material.family_list());
  }
  for (const PlanKind kind : kAllPlanKinds) {
    const MaterialKind& m = (*kinds)[index_of(kind)];
    ToolSetting& tool = profile.tools[index_of(kind)];
    KindPlan& plan = profile.plan.kinds[index_of(kind)];
    if (plan.mode == ToolMode::skip) continue;  // whether a kind is cut at all is the device's choice
    tool = ToolSetting{tool.pen, m.tool.force_g, m.tool.speed_cm_s, m.tool.pass_force_g, m.tool.pass_speed_cm_s};
    plan.passes = m.passes;
    plan.separate_passes = !m.tool.pass_force_g.empty() || !m.tool.pass_speed_cm_s.empty();
    if (!is_fold(kind)) continue;
    plan.mode = m.mode;
    plan.perforate_on_mm = m.perforate_on_mm;
    plan.perforate_off_mm = m.perforate_off_mm;
  }
  check_applied(profile, material, family);
}

}  // namespace popcut::drivers

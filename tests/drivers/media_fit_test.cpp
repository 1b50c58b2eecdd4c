// A card fitted to a device's media (import --fit-mm DEVICE) is planned and encoded for that device without running off
// its area.
#include <gtest/gtest.h>

#include <algorithm>

#include <filesystem>

#include "popcut/drivers/device_plan.h"
#include "popcut/drivers/profile.h"
#include "popcut/error.h"
#include "popcut/pattern/voxel_pattern.h"
#include "shipped_profiles.h"
#include "test_meshes.h"

namespace popcut::drivers {
namespace {

TEST(MediaFit, EveryShippedProfileCutsACardFittedToItsMedia) {
  // A tall tower, so that on a roll the sheet's height along the roll's width binds.
  TriangleSoup tower;
  testing::add_box(tower, 0, 0, 0, 20, 10, 100);
  for (const std::string& path : testing::shipped_profiles()) {
    const DeviceProfile profile = load_profile(path);
    const NamedMedia m = media_of(profile, std::filesystem::path(path).stem().string());
    const HpglDialect& d = profile.dialect;
    const double area_x = static_cast<double>(d.area_max_x_pu - d.area_min_x_pu) / d.units_per_mm_x;
    const double area_y = static_cast<double>(d.area_max_y_pu - d.area_min_y_pu) / d.units_per_mm_y;
    // The media stay a plotter unit inside the area (0.1 mm on a coarse GP-GL step).
    const double unit_mm = std::max(0.1, 1 / d.units_per_mm_x) + 1e-9;
    EXPECT_NEAR(d.swap_axes ? m.height_mm : m.width_mm, area_x, 2 * profile.plan.blade_offset_mm + unit_mm)
        << path << ": the sheet's x runs along the plotter's x unless the axes are swapped";
    EXPECT_LE(d.swap_axes ? m.width_mm : m.height_mm, area_y) << path;
    ImportOptions o;
    o.resolution = 20;
    o.fit = CardFit{m.width_mm, m.height_mm, true, m.name};
    const Pattern p = make_pattern(import_mesh(tower, o, "tower").model, "tower");
    const double h = p.sheet.max.v_mm - p.sheet.min.v_mm, w = p.sheet.max.x_mm - p.sheet.min.x_mm;
    EXPECT_TRUE(w <= m.width_mm && h <= m.height_mm) << path << ": " << w << " x " << h;
    EXPECT_TRUE(h > m.height_mm - 1e-3 || w > m.width_mm - 1e-3)
        << path << ": as large as the media allow: " << w << " x " << h;
    try {
      const DevicePlan plan = plan_for_device(p, profile, path);
      EXPECT_FALSE(plan.encoded.bytes.empty()) << path;
    } catch (const Error& e) {
      ADD_FAILURE() << path << ": a card fitted to the media is refused: " << e.what();
    }
  }
}

}  // namespace
}  // namespace popcut::drivers

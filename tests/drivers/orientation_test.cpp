// Every shipped profile cuts the card as it reads from its printed side: decoded HP-GL or GP-GL, mapped through each
// device's own axes, is the pattern turned, never mirrored.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "popcut/drivers/gpgl_reader.h"
#include "popcut/drivers/hpgl_reader.h"
#include "popcut/drivers/language.h"
#include "popcut/drivers/profile.h"
#include "popcut/hpgl/hpgl.h"
#include "popcut/io/model_io.h"
#include "shipped_profiles.h"

namespace popcut::drivers {
namespace {

namespace fs = std::filesystem;

// A point as the user sees the media from the front of the machine, looking down on its top
// (printed) side: mm to the right, mm away from the user.
struct View {
  double right_mm = 0;
  double away_mm = 0;
};
using Seg = std::array<View, 2>;

// Where a device's HP-GL axes run on the media as the user faces the machine (the view
// directions of +x and +y), and which way the card's top edge (pattern +v) should then point.
struct DeviceAxes {
  View plus_x, plus_y;
  const char* card_top;
};

View to_view(const DeviceAxes& a, double x_mm, double y_mm) {
  return {x_mm * a.plus_x.right_mm + y_mm * a.plus_y.right_mm, x_mm * a.plus_x.away_mm + y_mm * a.plus_y.away_mm};
}

// HP's frame ("facing the front of the plotter and looking down on it": origin lower left, +x
// right, +y up the sheet), which popcut's simulator draws too (plotter y up). The roll cutters'
// profiles declare x across the roll and y along the feed, which is that frame on a roll.
constexpr DeviceAxes kHpFrame{{1, 0}, {0, 1}, "away"};

// One entry per shipped profile (the test fails for a profile missing here): profiles.md,
// "Orientation", names the reference each follows.
// GP-GL on a Silhouette (Graphtec.py writes "M y,x", SilhouetteTest reverses x and y for the
// Curio): the first coordinate runs along the feed or tray, from the sheet's top edge toward you,
// the second with the head, left to right.
constexpr DeviceAxes kSilhouetteFrame{{0, -1}, {1, 0}, "away"};

const std::map<std::string, DeviceAxes> kDevices = {
    {"generic-hpgl", kHpFrame},
    {"sim", kHpFrame},
    {"roland-gx24", kHpFrame},
    {"graphtec-ce", kHpFrame},
    {"graphtec-ce6000", kHpFrame},
    {"uscutter-mh", kHpFrame},
    {"secabo", kHpFrame},
    {"silhouette-cameo3", kSilhouetteFrame},
    {"silhouette-cameo4", kSilhouetteFrame},
    {"silhouette-portrait3", kSilhouetteFrame},
    {"silhouette-curio", kSilhouetteFrame},
};

// Knife-down segments of a job in the device's frame, in mm, read by a plain HP-GL interpreter
// (PA/PR modes, PU/PD with or without coordinates, IN), independent of popcut's encoder.
std::vector<std::array<std::array<double, 2>, 2>> knife_down_mm(const std::string& job, const HpglDialect& d) {
  std::vector<std::array<std::array<double, 2>, 2>> out;
  bool absolute = true, down = false;
  double x = 0, y = 0;
  for (const HpglCommand& c : parse_hpgl(job)) {
    if (c.name == "IN") absolute = true, down = false;
    if (c.name == "PA") absolute = true;
    if (c.name == "PR") absolute = false;
    if (c.name == "PU") down = false;
    if (c.name == "PD") down = true;
    if (c.name != "PA" && c.name != "PR" && c.name != "PU" && c.name != "PD") continue;
    EXPECT_EQ(c.params.size() % 2, 0u) << c.name << " with an odd number of coordinates";
    for (std::size_t i = 0; i + 1 < c.params.size(); i += 2) {
      const double nx = absolute ? c.params[i] : x + c.params[i], ny = absolute ? c.params[i + 1] : y + c.params[i + 1];
      if (down)
        out.push_back({{{x / d.units_per_mm_x, y / d.units_per_mm_y}, {nx / d.units_per_mm_x, ny / d.units_per_mm_y}}});
      x = nx, y = ny;
    }
  }
  return out;
}

// The same for GP-GL, read by the device-side reader: M moves with the knife up, D with it down,
// both absolute; O and E relative.
std::vector<std::array<std::array<double, 2>, 2>> gpgl_knife_down_mm(const std::string& job, const PlotterFrame& d) {
  std::vector<std::array<std::array<double, 2>, 2>> out;
  double x = 0, y = 0;
  for (const DeviceCommand& c : parse_gpgl(job)) {
    const bool rel = c.name == "O" || c.name == "E";
    if (c.name != "M" && c.name != "D" && !rel) continue;
    EXPECT_EQ(c.params.size() % 2, 0u) << c.name << " with an odd number of coordinates";
    for (std::size_t i = 0; i + 1 < c.params.size(); i += 2) {
      const double nx = rel ? x + c.params[i] : c.params[i], ny = rel ? y + c.params[i + 1] : c.params[i + 1];
      if (c.name == "D" || c.name == "E")
        out.push_back({{{x / d.units_per_mm_x, y / d.units_per_mm_y}, {nx / d.units_per_mm_x, ny / d.units_per_mm_y}}});
      x = nx, y = ny;
    }
  }
  return out;
}

double dist_to_seg(View p, const Seg& s) {
  const double dx = s[1].right_mm - s[0].right_mm, dy = s[1].away_mm - s[0].away_mm;
  const double len2 = dx * dx + dy * dy;
  double t = len2 > 0 ? ((p.right_mm - s[0].right_mm) * dx + (p.away_mm - s[0].away_mm) * dy) / len2 : 0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(p.right_mm - (s[0].right_mm + t * dx), p.away_mm - (s[0].away_mm + t * dy));
}

// The farthest any point along `from` (sampled every 0.25 mm) lies from the nearest of `to`.
double farthest(const std::vector<Seg>& from, const std::vector<Seg>& to) {
  double worst = 0;
  for (const Seg& s : from) {
    const double len = std::hypot(s[1].right_mm - s[0].right_mm, s[1].away_mm - s[0].away_mm);
    const int n = std::max(1, static_cast<int>(std::ceil(len / 0.25)));
    for (int i = 0; i <= n; ++i) {
      const double t = static_cast<double>(i) / n;
      const View p{s[0].right_mm + t * (s[1].right_mm - s[0].right_mm),
                   s[0].away_mm + t * (s[1].away_mm - s[0].away_mm)};
      double best = std::numeric_limits<double>::infinity();
      for (const Seg& q : to) best = std::min(best, dist_to_seg(p, q));
      worst = std::max(worst, best);
    }
  }
  return worst;
}

std::array<double, 4> bounds(const std::vector<Seg>& segs) {  // min right, min away, max right, max away
  std::array<double, 4> b{1e300, 1e300, -1e300, -1e300};
  for (const Seg& s : segs) {
    for (const View& p : s) {
      b[0] = std::min(b[0], p.right_mm), b[1] = std::min(b[1], p.away_mm);
      b[2] = std::max(b[2], p.right_mm), b[3] = std::max(b[3], p.away_mm);
    }
  }
  return b;
}

// One of the eight ways to lay the pattern on the media square to its axes: (x, v) to
// (right, away) = (a x + b v, c x + e v); det +1 turns it, det -1 mirrors it.
struct Lay {
  int a, b, c, e;
  int det() const { return a * e - b * c; }
  View of(Point2 p) const { return {a * p.x_mm + b * p.v_mm, c * p.x_mm + e * p.v_mm}; }
};
constexpr std::array<Lay, 8> kLays = {{{1, 0, 0, 1},
                                       {-1, 0, 0, -1},
                                       {0, -1, 1, 0},
                                       {0, 1, -1, 0},
                                       {-1, 0, 0, 1},
                                       {1, 0, 0, -1},
                                       {0, 1, 1, 0},
                                       {0, -1, -1, 0}}};

struct Fit {
  Lay lay;
  double error_mm;
};

// How well each laying of the pattern explains what the knife cut: every knife-down point near a
// line the profile cuts, and every cut line (the asymmetric F among them) covered by the knife.
// Positions are matched by bounding boxes, so only the turn or mirror is judged.
std::vector<Fit> fits(const Pattern& pattern, const DeviceProfile& prof, const std::vector<Seg>& cut) {
  const auto cut_kind = [&](PlanKind k) { return prof.plan.kinds[index_of(k)].mode != ToolMode::skip; };
  std::vector<Fit> out;
  for (const Lay& lay : kLays) {
    std::vector<Seg> lines, cuts;
    for (const Segment& s : pattern.lines) {
      const PlanKind k = s.kind == LineKind::cut      ? PlanKind::cut
                         : s.kind == LineKind::valley ? PlanKind::valley
                                                      : PlanKind::mountain;
      if (!cut_kind(k)) continue;
      lines.push_back({lay.of(s.a), lay.of(s.b)});
      if (k == PlanKind::cut) cuts.push_back(lines.back());
    }
    if (cut_kind(PlanKind::outline)) {
      const Point2 lo = pattern.sheet.min, hi = pattern.sheet.max;
      const std::array<Point2, 4> c = {lo, Point2{hi.x_mm, lo.v_mm}, hi, Point2{lo.x_mm, hi.v_mm}};
      for (std::size_t i = 0; i < 4; ++i) lines.push_back({lay.of(c[i]), lay.of(c[(i + 1) % 4])});
    }
    const auto want = bounds(lines), got = bounds(cut);
    const double dr = (got[0] + got[2] - want[0] - want[2]) / 2, da = (got[1] + got[3] - want[1] - want[3]) / 2;
    for (auto* set : {&lines, &cuts}) {
      for (Seg& s : *set) {
        for (View& p : s) p.right_mm += dr, p.away_mm += da;
      }
    }
    out.push_back({lay, std::max(farthest(cut, lines), farthest(cuts, cut))});
  }
  return out;
}

const char* top_direction(const Lay& lay) {
  const View top = lay.of({0, 1});
  return top.away_mm > 0 ? "away" : top.away_mm < 0 ? "toward the user" : top.right_mm > 0 ? "right" : "left";
}

struct Verdict {
  Fit best{};
  double best_mirror_mm = std::numeric_limits<double>::infinity();
};

Verdict judge(const Pattern& pattern, const DeviceProfile& prof, const DeviceAxes& axes) {
  std::vector<Seg> cut;
  const std::string job = encode_for_device(plan_strokes(pattern, prof.plan), prof).bytes;
  for (const auto& s : prof.language == CutterLanguage::gpgl ? gpgl_knife_down_mm(job, prof.dialect)
                                                             : knife_down_mm(job, prof.dialect)) {
    cut.push_back({to_view(axes, s[0][0], s[0][1]), to_view(axes, s[1][0], s[1][1])});
  }
  Verdict v;
  v.best.error_mm = std::numeric_limits<double>::infinity();
  for (const Fit& f : fits(pattern, prof, cut)) {
    if (f.error_mm < v.best.error_mm) v.best = f;
    if (f.lay.det() < 0) v.best_mirror_mm = std::min(v.best_mirror_mm, f.error_mm);
  }
  return v;
}

Pattern letter_f() { return make_pattern(load_model(std::string(POPCUT_SOURCE_DIR) + "/tests/data/letter_f.json")); }

TEST(Orientation, EveryProfileCutsTheCardUnmirrored) {
  const Pattern pattern = letter_f();
  for (const std::string& file : testing::shipped_profiles()) {
    const std::string stem = fs::path(file).stem().string();
    const auto axes = kDevices.find(stem);
    ASSERT_NE(axes, kDevices.end()) << stem << ": a shipped profile needs its device's axes in kDevices";
    const DeviceProfile prof = load_profile(file);
    const Verdict v = judge(pattern, prof, axes->second);
    EXPECT_LT(v.best.error_mm, 1.0) << stem
                                    << ": the cut matches the pattern laid square (blade offset and overcut aside)";
    EXPECT_EQ(v.best.lay.det(), 1) << stem << ": the card comes out mirrored (best fit " << v.best.error_mm << " mm)";
    EXPECT_GT(v.best_mirror_mm, 3.0) << stem << ": a mirror image must not fit the cut as well: the F tells them apart";
    EXPECT_STREQ(top_direction(v.best.lay), axes->second.card_top)
        << stem << ": where the card's top edge lies (profiles.md)";
  }
}

TEST(Orientation, SwappedAxesAloneAreCaughtAsAMirror) {
  // The check itself: one axis swap with no flip turns nothing, it mirrors.
  const Pattern pattern = letter_f();
  DeviceProfile prof = load_profile(std::string(POPCUT_SOURCE_DIR) + "/configs/devices/generic-hpgl.toml");
  prof.dialect.swap_axes = true;
  const Verdict swapped = judge(pattern, prof, kHpFrame);
  EXPECT_EQ(swapped.best.lay.det(), -1) << "best fit " << swapped.best.error_mm << " mm";
  EXPECT_LT(swapped.best.error_mm, 1.0);
  prof.dialect.flip_x = true;  // and a flip after it makes it a quarter turn (profiles.md's table)
  const Verdict turned = judge(pattern, prof, kHpFrame);
  EXPECT_EQ(turned.best.lay.det(), 1);
  EXPECT_STREQ(top_direction(turned.best.lay), "left");
  prof.dialect.flip_x = false, prof.dialect.flip_y = true;
  EXPECT_STREQ(top_direction(judge(pattern, prof, kHpFrame).best.lay), "right");
  prof.dialect.flip_x = true;  // swap and both flips: a mirror again
  EXPECT_EQ(judge(pattern, prof, kHpFrame).best.lay.det(), -1);
  prof.dialect.flip_y = false;
  prof.dialect.swap_axes = false;  // a flip alone mirrors again
  EXPECT_EQ(judge(pattern, prof, kHpFrame).best.lay.det(), -1);
}

}  // namespace
}  // namespace popcut::drivers

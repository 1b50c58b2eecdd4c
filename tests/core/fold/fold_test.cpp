// Open/close simulation: rigid faces, joined folds, flat at 0° and 180°, over random models and angles; pictures of it.
#include "popcut/fold/fold.h"
#include "popcut/fold/render.h"

#include <gtest/gtest.h>
#include <stb_image.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <sstream>

#include "popcut/error.h"
#include "popcut/io/model_io.h"
#include "popcut/pattern/popup_check.h"
#include "popcut/pattern/voxel_pattern.h"
#include "random_models.h"

namespace popcut {
namespace {

double dist3(Point3 a, Point3 b) { return std::hypot(a.x_mm - b.x_mm, a.y_mm - b.y_mm, a.z_mm - b.z_mm); }
double dist2(Point2 a, Point2 b) { return std::hypot(a.x_mm - b.x_mm, a.v_mm - b.v_mm); }
double area2(const std::array<Point2, 3>& t) {
  return ((t[1].x_mm - t[0].x_mm) * (t[2].v_mm - t[0].v_mm) - (t[2].x_mm - t[0].x_mm) * (t[1].v_mm - t[0].v_mm)) / 2;
}

TEST(Fold, Equation7AtKeyAngles) {
  const Point3 p{1, 2, 3};
  EXPECT_EQ(fold_point(p, 90), p) << "90° is the designed card";
  EXPECT_EQ(fold_point(p, 180), (Point3{1, 5, 0})) << "180°: (x, y + z, 0), flat";
  EXPECT_EQ(fold_point(p, 0), (Point3{1, -1, 0})) << "0°: (x, y - z, 0) = (x, -v, 0), the flat sheet";
  const Point3 q = fold_point(p, 30);
  EXPECT_NEAR(q.y_mm, 2 - 3 * std::cos(M_PI / 6), 1e-12) << "eq. 7 y";
  EXPECT_NEAR(q.z_mm, 3 * std::sin(M_PI / 6), 1e-12) << "eq. 7 z";
  EXPECT_THROW(fold_card(Pattern{}, -1), Error) << "angles below 0 are refused";
  EXPECT_THROW(fold_card(Pattern{}, 180.5), Error) << "angles above 180 are refused";
}

TEST(Fold, TriangulationCoversFacesExactly) {
  std::mt19937_64 rng(5);
  testing::RandomModelSpec spec;
  spec.window_probability = 0.3;
  for (int trial = 0; trial < 200; ++trial) {
    const Pattern p = make_pattern(testing::random_model(rng, spec));
    for (const PatternFace& f : p.faces) {
      double area = 0;
      for (const auto& t : triangulate(f)) {
        const double a = area2(t);
        ASSERT_GT(a, 0) << "trial " << trial << ": triangles run counter-clockwise";
        area += a;
      }
      double expected = signed_area_mm2(f.outer);
      for (const Ring& h : f.holes) expected += signed_area_mm2(h);
      ASSERT_NEAR(area, expected, 1e-9 * std::max(1.0, expected))
          << "trial " << trial << ": triangles cover the face minus its holes";
    }
  }
}

// For every angle: faces rigid, folds joined; flat at both ends.
void check_folding(const Pattern& p, const std::string& what) {
  for (double angle : {0.0, 15.0, 45.0, 90.0, 120.0, 165.0, 180.0}) {
    const CardMesh m = fold_card(p, angle);
    for (const auto& t : m.triangles) {
      for (int i = 0; i < 3; ++i) {
        const std::uint32_t a = t[static_cast<std::size_t>(i)], b = t[static_cast<std::size_t>((i + 1) % 3)];
        ASSERT_NEAR(dist3(m.vertices[a], m.vertices[b]), dist2(m.pattern_points[a], m.pattern_points[b]), 1e-9)
            << what << " at " << angle << "°: faces move rigidly (edge lengths kept)";
      }
    }
    for (std::size_t i = 0; i < m.vertices.size(); ++i) {
      if (angle == 0) {
        ASSERT_EQ(m.vertices[i], (Point3{m.pattern_points[i].x_mm, -m.pattern_points[i].v_mm, 0}))
            << what << ": flat sheet at 0°";
      }
      if (angle == 180) {
        ASSERT_EQ(m.vertices[i].z_mm, 0) << what << ": closed card lies flat at 180°";
      }
    }
    // Each fold's ends, carried by the face above and by the face below, land on the same point.
    for (const Segment& s : p.lines) {
      if (s.kind == LineKind::cut) continue;
      for (const FoldLink& l : p.folds) {
        const PatternFace& up = p.faces[static_cast<std::size_t>(l.upper)];
        const PatternFace& lo = p.faces[static_cast<std::size_t>(l.lower)];
        const double v = s.a.v_mm;
        if (to_card(up.kind, up.t_mm, {0, v}).z_mm != to_card(lo.kind, lo.t_mm, {0, v}).z_mm) continue;
        for (const Point2& e : {s.a, s.b}) {
          ASSERT_NEAR(
              dist3(fold_point(to_card(up.kind, up.t_mm, e), angle), fold_point(to_card(lo.kind, lo.t_mm, e), angle)),
              0, 1e-9)
              << what << " at " << angle << "°: faces sharing a fold stay joined";
        }
      }
    }
  }
}

TEST(Fold, RandomVoxelCardsFoldRigidly) {
  std::mt19937_64 rng(8);
  testing::RandomModelSpec spec;
  spec.window_probability = 0.2;
  for (int trial = 0; trial < 60; ++trial)
    check_folding(make_pattern(testing::random_model(rng, spec)), "trial " + std::to_string(trial));
}

TEST(Fold, FaceModelExamplesFoldRigidly) {
  for (const char* name : {"pavilion", "porch", "openings"}) {
    const std::string path = std::string(POPCUT_SOURCE_DIR) + "/examples/faces/" + name + ".json";
    check_folding(make_pattern(load_model(path), path), name);
  }
}

// The share of pixels unlike their right-hand neighbour. A clean picture changes colour only at
// edges (1-2.5% of these pictures' pixels); layers a depth test cannot order speckle whole
// areas (6-8% when they were drawn at 180°).
double rough_share(const std::string& png) {
  int w = 0, h = 0, channels = 0;
  unsigned char* px = stbi_load_from_memory(reinterpret_cast<const unsigned char*>(png.data()),
                                            static_cast<int>(png.size()), &w, &h, &channels, 3);
  if (!px) return 1;
  int rough = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x + 1 < w; ++x) {
      int d = 0;
      for (int c = 0; c < 3; ++c) d += std::abs(px[3 * (y * w + x) + c] - px[3 * (y * w + x + 1) + c]);
      rough += d > 30;
    }
  }
  stbi_image_free(px);
  return static_cast<double>(rough) / (static_cast<double>(w - 1) * h);
}

TEST(Render, ClosedCardPicturesKeepTheirLayersApart) {
  for (const char* name : {"voxel/townhouse", "faces/porch"}) {
    const std::string path = std::string(POPCUT_SOURCE_DIR) + "/examples/" + name + ".json";
    const Pattern p = make_pattern(load_model(path), path);
    const CardMesh closed = fold_card_for_picture(p, 180), standing = fold_card_for_picture(p, 90);
    const ViewBox box = view_box({closed, standing});
    const double rough_closed = rough_share(render_png(closed, box, 400)),
                 rough_standing = rough_share(render_png(standing, box, 400));
    EXPECT_LT(rough_closed, 0.04) << name
                                  << ": the closed card changes colour only at its edges (no z-fighting speckle)";
    EXPECT_LT(rough_standing, 0.04) << name << ": so does the standing card";
    EXPECT_EQ(standing.vertices, fold_card(p, 90).vertices) << name << ": pictures fold open cards exactly";
  }
}

// A card with one block on it: a front wall at y = 20 (x from 20 to 60, 40 high) and its roof at
// z = 40, cut from the floor and the back wall behind them (so the block's sides are open).
constexpr double kBlockLeftMm = 20, kBlockRightMm = 60, kBlockDepthMm = 20, kBlockHeightMm = 40;
Pattern one_block_card() {
  const std::string json = R"({"format": "popcut.faces.v1", "name": "one block",
    "sheet": {"width": 120, "back": 80, "floor": 80},
    "edits": [{"op": "add_vface", "t": 20, "outline": [[20, 0], [60, 0], [60, 40], [20, 40]]},
              {"op": "add_hface", "t": 40, "outline": [[20, 0], [60, 0], [60, 20], [20, 20]]}]})";
  return make_pattern(parse_model(json, "one block"), "one block");
}

// Whether the lamp's ray from p (a point of the standing card, at 90°) passes through the block's
// wall or roof: the shadow worked out from render.h's lamp alone, without the renderer.
bool in_block_shadow(Point3 p) {
  const double lx = kPictureLight.x, ly = kPictureLight.z, lz = kPictureLight.y;  // Y-up frame to card
  const auto across_block = [](double x) { return x >= kBlockLeftMm && x <= kBlockRightMm; };
  if (p.y_mm < kBlockDepthMm && ly > 0) {  // to the wall's plane, y = depth
    const double s = (kBlockDepthMm - p.y_mm) / ly, z = p.z_mm + s * lz;
    if (across_block(p.x_mm + s * lx) && z >= 0 && z <= kBlockHeightMm) return true;
  }
  if (p.z_mm < kBlockHeightMm && lz > 0) {  // to the roof's plane, z = height
    const double s = (kBlockHeightMm - p.z_mm) / lz, y = p.y_mm + s * ly;
    if (across_block(p.x_mm + s * lx) && y >= 0 && y <= kBlockDepthMm) return true;
  }
  return false;
}

// The same answer for p and for the points 3 mm around it along `a` and `b` (two directions in
// p's face): far enough inside or outside the shadow that its soft edge cannot reach p's pixels.
bool clearly(bool shadowed, Point3 p, Point3 a, Point3 b) {
  for (int i = -1; i <= 1; ++i) {
    for (int j = -1; j <= 1; ++j) {
      const Point3 q{p.x_mm + 3 * (i * a.x_mm + j * b.x_mm), p.y_mm + 3 * (i * a.y_mm + j * b.y_mm),
                     p.z_mm + 3 * (i * a.z_mm + j * b.z_mm)};
      if (in_block_shadow(q) != shadowed) return false;
    }
  }
  return true;
}

struct Picture {
  int width_px = 0, height_px = 0;
  std::vector<unsigned char> rgb;
  // The grey level (mean of R, G, B) at pixel (x, y), or -1 outside the picture.
  double level(int x, int y) const {
    if (x < 0 || y < 0 || x >= width_px || y >= height_px) return -1;
    const std::size_t i =
        3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(width_px) + static_cast<std::size_t>(x));
    return (rgb[i] + rgb[i + 1] + rgb[i + 2]) / 3.0;
  }
  // The mean grey level over the 5 × 5 pixels around q.
  double patch_level(PicturePoint q) const {
    double sum = 0;
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx) sum += level(static_cast<int>(q.x_px) + dx, static_cast<int>(q.y_px) + dy);
    return sum / 25;
  }
};
Picture decode(const std::string& png) {
  Picture p;
  int channels = 0;
  unsigned char* px = stbi_load_from_memory(reinterpret_cast<const unsigned char*>(png.data()),
                                            static_cast<int>(png.size()), &p.width_px, &p.height_px, &channels, 3);
  if (px) p.rgb.assign(px, px + 3 * static_cast<std::size_t>(p.width_px) * static_cast<std::size_t>(p.height_px));
  stbi_image_free(px);
  return p;
}

TEST(Render, BlockCastsItsShadowOnTheFloorAndTheBackWall) {
  const CardMesh m = fold_card_for_picture(one_block_card(), 90);
  const ViewBox box = view_box({m});
  constexpr int kWidthPx = 400;
  const Picture pic = decode(render_png(m, box, kWidthPx));
  ASSERT_EQ(pic.width_px, kWidthPx) << "the PNG decodes";
  struct Probe {
    const char* where;
    Point3 shadowed, lit, a, b;  // two points of one face, and two directions in it
    double facing;               // the face's normal · kPictureLight
  };
  // Right of the block, where the camera (front right) sees them: the floor behind the wall's
  // right edge, and the back wall below the roof's right edge; the same faces further right are lit.
  const Probe probes[] = {{"floor", {65, 6, 0}, {100, 6, 0}, {1, 0, 0}, {0, 1, 0}, kPictureLight.y},
                          {"back wall", {65, 0, 14}, {100, 0, 14}, {1, 0, 0}, {0, 0, 1}, kPictureLight.z}};
  for (const Probe& p : probes) {
    ASSERT_TRUE(clearly(true, p.shadowed, p.a, p.b)) << p.where << ": the test's probe lies inside the shadow";
    ASSERT_TRUE(clearly(false, p.lit, p.a, p.b)) << p.where << ": the test's probe lies in the light";
    const double dark = pic.patch_level(picture_point(p.shadowed, box, kWidthPx));
    const double light = pic.patch_level(picture_point(p.lit, box, kWidthPx));
    EXPECT_LT(dark, 0.85 * light) << p.where << ": the block's shadow is darker than the lit part of the same face ("
                                  << dark << " in the shadow, " << light << " lit)";
    // A shadow keeps the ambient light only, so render.h's factors give the ratio (± rounding).
    const double ratio = kPictureAmbient / (kPictureAmbient + kPictureDiffuse * p.facing);
    EXPECT_NEAR(dark / light, ratio, 0.02) << p.where << ": a shadow keeps the ambient light only, so shadow / lit is "
                                           << ratio << " (" << dark << " vs " << light << ")";
  }
}

// Regions of the block card the lamp lights fully at any opening near 90° (nothing stands between
// them and the lamp), each 3 mm or more inside its face: corner + i·a + j·b for 0 ≤ i < n_a, 0 ≤ j < n_b.
struct LitRegion {
  const char* what;
  Point3 corner, a, b;
  int n_a, n_b;
};
const LitRegion kLitRegions[] = {
    {"floor in front of the block", {4, 26, 0}, {2, 0, 0}, {0, 2, 0}, 57, 26},
    {"front of the wall", {23, 20, 3}, {2, 0, 0}, {0, 0, 2}, 18, 18},
    {"roof", {23, 3, 40}, {2, 0, 0}, {0, 2, 0}, 18, 8},
    {"back wall above the roof", {4, 0, 44}, {2, 0, 0}, {0, 0, 2}, 57, 17},
};

TEST(Render, LitFacesHaveNoShadowSpeckle) {
  const Pattern card = one_block_card();
  for (double angle : {90.0, 75.0}) {
    const CardMesh m = fold_card_for_picture(card, angle);
    const ViewBox box = view_box({m});
    constexpr int kWidthPx = 400;
    const Picture pic = decode(render_png(m, box, kWidthPx));
    for (const LitRegion& r : kLitRegions) {
      std::vector<double> levels;
      for (int i = 0; i < r.n_a; ++i) {
        for (int j = 0; j < r.n_b; ++j) {
          const Point3 p{r.corner.x_mm + i * r.a.x_mm + j * r.b.x_mm, r.corner.y_mm + i * r.a.y_mm + j * r.b.y_mm,
                         r.corner.z_mm + i * r.a.z_mm + j * r.b.z_mm};
          if (angle == 90) {
            ASSERT_FALSE(in_block_shadow(p)) << r.what << ": the test's region lies in the light";
          }
          const PicturePoint q = picture_point(fold_point(p, angle), box, kWidthPx);
          levels.push_back(pic.level(static_cast<int>(q.x_px), static_cast<int>(q.y_px)));
        }
      }
      const auto [lo, hi] = std::minmax_element(levels.begin(), levels.end());
      EXPECT_LE(*hi - *lo, 1.0) << r.what << " at " << angle << "°: a lit face is one colour (levels from " << *lo
                                << " to " << *hi << " over " << levels.size() << " points: shadow acne)";
    }
  }
}

// Where two lit faces meet in a valley (the wall's foot on the floor, the roof's back edge on the
// back wall), a shadow-map lookup straddles the fold; the picture there must blend the two faces
// and never go darker than both (a dark line along every fold).
TEST(Render, LitFoldsHaveNoDarkLine) {
  const CardMesh m = fold_card_for_picture(one_block_card(), 90);
  const ViewBox box = view_box({m});
  constexpr int kWidthPx = 400;
  const Picture pic = decode(render_png(m, box, kWidthPx));
  struct Fold {
    const char* what;
    double y_mm, z_mm;      // the fold line: x from the block's left to its right at this y and z
    Point3 away_a, away_b;  // from the fold into each face, 4 mm
  };
  const Fold folds[] = {{"the wall's foot", kBlockDepthMm, 0, {0, 4, 0}, {0, 0, 4}},
                        {"the roof's back edge", 0, kBlockHeightMm, {0, 4, 0}, {0, 0, 4}}};
  for (const Fold& f : folds) {
    for (double x = kBlockLeftMm + 2; x <= kBlockRightMm - 2; x += 1) {
      const auto at = [&](Point3 d) {
        return pic.patch_level(picture_point({x + d.x_mm, f.y_mm + d.y_mm, f.z_mm + d.z_mm}, box, kWidthPx));
      };
      const double darker_face = std::min(at(f.away_a), at(f.away_b));
      const PicturePoint q = picture_point({x, f.y_mm, f.z_mm}, box, kWidthPx);
      for (int dy = -3; dy <= 3; ++dy) {
        const double level = pic.level(static_cast<int>(q.x_px), static_cast<int>(q.y_px) + dy);
        ASSERT_GE(level, darker_face - 2)
            << f.what << " at x = " << x << " mm, " << dy << " px off the fold: darker than either face (" << level
            << " against " << darker_face << "): the faces shadow each other at their fold";
      }
    }
  }
}

// Every fill colour of the SVG picture.
std::set<std::string> svg_fills(const std::string& svg) {
  std::set<std::string> fills;
  for (std::size_t at = svg.find("fill=\"#"); at != std::string::npos; at = svg.find("fill=\"#", at + 1))
    fills.insert(svg.substr(at + 6, 7));
  return fills;
}

TEST(Render, SvgIsShadedByTheSameLamp) {
  const CardMesh m = fold_card_for_picture(one_block_card(), 90);
  const ViewBox box = view_box({m});
  std::ostringstream svg;
  write_render_svg(svg, m, box, 2);
  const Picture pic = decode(render_png(m, box, 400));
  for (const LitRegion& r : kLitRegions) {
    const Point3 p{r.corner.x_mm + 2 * (r.a.x_mm + r.b.x_mm), r.corner.y_mm + 2 * (r.a.y_mm + r.b.y_mm),
                   r.corner.z_mm + 2 * (r.a.z_mm + r.b.z_mm)};
    const PicturePoint q = picture_point(p, box, 400);
    const std::size_t i = 3 * (static_cast<std::size_t>(q.y_px) * static_cast<std::size_t>(pic.width_px) +
                               static_cast<std::size_t>(q.x_px));
    char colour[8];
    std::snprintf(colour, sizeof colour, "#%02x%02x%02x", pic.rgb[i], pic.rgb[i + 1], pic.rgb[i + 2]);
    EXPECT_EQ(svg_fills(svg.str()).count(colour), 1u)
        << r.what << ": the PNG's lit colour " << colour << " is one of the SVG's, so both use one lamp";
  }
}

}  // namespace
}  // namespace popcut

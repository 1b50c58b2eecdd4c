// Open/close simulation: rigid faces, joined folds, flat at 0° and 180°, over random models and angles; pictures of it.
#include "popcut/fold/fold.h"
#include "popcut/fold/render.h"

#include <gtest/gtest.h>
#include <stb_image.h>

#include <cmath>
#include <random>

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

}  // namespace
}  // namespace popcut

// The face path equals the voxel path: same faces, lines and pop-up verdict over random models.
#include "popcut/pattern/face_pattern.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "arrangement_oracle.h"
#include "pattern_compare.h"
#include "pattern_oracle.h"
#include "popcut/io/voxel_json.h"
#include "popcut/pattern/popup_check.h"
#include "popcut/pattern/voxel_pattern.h"
#include "random_models.h"

namespace popcut {
namespace {

TEST(FacePattern, MatchesTheVoxelPathOnRandomModels) {
  std::mt19937_64 rng(99);
  testing::RandomModelSpec spec;
  spec.max_width = 5;
  spec.max_depth = 4;
  spec.max_height = 5;
  spec.window_probability = 0.3;
  spec.random_sheet = true;
  int failing = 0;
  const int trials = 250;
  for (int trial = 0; trial < trials; ++trial) {
    const VoxelModel m = testing::random_model(rng, spec);
    const Pattern voxel = make_pattern(m);
    const Pattern faces = make_pattern(to_face_model(m));
    const std::string diff = testing::compare_patterns(voxel, faces);
    ASSERT_EQ(diff, "") << "trial " << trial << ": the two paths disagree for\n" << to_voxel_json(m);
    const auto lines = testing::check_lines(faces, m.voxel_mm);
    ASSERT_TRUE(lines.empty()) << "trial " << trial << ": " << lines.front();
    failing += !check_popup(faces).pops_up();
  }
  EXPECT_GT(failing, 0) << "the sample includes cards that do not pop up";
}

TEST(FacePattern, VoxelSizesWithEndlessDecimalsKeepTheirFolds) {
  // 120 / 42 mm has no finite decimal form: snapped length by length, t_h - t_v and v would
  // disagree by a fraction of a nanometre and folds would turn into cuts.
  std::mt19937_64 rng(5);
  for (double voxel_mm : {120.0 / 42, 1.0 / 3, 0.1 + 0.2}) {
    const VoxelModel m = testing::random_staircase(rng, 6, 5, 6, voxel_mm);
    const LineCounts voxel = count_lines(make_pattern(m));
    const Pattern faces = make_pattern(to_face_model(m));
    const LineCounts face = count_lines(faces);
    EXPECT_EQ(face.mountain, voxel.mountain) << voxel_mm << " mm voxels";
    EXPECT_EQ(face.valley, voxel.valley) << voxel_mm << " mm voxels";
    EXPECT_EQ(face.cut, voxel.cut) << voxel_mm << " mm voxels";
    EXPECT_NEAR(face.mountain_mm, voxel.mountain_mm, 1e-3) << voxel_mm << " mm voxels";
    EXPECT_TRUE(check_popup(faces).pops_up()) << voxel_mm << " mm voxels: a staircase pops up";
  }
}

// Random face models: slanted edges, holes in both planes, coplanar neighbours.
std::vector<FaceModel> random_face_models(int count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<FaceModel> models;
  for (int i = 0; i < count; ++i) {
    testing::RandomFaceSpec spec;
    spec.edits = 2 + static_cast<int>(rng() % 10);
    models.push_back(testing::random_face_model(rng, spec));
  }
  return models;
}

TEST(FacePattern, LinesMatchCgalArrangementOnRandomFaceModels) {
  int slanted = 0, folds = 0;
  const auto models = random_face_models(300, 7);
  for (std::size_t i = 0; i < models.size(); ++i) {
    const Pattern p = make_pattern(models[i]);
    const Pattern oracle = testing::arrangement_lines(models[i]);
    ASSERT_EQ(p.lines, oracle.lines) << "model " << i << ": lines differ from the arrangement's";
    ASSERT_EQ(p.folds, oracle.folds) << "model " << i << ": folds differ from the arrangement's";
    for (const Segment& l : p.lines) slanted += l.a.x_mm != l.b.x_mm && l.a.v_mm != l.b.v_mm;
    folds += static_cast<int>(p.folds.size());
  }
  EXPECT_GT(slanted, 100) << "the sample has slanted cuts";
  EXPECT_GT(folds, 300) << "the sample has folds";
}

// Eq. 5 from the edits alone: at any point, the face is the one drawn last over it (a hole
// drawn as its equivalent face, eq. 6, or on the board where it reaches past it).
struct DrawnPlane {
  Ring ring;
  FaceKind kind;
  double t;
  bool spills;  // a hole's face that continues on the board beyond v = limit
  double limit;
};

double distance_to_segment(Point2 p, Point2 a, Point2 b) {
  const double dx = b.x_mm - a.x_mm, dv = b.v_mm - a.v_mm;
  const double len2 = dx * dx + dv * dv;
  const double u = std::clamp(((p.x_mm - a.x_mm) * dx + (p.v_mm - a.v_mm) * dv) / len2, 0.0, 1.0);
  return std::hypot(p.x_mm - a.x_mm - u * dx, p.v_mm - a.v_mm - u * dv);
}

TEST(FaceModel, RandomEditsFollowEquation5) {
  std::mt19937_64 rng(11);
  int checked = 0, holes = 0;
  const auto models = random_face_models(300, 8);
  for (std::size_t i = 0; i < models.size(); ++i) {
    const FaceModel& m = models[i];
    std::vector<DrawnPlane> drawn;
    for (const FaceEdit& e : m.edits()) {
      const bool vertical = e.op == EditOp::add_vface || e.op == EditOp::add_vhole;
      const bool hole = e.op == EditOp::add_vhole || e.op == EditOp::add_hhole;
      DrawnPlane d{{}, vertical ? FaceKind::vertical : FaceKind::horizontal, e.t_mm, false, 0};
      double lowest = 1e9;
      for (const auto& [x, second] : e.outline) {
        d.ring.push_back({x, vertical ? second - e.t_mm : e.t_mm - second});
        lowest = std::min(lowest, second);
      }
      if (hole) {
        holes++;
        d.kind = vertical ? FaceKind::horizontal : FaceKind::vertical;
        d.t = lowest;
        d.spills = true;
        d.limit = vertical ? lowest : -lowest;
      }
      drawn.push_back(std::move(d));
    }
    const Pattern p = make_pattern(m);
    const Rect sheet = m.sheet();
    for (int k = 0; k < 100; ++k) {
      const Point2 q{std::uniform_real_distribution<double>(sheet.min.x_mm, sheet.max.x_mm)(rng),
                     std::uniform_real_distribution<double>(sheet.min.v_mm, sheet.max.v_mm)(rng)};
      bool near_edge = std::abs(q.v_mm) < 1e-6;
      FaceKind kind = q.v_mm > 0 ? FaceKind::vertical : FaceKind::horizontal;
      double t = 0;
      for (const DrawnPlane& d : drawn) {
        for (std::size_t a = 0, b = d.ring.size() - 1; a < d.ring.size(); b = a++) {
          near_edge = near_edge || distance_to_segment(q, d.ring[a], d.ring[b]) < 1e-6;
        }
        PatternFace f;
        f.outer = d.ring;
        if (!testing::face_contains(f, q)) continue;
        kind = d.kind;
        t = d.t;
        if (d.spills) {
          near_edge = near_edge || std::abs(q.v_mm - d.limit) < 1e-6;
          const bool past = d.kind == FaceKind::horizontal ? q.v_mm > d.limit : q.v_mm < d.limit;
          if (past) {
            kind = d.kind == FaceKind::horizontal ? FaceKind::vertical : FaceKind::horizontal;
            t = 0;
          }
        }
      }
      if (near_edge) continue;
      const int at = testing::face_at(p, q);
      ASSERT_GE(at, 0) << "model " << i << ": (" << q.x_mm << ", " << q.v_mm << ") is in "
                       << (at == -1 ? "no face" : "two faces");
      const PatternFace& f = p.faces[static_cast<std::size_t>(at)];
      ASSERT_EQ(f.kind, kind) << "model " << i << ": face kind at (" << q.x_mm << ", " << q.v_mm << ")";
      ASSERT_NEAR(f.t_mm, t, 1e-9) << "model " << i << ": face offset at (" << q.x_mm << ", " << q.v_mm << ")";
      ++checked;
    }
  }
  EXPECT_GT(checked, 20000) << "most sample points are away from edges";
  EXPECT_GT(holes, 50) << "the sample has holes";
}

TEST(FaceModel, RandomEditsUndoAndRedoExactly) {
  auto models = random_face_models(100, 9);
  for (std::size_t i = 0; i < models.size(); ++i) {
    FaceModel& m = models[i];
    const Pattern full = make_pattern(m);
    const std::vector<FaceEdit> history = m.edits();
    const std::size_t edits = history.size();
    // Step back one edit at a time, asking for the pattern each time (as an editor would): each
    // state must equal the same edits replayed on a blank card.
    for (std::size_t k = edits; k-- > 0;) {
      ASSERT_TRUE(m.undo()) << "model " << i;
      const Rect sheet = m.sheet();
      FaceModel replay(sheet.max.x_mm - sheet.min.x_mm, sheet.max.v_mm, -sheet.min.v_mm);
      for (std::size_t e = 0; e < k; ++e) replay.apply(history[e]);
      ASSERT_EQ(make_pattern(m), make_pattern(replay)) << "model " << i << ": state after undo to " << k << " edits";
    }
    ASSERT_FALSE(m.undo()) << "model " << i << ": nothing more to undo";
    ASSERT_EQ(m.face_count(), 2u) << "model " << i << ": undoing every edit leaves the blank card";
    for (std::size_t k = 0; k < edits; ++k) ASSERT_TRUE(m.redo()) << "model " << i;
    ASSERT_FALSE(m.redo()) << "model " << i << ": nothing more to redo";
    ASSERT_EQ(make_pattern(m), full) << "model " << i << ": redoing every edit restores the pattern";
  }
}

}  // namespace
}  // namespace popcut

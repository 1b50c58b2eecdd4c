// webOAcard .oa cards at random and at scale: the derived pattern tiles the sheet and every wall stands where drawn.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "error_of.h"
#include "pattern_oracle.h"
#include "popcut/error.h"
#include "popcut/io/oa_model.h"
#include "popcut/pattern/face_pattern.h"
#include "popcut/pattern/pattern.h"

namespace popcut {
namespace {

using testing::check_tiling;
using testing::error_of;

struct DrawnFace {
  int mode;    // 0 wall, 1 hole, 2 pull
  double t;    // depth, mm
  Ring outer;  // {X, Y}
};

std::string face_json(const DrawnFace& f) {
  std::ostringstream o;
  o.precision(17);
  o << R"({"contours": [{"outer": [)";
  for (std::size_t i = 0; i < f.outer.size(); ++i)
    o << (i ? ", " : "") << R"({"X": )" << f.outer[i].x_mm << R"(, "Y": )" << f.outer[i].v_mm << "}";
  o << R"(], "holes": [[]]}], "type": "VFACE", "mode": )" << f.mode << R"(, "t": )" << f.t << "}";
  return o.str();
}

std::string card_json(const std::vector<DrawnFace>& faces, double width = 120, double half = 100) {
  std::string out = R"({"settings": {"cardW": )" + std::to_string(width) + R"(, "cardH": )" + std::to_string(half) +
                    R"(}, "faces": [)";
  for (std::size_t i = 0; i < faces.size(); ++i) out += (i ? "," : "") + face_json(faces[i]);
  return out + "]}";
}

// Even-odd containment; the label of a face never lies on a drawn edge in practice (random decimals).
bool inside(const Ring& ring, double x, double y) {
  bool in = false;
  for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
    const Point2 a = ring[i], b = ring[j];
    if ((a.v_mm > y) != (b.v_mm > y) && x < (b.x_mm - a.x_mm) * (y - a.v_mm) / (b.v_mm - a.v_mm) + a.x_mm) in = !in;
  }
  return in;
}

// A random small card as the editor draws one: walls with slanted tops standing on the floor,
// holes at random depths, pulls rising from a wall's depth; coordinates in 0.001 mm.
std::vector<DrawnFace> random_card(std::mt19937& rng) {
  const auto mm = [&](double lo, double hi) {
    return std::round(std::uniform_real_distribution<double>(lo, hi)(rng) * 1000) / 1000;
  };
  std::vector<DrawnFace> faces;
  std::vector<double> depths;
  const int walls = std::uniform_int_distribution<int>(1, 6)(rng);
  for (int i = 0; i < walls; ++i) {
    const double t = mm(1, 60), x0 = mm(0, 90), x1 = x0 + mm(5, 40);
    // Y = t - z: the foot at z 0, the top slanted between heights 5 and 70.
    faces.push_back({0, t, {{x0, t}, {x1, t}, {x1, t - mm(5, 70)}, {x0, t - mm(5, 70)}}});
    depths.push_back(t);
  }
  const int holes = std::uniform_int_distribution<int>(0, 2)(rng);
  for (int i = 0; i < holes; ++i) {
    const double t = mm(1, 60), x = mm(0, 100), y = t - mm(0, 60);  // a corner above the floor
    faces.push_back(
        {1, t, {{x, y}, {x + mm(2, 20), y + mm(-3, 3)}, {x + mm(2, 20), y - mm(2, 15)}, {x, y - mm(2, 15)}}});
  }
  const int pulls = std::uniform_int_distribution<int>(0, 2)(rng);
  for (int i = 0; i < pulls; ++i) {
    const double t = depths[std::uniform_int_distribution<std::size_t>(0, depths.size() - 1)(rng)];
    const double x = mm(0, 100), y = t - mm(0, 40);
    faces.push_back({2, t, {{x, y}, {x + mm(2, 15), y}, {x + mm(2, 15), y - mm(3, 20)}, {x, y - mm(3, 20)}}});
  }
  return faces;
}

TEST(OaProperty, RandomCardsTileTheSheetAndEveryWallStandsWhereItIsDrawn) {
  std::mt19937 rng(20240611);
  for (int n = 0; n < 40; ++n) {
    const std::vector<DrawnFace> drawn = random_card(rng);
    const std::string text = card_json(drawn);
    SCOPED_TRACE("card " + std::to_string(n) + ": " + text);
    const FaceModel m = parse_oa_model(text, "random.oa");
    const Pattern p = make_pattern(m, "random.oa");
    // Samples off the 0.001 mm grid the cards are drawn on, so none lies on a drawn edge.
    const std::vector<std::string> problems = check_tiling(p, 0.2371);
    EXPECT_TRUE(problems.empty()) << "the faces tile the sheet: " << (problems.empty() ? "" : problems.front());
    for (const PatternFace& f : p.faces) {
      if (f.kind != FaceKind::vertical || f.t_mm == 0) continue;
      // The .oa's (X, Y) at depth t is (x, y, z) = (X, t, t - Y); the pattern's (x, v) of a VFace
      // at t is (x, t, v + t): the face's point must be drawn at X = x, Y = -v.
      const double x = f.label.x_mm, y = -f.label.v_mm;
      bool drawn_here = false, holed = false;
      for (const DrawnFace& d : drawn) {
        if (d.mode != 1 && std::abs(d.t - f.t_mm) < 1e-6 && inside(d.outer, x, y)) drawn_here = true;
        if (d.mode == 1 && d.t >= f.t_mm - 1e-6 && inside(d.outer, x, y)) holed = true;
      }
      EXPECT_TRUE(drawn_here) << "the wall at t " << f.t_mm << " with point (" << x << ", " << -y
                              << ") stands where a wall or pull of that depth is drawn";
      EXPECT_FALSE(holed) << "no hole at its depth or in front of it covers (" << x << ", " << -y << ")";
      const Point3 at = to_card(f.kind, f.t_mm, f.label);
      EXPECT_NEAR(at.y_mm, f.t_mm, 1e-9) << "a wall stands at its depth";
      EXPECT_NEAR(at.z_mm, f.t_mm - y, 1e-9) << "at height t - Y";
    }
  }
}

TEST(OaProperty, SlantedEdgesCrossingOffTheGridStillTileTheSheet) {
  // Tops at thirds of a mm and slopes whose crossings are quotients far off the 1 nm grid.
  const std::vector<DrawnFace> drawn = {
      {0, 20, {{10, 20}, {90, 20}, {90, -30.333}, {10, -10.111}}},
      {0, 35.5, {{5, 35.5}, {70, 35.5}, {70, 0.777}, {5, 14.321}}},
      {0, 47.3, {{30, 47.3}, {110, 47.3}, {110, 30.001}, {30, 11.113}}},
      {1, 40, {{40, -5.5}, {77, -1.25}, {77, 9.999}, {40, 3.333}}},
      {2, 20, {{50, -30}, {57.123, -45.777}, {63, -20}}},
  };
  const FaceModel m = parse_oa_model(card_json(drawn), "slanted.oa");
  const Pattern p = make_pattern(m, "slanted.oa");
  const std::vector<std::string> problems = check_tiling(p, 0.1);
  EXPECT_TRUE(problems.empty()) << "the faces tile the sheet: " << (problems.empty() ? "" : problems.front());
  for (const PatternFace& f : p.faces) {
    for (const Point2& q : f.outer) {
      EXPECT_NEAR(q.x_mm * 1e6, std::round(q.x_mm * 1e6), 1e-3) << "every output vertex is on the 1 nm grid";
      EXPECT_NEAR(q.v_mm * 1e6, std::round(q.v_mm * 1e6), 1e-3) << "every output vertex is on the 1 nm grid";
    }
  }
}

// 25 × 20 walls of 4 × 4 mm, each at its own depth with a slanted top: far more than the editor's
// cards (tens of faces), well under the limit.
TEST(OaLimits, FiveHundredWallsAreDerived) {
  std::vector<DrawnFace> drawn;
  for (int i = 0; i < 500; ++i) {
    const double x = 4.0 * (i % 25), t = 1 + 0.1 * i, z = 4.0 * (i / 25);
    drawn.push_back({0, t, {{x, t - z}, {x + 4, t - z}, {x + 4, t - z - 3.5}, {x, t - z - 3}}});
  }
  const FaceModel m = parse_oa_model(card_json(drawn), "many.oa");
  EXPECT_GT(m.face_count(), 500u) << "every wall and its top face is derived";
}

TEST(OaLimits, AFileJustOverTheLimitsIsRefusedAtOnce) {
  std::vector<DrawnFace> drawn(kMaxOaFaces + 1, DrawnFace{0, 10, {{10, 0}, {20, 0}, {20, -10}, {10, -10}}});
  const Error faces = error_of([&] { parse_oa_model(card_json(drawn), "big.oa"); });
  EXPECT_EQ(faces.code(), ErrorCode::limit) << "too many faces is over a limit";
  EXPECT_EQ(faces.source(), "big.oa") << "the file is named";
  EXPECT_EQ(faces.location() + ": " + faces.message(), "faces: has 2001 faces; the limit for a .oa card is 2000")
      << "the field and the limit are named";
  // 11 faces of 10000 points: the 11th ring brings the card past 100000.
  DrawnFace ring{0, 10, {}};
  for (int i = 0; i < 10000; ++i) {
    const double a = 2 * M_PI * i / 10000;
    ring.outer.push_back({60 + 20 * std::cos(a), -20 + 20 * std::sin(a)});
  }
  const Error points = error_of([&] { parse_oa_model(card_json(std::vector<DrawnFace>(11, ring)), "big.oa"); });
  EXPECT_EQ(points.code(), ErrorCode::limit) << "too many points is over a limit";
  EXPECT_EQ(points.location() + ": " + points.message(),
            "faces[10].contours[0].outer: brings the card's points to 110000; the limit for a .oa card is 100000")
      << "the ring that passes the limit and the limit are named";
}

}  // namespace
}  // namespace popcut

// Cross-check with Debian's hp2xx (when installed): it reads every job and draws the lines we planned.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>

#include "popcut/drivers/profile.h"
#include "popcut/hpgl/hpgl.h"
#include "popcut/io/model_io.h"
#include "popcut/pattern/voxel_pattern.h"
#include "random_models.h"
#include "shipped_profiles.h"

namespace popcut::drivers {
namespace {

namespace fs = std::filesystem;

bool have_hp2xx() { return std::system("command -v hp2xx >/dev/null 2>&1") == 0; }

struct Seg {
  double x0, y0, x1, y1;
};

// Knife-down segments of hp2xx's normalised output ("PUx,y;PDx,y;..." with absolute floats).
std::vector<Seg> read_hp2xx(const std::string& text) {
  std::vector<Seg> segs;
  double x = 0, y = 0;
  std::size_t i = 0;
  while (i + 1 < text.size()) {
    const std::string cmd = text.substr(i, 2);
    const std::size_t end = text.find(';', i);
    const std::string args = text.substr(i + 2, (end == std::string::npos ? text.size() : end) - i - 2);
    if ((cmd == "PU" || cmd == "PD") && !args.empty()) {
      double nx = 0, ny = 0;
      if (std::sscanf(args.c_str(), "%lf,%lf", &nx, &ny) == 2) {
        if (cmd == "PD") segs.push_back({x, y, nx, ny});
        x = nx, y = ny;
      }
    }
    if (end == std::string::npos) break;
    i = end + 1;
  }
  return segs;
}

TEST(Hp2xx, ReadsEveryProfilesJobAndDrawsThePlannedLines) {
  if (!have_hp2xx()) GTEST_SKIP() << "hp2xx is not installed";
  const fs::path dir = fs::temp_directory_path() / ("popcut-hp2xx-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::mt19937_64 rng(17);
  testing::RandomModelSpec spec;
  spec.window_probability = 0.2;
  std::vector<Pattern> patterns = {
      make_pattern(load_model(std::string(POPCUT_SOURCE_DIR) + "/examples/voxel/townhouse.json"))};
  for (int i = 0; i < 3; ++i) patterns.push_back(make_pattern(testing::random_model(rng, spec)));
  for (const std::string& file : testing::shipped_profiles()) {
    const DeviceProfile prof = load_profile(file);
    for (std::size_t n = 0; n < patterns.size(); ++n) {
      const std::string what = fs::path(file).filename().string() + " model " + std::to_string(n);
      const StrokePlan plan = plan_strokes(patterns[n], prof.plan);
      const fs::path in = dir / "job.hpgl", out = dir / "out.hpgl", err = dir / "err.txt";
      std::ofstream(in) << encode_hpgl(plan, prof.dialect, prof.tools);
      const std::string cmd = "hp2xx -q -m hpgl -f " + out.string() + " " + in.string() + " 2>" + err.string();
      ASSERT_EQ(std::system(cmd.c_str()), 0) << what << ": hp2xx failed";
      std::stringstream ss;
      ss << std::ifstream(out).rdbuf();
      const std::vector<Seg> theirs = read_hp2xx(ss.str());
      // Ours: every knife-down segment in plotter units.
      std::vector<Seg> ours;
      for (const auto& path : plan_in_plotter_units(plan, prof.dialect)) {
        for (std::size_t k = 1; k < path.size(); ++k) {
          ours.push_back({double(path[k - 1][0]), double(path[k - 1][1]), double(path[k][0]), double(path[k][1])});
        }
      }
      // hp2xx scales the drawing to its page: undo that with the bounding boxes, per axis.
      const auto box = [](const std::vector<Seg>& v) {
        std::array<double, 4> b{1e300, 1e300, -1e300, -1e300};
        for (const Seg& s : v) {
          b = {std::min({b[0], s.x0, s.x1}), std::min({b[1], s.y0, s.y1}), std::max({b[2], s.x0, s.x1}),
               std::max({b[3], s.y0, s.y1})};
        }
        return b;
      };
      const auto bo = box(ours), bt = box(theirs);
      const double sx = (bo[2] - bo[0]) / std::max(1e-9, bt[2] - bt[0]),
                   sy = (bo[3] - bo[1]) / std::max(1e-9, bt[3] - bt[1]);
      std::map<std::array<long, 4>, int> count;
      const auto norm = [](double a, double b, double c, double d) {
        std::array<long, 4> k{std::lround(a), std::lround(b), std::lround(c), std::lround(d)};
        if (std::make_pair(k[2], k[3]) < std::make_pair(k[0], k[1])) k = {k[2], k[3], k[0], k[1]};
        return k;
      };
      for (const Seg& s : ours) ++count[norm(s.x0, s.y0, s.x1, s.y1)];
      int unmatched = 0;
      std::size_t drawn = 0;
      for (const Seg& s : theirs) {
        const double x0 = bo[0] + (s.x0 - bt[0]) * sx, y0 = bo[1] + (s.y0 - bt[1]) * sy;
        const double x1 = bo[0] + (s.x1 - bt[0]) * sx, y1 = bo[1] + (s.y1 - bt[1]) * sy;
        if (std::hypot(x1 - x0, y1 - y0) < 0.5) continue;  // hp2xx marks each pen-down with a dot
        ++drawn;
        if (--count[norm(x0, y0, x1, y1)] < 0) ++unmatched;
      }
      EXPECT_EQ(drawn, ours.size()) << what << ": hp2xx draws as many segments as we cut";
      EXPECT_EQ(unmatched, 0) << what << ": hp2xx's segments, scaled back, are ours (within rounding)";
    }
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace popcut::drivers

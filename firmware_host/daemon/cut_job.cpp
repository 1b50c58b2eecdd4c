// Stroke-boundary encoding: sendable plans, resume from stroke N, byte offsets of stroke ends.
#include "cut_job.h"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "popcut/drivers/hpgl_reader.h"
#include "popcut/error.h"

namespace popcut::daemon {

StrokePlan sendable_plan(const StrokePlan& plan, const drivers::DeviceProfile& profile) {
  StrokePlan out = plan;
  out.sheet = plan.extent();
  out.strokes.clear();
  // A stroke that rounds to one plotter point is never sent; a one-stroke plan with the same
  // frame rounds exactly as the whole does.
  StrokePlan one = out;
  for (const Stroke& s : plan.strokes) {
    one.strokes = {s};
    if (!plan_in_plotter_units(one, profile.dialect).empty()) out.strokes.push_back(s);
  }
  return out;
}

EncodedCut encode_from(const StrokePlan& sendable, const drivers::DeviceProfile& profile, std::size_t first_stroke) {
  StrokePlan tail = sendable;
  tail.strokes.assign(sendable.strokes.begin() + static_cast<std::ptrdiff_t>(std::min(first_stroke, sendable.strokes.size())),
                      sendable.strokes.end());
  EncodedCut c;
  c.bytes = encode_hpgl(tail, profile.dialect, profile.tools);
  c.paths = plan_in_plotter_units(tail, profile.dialect);
  // A stroke ends where the next pen-up (or anything but more pen-down coordinates) begins.
  bool down = false;
  for (const drivers::HpglCommand& cmd : drivers::parse_hpgl(c.bytes)) {
    if (cmd.name == "PD") {
      down = true;
    } else if (down && cmd.name != "PA" && cmd.name != "PR") {
      c.stroke_ends.push_back(cmd.offset);
      down = false;
    }
  }
  if (down) c.stroke_ends.push_back(c.bytes.size());
  if (c.stroke_ends.size() != tail.strokes.size() || c.paths.size() != tail.strokes.size()) {
    throw Error(ErrorCode::internal, profile.source, "encode",
                "the encoded job holds " + std::to_string(c.stroke_ends.size()) + " pen-down paths for " +
                    std::to_string(tail.strokes.size()) + " strokes");
  }
  return c;
}

std::size_t strokes_sent(const EncodedCut& cut, std::size_t bytes_sent) {
  return static_cast<std::size_t>(std::upper_bound(cut.stroke_ends.begin(), cut.stroke_ends.end(), bytes_sent) - cut.stroke_ends.begin());
}

std::string plan_to_json(const StrokePlan& plan) {
  using nlohmann::json;
  json strokes = json::array();
  for (const Stroke& s : plan.strokes) {
    json pts = json::array();
    for (Point2 p : s.points) pts.push_back({p.x_mm, p.v_mm});
    strokes.push_back({{"kind", to_string(s.kind)}, {"points", pts}});
  }
  return json{{"format", "popcut.strokes.v1"},
              {"sheet", {plan.sheet.min.x_mm, plan.sheet.min.v_mm, plan.sheet.max.x_mm, plan.sheet.max.v_mm}},
              {"home", {plan.home.x_mm, plan.home.v_mm}},
              {"strokes", strokes}}
      .dump();
}

StrokePlan plan_from_json(const std::string& text, const std::string& source) {
  try {
    const nlohmann::json j = nlohmann::json::parse(text);
    if (j.at("format") != "popcut.strokes.v1") throw Error(ErrorCode::invalid_input, source, "format", "expected popcut.strokes.v1");
    StrokePlan p;
    const auto& sh = j.at("sheet");
    p.sheet = {{sh.at(0).get<double>(), sh.at(1).get<double>()}, {sh.at(2).get<double>(), sh.at(3).get<double>()}};
    p.home = {j.at("home").at(0).get<double>(), j.at("home").at(1).get<double>()};
    for (const auto& s : j.at("strokes")) {
      Stroke st;
      const std::string kind = s.at("kind").get<std::string>();
      std::size_t k = 0;
      while (k < kAllPlanKinds.size() && kind != to_string(kAllPlanKinds[k])) ++k;
      if (k == kAllPlanKinds.size()) throw Error(ErrorCode::invalid_input, source, "strokes.kind", "unknown kind " + kind);
      st.kind = kAllPlanKinds[k];
      for (const auto& pt : s.at("points")) st.points.push_back({pt.at(0).get<double>(), pt.at(1).get<double>()});
      p.strokes.push_back(std::move(st));
    }
    return p;
  } catch (const nlohmann::json::exception& e) {
    throw Error(ErrorCode::invalid_input, source, "", e.what());
  }
}

}  // namespace popcut::daemon

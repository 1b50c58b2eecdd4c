// Stroke plans as JSON job files: what a device worker re-reads to cut or resume a job.
#include "cut_job.h"

#include <filesystem>
#include <nlohmann/json.hpp>

#include "popcut/error.h"
#include "popcut/io/files.h"

namespace popcut::daemon {

std::string plan_to_json(const StrokePlan& plan) {
  using nlohmann::json;
  json strokes = json::array();
  for (const Stroke& s : plan.strokes) {
    json pts = json::array();
    for (Point2 p : s.points) pts.push_back({p.x_mm, p.v_mm});
    json stroke = {{"kind", to_string(s.kind)}, {"points", pts}};
    if (s.pass != 0) stroke["pass"] = s.pass;  // per-pass settings pick the force by it
    strokes.push_back(std::move(stroke));
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
    if (j.at("format") != "popcut.strokes.v1")
      throw Error(ErrorCode::invalid_input, source, "format", "expected popcut.strokes.v1");
    StrokePlan p;
    const auto& sh = j.at("sheet");
    p.sheet = {{sh.at(0).get<double>(), sh.at(1).get<double>()}, {sh.at(2).get<double>(), sh.at(3).get<double>()}};
    p.home = {j.at("home").at(0).get<double>(), j.at("home").at(1).get<double>()};
    for (const auto& s : j.at("strokes")) {
      Stroke st;
      const std::string kind = s.at("kind").get<std::string>();
      std::size_t k = 0;
      while (k < kAllPlanKinds.size() && kind != to_string(kAllPlanKinds[k])) ++k;
      if (k == kAllPlanKinds.size())
        throw Error(ErrorCode::invalid_input, source, "strokes.kind", "unknown kind " + kind);
      st.kind = kAllPlanKinds[k];
      st.pass = s.value("pass", 0);
      for (const auto& pt : s.at("points")) st.points.push_back({pt.at(0).get<double>(), pt.at(1).get<double>()});
      p.strokes.push_back(std::move(st));
    }
    return p;
  } catch (const nlohmann::json::exception& e) {
    throw Error(ErrorCode::invalid_input, source, "", e.what());
  }
}

SheetRun sheet_run(const std::string& dir, const Job& job, std::int64_t done_before) {
  SheetRun run;
  run.sheet = job.sheet_of(done_before + 1);
  run.offset = run.sheet * job.sheet_strokes;
  const std::filesystem::path last = std::filesystem::path(dir) / "plan-last.json";
  std::error_code ec;
  const bool on_last = job.sheets() > 1 && run.sheet + 1 == job.sheets() && std::filesystem::exists(last, ec);
  const std::string path = (on_last ? last : std::filesystem::path(dir) / "plan.json").string();
  run.plan = plan_from_json(read_text_file(path, std::size_t{1} << 30), path);
  return run;
}

}  // namespace popcut::daemon

// Checks of popcutd's answers against the shapes docs/api.md gives, before popcut reads a field.
#include "cli/client_answers.h"

#include <array>
#include <string_view>

namespace popcut::cli {
namespace {

using nlohmann::json;

enum class Kind { text, text_or_null, count, count_or_null, positive };

bool fits(const json& v, Kind k) {
  switch (k) {
    case Kind::text: return v.is_string();
    case Kind::text_or_null: return v.is_string() || v.is_null();
    case Kind::count: return v.is_number_integer() && v.get<long long>() >= 0;
    case Kind::count_or_null: return v.is_null() || (v.is_number_integer() && v.get<long long>() >= 0);
    case Kind::positive: return v.is_number_integer() && v.get<long long>() >= 1;
  }
  return false;
}

const char* expected(Kind k) {
  switch (k) {
    case Kind::text: return "text";
    case Kind::text_or_null: return "text or null";
    case Kind::count: return "a whole number from 0";
    case Kind::count_or_null: return "a whole number from 0, or null";
    case Kind::positive: return "a whole number from 1";
  }
  return "";
}

// "\"key\" is VALUE, expected WHAT", or "no \"key\"".
std::string wrong(const std::string& key, const json* v, const std::string& what) {
  if (!v) return "no \"" + key + "\", expected " + what;
  return "\"" + key + "\" is " + excerpt(*v, 40) + ", expected " + what;
}

// Every field of a job that popcut reads or prints; popcutd always sends these.
struct Field {
  const char* key;
  Kind kind;
  bool always;  // false: sent in some states only (and then of this kind)
};
constexpr std::array<Field, 12> kJobFields{{{"id", Kind::positive, true},
                                            {"name", Kind::text, true},
                                            {"profile", Kind::text, true},
                                            {"device", Kind::text_or_null, true},
                                            {"cut_on", Kind::text_or_null, true},
                                            {"strokes_total", Kind::count, true},
                                            {"strokes_sent", Kind::count, true},
                                            {"resume_from", Kind::count, true},
                                            {"resume_point", Kind::text_or_null, true},
                                            {"strokes_executed", Kind::count_or_null, true},
                                            {"place_in_line", Kind::count_or_null, true},
                                            {"cancel", Kind::text_or_null, false}}};

constexpr std::array<std::string_view, 8> kStates{"queued", "planning", "ready",     "cutting",
                                                  "done",   "failed",   "cancelled", "interrupted"};

}  // namespace

std::string excerpt(const json& answer, std::size_t max_chars) {
  std::string text = answer.dump(-1, ' ', true, json::error_handler_t::replace);
  if (text.size() > max_chars) text = text.substr(0, max_chars) + "...";
  return text;
}

std::string job_shape_problem(const json& j) {
  if (!j.is_object()) return "a job is a JSON object, not " + excerpt(j, 40);
  for (const Field& f : kJobFields) {
    const auto it = j.find(f.key);
    if (it == j.end() ? f.always : !fits(*it, f.kind))
      return wrong(f.key, it == j.end() ? nullptr : &*it, expected(f.kind));
  }
  const auto state = j.find("state");
  bool known = false;
  for (const std::string_view s : kStates)
    known = known || (state != j.end() && state->is_string() && state->get<std::string>() == s);
  if (!known)
    return wrong("state", state == j.end() ? nullptr : &*state,
                 "one of queued, planning, ready, cutting, done, failed, cancelled, interrupted");
  if (const auto e = j.find("error"); e != j.end()) {
    if (!e->is_object() || !e->contains("code") || !(*e)["code"].is_string() || !e->contains("message") ||
        !(*e)["message"].is_string()) {
      return wrong("error", &*e, "{\"code\": text, \"message\": text}");
    }
  }
  return "";
}

std::string job_list_shape_problem(const json& j) {
  if (!j.is_object()) return "a job list is a JSON object, not " + excerpt(j, 40);
  if (!j.contains("jobs")) return wrong("jobs", nullptr, "an array of jobs");
  const json& jobs = j["jobs"];
  if (!jobs.is_array()) return wrong("jobs", &jobs, "an array of jobs");
  std::size_t i = 0;
  for (const json& job : jobs) {
    if (std::string p = job_shape_problem(job); !p.empty()) return "jobs[" + std::to_string(i) + "]: " + p;
    ++i;
  }
  return "";
}

std::string error_shape_problem(const json& j) {
  if (!j.is_object()) return "an error answer is a JSON object, not " + excerpt(j, 40);
  const auto e = j.find("error");
  if (e == j.end() || !e->is_object())
    return wrong("error", e == j.end() ? nullptr : &*e, "{\"code\": text, \"message\": text}");
  for (const char* key : {"code", "message"}) {
    const auto v = e->find(key);
    if (v == e->end() || !v->is_string())
      return wrong(std::string("error.") + key, v == e->end() ? nullptr : &*v, "text");
  }
  if (const auto f = e->find("field"); f != e->end() && !f->is_string()) return wrong("error.field", &*f, "text");
  return "";
}

}  // namespace popcut::cli

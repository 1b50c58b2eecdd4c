// The shapes of popcutd's answers as popcut reads them: an answer of any other shape is not popcutd's.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace popcut::cli {

// Each returns "" when `answer` has the shape popcutd sends (docs/api.md), else what is wrong
// with it, naming the field ("\"jobs\" is \"nope\", expected an array of jobs"). Fields popcut
// does not read may be added by a later popcutd and are not looked at.
std::string job_shape_problem(const nlohmann::json& answer);       // one job
std::string job_list_shape_problem(const nlohmann::json& answer);  // {"jobs": [job, ...]}
std::string error_shape_problem(const nlohmann::json& answer);     // {"error": {"code", "message", "field"?}}

// At most `max_chars` of `answer` as compact ASCII JSON (control characters escaped), for a
// message that shows what a server answered.
std::string excerpt(const nlohmann::json& answer, std::size_t max_chars = 120);

}  // namespace popcut::cli

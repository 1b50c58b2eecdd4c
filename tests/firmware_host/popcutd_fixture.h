// The fixture popcutd's end-to-end tests share: a data directory, a daemon started on a config, the job calls, and the
// CLI.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdint>
#include <cstdlib>
#include <memory>
#include <string>

#include "popcutd_process.h"

namespace popcut::testing::e2e {

using nlohmann::json;

inline const std::string kSrc = POPCUT_SOURCE_DIR;
inline const std::string kKiosk = "kiosk-change-me-0123456789";  // configs/popcutd.toml's tokens
inline const std::string kAdmin = "admin-change-me-0123456789";

inline std::string example(const std::string& rel) { return read_file(kSrc + "/examples/" + rel); }

inline std::string submission(const std::string& model, const std::string& target_key, const std::string& target,
                              const std::string& name) {
  return json{{"model", json::parse(model)}, {target_key, target}, {"name", name}}.dump();
}

class Popcutd : public ::testing::Test {
 protected:
  TempDir dir_{"popcutd-test"};
  std::string data_ = (dir_.path() / "data").string();
  std::unique_ptr<PopcutdProcess> start(const std::string& config) {
    return std::make_unique<PopcutdProcess>(POPCUTD, config, data_);
  }
  static json job(httplib::Client& c, std::int64_t id) {
    return get_json(c, "/api/v1/jobs/" + std::to_string(id)).body;
  }
  static bool final_state(const json& j) {
    const std::string s = j.value("state", "");
    return s == "done" || s == "failed" || s == "cancelled" || s == "interrupted";
  }
  static std::int64_t submit(httplib::Client& c, const std::string& body) {
    const Reply r = post_json(c, "/api/v1/jobs", body);
    EXPECT_EQ(r.status, 201) << "submission accepted: " << r.body.dump();
    return r.body.value("id", std::int64_t{0});
  }
};

struct CliRun {
  int code;
  std::string out, err;
};

class PopcutClient : public Popcutd {
 protected:
  CliRun cli(const std::string& args) {
    const std::string out = (dir_.path() / "cli.out").string(), err = (dir_.path() / "cli.err").string();
    const int status = std::system((std::string(POPCUT_CLI) + " " + args + " >" + out + " 2>" + err).c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_file(out), read_file(err)};
  }
};

}  // namespace popcut::testing::e2e

// Config lookup: search order, the error when nothing is found, and an installed popcut finding its profiles.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "config_dir.h"
#include "popcut/error.h"

namespace popcut::cli {
namespace {

namespace fs = std::filesystem;

class ConfigDir : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("popcut-config-" + std::to_string(::getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  static std::string slurp(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
  // Runs `cmd` through the shell; stdout and stderr go to files in dir_.
  int sh(const std::string& cmd) {
    const int status = std::system((cmd + " >" + (dir_ / "out").string() + " 2>" + (dir_ / "err").string()).c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  fs::path dir_;
};

TEST_F(ConfigDir, SearchOrder) {
  const auto dirs = config_dirs(nullptr, "/opt/pc/bin/popcut");
  ASSERT_EQ(dirs.size(), 2u) << "installed tree, then source tree";
  EXPECT_EQ(dirs[0], fs::path("/opt/pc/share/popcut/configs")) << "next to the binary's bin/";
  EXPECT_EQ(dirs[1], fs::path(POPCUT_SOURCE_DIR) / "configs") << "the source tree last, for build trees";
  EXPECT_EQ(config_dirs("/etc/pc", "/opt/pc/bin/popcut"), std::vector<fs::path>{"/etc/pc"})
      << "$POPCUT_CONFIG_DIR alone when set";
  EXPECT_EQ(config_dirs("", "/opt/pc/bin/popcut").size(), 2u) << "an empty variable counts as unset";
}

TEST_F(ConfigDir, FirstDirectoryHoldingTheFileWinsAndMissingNamesEveryPlace) {
  fs::create_directories(dir_ / "a" / "devices");
  fs::create_directories(dir_ / "b" / "devices");
  std::ofstream(dir_ / "b" / "devices" / "sim.toml") << "x";
  EXPECT_EQ(find_config_file("devices/sim.toml", {dir_ / "a", dir_ / "b"}),
            (dir_ / "b" / "devices" / "sim.toml").string())
      << "a lacks the file, b has it";
  try {
    find_config_file("devices/x.toml", {dir_ / "a", dir_ / "b"});
    ADD_FAILURE() << "a missing file must be an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::invalid_input) << "exit 2 in the CLI";
    EXPECT_NE(e.message().find((dir_ / "a" / "devices/x.toml").string()), std::string::npos) << e.message();
    EXPECT_NE(e.message().find((dir_ / "b" / "devices/x.toml").string()), std::string::npos) << e.message();
    EXPECT_NE(e.message().find("POPCUT_CONFIG_DIR"), std::string::npos) << "says how to fix it: " << e.message();
  }
}

// `cmake --install` into a temporary prefix: the installed binary finds the installed sim profile
// (renamed here so the source tree's copy cannot pass for it), and $POPCUT_CONFIG_DIR overrides.
TEST_F(ConfigDir, InstalledPopcutFindsItsProfiles) {
  const fs::path prefix = dir_ / "prefix";
  ASSERT_EQ(
      sh(std::string("'") + POPCUT_CMAKE + "' --install '" + POPCUT_BUILD_DIR + "' --prefix '" + prefix.string() + "'"),
      0)
      << slurp(dir_ / "err");
  const fs::path installed = prefix / "share/popcut/configs/devices/sim.toml";
  ASSERT_TRUE(fs::exists(prefix / "bin/popcut")) << "the binary is installed";
  ASSERT_TRUE(fs::exists(installed)) << "the device profiles are installed";
  std::string text = slurp(installed);
  const std::size_t name = text.find("name = \"");
  ASSERT_NE(name, std::string::npos);
  text.insert(name + 8, "installed ");
  std::ofstream(installed) << text;
  const fs::path model = dir_ / "box.json";
  std::ofstream(model) << R"({"format": "popcut.voxel.v1", "voxel_mm": 2, "heights": [[3, 3], [3, 3]]})";
  const std::string cut = (prefix / "bin/popcut").string() + " cut " + model.string() + " --device sim --json --out " +
                          (dir_ / "job").string();
  ASSERT_EQ(sh("env -u POPCUT_CONFIG_DIR " + cut), 0) << slurp(dir_ / "err");
  const auto report = nlohmann::json::parse(slurp(dir_ / "out"));
  EXPECT_EQ(report.at("profile"), installed.string()) << "the installed profile, not the source tree's";
  EXPECT_EQ(report.at("device").get<std::string>().rfind("installed ", 0), 0u) << report.at("device");

  fs::create_directories(dir_ / "empty");
  EXPECT_EQ(sh("POPCUT_CONFIG_DIR='" + (dir_ / "empty").string() + "' " + cut), 2)
      << "an explicit directory without it: bad input";
  EXPECT_NE(slurp(dir_ / "err").find((dir_ / "empty" / "devices/sim.toml").string()), std::string::npos)
      << "names where it looked: " << slurp(dir_ / "err");
}

}  // namespace
}  // namespace popcut::cli

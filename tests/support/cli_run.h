// Runs the popcut binary as a user would, in a scratch folder of the test's own: exit code, stdout and stderr.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace popcut::testing {

struct CliRun {
  int code = -1;  // the exit status; -1 when it did not exit (killed by a signal)
  std::string out, err;
};

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A fixture with a fresh folder named after the running test (prefix-PID-TEST), removed after it.
class CliFixture : public ::testing::Test {
 protected:
  explicit CliFixture(std::string prefix) : prefix_(std::move(prefix)) {}
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / (prefix_ + "-" + std::to_string(::getpid()) + "-" +
                                                     ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  // `popcut ARGS` through the shell, with no standard input.
  CliRun run(const std::string& args) const {
    const std::string cmd = std::string(POPCUT_CLI) + " " + args + " </dev/null >" + (dir_ / "cli.stdout").string() +
                            " 2>" + (dir_ / "cli.stderr").string();
    const int status = std::system(cmd.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(dir_ / "cli.stdout"), slurp(dir_ / "cli.stderr")};
  }
  std::filesystem::path dir_;

 private:
  std::string prefix_;
};

}  // namespace popcut::testing

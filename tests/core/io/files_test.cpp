// Bounded reads and atomic writes: limits, missing files, directories, and no half-written output.
#include "popcut/io/files.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "popcut/error.h"

namespace popcut {
namespace {
namespace fs = std::filesystem;

class Files : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("popcut-files-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(Files, WriteThenRead) {
  const std::string path = (dir_ / "a.txt").string();
  write_text_file(path, "hello");
  EXPECT_EQ(read_text_file(path), "hello") << "content survives";
  write_text_file(path, "bye");
  EXPECT_EQ(read_text_file(path), "bye") << "overwrite replaces the whole file";
  int leftovers = 0;
  for (const auto& e : fs::directory_iterator(dir_)) leftovers += e.path().filename().string().front() == '.';
  EXPECT_EQ(leftovers, 0) << "no temporary files are left behind";
}

TEST_F(Files, ErrorsNameTheFile) {
  try {
    read_text_file((dir_ / "missing.json").string());
    FAIL() << "a missing file is an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::io) << e.what();
    EXPECT_NE(e.source().find("missing.json"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_text_file(dir_.string()), Error) << "a directory is not a model file";
  EXPECT_THROW(write_text_file((dir_ / "no" / "such" / "dir.json").string(), "x"), Error) << "missing directory";
}

TEST_F(Files, SizeLimit) {
  const std::string path = (dir_ / "big.txt").string();
  std::ofstream(path) << std::string(2048, 'x');
  try {
    read_text_file(path, 1024);
    FAIL() << "a file over the limit is refused before it is read";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::limit) << e.what();
  }
}

}  // namespace
}  // namespace popcut

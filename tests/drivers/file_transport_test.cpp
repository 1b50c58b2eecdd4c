// File transport: bytes arrive intact, counts are honest, errors are classified.
#include "popcut/drivers/file_transport.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>
#include <vector>

namespace popcut::drivers {
namespace {
namespace fs = std::filesystem;
using namespace std::chrono_literals;

TEST(FileTransport, WritesEveryByte) {
  const fs::path path = fs::temp_directory_path() / ("popcut-ft-" + std::to_string(::getpid()) + ".hpgl");
  std::vector<std::uint8_t> data(100000);
  for (std::size_t i = 0; i < data.size(); ++i) data[i] = static_cast<std::uint8_t>(i * 7);
  {
    FileTransport t(path.string());
    ASSERT_TRUE(t.open().ok()) << "open " << path;
    const IoResult r = t.write(data, 1000ms);
    EXPECT_TRUE(r.status.ok()) << r.status.message;
    EXPECT_EQ(r.bytes, data.size()) << "the byte count covers the whole buffer";
    EXPECT_TRUE(t.drain(1000ms).ok()) << "drain flushes to disk";
    std::uint8_t buf[4];
    EXPECT_EQ(t.read(buf, 10ms).status.error, TransportError::unsupported) << "a file cannot answer queries";
    EXPECT_EQ(t.describe(), "file:" + path.string()) << "describe names the path";
  }
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string got = ss.str();
  EXPECT_EQ(got.size(), data.size()) << "file has every byte";
  EXPECT_TRUE(std::equal(got.begin(), got.end(), data.begin(), [](char a, std::uint8_t b) {
    return static_cast<std::uint8_t>(a) == b;
  })) << "and in order";
  fs::remove(path);
}

TEST(FileTransport, ErrorsAreClassified) {
  FileTransport missing("/nonexistent-dir-popcut/job.hpgl");
  const TransportStatus s = missing.open();
  EXPECT_EQ(s.error, TransportError::not_found) << s.message;
  EXPECT_NE(s.os_error, 0) << "the OS error is kept";
  FileTransport unopened("/tmp/x");
  const std::uint8_t byte = 0;
  EXPECT_EQ(unopened.write({&byte, 1}, 10ms).status.error, TransportError::bad_argument) << "write before open";
  FileTransport dir("/tmp");
  EXPECT_EQ(dir.open().error, TransportError::bad_argument) << "a directory is not a writable file";
  FileTransport empty("");
  EXPECT_EQ(empty.open().error, TransportError::bad_argument) << "an empty path is refused";
}

}  // namespace
}  // namespace popcut::drivers

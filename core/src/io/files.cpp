// Bounded whole-file reads and atomic writes (temporary file + rename).
#include "popcut/io/files.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <streambuf>
#include <system_error>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "popcut/error.h"

namespace popcut {
namespace fs = std::filesystem;

namespace {
std::string too_large(std::size_t max_bytes) {
  return "file is larger than the limit of " + std::to_string(max_bytes >> 20) + " MiB";
}
}  // namespace

std::string read_text_file(const std::string& path, std::size_t max_bytes) {
  if (path == "-") {
    std::string text;
    char buf[65536];
    while (std::cin.read(buf, sizeof buf) || std::cin.gcount() > 0) {
      text.append(buf, static_cast<std::size_t>(std::cin.gcount()));
      if (text.size() > max_bytes) throw Error(ErrorCode::limit, "<stdin>", "", too_large(max_bytes));
    }
    return text;
  }
  std::error_code ec;
  const auto status = fs::status(path, ec);
  if (ec || !fs::exists(status)) throw Error(ErrorCode::io, path, "", "cannot read: no such file");
  if (!fs::is_regular_file(status)) throw Error(ErrorCode::io, path, "", "cannot read: not a regular file");
  const auto size = fs::file_size(path, ec);
  if (!ec && size > max_bytes) throw Error(ErrorCode::limit, path, "", too_large(max_bytes));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(ErrorCode::io, path, "", std::string("cannot open: ") + std::strerror(errno));
  std::string text;
  text.reserve(static_cast<std::size_t>(ec ? 0 : size));
  char buf[65536];
  while (in.read(buf, sizeof buf) || in.gcount() > 0) {
    text.append(buf, static_cast<std::size_t>(in.gcount()));
    if (text.size() > max_bytes) throw Error(ErrorCode::limit, path, "", too_large(max_bytes));
  }
  if (in.bad()) throw Error(ErrorCode::io, path, "", "read failed");
  return text;
}

namespace {

// Buffered output to a file descriptor that remembers the first write error.
class FdBuf : public std::streambuf {
 public:
  explicit FdBuf(int fd) : fd_(fd) { setp(buf_, buf_ + sizeof buf_); }
  int error() const { return error_; }

 protected:
  int_type overflow(int_type ch) override {
    if (!flush_buffer()) return traits_type::eof();
    if (!traits_type::eq_int_type(ch, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(ch);
      pbump(1);
    }
    return traits_type::not_eof(ch);
  }
  int sync() override { return flush_buffer() ? 0 : -1; }

 private:
  bool flush_buffer() {
    const char* p = pbase();
    while (p < pptr()) {
      const ssize_t n = ::write(fd_, p, static_cast<std::size_t>(pptr() - p));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        if (!error_) error_ = n < 0 ? errno : EIO;
        return false;
      }
      p += n;
    }
    setp(buf_, buf_ + sizeof buf_);
    return true;
  }
  int fd_;
  int error_ = 0;
  char buf_[1 << 16];
};

// The file a write to `path` should replace: a symbolic link is followed (as `>` in a shell would),
// so renaming the temporary file over it updates the link's target instead of replacing the link.
fs::path final_target(const std::string& path) {
  fs::path p(path);
  for (int hops = 0; hops < 40; ++hops) {
    std::error_code ec;
    if (!fs::is_symlink(fs::symlink_status(p, ec)) || ec) return p;
    const fs::path next = fs::read_symlink(p, ec);
    if (ec) return p;
    p = next.is_absolute() ? next : p.parent_path() / next;
  }
  throw Error(ErrorCode::io, path, "", "cannot write: too many levels of symbolic links");
}

// Runs `write` into fd; the errno of the first failed write (0: all written). If `write` throws,
// `cleanup` runs (close, and remove a temporary file) before the exception goes on.
int write_to_fd(int fd, const std::function<void(std::ostream&)>& write, const std::function<void()>& cleanup) {
  FdBuf buf(fd);
  std::ostream out(&buf);
  try {
    write(out);
  } catch (...) {
    cleanup();
    throw;
  }
  out.flush();
  return buf.error() ? buf.error() : (!out ? EIO : 0);
}

void write_in_place(const std::string& path, const fs::path& target, const std::function<void(std::ostream&)>& write) {
  const int fd = ::open(target.c_str(), O_WRONLY | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) throw Error(ErrorCode::io, path, "", std::string("cannot write: ") + std::strerror(errno));
  const int write_err = write_to_fd(fd, write, [&] { ::close(fd); });
  if (::close(fd) != 0 && write_err == 0)
    throw Error(ErrorCode::io, path, "", std::string("write failed: ") + std::strerror(errno));
  if (write_err) throw Error(ErrorCode::io, path, "", std::string("write failed: ") + std::strerror(write_err));
}

}  // namespace

void write_text_file(const std::string& path, const std::string& content) {
  write_text_file(path,
                  [&](std::ostream& out) { out.write(content.data(), static_cast<std::streamsize>(content.size())); });
}

void write_text_file(const std::string& path, const std::function<void(std::ostream&)>& write) {
  if (path == "-") {
    write(std::cout);
    std::cout.flush();
    if (!std::cout) throw Error(ErrorCode::io, "<stdout>", "", "write failed");
    return;
  }
  const fs::path target = final_target(path);
  std::error_code ec;
  const auto target_status = fs::status(target, ec);
  if (fs::is_directory(target_status)) throw Error(ErrorCode::io, path, "", "cannot write: it is a directory");
  if (fs::exists(target_status) && !fs::is_regular_file(target_status)) {
    // A device or a pipe (/dev/null, /dev/lp0, a FIFO) is written in place: renaming a temporary
    // file over it would replace the device node itself.
    write_in_place(path, target, write);
    return;
  }
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  if (!fs::is_directory(dir, ec))
    throw Error(ErrorCode::io, path, "", "cannot write: directory " + dir.string() + " does not exist");
  std::string tmp = (dir / ("." + target.filename().string() + ".XXXXXX")).string();
  const int fd = ::mkstemp(tmp.data());
  if (fd < 0) throw Error(ErrorCode::io, path, "", std::string("cannot write: ") + std::strerror(errno));
  const auto fail = [&](int err, const char* what) {
    ::close(fd);
    ::unlink(tmp.c_str());
    throw Error(ErrorCode::io, path, "", std::string(what) + std::strerror(err));
  };
  const int write_err = write_to_fd(fd, write, [&] {
    ::close(fd);
    ::unlink(tmp.c_str());
  });
  if (write_err) fail(write_err, "write failed: ");
  // New files get the usual permissions rather than mkstemp's 0600.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  ::fchmod(fd, 0666 & ~mask);
  if (::fsync(fd) != 0) fail(errno, "write failed: ");
  if (::close(fd) != 0) {
    const int err = errno;
    ::unlink(tmp.c_str());
    throw Error(ErrorCode::io, path, "", std::string("write failed: ") + std::strerror(err));
  }
  if (std::rename(tmp.c_str(), target.c_str()) != 0) {
    const int err = errno;
    ::unlink(tmp.c_str());
    throw Error(ErrorCode::io, path, "", std::string("cannot write: ") + std::strerror(err));
  }
}

}  // namespace popcut

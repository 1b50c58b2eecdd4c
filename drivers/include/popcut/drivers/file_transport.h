// Transport that writes the job to a file or a raw device node (file:PATH), e.g. /dev/usb/lp0 or a .hpgl.
#pragma once

#include <string>

#include "popcut/drivers/transport.h"

namespace popcut::drivers {

class FileTransport final : public Transport {
 public:
  explicit FileTransport(std::string path) : path_(std::move(path)) {}
  ~FileTransport() override;
  FileTransport(const FileTransport&) = delete;
  FileTransport& operator=(const FileTransport&) = delete;

  TransportStatus open() override;
  IoResult write(std::span<const std::uint8_t> data, std::chrono::milliseconds timeout) override;
  // Files have nothing to say back; a read reports `unsupported`.
  IoResult read(std::span<std::uint8_t> buffer, std::chrono::milliseconds timeout) override;
  TransportStatus drain(std::chrono::milliseconds timeout) override;
  void close() override;
  std::string describe() const override { return "file:" + path_; }
  bool answers() const override { return false; }

 private:
  std::string path_;
  int fd_ = -1;
};

}  // namespace popcut::drivers

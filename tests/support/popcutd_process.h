// Real popcutd and sim-plotter processes for tests and benchmarks: started, talked to, killed and reaped on scope exit.
#pragma once

#include <httplib.h>
#include <sys/types.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace popcut::testing {

// A temporary directory removed with everything in it when the object goes.
class TempDir {
 public:
  explicit TempDir(const std::string& prefix);
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::string write(const std::string& name, const std::string& content) const;

 private:
  std::filesystem::path path_;
};

class PopcutdProcess {
 public:
  // Runs `binary --config config --data-dir data_dir --port 0` and reads the port it prints;
  // throws std::runtime_error (with its standard error) if it exits first. `env`: NAME=VALUE
  // entries added to its environment (LD_PRELOAD for a serial device on a pseudo-terminal).
  PopcutdProcess(const std::string& binary, const std::string& config, const std::string& data_dir,
                 const std::vector<std::string>& env = {});
  ~PopcutdProcess();  // SIGKILL if still running, then reaped
  PopcutdProcess(const PopcutdProcess&) = delete;
  PopcutdProcess& operator=(const PopcutdProcess&) = delete;

  int port() const { return port_; }
  pid_t pid() const { return pid_; }
  std::string log() const;  // its standard error so far
  // Sends `sig` and waits for the exit; returns the exit status (128 + signal if killed).
  int stop(int sig);

  httplib::Client client(const std::string& token) const;

 private:
  pid_t pid_ = -1;
  int port_ = 0;
  std::string log_path_;
};

// `popcut sim-plotter ARGS --report REPORT`: a simulated cutter on the far side of a fresh
// pseudo-terminal, serving one session; killed and reaped on scope exit if still running.
class SimPlotterProcess {
 public:
  // Throws std::runtime_error (with its standard error) if it prints no /dev/pts/ port.
  SimPlotterProcess(const std::string& popcut, const std::vector<std::string>& args, const std::string& report_path);
  ~SimPlotterProcess();
  SimPlotterProcess(const SimPlotterProcess&) = delete;
  SimPlotterProcess& operator=(const SimPlotterProcess&) = delete;

  const std::string& port() const { return port_; }
  pid_t pid() const { return pid_; }  // kill -USR1 loads a sheet, -USR2 takes it out
  // Its exit status once the host has closed the port, or -1 if it still runs after `give_up_s`.
  int wait(double give_up_s = 120);
  std::string log() const;        // its standard error
  nlohmann::json report() const;  // what it received and cut (popcut.sim-plotter.v1), after wait()

 private:
  pid_t pid_ = -1;
  std::string port_, report_path_, log_path_;
};

// The strokes a sim-plotter report says it cut (points in plotter units): popcut::PlotterPath's.
std::vector<std::vector<std::array<std::int64_t, 2>>> sim_plotter_strokes(const nlohmann::json& report);

// A TCP connection to 127.0.0.1:port, as a raw socket to send bytes on (-1 if it cannot connect).
int connect_loopback(int port);

// A whole file as text ("" when it cannot be read).
std::string read_file(const std::string& path);

struct Reply {
  int status = 0;  // 0: no answer at all
  nlohmann::json body;
};
Reply get_json(httplib::Client& c, const std::string& path);
Reply post_json(httplib::Client& c, const std::string& path, const std::string& body);
// A multipart upload as the kiosk and `popcut submit MESH` send it: the file as `mesh`, then fields.
Reply post_mesh(httplib::Client& c, const std::string& path, const std::string& content, const std::string& filename,
                const std::vector<std::pair<std::string, std::string>>& fields);

// Polls `condition` every 20 ms until true; false only if popcutd stopped answering or
// `give_up_s` passed (a safety net so a broken daemon fails the test instead of hanging it).
bool wait_until(const std::function<bool()>& condition, double give_up_s = 300);

}  // namespace popcut::testing

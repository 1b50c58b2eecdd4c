// Starting, talking to and stopping real popcutd (and sim-plotter) processes for the tests and benchmarks.
#include "popcutd_process.h"

#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <tuple>

namespace popcut::testing {

TempDir::TempDir(const std::string& prefix) {
  std::string tmpl = (std::filesystem::temp_directory_path() / (prefix + "-XXXXXX")).string();
  if (!::mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed for " + tmpl);
  path_ = tmpl;
}

TempDir::~TempDir() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

std::string TempDir::write(const std::string& name, const std::string& content) const {
  const std::filesystem::path p = path_ / name;
  std::filesystem::create_directories(p.parent_path());
  std::ofstream(p) << content;
  return p.string();
}

namespace {

// Runs `args` (args[0] the binary) with `env` entries added, its standard error appended to
// `err_path`, and returns its pid and the first line it prints on standard output ("" if it
// closed that first: it exited).
std::pair<pid_t, std::string> spawn(std::vector<std::string> args, const std::string& err_path,
                                    std::vector<std::string> env) {
  // Everything the child needs is built before fork: the child of a threaded process may only
  // make async-signal-safe calls (no allocation) before exec.
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::vector<char*> envp;  // the added entries first: the first of a name is the one in effect
  for (std::string& e : env) envp.push_back(e.data());
  for (char** e = environ; *e; ++e) envp.push_back(*e);
  envp.push_back(nullptr);
  int out[2];
  if (::pipe(out) != 0) throw std::runtime_error("pipe failed");
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    ::dup2(out[1], STDOUT_FILENO);
    const int err = ::open(err_path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    if (err >= 0) ::dup2(err, STDERR_FILENO);
    ::close(out[0]);
    ::close(out[1]);
    ::execve(argv[0], argv.data(), envp.data());
    ::_exit(127);
  }
  ::close(out[1]);
  std::string line;
  char ch;
  while (::read(out[0], &ch, 1) == 1 && ch != '\n') line += ch;
  ::close(out[0]);
  return {pid, line};
}

}  // namespace

PopcutdProcess::PopcutdProcess(const std::string& binary, const std::string& config, const std::string& data_dir,
                               const std::vector<std::string>& env) {
  log_path_ = data_dir + ".log";
  // The first line says where it listens; none means it exited (bad config, cannot bind).
  const auto [pid, line] = spawn({binary, "--config", config, "--data-dir", data_dir, "--port", "0"}, log_path_, env);
  pid_ = pid;
  const std::size_t colon = line.rfind(':');
  if (line.find("listening on") == std::string::npos || colon == std::string::npos) {
    const int status = stop(SIGKILL);
    throw std::runtime_error("popcutd did not start (status " + std::to_string(status) + "): " + log());
  }
  port_ = std::atoi(line.c_str() + colon + 1);
}

PopcutdProcess::~PopcutdProcess() {
  if (pid_ > 0) stop(SIGKILL);
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string PopcutdProcess::log() const { return read_file(log_path_); }

int PopcutdProcess::stop(int sig) {
  if (pid_ <= 0) return -1;
  ::kill(pid_, sig);
  int status = 0;
  ::waitpid(pid_, &status, 0);
  pid_ = -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

httplib::Client PopcutdProcess::client(const std::string& token) const {
  httplib::Client c("127.0.0.1", port_);
  if (!token.empty()) c.set_default_headers({{"Authorization", "Bearer " + token}});
  c.set_read_timeout(120);
  c.set_tcp_nodelay(true);
  return c;
}

static Reply reply_of(const httplib::Result& r) {
  Reply out;
  if (!r) return out;
  out.status = r->status;
  out.body = nlohmann::json::parse(r->body, nullptr, false);
  return out;
}

Reply get_json(httplib::Client& c, const std::string& path) { return reply_of(c.Get(path.c_str())); }
Reply post_json(httplib::Client& c, const std::string& path, const std::string& body) {
  return reply_of(c.Post(path.c_str(), body, "application/json"));
}

Reply post_mesh(httplib::Client& c, const std::string& path, const std::string& content, const std::string& filename,
                const std::vector<std::pair<std::string, std::string>>& fields) {
  httplib::MultipartFormDataItems items{{"mesh", content, filename, "application/octet-stream"}};
  for (const auto& [k, v] : fields) items.push_back({k, v, "", ""});
  return reply_of(c.Post(path.c_str(), items));
}

bool wait_until(const std::function<bool()>& condition, double give_up_s) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(give_up_s);
  while (std::chrono::steady_clock::now() < end) {
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

SimPlotterProcess::SimPlotterProcess(const std::string& popcut, const std::vector<std::string>& args,
                                     const std::string& report_path)
    : report_path_(report_path), log_path_(report_path + ".log") {
  std::vector<std::string> all = {popcut, "sim-plotter"};
  all.insert(all.end(), args.begin(), args.end());
  all.insert(all.end(), {"--report", report_path});
  // The first line is the port; none means it exited (a bad option).
  std::tie(pid_, port_) = spawn(all, log_path_, {});
  if (port_.rfind("/dev/pts/", 0) != 0) {
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, nullptr, 0);
    pid_ = -1;
    throw std::runtime_error("sim-plotter printed no port: " + log());
  }
}

SimPlotterProcess::~SimPlotterProcess() {
  if (pid_ <= 0) return;
  ::kill(pid_, SIGKILL);
  ::waitpid(pid_, nullptr, 0);
}

int SimPlotterProcess::wait(double give_up_s) {
  if (pid_ <= 0) return -1;
  int status = 0;
  if (!wait_until([&] { return ::waitpid(pid_, &status, WNOHANG) == pid_; }, give_up_s)) return -1;
  pid_ = -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

std::string SimPlotterProcess::log() const { return read_file(log_path_); }

nlohmann::json SimPlotterProcess::report() const {
  return nlohmann::json::parse(read_file(report_path_), nullptr, false);
}

std::vector<std::vector<std::array<std::int64_t, 2>>> sim_plotter_strokes(const nlohmann::json& report) {
  std::vector<std::vector<std::array<std::int64_t, 2>>> out;
  for (const auto& s : report["strokes"]) {
    std::vector<std::array<std::int64_t, 2>> path;
    for (const auto& q : s["points_pu"]) path.push_back({q[0].get<std::int64_t>(), q[1].get<std::int64_t>()});
    out.push_back(path);
  }
  return out;
}

int connect_loopback(int port) {
  const int s = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (s >= 0 && ::connect(s, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0) return s;
  if (s >= 0) ::close(s);
  return -1;
}

}  // namespace popcut::testing

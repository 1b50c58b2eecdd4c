// Headless Chromium driven over WebDriver (chromedriver), for tests of the kiosk page against a real popcutd.
#pragma once

#include <gtest/gtest.h>
#include <httplib.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>
#include <stdexcept>
#include <filesystem>
#include <string>
#include <vector>

#include "popcutd_process.h"

namespace popcut::testing {

// A picture popcutd rendered has loaded: an object URL (the page's empty placeholder is a data:
// URL, which has a size too) whose image decoded.
inline const std::string kRendered =
    "const rendered = (id) => { const i = document.getElementById(id); return i.src.startsWith('blob:') && i.complete "
    "&& i.naturalWidth > 0; };";

// A loopback port nobody listens on now (chromedriver cannot be asked for port 0).
inline int free_port() {
  const int s = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ::bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a);
  socklen_t len = sizeof a;
  ::getsockname(s, reinterpret_cast<sockaddr*>(&a), &len);
  ::close(s);
  return static_cast<int>(ntohs(a.sin_port));
}

inline std::string base64_decode(const std::string& in) {
  std::string out;
  int val = 0, bits = -8;
  for (const char ch : in) {
    const int c = static_cast<unsigned char>(ch);
    int d;
    if (c >= 'A' && c <= 'Z')
      d = c - 'A';
    else if (c >= 'a' && c <= 'z')
      d = c - 'a' + 26;
    else if (c >= '0' && c <= '9')
      d = c - '0' + 52;
    else if (c == '+')
      d = 62;
    else if (c == '/')
      d = 63;
    else
      continue;
    val = (val << 6) + d;
    bits += 6;
    if (bits >= 0) {
      out.push_back(static_cast<char>((val >> bits) & 0xff));
      bits -= 8;
    }
  }
  return out;
}

// chromedriver on a free port, a headless Chromium session, both ended on scope exit.
class Browser {
 public:
  // `extra_args`: more Chromium switches (the designer's 3D view asks for SwiftShader's WebGL).
  explicit Browser(const std::string& profile_dir, const std::vector<std::string>& extra_args = {})
      : port_(free_port()), http_("127.0.0.1", port_) {
    pid_ = ::fork();
    if (pid_ == 0) {
      const std::string port = "--port=" + std::to_string(port_);
      ::execl("/usr/bin/chromedriver", "chromedriver", port.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
    http_.set_read_timeout(120);
    if (!wait_until([&] { return static_cast<bool>(http_.Get("/status")); }, 60))
      throw std::runtime_error("chromedriver did not start");
    nlohmann::json args = {"--headless=new",          "--no-sandbox",           "--disable-gpu",
                           "--disable-dev-shm-usage", "--window-size=1024,768", "--user-data-dir=" + profile_dir};
    for (const std::string& a : extra_args) args.push_back(a);
    const nlohmann::json caps = {
        {"capabilities",
         {{"alwaysMatch",
           {{"browserName", "chrome"}, {"goog:chromeOptions", {{"binary", "/usr/bin/chromium"}, {"args", args}}}}}}}};
    const nlohmann::json r = call("POST", "/session", caps);
    session_ = r["value"].value("sessionId", "");
    if (session_.empty()) throw std::runtime_error("no browser session: " + r.dump());
  }
  ~Browser() {
    if (!session_.empty()) http_.Delete(("/session/" + session_).c_str());
    ::kill(pid_, SIGTERM);
    ::waitpid(pid_, nullptr, 0);
  }
  nlohmann::json call(const std::string& method, const std::string& path,
                      const nlohmann::json& body = nlohmann::json::object()) {
    const httplib::Result r =
        method == "GET" ? http_.Get(path.c_str()) : http_.Post(path.c_str(), body.dump(), "application/json");
    if (!r) throw std::runtime_error("chromedriver did not answer " + path);
    return nlohmann::json::parse(r->body);
  }
  nlohmann::json session(const std::string& method, const std::string& path,
                         const nlohmann::json& body = nlohmann::json::object()) {
    return call(method, "/session/" + session_ + path, body)["value"];
  }
  nlohmann::json run(const std::string& script) {
    return session("POST", "/execute/sync", {{"script", script}, {"args", nlohmann::json::array()}});
  }
  // A real mouse click (move, press, release) at viewport pixel (x, y).
  void click_at(int x, int y) {
    const nlohmann::json actions = {
        {"actions",
         {{{"type", "pointer"},
           {"id", "mouse"},
           {"parameters", {{"pointerType", "mouse"}}},
           {"actions",
            {{{"type", "pointerMove"}, {"duration", 0}, {"origin", "viewport"}, {"x", x}, {"y", y}},
             {{"type", "pointerDown"}, {"button", 0}},
             {{"type", "pointerUp"}, {"button", 0}}}}}}}};
    session("POST", "/actions", actions);
  }
  // Replaces an input's text as typed keys do (each key an input event).
  void type(const std::string& css, const std::string& text) {
    const nlohmann::json el = session("POST", "/element", {{"using", "css selector"}, {"value", css}});
    ASSERT_TRUE(el.is_object() && !el.empty()) << "element " << css << " exists: " << el.dump();
    const std::string id = el.begin().value().get<std::string>();
    session("POST", "/element/" + id + "/clear");
    session("POST", "/element/" + id + "/value", {{"text", text}});
  }
  // Chooses a file in a file input, as a person picking it in the dialog does (a change event).
  void choose_file(const std::string& css, const std::string& path) {
    const nlohmann::json el = session("POST", "/element", {{"using", "css selector"}, {"value", css}});
    ASSERT_TRUE(el.is_object() && !el.empty()) << "element " << css << " exists: " << el.dump();
    // ChromeDriver takes only a canonical path.
    const nlohmann::json r = session("POST", "/element/" + el.begin().value().get<std::string>() + "/value",
                                     {{"text", std::filesystem::canonical(path).string()}});
    ASSERT_TRUE(r.is_null()) << "the file input took " << path << ": " << r.dump();
  }
  void click(const std::string& css) {
    const nlohmann::json el = session("POST", "/element", {{"using", "css selector"}, {"value", css}});
    ASSERT_TRUE(el.is_object() && !el.empty()) << "element " << css << " exists: " << el.dump();
    session("POST", "/element/" + el.begin().value().get<std::string>() + "/click");
  }

 private:
  int port_;
  pid_t pid_ = -1;
  httplib::Client http_;
  std::string session_;
};

}  // namespace popcut::testing

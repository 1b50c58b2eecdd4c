// The kiosk page in headless Chromium (driven over WebDriver by chromedriver) against a real popcutd.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <thread>

#include "popcutd_process.h"

namespace {
using nlohmann::json;
using popcut::testing::PopcutdProcess;
using popcut::testing::TempDir;
using popcut::testing::wait_until;

const std::string kSrc = POPCUT_SOURCE_DIR;
// A picture popcutd rendered has loaded: an object URL (the page's empty placeholder is a data:
// URL, which has a size too) whose image decoded.
const std::string kRendered =
    "const rendered = (id) => { const i = document.getElementById(id); return i.src.startsWith('blob:') && i.complete && i.naturalWidth > 0; };";

// A loopback port nobody listens on now (chromedriver cannot be asked for port 0).
int free_port() {
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

std::string base64_decode(const std::string& in) {
  std::string out;
  int val = 0, bits = -8;
  for (const char ch : in) {
    const int c = static_cast<unsigned char>(ch);
    int d;
    if (c >= 'A' && c <= 'Z') d = c - 'A';
    else if (c >= 'a' && c <= 'z') d = c - 'a' + 26;
    else if (c >= '0' && c <= '9') d = c - '0' + 52;
    else if (c == '+') d = 62;
    else if (c == '/') d = 63;
    else continue;
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
  explicit Browser(const std::string& profile_dir) : port_(free_port()), http_("127.0.0.1", port_) {
    pid_ = ::fork();
    if (pid_ == 0) {
      const std::string port = "--port=" + std::to_string(port_);
      ::execl("/usr/bin/chromedriver", "chromedriver", port.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
    http_.set_read_timeout(120);
    if (!wait_until([&] { return static_cast<bool>(http_.Get("/status")); }, 60)) throw std::runtime_error("chromedriver did not start");
    const json caps = {{"capabilities",
                        {{"alwaysMatch",
                          {{"browserName", "chrome"},
                           {"goog:chromeOptions",
                            {{"binary", "/usr/bin/chromium"},
                             {"args", {"--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                                       "--window-size=1024,768", "--user-data-dir=" + profile_dir}}}}}}}}};
    const json r = call("POST", "/session", caps);
    session_ = r["value"].value("sessionId", "");
    if (session_.empty()) throw std::runtime_error("no browser session: " + r.dump());
  }
  ~Browser() {
    if (!session_.empty()) http_.Delete(("/session/" + session_).c_str());
    ::kill(pid_, SIGTERM);
    ::waitpid(pid_, nullptr, 0);
  }
  json call(const std::string& method, const std::string& path, const json& body = json::object()) {
    const httplib::Result r = method == "GET" ? http_.Get(path.c_str()) : http_.Post(path.c_str(), body.dump(), "application/json");
    if (!r) throw std::runtime_error("chromedriver did not answer " + path);
    return json::parse(r->body);
  }
  json session(const std::string& method, const std::string& path, const json& body = json::object()) {
    return call(method, "/session/" + session_ + path, body)["value"];
  }
  json run(const std::string& script) { return session("POST", "/execute/sync", {{"script", script}, {"args", json::array()}}); }
  void click(const std::string& css) {
    const json el = session("POST", "/element", {{"using", "css selector"}, {"value", css}});
    ASSERT_TRUE(el.is_object() && !el.empty()) << "element " << css << " exists: " << el.dump();
    session("POST", "/element/" + el.begin().value().get<std::string>() + "/click");
  }

 private:
  int port_;
  pid_t pid_ = -1;
  httplib::Client http_;
  std::string session_;
};

TEST(Kiosk, PicksAnExampleQueuesItAndSeesItCut) {
  TempDir dir("popcut-kiosk");
  PopcutdProcess d(POPCUTD, kSrc + "/configs/popcutd.toml", (dir.path() / "data").string());
  Browser b((dir.path() / "chromium").string());
  b.session("POST", "/url", {{"url", "http://127.0.0.1:" + std::to_string(d.port()) + "/?token=kiosk-change-me-0123456789"}});
  ASSERT_TRUE(wait_until([&] { return b.run("return document.querySelectorAll('#example option').length").get<int>() > 3; }, 60))
      << "the page lists the examples";
  ASSERT_TRUE(wait_until([&] { return b.run("return document.querySelectorAll('#device option').length").get<int>() == 2; }, 60))
      << "the page lists both cutters";
  b.click("#example option[value='voxel-castle']");
  ASSERT_TRUE(wait_until([&] { return !b.run("return document.getElementById('queue').disabled").get<bool>(); }, 60))
      << "the pattern renders and Queue becomes available; page says: " << b.run("return document.body.innerText").dump();
  ASSERT_TRUE(wait_until([&] { return b.run(kRendered + "return rendered('preview')").get<bool>(); }, 60))
      << "the card preview shows";
  EXPECT_TRUE(b.run(kRendered + "return rendered('pattern')").get<bool>()) << "the pattern shows";
  // The slider asks for another angle; the picture changes.
  const std::string before = b.run("return document.getElementById('preview').src").get<std::string>();
  b.run("const a = document.getElementById('angle'); a.value = 150; a.dispatchEvent(new Event('input'));");
  ASSERT_TRUE(wait_until([&] { return b.run("return document.getElementById('preview').src").get<std::string>() != before; }, 60))
      << "moving the opening-angle slider renders a new preview";
  EXPECT_EQ(b.run("return document.getElementById('angle-value').textContent").get<std::string>(), "150") << "the angle is shown";
  const std::string at150 = b.run("return document.getElementById('preview').src").get<std::string>();
  b.run("const a = document.getElementById('angle'); a.value = 60; a.dispatchEvent(new Event('input'));");
  ASSERT_TRUE(wait_until([&] { return b.run("return document.getElementById('preview').src").get<std::string>() != at150; }, 60))
      << "and again at 60 degrees";
  b.click("#device option[value='sim-b']");
  b.click("#queue");
  ASSERT_TRUE(wait_until([&] { return b.run("return document.querySelectorAll('#jobs .job').length").get<int>() == 1; }, 60))
      << "the queued card appears under My cards";
  std::string state;
  ASSERT_TRUE(wait_until([&] {
    state = b.run("return document.querySelector('#jobs .job').dataset.state").get<std::string>();
    return state == "done" || state == "failed" || state == "cancelled";
  }, 300)) << "the card finishes on the simulated cutter";
  EXPECT_EQ(state, "done") << "the card was cut; page: " << b.run("return document.body.innerText").dump();
  EXPECT_EQ(b.run("return document.querySelector('#jobs .job progress').value").get<double>(), 1.0) << "the progress bar is full";
  EXPECT_NE(b.run("return document.querySelector('#jobs .job .where').textContent").get<std::string>().find("on sim-b"), std::string::npos)
      << "it says which cutter cut it";
  // Every kiosk file came from the daemon: nothing from elsewhere.
  EXPECT_EQ(b.run("return performance.getEntriesByType('resource').filter(e => !e.name.startsWith(location.origin)).length").get<int>(), 0)
      << "no resource is loaded from outside popcutd";
  const std::string png = base64_decode(b.session("GET", "/screenshot").get<std::string>());
  EXPECT_EQ(png.substr(1, 3), "PNG") << "a screenshot of the page";
  std::ofstream(POPCUT_KIOSK_SCREENSHOT, std::ios::binary) << png;
}

TEST(Kiosk, UploadsAModelAndCancelsItsOwnJobWhileItCuts) {
  TempDir dir("popcut-kiosk");
  const std::string cfg = dir.write("slow.toml", "[server]\ndata_dir = \"x\"\n[[device]]\nname = \"slow\"\nprofile = \"" + kSrc +
                                                     "/configs/devices/sim.toml\"\ntransport = \"sim\"\nsim_time_scale = 1\nsim_slowdown = 20\n"
                                                     "[[token]]\nname = \"kiosk\"\ntoken = \"kiosk-change-me-0123456789\"\n");
  PopcutdProcess d(POPCUTD, cfg, (dir.path() / "data").string());
  Browser b((dir.path() / "chromium").string());
  b.session("POST", "/url", {{"url", "http://127.0.0.1:" + std::to_string(d.port()) + "/?token=kiosk-change-me-0123456789"}});
  ASSERT_TRUE(wait_until([&] { return b.run("return document.querySelectorAll('#example option').length").get<int>() > 3; }, 60))
      << "the page lists the examples";
  // This time the model comes from a file, as a visitor's own would.
  const json input = b.session("POST", "/element", {{"using", "css selector"}, {"value", "#upload"}});
  b.session("POST", "/element/" + input.begin().value().get<std::string>() + "/value", {{"text", kSrc + "/examples/voxel/castle.json"}});
  ASSERT_TRUE(wait_until([&] { return !b.run("return document.getElementById('queue').disabled").get<bool>(); }, 60))
      << "the uploaded model renders and can be queued; page: " << b.run("return document.body.innerText").dump();
  EXPECT_EQ(b.run("return document.getElementById('model-name').textContent").get<std::string>(), "castle") << "named after the file";
  b.click("#queue");
  ASSERT_TRUE(wait_until([&] {
    return b.run("const j = document.querySelector('#jobs .job'); return j ? j.dataset.state : ''").get<std::string>() == "cutting";
  }, 120)) << "the castle is being cut (slowly)";
  b.click("#jobs .job .cancel");
  ASSERT_TRUE(wait_until([&] { return b.run("return document.querySelector('#jobs .job').dataset.state").get<std::string>() == "cancelled"; }, 120))
      << "the kiosk cancels its own job mid-cut";
  EXPECT_TRUE(b.run("return document.querySelector('#jobs .job .cancel').hidden").get<bool>()) << "no cancel button on a cancelled job";
}

// A visitor's 3D mesh: popcutd imports it with the options on the page, the card shows, it is cut.
TEST(Kiosk, UploadsAMeshImportsItAndSeesItCut) {
  TempDir dir("popcut-kiosk");
  PopcutdProcess d(POPCUTD, kSrc + "/configs/popcutd.toml", (dir.path() / "data").string());
  Browser b((dir.path() / "chromium").string());
  b.session("POST", "/url", {{"url", "http://127.0.0.1:" + std::to_string(d.port()) + "/?token=kiosk-change-me-0123456789"}});
  ASSERT_TRUE(wait_until([&] { return b.run("return document.querySelectorAll('#device option').length").get<int>() == 2; }, 60))
      << "the page lists both cutters";
  b.run("document.getElementById('resolution').value = 30;");
  const json input = b.session("POST", "/element", {{"using", "css selector"}, {"value", "#upload"}});
  b.session("POST", "/element/" + input.begin().value().get<std::string>() + "/value", {{"text", kSrc + "/examples/meshes/house.obj"}});
  ASSERT_TRUE(wait_until([&] { return !b.run("return document.getElementById('queue').disabled").get<bool>(); }, 120))
      << "the mesh is imported and can be queued; page: " << b.run("return document.body.innerText").dump();
  EXPECT_FALSE(b.run("return document.getElementById('import').hidden").get<bool>()) << "the import options show for a mesh";
  EXPECT_EQ(b.run("return document.getElementById('model-name').textContent").get<std::string>().rfind("house.obj: 30 x ", 0), 0u)
      << "the page says what the import made: " << b.run("return document.getElementById('model-name').textContent").dump();
  ASSERT_TRUE(wait_until([&] { return b.run(kRendered + "return rendered('preview')").get<bool>(); }, 60))
      << "the card preview shows";
  // A bad option: the importer's message shows on the page.
  b.run("document.getElementById('up').value = '-y';");
  b.click("#reimport");
  ASSERT_TRUE(wait_until([&] { return !b.run("return document.getElementById('model-error').hidden").get<bool>(); }, 60))
      << "an impossible orientation is refused";
  EXPECT_NE(b.run("return document.getElementById('model-error').textContent").get<std::string>().find("perpendicular"), std::string::npos)
      << "with the importer's message: " << b.run("return document.getElementById('model-error').textContent").dump();
  b.run("document.getElementById('up').value = '+z';");
  b.click("#reimport");
  ASSERT_TRUE(wait_until([&] { return !b.run("return document.getElementById('queue').disabled").get<bool>(); }, 120))
      << "imported again with a good orientation";
  b.click("#queue");
  std::string state;
  ASSERT_TRUE(wait_until([&] {
    state = b.run("const j = document.querySelector('#jobs .job'); return j ? j.dataset.state : ''").get<std::string>();
    return state == "done" || state == "failed" || state == "cancelled";
  }, 300)) << "the card finishes on the simulated cutter";
  EXPECT_EQ(state, "done") << "the imported card was cut; page: " << b.run("return document.body.innerText").dump();
  const std::string title = b.run("return document.querySelector('#jobs .job .title').textContent").get<std::string>();
  EXPECT_EQ(title.substr(title.find(' ') + 1), "house") << "the job is named after the file as the API names it: " << title;
}

}  // namespace

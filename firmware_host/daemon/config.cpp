// popcutd.toml loader: each section read through drivers' typed, range-checked TOML getters.
#include "config.h"

#include <arpa/inet.h>
#include <netinet/in.h>

#include <algorithm>
#include <filesystem>
#include <optional>
#include <set>
#include <toml++/toml.h>

#include "popcut/drivers/device.h"
#include "popcut/drivers/toml_section.h"
#include "popcut/error.h"
#include "popcut/io/files.h"
#include "popcut/utf8.h"

#ifndef POPCUT_KIOSK_DIR
#define POPCUT_KIOSK_DIR "firmware_host/kiosk"
#endif
#ifndef POPCUT_EXAMPLES_DIR
#define POPCUT_EXAMPLES_DIR "examples"
#endif

namespace popcut::daemon {
namespace {

using drivers::parse_toml;
using drivers::TomlSection;

// Relative paths in the file mean: next to the file, so a config and its profiles travel together.
std::string resolve(const std::string& path, const std::string& source) {
  const std::filesystem::path p(path);
  if (p.is_absolute()) return p.lexically_normal().string();
  return (std::filesystem::path(source).parent_path() / p).lexically_normal().string();
}

// An address literal is checked here (999.1.1.1 is a typo, not a host name to look up); a host
// name is resolved when popcutd binds.
void check_listen(const TomlSection& s, const std::string& listen) {
  if (listen.empty()) s.fail("listen", "must not be empty (127.0.0.1 for this machine only)");
  const bool v4_like = listen.find_first_not_of("0123456789.") == std::string::npos;
  const bool v6_like = listen.find(':') != std::string::npos;
  unsigned char addr[sizeof(in6_addr)];
  if (v4_like && ::inet_pton(AF_INET, listen.c_str(), addr) != 1)
    s.fail("listen", "\"" + listen + "\" is not an IPv4 address (e.g. 127.0.0.1, 0.0.0.0)");
  if (v6_like && ::inet_pton(AF_INET6, listen.c_str(), addr) != 1)
    s.fail("listen", "\"" + listen + "\" is not an IPv6 address (e.g. ::1, ::; the port goes in [server] port)");
  if (!v4_like && !v6_like &&
      listen.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789.-") !=
          std::string::npos) {
    s.fail("listen", "\"" + listen + "\" is neither an IP address nor a host name");
  }
}

// A directory key: resolved against the config file, or `fallback` when not given.
std::string directory(TomlSection& s, const std::string& key, const std::string& fallback, const std::string& source) {
  const std::string dir = s.text(key, "", 4096);
  return dir.empty() ? fallback : resolve(dir, source);
}

// [server] materials_dir and every material in it; the default directory may be missing.
void read_materials(TomlSection& s, const std::string& source, DaemonConfig& c) {
  const bool given = s.node("materials_dir") != nullptr;
  c.materials_dir = directory(s, "materials_dir", resolve("materials", source), source);
  std::error_code ec;
  if (!std::filesystem::is_directory(c.materials_dir, ec)) {
    if (given) s.fail("materials_dir", "\"" + c.materials_dir + "\" is not a directory");
    return;
  }
  for (const std::string& name : drivers::material_names(c.materials_dir))
    c.materials.push_back(drivers::find_material(c.materials_dir, name));
}

// [server]
void read_server(TomlSection s, const std::string& source, DaemonConfig& c) {
  c.listen = s.text("listen", "127.0.0.1", 64);
  check_listen(s, c.listen);
  c.port = s.integer("port", 8742, 0, 65535);
  const std::string data_dir = s.text("data_dir", "", 4096);
  if (data_dir.empty()) s.fail("data_dir", "missing: where the job database and job files live");
  c.data_dir = resolve(data_dir, source);
  c.kiosk_dir = directory(s, "kiosk_dir", POPCUT_KIOSK_DIR, source);
  c.examples_dir = directory(s, "examples_dir", POPCUT_EXAMPLES_DIR, source);
  c.three_dir = directory(s, "three_dir", "/usr/share/javascript/three", source);
  c.http_threads = s.integer("http_threads", 64, 1, 1024);
  c.keep_alive_timeout_s = s.integer("keep_alive_timeout_s", 2, 1, 300);
  c.header_timeout_s = s.integer("header_timeout_s", 5, 1, 300);
  c.listen_backlog = s.integer("listen_backlog", 1024, 16, 65535);
  c.planners = s.integer("planners", 1, 1, 64);
  read_materials(s, source, c);
  s.reject_unknown();
}

// [limits]
Limits read_limits(TomlSection l) {
  Limits limits;
  limits.upload_bytes = static_cast<std::size_t>(l.integer("upload_bytes", 1 << 20, 1024, 1 << 30));
  limits.model_cells = l.integer("model_cells", 1000000, 1, 100000000);
  limits.pattern_faces = l.integer("pattern_faces", 5000, 1, 10000000);
  limits.queue_length = l.integer("queue_length", 10000, 1, 10000000);
  limits.mesh_triangles = l.integer("mesh_triangles", 200000, 1, 10000000);
  limits.preview_cache_bytes = static_cast<std::size_t>(l.integer("preview_cache_bytes", 32 << 20, 0, 1 << 30));
  limits.design_sessions = l.integer("design_sessions", 64, 1, 100000);
  l.reject_unknown();
  return limits;
}

// One [[device]]; `names` holds the names of those before it.
DeviceConfig read_device(TomlSection& d, const std::string& source, std::set<std::string>& names) {
  DeviceConfig dev;
  dev.name = d.text("name", "", 64);
  if (!is_safe_name(dev.name) || dev.name.find(' ') != std::string::npos) {
    d.fail("name", "\"" + dev.name + "\": 1 to 64 letters, digits, '-', '_' or '.', not starting with '.'");
  }
  if (!names.insert(dev.name).second) d.fail("name", "\"" + dev.name + "\" is used by another device");
  const std::string profile = d.text("profile", "", 4096);
  if (profile.empty()) d.fail("profile", "missing: the device profile (e.g. devices/sim.toml)");
  dev.profile_path = resolve(profile, source);
  dev.transport = d.text("transport", "", 4096);
  drivers::DeviceAddress address;
  if (const drivers::TransportStatus st = drivers::parse_device(dev.transport, address); !st.ok())
    d.fail("transport", st.message);
  if (address.kind == drivers::DeviceKind::file) dev.transport = "file:" + resolve(address.path, source);
  dev.sim_slowdown = d.number("sim_slowdown", 1, 1, 100000);
  dev.sim_time_scale = d.number("sim_time_scale", 0, 0, 100);
  if (address.kind != drivers::DeviceKind::sim && (d.node("sim_slowdown") || d.node("sim_time_scale"))) {
    d.fail("sim_slowdown", "sim_* settings apply to transport = \"sim\" only");
  }
  dev.blade_life_m = d.optional_number("blade_life_m", 0.001, 1e6);
  // A simulated cutter has no sheet to change; a real one cuts the next job onto the last one's.
  dev.confirm_sheet = d.boolean("confirm_sheet", address.kind != drivers::DeviceKind::sim);
  d.reject_unknown();
  try {
    dev.profile = drivers::load_profile(dev.profile_path);
  } catch (const Error& e) {
    d.fail("profile", e.what());  // names both files: the config's entry and the profile's problem
  }
  return dev;
}

// One [[token]]; `names` and `secrets` hold those of the tokens before it.
TokenConfig read_token(TomlSection& t, std::set<std::string>& names, std::set<std::string>& secrets) {
  TokenConfig tok;
  tok.name = t.text("name", "", 64);
  if (!is_safe_name(tok.name)) t.fail("name", "\"" + tok.name + "\": 1 to 64 letters, digits, '-', '_', '.'");
  if (!names.insert(tok.name).second) t.fail("name", "\"" + tok.name + "\" is used by another token");
  tok.token = t.text("token", "", 256);
  if (tok.token.size() < 16) t.fail("token", "must be at least 16 characters");
  for (const char ch : tok.token) {
    if (static_cast<unsigned char>(ch) <= ' ' || static_cast<unsigned char>(ch) >= 127)
      t.fail("token", "printable ASCII without spaces only");
  }
  if (!secrets.insert(tok.token).second) t.fail("token", "the same secret is used by another token");
  tok.role = t.choice("role", Role::kiosk, kRoleNames);
  t.reject_unknown();
  return tok;
}

// A webhook's URL split into what a client connects to and the path it posts to. Only what a
// shop's receiver needs: no user:password@ (the secret authenticates), no fragment.
void split_notify_url(const TomlSection& s, NotifyConfig& n) {
  const std::string& url = n.url;
  const std::size_t sep = url.find("://");
  std::string scheme = sep == std::string::npos ? "" : url.substr(0, sep);
  for (char& ch : scheme) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  if (scheme != "http" && scheme != "https")
    s.fail("url", "\"" + url + "\": expected http://HOST[:PORT]/PATH or https://HOST[:PORT]/PATH");
  for (const char ch : url) {
    if (static_cast<unsigned char>(ch) <= ' ' || static_cast<unsigned char>(ch) >= 127)
      s.fail("url", "\"" + url + "\": spaces, control and non-ASCII characters must be %-encoded");
  }
  const std::size_t host_start = sep + 3;
  const std::size_t path_start = std::min(url.find_first_of("/?", host_start), url.size());
  const std::string authority = url.substr(host_start, path_start - host_start);
  if (authority.find('@') != std::string::npos)
    s.fail("url", "no user:password@ in the URL: set secret, and the receiver checks X-Popcut-Signature");
  if (url.find('#') != std::string::npos) s.fail("url", "a URL fragment (#...) is never sent: remove it");
  // [v6]:port, host:port or host.
  std::string host = authority, port_text;
  if (!authority.empty() && authority.front() == '[') {
    const std::size_t close = authority.find(']');
    if (close == std::string::npos) s.fail("url", "\"" + url + "\": an IPv6 address needs its closing ']'");
    host = authority.substr(1, close - 1);
    if (close + 1 < authority.size()) {
      if (authority[close + 1] != ':') s.fail("url", "\"" + url + "\": expected ':' and a port after ']'");
      port_text = authority.substr(close + 2);
    }
    unsigned char addr[sizeof(in6_addr)];
    if (::inet_pton(AF_INET6, host.c_str(), addr) != 1) s.fail("url", "\"" + host + "\" is not an IPv6 address");
  } else if (const std::size_t colon = authority.find(':'); colon != std::string::npos) {
    host = authority.substr(0, colon);
    port_text = authority.substr(colon + 1);
  }
  if (host.empty() ||
      host.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789.-:") != std::string::npos)
    s.fail("url", "\"" + url + "\": no host name or address");
  int port = scheme == "https" ? 443 : 80;
  if (authority.find(':') != std::string::npos && authority.back() != ']') {
    if (port_text.empty() || port_text.size() > 5 || port_text.find_first_not_of("0123456789") != std::string::npos ||
        std::stoi(port_text) < 1 || std::stoi(port_text) > 65535)
      s.fail("url", "\"" + url + "\": the port must be 1 to 65535");
    port = std::stoi(port_text);
  }
  const bool v6 = host.find(':') != std::string::npos;
  n.origin = scheme + "://" + (v6 ? "[" + host + "]" : host) + ":" + std::to_string(port);
  n.path = path_start < url.size() ? url.substr(path_start) : "/";
  if (n.path.front() == '?') n.path = "/" + n.path;
}

// [[notify]] events: names from kEventKindNames, each once; every event when absent.
std::vector<EventKind> notify_events(TomlSection& s) {
  std::vector<EventKind> out;
  const toml::array* list = s.array("events");
  if (!list) {
    for (const auto& [kind, name] : kEventKindNames.entries) out.push_back(kind);
    return out;
  }
  if (list->empty()) s.fail("events", "empty: name the events to send (" + kEventKindNames.list(", ") + ")");
  for (const toml::node& e : *list) {
    const std::optional<std::string> name = e.value<std::string>();
    const std::optional<EventKind> kind = name ? kEventKindNames.find(*name) : std::nullopt;
    if (!e.is_string() || !kind)
      s.fail("events", (e.is_string() ? "\"" + *name + "\" is not an event" : std::string("expected strings")) +
                           " (known: " + kEventKindNames.list(", ") + ")");
    if (std::find(out.begin(), out.end(), *kind) != out.end()) s.fail("events", "\"" + *name + "\" is listed twice");
    out.push_back(*kind);
  }
  return out;
}

// One [[notify]].
NotifyConfig read_notify(TomlSection& s, const std::string& source) {
  NotifyConfig n;
  n.url = s.text("url", "", 2048);
  if (n.url.empty()) s.fail("url", "missing: where to POST the events (http://HOST:PORT/PATH)");
  split_notify_url(s, n);
  n.events = notify_events(s);
  n.secret = s.text("secret", "", 256);
  if (s.node("secret") && n.secret.size() < 16) s.fail("secret", "must be at least 16 characters");
  n.timeout_s = s.number("timeout_s", 5, 0.1, 300);
  n.retries = s.integer("retries", 3, 0, 20);
  const bool https = n.origin.rfind("https", 0) == 0;
  n.ca_file = s.node("ca_file") ? resolve(s.text("ca_file", "", 4096), source) : "";
  if (!n.ca_file.empty() && !https) s.fail("ca_file", "applies to https:// URLs only");
  std::error_code ec;
  if (!n.ca_file.empty() && !std::filesystem::is_regular_file(n.ca_file, ec))
    s.fail("ca_file", "\"" + n.ca_file + "\" is not a file");
#ifndef CPPHTTPLIB_OPENSSL_SUPPORT
  if (https) s.fail("url", "this popcutd was built without TLS (cpp-httplib without OpenSSL): use http://");
#endif
  s.reject_unknown();
  return n;
}

// The document's sections: [server] and [limits] tables, [[device]] and [[token]] arrays of tables.
class ConfigSections {
 public:
  ConfigSections(const toml::table& root, const std::string& source) : root_(root), source_(source) {
    for (const auto& [k, v] : root) {
      const std::string key(k.str());
      if (key != "server" && key != "limits" && key != "device" && key != "token" && key != "notify") {
        throw Error(ErrorCode::invalid_input, source, "[" + key + "]",
                    "unknown section (expected server, limits, [[device]], [[token]], [[notify]])");
      }
    }
  }
  TomlSection table(const std::string& name) const {
    const toml::node* n = root_.get(name);
    if (n && !n->is_table()) throw Error(ErrorCode::invalid_input, source_, "[" + name + "]", "expected a table");
    return TomlSection(n ? n->as_table() : nullptr, name, source_);
  }
  // Each entry a section of its own, named "device.0", "device.1" ...
  std::vector<TomlSection> entries(const std::string& name) const {
    std::vector<TomlSection> out;
    const toml::node* n = root_.get(name);
    if (!n) return out;
    if (!n->is_array_of_tables())
      throw Error(ErrorCode::invalid_input, source_, "[[" + name + "]]", "expected [[" + name + "]] tables");
    std::size_t i = 0;
    for (const toml::node& e : *n->as_array())
      out.emplace_back(e.as_table(), name + "." + std::to_string(i++), source_);
    return out;
  }

 private:
  const toml::table& root_;
  const std::string& source_;
};

}  // namespace

const char* to_string(Role role) { return kRoleNames.name(role).data(); }

bool is_safe_name(const std::string& name) {
  if (name.empty() || name.size() > 64 || name.front() == '.' || name.front() == ' ' || name.back() == ' ')
    return false;
  for (const char ch : name) {
    const auto c = static_cast<unsigned char>(ch);
    if (!(std::isalnum(c) || c == '-' || c == '_' || c == '.' || c == ' ')) return false;
  }
  return name.find("..") == std::string::npos;
}

bool is_job_label(const std::string& name) {
  if (name.empty() || name.front() == ' ' || name.back() == ' ' || name.front() == '.') return false;
  // Never a path, should a name ever reach a file system (exports, logs that get split on '/').
  if (name.find_first_of("/\\") != std::string::npos || name.find("..") != std::string::npos) return false;
  // Spaces of any kind at either end make two names look alike.
  const auto blank = [](char32_t cp) {
    return cp == 0x20 || cp == 0xa0 || cp == 0x1680 || (cp >= 0x2000 && cp <= 0x200b) || cp == 0x202f || cp == 0x205f ||
           cp == 0x3000;
  };
  const std::optional<std::u32string> cps = decode_utf8(name);
  if (!cps) return false;
  for (const char32_t cp : *cps) {
    if (cp < 0x20 || (cp >= 0x7f && cp <= 0x9f)) return false;  // control characters
    if ((cp >= 0x202a && cp <= 0x202e) || (cp >= 0x2066 && cp <= 0x2069) || cp == 0x200e || cp == 0x200f ||
        cp == 0x061c)
      return false;                                  // bidi
    if (cp == 0xfeff) return false;                  // byte-order mark
    if (cp == 0x2028 || cp == 0x2029) return false;  // line breaks
  }
  return cps->size() <= 64 && !blank(cps->front()) && !blank(cps->back());
}

std::string job_label_from(const std::string& name) {
  if (is_job_label(name)) return name;
  std::size_t end = 0;
  for (int chars = 0; chars < 63 && end < name.size(); ++chars) {
    ++end;
    while (end < name.size() && (static_cast<unsigned char>(name[end]) & 0xc0) == 0x80)
      ++end;  // UTF-8 continuation bytes
  }
  if (end >= name.size()) return "";  // not too long: refused for another reason
  std::string cut = name.substr(0, end);
  while (!cut.empty() && cut.back() == ' ') cut.pop_back();
  cut += "\u2026";
  return is_job_label(cut) ? cut : "";
}

DaemonConfig parse_daemon_config(const std::string& text, const std::string& source) {
  const toml::table root = parse_toml(text, source);
  const ConfigSections sections(root, source);
  DaemonConfig c;
  c.source = source;
  read_server(sections.table("server"), source, c);
  c.limits = read_limits(sections.table("limits"));
  std::set<std::string> device_names;
  for (TomlSection& d : sections.entries("device")) c.devices.push_back(read_device(d, source, device_names));
  if (c.devices.empty())
    throw Error(ErrorCode::invalid_input, source, "[[device]]", "no devices: add at least one [[device]]");
  std::set<std::string> token_names, secrets;
  for (TomlSection& t : sections.entries("token")) c.tokens.push_back(read_token(t, token_names, secrets));
  if (c.tokens.empty())
    throw Error(ErrorCode::invalid_input, source, "[[token]]", "no tokens: add at least one [[token]]");
  for (TomlSection& n : sections.entries("notify")) c.notify.push_back(read_notify(n, source));
  return c;
}

DaemonConfig load_daemon_config(const std::string& path) {
  return parse_daemon_config(read_text_file(path, 1 << 20), path);
}

}  // namespace popcut::daemon

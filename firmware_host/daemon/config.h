// popcutd's configuration (popcutd.toml): listen address, data directory, devices, tokens, limits.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "popcut/drivers/material.h"
#include "popcut/drivers/profile.h"
#include "notify_event.h"
#include "popcut/names.h"

namespace popcut::daemon {

enum class Role { kiosk, admin };
inline constexpr auto kRoleNames = enum_names<Role>({{Role::kiosk, "kiosk"}, {Role::admin, "admin"}});
const char* to_string(Role role);

struct DeviceConfig {
  std::string name;          // [A-Za-z0-9_-], unique
  std::string profile_path;  // resolved against the config file's directory
  drivers::DeviceProfile profile;
  std::string transport;  // a device string: sim, file:PATH, serial:..., usb:... (drivers/device.h)
  // sim only: the simulated motion takes this many times longer, and each simulated second takes
  // sim_time_scale wall-clock seconds (0: as fast as the host can go). A slow sim device gives
  // tests and demos a cut long enough to watch, cancel or kill.
  double sim_slowdown = 1;
  double sim_time_scale = 0;
  // Metres of knife-down cut a blade is good for: past it the device shows blade.worn and
  // blade_worn is raised once (until an admin resets the counters). Unset: never worn.
  std::optional<double> blade_life_m;
  // After each job the device waits in awaiting_sheet until someone confirms a fresh sheet
  // (docs/api.md "Sheets"). Default: true for every transport but sim.
  bool confirm_sheet = true;
};

// One [[notify]]: a webhook that is POSTed the events it names (docs/api.md "Webhooks").
struct NotifyConfig {
  std::string url;     // as written: http://HOST[:PORT][/PATH] or https://...
  std::string origin;  // scheme://host:port, what an HTTP client connects to
  std::string path;    // from the first '/' (with any query); "/" when the URL has none
  std::vector<EventKind> events;
  std::string secret;    // "" none: no X-Popcut-Signature; else at least 16 characters
  double timeout_s = 5;  // to connect, and for each read and write of a request
  int retries = 3;       // further attempts after a failed one, with growing pauses
  std::string ca_file;   // https: the certificates to trust instead of the system's ("" system's)
};

struct TokenConfig {
  std::string name;   // who: jobs are owned by this name
  std::string token;  // the bearer secret, at least 16 characters
  Role role = Role::kiosk;
};

struct Limits {
  std::size_t upload_bytes = 1 << 20;    // request bodies
  int model_cells = 100000;              // voxel models: width x depth x height
  int pattern_faces = 5000;              // face models: edits (or faces); every model: faces of its pattern
  int queue_length = 10000;              // jobs not yet finished (queued .. cutting, interrupted)
  std::int64_t mesh_triangles = 200000;  // uploaded meshes (after splitting polygons into triangles)
  std::size_t preview_cache_bytes = std::size_t{32} << 20;  // rendered previews kept in memory (LRU)
  int design_sessions = 64;  // designer drafts kept live in memory with their undo history (LRU)
};

struct DaemonConfig {
  std::string source;  // the file read
  std::string listen = "127.0.0.1";
  int port = 8742;  // 0: any free port (popcutd prints the one it bound)
  std::string data_dir;
  std::string kiosk_dir;     // the kiosk page's files; default: the source tree's firmware_host/kiosk
  std::string examples_dir;  // example models offered by the kiosk; default: the source tree's examples
  std::string three_dir;     // three.js for the designer's 3D view; default: Debian's libjs-three
  // httplib serves a connection on one thread for its whole life: enough threads for a
  // classroom of kiosk tablets plus a few idle sockets (an idle thread: ~20 KB resident, docs/api.md).
  int http_threads = 64;
  int keep_alive_timeout_s = 2;  // an idle kept-alive connection is closed after this
  int header_timeout_s = 5;      // a request's line and headers must arrive within this
  int listen_backlog = 1024;     // new connections the kernel holds until they are taken up (capped by somaxconn)
  int planners = 1;
  // Materials jobs may name ([server] materials_dir, default materials/ beside this file; none
  // when that default is missing). Loaded and checked at start-up like the profiles.
  std::string materials_dir;
  std::vector<drivers::Material> materials;
  std::vector<DeviceConfig> devices;
  std::vector<TokenConfig> tokens;
  std::vector<NotifyConfig> notify;
  Limits limits;
};

// Reads and checks the whole file; throws popcut::Error(invalid_input) naming the file,
// "[section] key" and what was expected. Device profiles are loaded (and checked) too.
DaemonConfig parse_daemon_config(const std::string& text, const std::string& source);
DaemonConfig load_daemon_config(const std::string& path);

// Names of devices, tokens and uploaded files: letters, digits, '-', '_', '.', ' ' (not leading),
// 1..64 bytes; nothing a path or a shell could take as structure.
bool is_safe_name(const std::string& name);

// A job's name is a label people read ("Castle", "城", "café 2"): valid UTF-8, 1 to 64
// characters, no control characters or bidirectional overrides (which could disguise a name in
// the kiosk's list), no space at either end, and nothing of a path ('/', '\\', '..', leading '.').
bool is_job_label(const std::string& name);
// A model's name as a job label: itself when it is one; a longer one cut to 63 characters and
// "…" (at a character, blanks at the cut dropped); "" when it cannot be one (a path, controls).
std::string job_label_from(const std::string& name);

}  // namespace popcut::daemon

// popcut devices: serial ports (with USB ids) and USB devices that match a shipped device profile.
#include "cli/devices.h"

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <map>

#include "cli/common.h"
#include "config_dir.h"
#include "popcut/drivers/device.h"
#include "popcut/drivers/device_plan.h"
#include "popcut/drivers/ports.h"
#include "popcut/drivers/profile.h"
#include "popcut/error.h"

namespace popcut::cli {
namespace {

using nlohmann::json;

// A shipped profile naming a USB id: its file and the device's name ([device] name).
struct KnownProfile {
  std::string path, name;
};

// USB id -> profiles listing it in [transport] usb_ids.
std::map<std::string, std::vector<KnownProfile>> known_ids() {
  std::map<std::string, std::vector<KnownProfile>> ids;
  std::string dir;
  try {
    dir = find_config_dir("devices");
  } catch (const Error&) {
    return ids;  // no profiles installed: no device is known, every one is listed by its ids alone
  }
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
    if (e.path().extension() != ".toml") continue;
    try {
      const drivers::DeviceProfile p = drivers::load_profile(e.path().string());
      for (const std::string& id : p.transport.usb_ids) ids[id].push_back({e.path().string(), p.name});
    } catch (const std::exception&) {
      // A broken profile is reported when it is used, not here.
    }
  }
  return ids;
}

int run_devices(const DevicesCommand& s) {
  return run_guarded(s.json_out, [&] {
    const auto ids = known_ids();
    std::vector<drivers::SerialPortInfo> ports;
    const drivers::TransportStatus sst = drivers::list_serial_ports(ports);
    std::vector<drivers::UsbDeviceInfo> usb;
    const drivers::TransportStatus ust = drivers::list_usb_devices(usb);
    json jp = json::array(), ju = json::array();
    for (const auto& p : ports) {
      json j = {{"device", "serial:" + p.path}, {"path", p.path}, {"description", p.description}};
      if (p.vid) {
        j["usb_id"] = drivers::usb_id_string(*p.vid, *p.pid);
        j["serial_number"] = p.serial_number;
      }
      jp.push_back(j);
    }
    for (const auto& u : usb) {
      const std::string id = drivers::usb_id_string(u.vid, u.pid);
      const auto it = ids.find(id);
      if (it == ids.end() && !s.all_usb) continue;
      json paths = json::array(), names = json::array();
      for (const KnownProfile& k : it == ids.end() ? std::vector<KnownProfile>{} : it->second) {
        paths.push_back(k.path);
        names.push_back(k.name);
      }
      ju.push_back({{"device", "usb:" + id + (u.serial_number.empty() ? "" : ":" + u.serial_number)},
                    {"usb_id", id},
                    {"bus", u.bus},
                    {"address", u.address},
                    {"product", u.product},
                    {"serial_number", u.serial_number},
                    {"bulk_out", u.has_bulk_out},
                    {"profiles", paths},
                    {"names", names}});
    }
    if (s.json_out) {
      json r = {{"format", "popcut.devices.v1"}, {"serial", jp}, {"usb", ju}};
      if (!sst.ok()) r["serial_error"] = sst.message;
      if (!ust.ok()) r["usb_error"] = ust.message;
      print_json_line(r);
      return static_cast<int>(kOk);
    }
    std::cout << "serial ports:" << (jp.empty() ? " none" : "") << "\n";
    if (!sst.ok()) std::cout << "  (" << sst.message << ")\n";
    for (const auto& j : jp) {
      std::cout << "  " << j["device"].get<std::string>();
      if (j.contains("usb_id"))
        std::cout << "  usb " << j["usb_id"].get<std::string>() << "  serial " << j["serial_number"].get<std::string>();
      std::cout << "  " << j["description"].get<std::string>() << "\n";
    }
    std::cout << (s.all_usb ? "USB devices:" : "USB cutters (devices matching a profile's usb_ids):")
              << (ju.empty() ? " none" : "") << "\n";
    if (!ust.ok()) std::cout << "  (" << ust.message << ")\n";
    for (const auto& j : ju) {
      std::cout << "  " << j["device"].get<std::string>() << "  bus " << j["bus"] << " address " << j["address"] << "  "
                << j["product"].get<std::string>();
      // By the device's name first: "Silhouette Cameo 4 (profile .../silhouette-cameo4.toml)".
      for (std::size_t i = 0; i < j["profiles"].size(); ++i) {
        std::cout << "  " << j["names"][i].get<std::string>() << " (profile " << j["profiles"][i].get<std::string>()
                  << ")";
      }
      std::cout << "\n";
    }
    return static_cast<int>(kOk);
  });
}

}  // namespace

std::vector<NamedMedia> profile_media() {
  std::vector<NamedMedia> media;
  std::string dir;
  try {
    dir = find_config_dir("devices");
  } catch (const Error&) {
    return media;
  }
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
    if (e.path().extension() != ".toml") continue;
    try {
      media.push_back(drivers::media_of(drivers::load_profile(e.path().string()), e.path().stem().string()));
    } catch (const std::exception&) {
      // As in known_ids: a broken profile is reported when it is used.
    }
  }
  std::sort(media.begin(), media.end(), [](const NamedMedia& a, const NamedMedia& b) { return a.name < b.name; });
  return media;
}

void add_devices_command(CLI::App& app, DevicesCommand& s) {
  s.app =
      app.add_subcommand("devices",
                         "List serial ports (with the USB ids of adapters) and USB cutters matching a known profile,\n"
                         "as device strings for `popcut cut --device`.");
  s.app->add_flag("--json", s.json_out, "Print JSON (popcut.devices.v1)");
  s.app->add_flag("--all-usb", s.all_usb, "List every USB device, not only those a profile names");
}

std::optional<int> run_devices_command(const DevicesCommand& s) {
  if (s.app && *s.app) return run_devices(s);
  return std::nullopt;
}

}  // namespace popcut::cli

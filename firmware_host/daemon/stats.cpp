// Shop statistics from the job history: per local day and per device (docs/api.md "Statistics").
#include "stats.h"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <map>

namespace popcut::daemon {
namespace {

std::tm local_tm(double unix_s) {
  const std::time_t t = static_cast<std::time_t>(std::floor(unix_s));
  std::tm tm{};
  localtime_r(&t, &tm);
  return tm;
}

std::string date_of(const std::tm& tm) {
  char buf[16];
  std::strftime(buf, sizeof buf, "%Y-%m-%d", &tm);
  return buf;
}

// The local date `back` days before the one holding `now_s` (mktime normalises the day of the month).
std::tm days_before(double now_s, int back) {
  std::tm tm = local_tm(now_s);
  tm.tm_mday -= back;
  tm.tm_hour = 12;  // noon: a daylight-saving change at midnight cannot move it to another day
  tm.tm_min = tm.tm_sec = 0;
  tm.tm_isdst = -1;
  std::mktime(&tm);
  return tm;
}

DeviceStats& device_entry(std::vector<DeviceStats>& devices, const std::string& name) {
  for (DeviceStats& d : devices) {
    if (d.name == name) return d;
  }
  devices.push_back({name, false, 0, 0, 0, 0, 0, std::nullopt});
  return devices.back();
}

}  // namespace

double stats_window_start(int days, double now_s) {
  std::tm tm = days_before(now_s, days - 1);
  tm.tm_hour = tm.tm_min = tm.tm_sec = 0;
  tm.tm_isdst = -1;
  return static_cast<double>(std::mktime(&tm));
}

StatsReport job_stats(const std::vector<StatsRow>& rows, int days, double now_s,
                      const std::vector<std::string>& configured_devices) {
  StatsReport r;
  r.since_s = stats_window_start(days, now_s);
  std::map<std::string, std::size_t> day_index;
  for (int back = days - 1; back >= 0; --back) {
    const std::string date = date_of(days_before(now_s, back));
    day_index[date] = r.days.size();
    r.days.push_back({date});
  }
  const auto day = [&](double t) -> DayStats* {
    if (t < r.since_s || t <= 0) return nullptr;
    const auto it = day_index.find(date_of(local_tm(t)));
    return it == day_index.end() ? nullptr : &r.days[it->second];
  };
  for (const std::string& name : configured_devices) r.devices.push_back({name, true, 0, 0, 0, 0, 0, std::nullopt});
  const std::size_t configured = r.devices.size();
  for (const StatsRow& row : rows) {
    if (DayStats* d = day(row.created_at)) ++d->submitted;
    DayStats* ended = is_terminal(row.state) ? day(row.finished_at) : nullptr;
    if (ended) {
      if (row.state == JobState::done) ++ended->done;
      if (row.state == JobState::failed) ++ended->failed;
      if (row.state == JobState::cancelled) ++ended->cancelled;
    }
    if (row.device.empty()) continue;
    const bool cut_in_window = row.state == JobState::cutting || (row.last_cut_at >= r.since_s && row.last_cut_at > 0);
    if (!ended && !cut_in_window) continue;
    DeviceStats& dev = device_entry(r.devices, row.device);
    if (ended) {
      ++dev.jobs;
      if (row.state == JobState::done) ++dev.done;
      if (row.state == JobState::failed) ++dev.failed;
      if (row.state == JobState::cancelled) ++dev.cancelled;
    }
    if (cut_in_window) {
      dev.cutting_s += row.cutting_s;
      if (row.state == JobState::cutting && row.run_started_at > 0)
        dev.cutting_s += std::max(0.0, now_s - row.run_started_at);
    }
  }
  std::sort(r.devices.begin() + static_cast<std::ptrdiff_t>(configured), r.devices.end(),
            [](const DeviceStats& a, const DeviceStats& b) { return a.name < b.name; });
  for (DeviceStats& dev : r.devices) {
    if (dev.done + dev.failed > 0)
      dev.failure_rate = static_cast<double>(dev.failed) / static_cast<double>(dev.done + dev.failed);
  }
  return r;
}

}  // namespace popcut::daemon

// popcutd soak on loopback: sim cutters, idempotent submissions, a seeded driver that pauses, cancels, confirms sheets
// and kill -9s popcutd; then an audit for lost jobs, strokes cut twice unasked and cuts onto unconfirmed sheets.
#include <benchmark/benchmark.h>
#include <signal.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <random>
#include <set>
#include <sstream>
#include <thread>
#include <vector>

#include "bench_table.h"
#include "popcutd_process.h"
#include "soak_log_audit.h"

namespace {

using nlohmann::json;
using popcut::bench::LogAudit;
using popcut::testing::PopcutdProcess;
using popcut::testing::read_file;
using popcut::testing::TempDir;
using Clock = std::chrono::steady_clock;

const std::string kSource = POPCUT_SOURCE_DIR;
const std::string kKiosk = "kiosk-0123456789abcdef";
const std::string kAdmin = "admin-0123456789abcdef";

double env_or(const char* name, double fallback) {
  const char* v = std::getenv(name);
  return v && *v ? std::atof(v) : fallback;
}

struct Options {
  int devices = 8, jobs_per_device = 200;
  double kill_every_s = 2;
  int max_kills = -1;  // -1: one every kill_every_s (jittered) while there is work
  std::uint64_t seed = 1;
  // box.json (~6.8 s modelled) cuts in ~0.14 s, so kills land mid-cut; its 8 strokes fit the sim's 1 KiB buffer at
  // once, so resumes and pauses mid-plan need a bigger model (POPCUT_SOAK_MODEL=voxel/castle.json: 93 strokes).
  double time_scale = 0.02;
  double give_up_s = 1200;  // a daemon that stops making progress ends the soak (and shows as jobs lost)
  int window = 3;           // unfinished jobs a submitter keeps per device: spreads submissions over the run
  std::string model = "voxel/box.json";  // under examples/
};

// Each job's fate, drawn from the seed and the job's own key only, so a seed gives the same plans whatever the timing.
struct Plan {
  bool cancel = false, cancel_waiting = false;
  double cancel_at = 0, pause_at = 0;  // fractions of the strokes sent when the driver acts
  int pauses = 0;
  double continue_after_s = 0;
  bool move = false;
};

Plan plan_for(std::uint64_t seed, int index) {
  const std::uint64_t mixed = seed * std::uint64_t{1000003} + static_cast<std::uint64_t>(index);
  std::mt19937_64 r(mixed);
  std::uniform_real_distribution<double> u(0, 1);
  Plan p;
  p.cancel = u(r) < 0.05;
  p.cancel_waiting = u(r) < 0.4;  // the rest are cancelled mid-cut
  p.cancel_at = u(r) * 0.8;
  p.pauses = u(r) < 0.15 ? 1 + static_cast<int>(u(r) * 2) : 0;
  p.pause_at = u(r) * 0.8;
  p.continue_after_s = 0.05 + u(r) * 0.4;
  p.move = u(r) < 0.03;
  return p;
}

std::string key_of(std::uint64_t seed, int index) {
  return "soak-" + std::to_string(seed) + "-" + std::to_string(index);
}

std::string config(const TempDir& dir, const Options& o) {
  std::ostringstream c;
  c << "[server]\ndata_dir = \"x\"\nhttp_threads = 64\nplanners = 2\n";
  for (int d = 0; d < o.devices; ++d) {
    c << "[[device]]\nname = \"d" << d << "\"\nprofile = \"" << kSource << "/configs/devices/sim.toml\"\n"
      << "transport = \"sim\"\nconfirm_sheet = true\nsim_time_scale = " << o.time_scale << "\n";
  }
  c << "[[token]]\nname = \"kiosk\"\ntoken = \"" << kKiosk << "\"\n"
    << "[[token]]\nname = \"admin\"\ntoken = \"" << kAdmin << "\"\nrole = \"admin\"\n";
  return dir.write("soak.toml", c.str());
}

struct Answer {
  int status = 0;  // 0: no answer (popcutd down, being restarted, or killed mid-request)
  json body;
};

// One request on a fresh connection to whatever port popcutd listens on now: a kill never strands a kept-alive one.
Answer call(int port, const std::string& method, const std::string& path, const std::string& token,
            const std::string& body = "", const httplib::Headers& extra = {}) {
  if (port <= 0) return {};
  httplib::Client c("127.0.0.1", port);
  c.set_connection_timeout(1);
  c.set_read_timeout(30);
  httplib::Headers h{{"Authorization", "Bearer " + token}};
  h.insert(extra.begin(), extra.end());
  const httplib::Result r = method == "GET"     ? c.Get(path, h)
                            : method == "PATCH" ? c.Patch(path, h, body, "application/json")
                                                : c.Post(path, h, body, "application/json");
  if (!r) return {};
  return {r->status, json::parse(r->body, nullptr, false)};
}

struct Counts {
  std::atomic<int> kills{0}, outages{0}, pauses{0}, continues{0}, cancels{0}, confirms{0}, confirm_refused{0};
  std::atomic<int> resumes{0}, moves{0}, answers_lost{0}, replayed{0}, submit_errors{0};
};

// Everything the submitters and the driver share.
struct Soak {
  Options o;
  TempDir dir{"popcutd-soak"};
  std::string cfg, data;
  std::unique_ptr<PopcutdProcess> daemon;  // the driver's alone: it kills and restarts it
  std::atomic<int> port{0};
  std::atomic<int> submitters_left{0};
  std::atomic<bool> stop{false};
  Counts n;
  std::mutex m;
  std::set<std::int64_t> unfinished;  // in the driver's latest snapshot
  std::uint64_t snapshot_seq = 0;
  std::vector<std::int64_t> answered;  // per key index: the job id its submission was answered with (0: none)
  std::vector<std::string> errors;
};

// Submits one device's jobs, each with its own Idempotency-Key; an answer lost to a kill is asked again with that key.
void submit_device(Soak& s, int d) {
  const json box = json::parse(read_file(kSource + "/examples/" + s.o.model));
  std::vector<std::pair<std::int64_t, std::uint64_t>> mine;  // job id, snapshot count when it was answered
  const auto outstanding = [&] {
    std::lock_guard lock(s.m);
    int n = 0;
    // A job answered after the latest snapshot started is not in it yet, but is not finished either.
    for (const auto& [id, seq] : mine) n += s.unfinished.count(id) || s.snapshot_seq < seq + 2;
    return n;
  };
  for (int i = 0; i < s.o.jobs_per_device && !s.stop; ++i) {
    while (!s.stop && outstanding() >= s.o.window) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    const int index = d * s.o.jobs_per_device + i;
    const std::string key = key_of(s.o.seed, index);
    const std::string body = json{{"device", "d" + std::to_string(d)}, {"name", key}, {"model", box}}.dump();
    for (int attempt = 0; !s.stop; ++attempt) {
      const Answer a = call(s.port, "POST", "/api/v1/jobs", kKiosk, body, {{"Idempotency-Key", key}});
      if (a.status == 201 || a.status == 200) {
        if (a.status == 200) ++s.n.replayed;
        std::lock_guard lock(s.m);
        s.answered[static_cast<std::size_t>(index)] = a.body.value("id", std::int64_t{0});
        mine.emplace_back(s.answered[static_cast<std::size_t>(index)], s.snapshot_seq);
        break;
      }
      if (a.status == 0 || a.status == 503) {  // popcutd down or restarting: the same key again shortly
        if (attempt == 0 && a.status == 0) ++s.n.answers_lost;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        continue;
      }
      ++s.n.submit_errors;
      std::lock_guard lock(s.m);
      s.errors.push_back(key + ": " + std::to_string(a.status) + " " + a.body.dump());
      break;
    }
  }
  --s.submitters_left;
}

void restart(Soak& s, bool asked) {
  s.port = 0;  // submitters wait instead of talking to a port that is going away
  if (asked) ++s.n.kills;
  s.daemon->stop(SIGKILL);
  s.daemon = std::make_unique<PopcutdProcess>(POPCUTD, s.cfg, s.data);  // throws, with its log, if it cannot start
  s.port = s.daemon->port();
}

// What the driver did to each job so far.
struct Done {
  std::map<std::int64_t, int> pauses;
  std::map<std::int64_t, Clock::time_point> paused_since;
  std::set<std::int64_t> moved, cancelled;
};

// The driver's actions on one unfinished job, by its state and its plan.
void act_on(Soak& s, const json& j, const Plan& p, Done& done) {
  const std::int64_t id = j.value("id", std::int64_t{0});
  const std::string state = j.value("state", ""), path = "/api/v1/jobs/" + std::to_string(id);
  const int sent = j.value("strokes_sent", 0), total = std::max(1, j.value("strokes_total", 1));
  const bool waiting = state == "queued" || state == "planning" || state == "ready";
  const auto now = Clock::now();
  // Cancelled once: a second cancel of a cut would give up waiting for a device that holds the line.
  if (p.cancel && !done.cancelled.count(id) &&
      ((p.cancel_waiting && waiting) || (state == "cutting" && sent >= p.cancel_at * total))) {
    if (const int st = call(s.port, "POST", path + "/cancel", kAdmin).status; st == 202 || st == 200) {
      ++s.n.cancels;
      done.cancelled.insert(id);
    }
  } else if (state == "interrupted") {
    if (call(s.port, "POST", path + "/resume", kAdmin, "{}").status == 202) ++s.n.resumes;
  } else if (state == "paused") {
    const auto since = done.paused_since.emplace(id, now).first->second;  // also a pause found after a restart
    if (now - since >= std::chrono::duration<double>(p.continue_after_s) &&
        call(s.port, "POST", path + "/continue", kAdmin).status == 200) {
      ++s.n.continues;
      done.paused_since.erase(id);
    }
  } else if (done.pauses[id] < p.pauses && (state == "ready" || (state == "cutting" && sent >= p.pause_at * total))) {
    if (const int st = call(s.port, "POST", path + "/pause", kAdmin).status; st == 202 || st == 200) {
      ++s.n.pauses;
      ++done.pauses[id];
    }
  } else if (p.move && waiting && done.moved.insert(id).second) {
    if (call(s.port, "PATCH", path, kAdmin, json{{"priority", static_cast<int>(id % 7) - 3}}.dump()).status == 200)
      ++s.n.moves;
  }
}

// Confirms a fresh sheet on each device that waits for one, and only those.
void confirm_sheets(Soak& s, const json& devices, LogAudit& audit) {
  for (const json& d : devices.value("devices", json::array())) {
    if (d.value("sheet", "") != "awaiting_sheet") continue;
    const json used_by = d.value("sheet_job", json());
    const int st = call(s.port, "POST", "/api/v1/devices/" + d.value("name", "") + "/sheet", kAdmin).status;
    // Noted before the log is read again, so before any run it let start; an answer lost to a kill may have confirmed.
    if (st == 200 || st == 0)
      audit.confirmed(d.value("name", ""), used_by.is_number() ? used_by.get<std::int64_t>() : 0);
    if (st == 200) ++s.n.confirms;
    if (st == 409) ++s.n.confirm_refused;  // a paused or interrupted job's half-cut sheet is still on it
  }
}

// The driver: snapshots, the log read, actions, kills; until every submission is in and every job is final.
void drive(Soak& s, LogAudit& audit) {
  std::mt19937_64 rng(s.o.seed);
  std::uniform_real_distribution<double> jitter(0.5, 1.5);
  Done done;
  const auto t0 = Clock::now();
  auto next_kill = t0 + std::chrono::duration<double>(s.o.kill_every_s * jitter(rng));
  auto last_answer = t0;
  const std::string unfinished_q = "/api/v1/jobs?limit=10000&state=queued,planning,ready,cutting,paused,interrupted";
  while (Clock::now() - t0 < std::chrono::duration<double>(s.o.give_up_s)) {
    const Answer jobs = call(s.port, "GET", unfinished_q, kAdmin);
    const Answer devices = call(s.port, "GET", "/api/v1/devices", kAdmin);
    audit.read_new();  // after the snapshot: every run it shows has its line read (see LogAudit::observe)
    if (jobs.status != 200 || devices.status != 200) {
      if (Clock::now() - last_answer > std::chrono::seconds(5)) {  // it died without being asked: a defect too
        ++s.n.outages;
        restart(s, false);
        last_answer = Clock::now();
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      continue;
    }
    last_answer = Clock::now();
    std::set<std::int64_t> ids;
    for (const json& j : jobs.body["jobs"]) {
      const std::int64_t id = j.value("id", std::int64_t{0});
      ids.insert(id);
      audit.observe(id, j.value("state", ""), j.value("strokes_sent", 0));
      const std::string name = j.value("name", "");
      const int index = std::atoi(name.substr(name.rfind('-') + 1).c_str());
      act_on(s, j, plan_for(s.o.seed, index), done);
    }
    {
      std::lock_guard lock(s.m);
      s.unfinished = ids;
      ++s.snapshot_seq;
    }
    confirm_sheets(s, devices.body, audit);
    const bool more_kills = s.o.max_kills < 0 || s.n.kills < s.o.max_kills;
    if (ids.empty() && s.submitters_left == 0 && (s.n.kills > 0 || !more_kills)) break;
    if (more_kills && Clock::now() >= next_kill) {
      restart(s, true);
      next_kill = Clock::now() + std::chrono::duration<double>(s.o.kill_every_s * jitter(rng));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  s.stop = true;
}

struct Findings {
  int lost = 0, duplicates = 0, not_final = 0, wrong_answer = 0, failed = 0, sim_mismatch = 0, wear_mismatch = 0;
  std::vector<std::string> lines;
};

// Every submission by its key: one job, answered with that id, final; done ones cut exactly their plan.
void audit_jobs(const Soak& s, const json& all, Findings& f) {
  std::map<std::string, std::vector<json>> by_key;
  for (const json& j : all) by_key[j.value("name", "")].push_back(j);
  for (int index = 0; index < s.o.devices * s.o.jobs_per_device; ++index) {
    const std::string key = key_of(s.o.seed, index);
    const std::vector<json>& js = by_key[key];
    const std::int64_t answered = s.answered[static_cast<std::size_t>(index)];
    if (js.empty()) {
      ++f.lost;
      f.lines.push_back("lost: " + key + " has no job (answered with id " + std::to_string(answered) + ")");
      continue;
    }
    if (js.size() > 1 && ++f.duplicates) f.lines.push_back("duplicate: " + key + " has " + json(js).dump());
    for (const json& j : js) {
      const std::string state = j.value("state", "");
      if (answered != j.value("id", std::int64_t{0}) && js.size() == 1 && ++f.wrong_answer)
        f.lines.push_back("answer: " + key + " was answered with id " + std::to_string(answered) + ", its job is " +
                          std::to_string(j.value("id", 0)));
      if (state == "failed") ++f.failed;
      if (state != "done" && state != "cancelled") {
        ++f.not_final;
        f.lines.push_back("not final: " + j.dump());
      }
      if (state == "done" &&
          (!j.value("sim_match", false) || j.value("strokes_sent", 0) != j.value("strokes_total", -1))) {
        ++f.sim_mismatch;
        f.lines.push_back("done but not cut as planned: " + j.dump());
      }
      // Each run counts from resume_from + 1 (only default resumes here): more than the plan is a stroke counted twice.
      if (j.value("knife_down_strokes", 0) > j.value("strokes_total", 0) && ++f.wear_mismatch)
        f.lines.push_back("wear: more knife-down strokes counted than planned: " + j.dump());
    }
  }
}

// Knife-down strokes: each device's blade counters against the sum of its jobs' (both committed in one transaction).
void audit_wear(const json& all, const json& devices, Findings& f) {
  std::map<std::string, long long> jobs_strokes, planned;
  for (const json& j : all) {
    if (!j["cut_on"].is_string()) continue;
    jobs_strokes[j["cut_on"]] += j.value("knife_down_strokes", 0LL);
    if (j.value("state", "") == "done") planned[j["cut_on"]] += j.value("strokes_total", 0LL);
  }
  std::printf("\n%-8s %14s %16s %22s\n", "device", "blade strokes", "sum of its jobs", "strokes of done jobs");
  for (const json& d : devices.value("devices", json::array())) {
    const std::string name = d.value("name", "");
    const long long blade = d["blade"].value("knife_down_strokes", 0LL);
    std::printf("%-8s %14lld %16lld %22lld\n", name.c_str(), blade, jobs_strokes[name], planned[name]);
    if (blade != jobs_strokes[name]) {
      ++f.wear_mismatch;
      f.lines.push_back("wear: " + name + " blade counts " + std::to_string(blade) + " knife-down strokes, its jobs " +
                        std::to_string(jobs_strokes[name]));
    }
  }
}

void print_evidence(const char* what, const std::vector<std::string>& lines) {
  if (lines.empty()) return;
  std::printf("\n%s (%zu):\n", what, lines.size());
  for (std::size_t i = 0; i < lines.size() && i < 20; ++i) std::printf("  %s\n", lines[i].c_str());
}

void BM_Soak(benchmark::State& state, Options o) {
  for (auto _ : state) {
    Soak s;
    s.o = o;
    s.cfg = config(s.dir, o);
    s.data = (s.dir.path() / "data").string();
    s.answered.assign(static_cast<std::size_t>(o.devices * o.jobs_per_device), 0);
    std::printf("soak: %d devices x %d jobs, kill -9 every ~%.1f s, seed %llu (POPCUT_SOAK_SEED)\n", o.devices,
                o.jobs_per_device, o.kill_every_s, static_cast<unsigned long long>(o.seed));
    std::fflush(stdout);
    s.daemon = std::make_unique<PopcutdProcess>(POPCUTD, s.cfg, s.data);
    s.port = s.daemon->port();
    LogAudit audit(s.data + ".log");  // PopcutdProcess appends every process's standard error here
    const auto t0 = Clock::now();
    s.submitters_left = o.devices;
    std::vector<std::thread> submitters;
    for (int d = 0; d < o.devices; ++d) submitters.emplace_back([&s, d] { submit_device(s, d); });
    drive(s, audit);
    for (auto& t : submitters) t.join();
    const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
    const Answer all = call(s.port, "GET", "/api/v1/jobs?limit=10000", kAdmin);
    const Answer devices = call(s.port, "GET", "/api/v1/devices", kAdmin);
    audit.read_new();
    for (const json& j : all.body.value("jobs", json::array()))
      audit.observe(j.value("id", std::int64_t{0}), j.value("state", ""), j.value("strokes_sent", 0));
    Findings f;
    audit_jobs(s, all.body.value("jobs", json::array()), f);
    audit_wear(all.body.value("jobs", json::array()), devices.body, f);
    // The whole log for whoever checks a finding by hand (the data dir goes with the soak).
    if (const char* keep = std::getenv("POPCUT_SOAK_LOG"); keep && *keep)
      std::ofstream(keep) << read_file(s.data + ".log");
    print_evidence("submission errors", s.errors);
    print_evidence("job records", f.lines);
    print_evidence("cut twice unasked (popcutd's log)", audit.cut_twice);
    print_evidence("sheet violations (popcutd's log, the driver's confirmations)", audit.sheet_violations);
    print_evidence("fresh-sheet line logged after the next job's run line (log order only)", audit.late_log);
    const auto set = [&](const char* k, double v) { state.counters[k] = v; };
    set("devices", o.devices), set("jobs", o.devices * o.jobs_per_device), set("wall_s", wall);
    set("kills", s.n.kills), set("outages", s.n.outages), set("pauses", s.n.pauses), set("continues", s.n.continues);
    set("cancels", s.n.cancels), set("confirms", s.n.confirms), set("confirm_refused", s.n.confirm_refused);
    set("resumes", s.n.resumes), set("moves", s.n.moves), set("answers_lost", s.n.answers_lost);
    set("replayed", s.n.replayed), set("runs", audit.runs), set("seed", static_cast<double>(o.seed));
    set("lost", f.lost + f.duplicates + f.not_final + f.wrong_answer + s.n.submit_errors), set("failed", f.failed);
    set("cut_twice", static_cast<double>(audit.cut_twice.size())), set("plan_mismatch", f.sim_mismatch);
    set("sheet_violations", static_cast<double>(audit.sheet_violations.size())), set("wear_mismatch", f.wear_mismatch);
    set("late_log", static_cast<double>(audit.late_log.size()));
  }
}

Options options_from_env() {
  Options o;
  o.devices = static_cast<int>(env_or("POPCUT_SOAK_DEVICES", 8));
  o.jobs_per_device = static_cast<int>(env_or("POPCUT_SOAK_JOBS_PER_DEVICE", 200));
  o.kill_every_s = env_or("POPCUT_SOAK_KILL_EVERY_S", 2);
  o.time_scale = env_or("POPCUT_SOAK_TIME_SCALE", 0.02);
  o.give_up_s = env_or("POPCUT_SOAK_GIVE_UP_S", 1200);
  if (const char* m = std::getenv("POPCUT_SOAK_MODEL"); m && *m) o.model = m;
  const char* seed = std::getenv("POPCUT_SOAK_SEED");
  o.seed = seed && *seed
               ? std::strtoull(seed, nullptr, 10)
               : static_cast<std::uint64_t>(std::chrono::system_clock::now().time_since_epoch().count() % 1000000007);
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  // BM_Soak/smoke: what ctest runs (2 devices x 5 jobs, one kill); BM_Soak/full: the soak, scaled by POPCUT_SOAK_*.
  Options full = options_from_env(), smoke = full;
  smoke.devices = 2, smoke.jobs_per_device = 5, smoke.kill_every_s = 1, smoke.max_kills = 1, smoke.give_up_s = 120;
  for (const auto& [name, o] : {std::pair{"BM_Soak/smoke", smoke}, std::pair{"BM_Soak/full", full}})
    benchmark::RegisterBenchmark(name, BM_Soak, o)->Iterations(1)->UseRealTime()->Unit(benchmark::kSecond);
  int defects = 0;
  const int rc = popcut::bench::run_with_table(argc, argv, [&](const popcut::bench::CollectingReporter& r) {
    std::printf(
        "\npopcutd soak on loopback, sim cutters with confirm_sheet. lost: submissions without exactly one "
        "final job, answered\nwith its id; cut2: runs from a stroke an earlier run certainly sent, or after "
        "done/cancelled; sheet: a job cut\nafter another's with no fresh sheet confirmed; plan: done jobs not "
        "cut as planned; wear: a device's blade != its jobs',\nor a job counting more knife-down strokes than "
        "its plan; late: fresh-sheet log lines after the next job's run line\n");
    const char* head[] = {"dev x job", "wall s", "kills",  "pauses", "cont", "cancel", "sheets", "refused", "resume",
                          "moves",     "retry",  "replay", "lost",   "cut2", "sheet",  "plan",   "wear",    "late"};
    const char* keys[] = {
        "wall_s",        "kills",         "pauses",       "continues", "cancels", "confirms",  "confirm_refused",
        "resumes",       "moves",         "answers_lost", "replayed",  "lost",    "cut_twice", "sheet_violations",
        "plan_mismatch", "wear_mismatch", "late_log"};
    std::printf("%-6s", "case");
    for (const char* h : head) std::printf(" %7s", h);
    std::printf(" seed\n");
    for (const popcut::bench::Row& row : r.rows()) {
      const auto c = [&](const char* k) { return row.counters.count(k) ? row.counters.at(k) : 0.0; };
      const std::string size = std::to_string(static_cast<int>(c("devices"))) + "x" +
                               std::to_string(static_cast<int>(c("jobs") / std::max(1.0, c("devices"))));
      std::printf("%-6s %9s", row.name.substr(8, row.name.find('/', 8) - 8).c_str(), size.c_str());  // BM_Soak/NAME/..
      for (const char* k : keys) std::printf(" %7.*f", k == keys[0] ? 1 : 0, c(k));
      std::printf(" %.0f\n", c("seed"));
      if (c("outages") > 0) std::printf("       popcutd stopped answering unasked %.0f times\n", c("outages"));
      defects += static_cast<int>(c("lost") + c("cut_twice") + c("sheet_violations") + c("plan_mismatch") +
                                  c("wear_mismatch") + c("outages"));
    }
  });
  // A defect fails the run (and the ctest smoke), unlike a timing, which people read.
  return rc != 0 ? rc : defects != 0 ? 1 : 0;
}

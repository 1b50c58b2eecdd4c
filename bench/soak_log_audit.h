// The soak's reading of popcutd's log: every run of every job checked against what earlier runs
// certainly sent, and every run on a device against the sheets the soak's driver confirmed.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace popcut::bench {

// What the log and the driver's snapshots say about one job, to tell a resume from a cut repeated unasked.
struct JobLog {
  std::vector<std::string> runs;  // its "cutting on" lines, in order
  int known_sent = 0;             // strokes certainly sent by its earlier runs (records seen, pause lines)
  int run_seen = 0;               // the most strokes_sent seen during its latest run
  bool final_seen = false;        // seen done or cancelled: no run may follow
};

// Reads popcutd's standard error as it grows (every process appends to the same file, in order) and checks each run.
class LogAudit {
 public:
  explicit LogAudit(std::string path) : path_(std::move(path)) {}
  void read_new() {
    std::ifstream in(path_, std::ios::binary);
    in.seekg(offset_);
    for (std::string line; std::getline(in, line) && !in.eof();) {  // a line without its newline: read next time
      offset_ += static_cast<std::streamoff>(line.size()) + 1;
      parse(line);
    }
  }
  // A snapshot taken before the last read_new(): a run it shows has its "cutting on" line read already.
  void observe(std::int64_t id, const std::string& state, int strokes_sent) {
    JobLog& j = jobs_[id];
    j.run_seen = std::max(j.run_seen, strokes_sent);
    if (state == "done" || state == "cancelled") j.final_seen = true;
  }
  // The driver confirmed a fresh sheet on `device` after job `job` used the sheet (or got no answer asking).
  void confirmed(const std::string& device, std::int64_t job) { confirmed_.insert({device, job}); }
  std::vector<std::string> cut_twice, sheet_violations, late_log;
  int runs = 0;

 private:
  void parse(const std::string& line) {
    long long id = 0;
    int from = 0, total = 0;
    char dev[64] = {};
    if (std::sscanf(line.c_str(), "popcutd: job %lld: cutting on %63s from stroke %d of %d", &id, dev, &from, &total) ==
        4) {
      run(id, dev, from, line);
    } else if (std::sscanf(line.c_str(), "popcutd: job %lld: paused on %63s after stroke %d", &id, dev, &from) == 3) {
      jobs_[id].run_seen = std::max(jobs_[id].run_seen, from);
    } else if (const std::string tail = ": a fresh sheet is loaded";
               line.rfind("popcutd: ", 0) == 0 && line.size() > tail.size() + 9 &&
               line.compare(line.size() - tail.size(), tail.size(), tail) == 0) {
      Sheet& sh = sheets_[line.substr(9, line.size() - tail.size() - 9)];
      sh.fresh = !sh.late;  // a line logged late belongs to the run before it, not to the next
      sh.late = false;
    }
  }
  void run(std::int64_t id, const std::string& dev, int from, const std::string& line) {
    ++runs;
    JobLog& j = jobs_[id];
    j.known_sent = std::max(j.known_sent, j.run_seen);
    // Only default resumes (after the strokes received) are asked for: a run never starts at or before a stroke an
    // earlier run of the job certainly sent, and none follows a done or cancelled job.
    if (j.final_seen || from - 1 < j.known_sent) {
      std::string why = j.final_seen ? "cut again after it was seen done or cancelled"
                                     : "strokes " + std::to_string(from) + ".." + std::to_string(j.known_sent) +
                                           " were certainly sent by an earlier run";
      std::string evidence;
      for (const std::string& r : j.runs) evidence += "\n      earlier: " + r;
      cut_twice.push_back("job " + std::to_string(id) + ": " + why + evidence + "\n      this:    " + line);
    }
    j.known_sent = std::max(j.known_sent, from - 1);
    j.run_seen = 0;
    j.runs.push_back(line);
    // Between runs of two jobs on one device someone confirmed a fresh sheet; a job's own later run goes on its sheet.
    // The driver is the only one who confirms, and notes each confirmation with the job the sheet was used by: that is
    // the evidence. The log's line is checked too, but popcutd writes it after committing the confirmation, when the
    // worker may already have claimed the next job and logged its run first.
    Sheet& s = sheets_[dev];
    if (s.last_job != 0 && s.last_job != id) {
      if (!confirmed_.count({dev, s.last_job}))
        sheet_violations.push_back(dev + ": job " + std::to_string(id) + " cut onto job " + std::to_string(s.last_job) +
                                   "'s sheet, nobody confirmed a fresh one: " + line);
      if (!s.fresh) {
        s.late = true;
        late_log.push_back(dev + ": job " + std::to_string(id) + " after job " + std::to_string(s.last_job) +
                           " with no fresh-sheet line before it: " + line);
      }
    } else if (s.last_job == id && s.fresh) {
      sheet_violations.push_back(dev + ": job " + std::to_string(id) + " resumed onto a fresh sheet: " + line);
    }
    s.last_job = id;
    s.fresh = false;
  }
  struct Sheet {
    std::int64_t last_job = 0;  // 0: the device's first sheet, loaded at the start
    bool fresh = false, late = false;
  };
  std::set<std::pair<std::string, std::int64_t>> confirmed_;
  std::string path_;
  std::streamoff offset_ = 0;
  std::map<std::int64_t, JobLog> jobs_;
  std::map<std::string, Sheet> sheets_;
};

}  // namespace popcut::bench

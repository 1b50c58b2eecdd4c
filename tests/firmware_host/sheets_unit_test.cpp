// The sheet step without processes: [[device]] confirm_sheet, and the store's device_sheets against a real SQLite file.
#include <gtest/gtest.h>

#include "config.h"
#include "popcut/error.h"
#include "popcutd_process.h"
#include "store.h"

namespace {
using namespace popcut;
using namespace popcut::daemon;

const std::string kSrc = POPCUT_SOURCE_DIR;

std::string device_config(const std::string& transport, const std::string& extra) {
  return "[server]\ndata_dir = \"/tmp/x\"\n[[device]]\nname = \"a\"\nprofile = \"devices/sim.toml\"\ntransport = \"" +
         transport + "\"\n" + extra + "[[token]]\nname = \"k\"\ntoken = \"kiosk-secret-0123456789\"\n";
}

DaemonConfig parse(const std::string& text) { return parse_daemon_config(text, kSrc + "/configs/test.toml"); }

TEST(ConfirmSheet, DefaultsToTrueForEveryTransportButSim) {
  EXPECT_FALSE(parse(device_config("sim", "")).devices[0].confirm_sheet) << "a simulated cutter has no sheet";
  EXPECT_TRUE(parse(device_config("file:out.hpgl", "")).devices[0].confirm_sheet);
  EXPECT_TRUE(parse(device_config("serial:/dev/ttyUSB0", "")).devices[0].confirm_sheet);
  EXPECT_TRUE(parse(device_config("sim", "confirm_sheet = true\n")).devices[0].confirm_sheet);
  EXPECT_FALSE(parse(device_config("file:out.hpgl", "confirm_sheet = false\n")).devices[0].confirm_sheet);
}

TEST(ConfirmSheet, ANonBooleanNamesFileSectionAndKey) {
  try {
    parse(device_config("sim", "confirm_sheet = \"yes\"\n"));
    ADD_FAILURE() << "confirm_sheet = \"yes\" loads";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("test.toml"), std::string::npos) << what;
    EXPECT_NE(what.find("[device.0] confirm_sheet"), std::string::npos) << what;
    EXPECT_NE(what.find("expected true or false"), std::string::npos) << what;
  }
}

class Sheets : public ::testing::Test {
 protected:
  popcut::testing::TempDir dir_{"popcut-sheets"};
  std::string db() const { return (dir_.path() / "jobs.db").string(); }
  // A job planned and waiting for `device`.
  static std::int64_t ready_job(JobStore& s, const std::string& device) {
    const std::int64_t id = *s.insert({"kiosk", "card", device, "sim", "{}"}, 100);
    EXPECT_EQ(s.claim_for_planning()->id, id);
    s.set_planned(id, 10, 5.0);
    return id;
  }
};

TEST_F(Sheets, AClaimUsesTheSheetAndNothingMoreIsClaimedUntilConfirmed) {
  JobStore s(db());
  EXPECT_EQ(s.device_sheet("a").state, SheetState::loaded) << "a device never seen starts with its sheet loaded";
  const std::int64_t first = ready_job(s, "a");
  const std::int64_t second = ready_job(s, "a");
  ASSERT_EQ(s.claim_for_device("a", "sim", true)->id, first);
  const DeviceSheet used = s.device_sheet("a");
  EXPECT_EQ(used.state, SheetState::used) << "marked in the claim's own transaction";
  EXPECT_EQ(used.last_job, first);
  EXPECT_FALSE(s.confirm_sheet("a").sheet.has_value()) << "no confirmation while a job is cutting on the device";
  EXPECT_EQ(s.device_sheet("a").state, SheetState::used) << "and it changed nothing";
  s.finish(first, JobState::done, "", "");
  EXPECT_FALSE(s.claim_for_device("a", "sim", true).has_value()) << "the next job waits for a fresh sheet";
  EXPECT_EQ(s.get(second)->state, JobState::ready);
  const std::optional<DeviceSheet> fresh = s.confirm_sheet("a").sheet;
  ASSERT_TRUE(fresh.has_value());
  EXPECT_EQ(fresh->state, SheetState::loaded);
  EXPECT_EQ(fresh->last_job, first) << "who used it last is kept (the kiosk's owner check reads it)";
  EXPECT_EQ(s.claim_for_device("a", "sim", true)->id, second) << "confirmed: the next job is claimed";
}

TEST_F(Sheets, ADeviceWithoutConfirmSheetNeverWaits) {
  JobStore s(db());
  const std::int64_t first = ready_job(s, "a");
  const std::int64_t second = ready_job(s, "a");
  ASSERT_EQ(s.claim_for_device("a", "sim", false)->id, first);
  s.finish(first, JobState::done, "", "");
  EXPECT_EQ(s.device_sheet("a").state, SheetState::loaded);
  EXPECT_EQ(s.claim_for_device("a", "sim", false)->id, second);
}

TEST_F(Sheets, AUsedSheetSurvivesACrashAndOnlyItsOwnJobMayGoOnCuttingIt) {
  std::int64_t first = 0, other = 0;
  {
    JobStore s(db());
    first = ready_job(s, "a");
    other = ready_job(s, "a");
    ASSERT_EQ(s.claim_for_device("a", "sim", true)->id, first);
    s.set_progress(first, 4);
  }  // the process dies here: nothing else is written
  JobStore s(db());
  ASSERT_EQ(s.recover().interrupted, 1);
  EXPECT_EQ(s.device_sheet("a").state, SheetState::used) << "the state came back from the file";
  EXPECT_FALSE(s.claim_for_device("a", "sim", true).has_value()) << "no other job onto the half-cut sheet";
  ASSERT_EQ(s.resume(first), ResumeResult::resumed);
  const std::optional<Job> again = s.claim_for_device("a", "sim", true);
  ASSERT_TRUE(again.has_value()) << "the job whose sheet it is goes on cutting it";
  EXPECT_EQ(again->id, first);
  EXPECT_EQ(again->resume_from, 4);
  s.finish(first, JobState::done, "", "");
  EXPECT_FALSE(s.claim_for_device("a", "sim", true).has_value());
  ASSERT_TRUE(s.confirm_sheet("a").sheet.has_value());
  EXPECT_EQ(s.claim_for_device("a", "sim", true)->id, other);
}

TEST_F(Sheets, SheetsAreKeptPerDevice) {
  JobStore s(db());
  const std::int64_t on_a = ready_job(s, "a");
  const std::int64_t on_b = ready_job(s, "b");
  ASSERT_EQ(s.claim_for_device("a", "sim", true)->id, on_a);
  s.finish(on_a, JobState::cancelled, "cancelled", "cancelled during the cut");
  EXPECT_EQ(s.device_sheet("a").state, SheetState::used) << "a cancelled cut used the sheet too";
  EXPECT_EQ(s.device_sheet("b").state, SheetState::loaded);
  EXPECT_EQ(s.claim_for_device("b", "sim", true)->id, on_b) << "b's sheet is its own";
}

// "No sheet loaded" before the first byte: the job goes back in line in its place and the device's
// tray is empty, which no claim passes, confirmed sheets or not, until a sheet is loaded.
TEST_F(Sheets, AnEmptyTraySendsTheJobBackAndBlocksEveryClaim) {
  JobStore s(db());
  for (const bool confirm : {true, false}) {
    const std::string dev = confirm ? "a" : "b";
    const std::int64_t id = ready_job(s, dev);
    ASSERT_EQ(s.claim_for_device(dev, "sim", confirm)->id, id);
    ASSERT_TRUE(s.back_for_no_sheet(id, dev));
    const Job j = *s.get(id);
    EXPECT_EQ(j.state, JobState::ready);
    EXPECT_EQ(j.device, "") << "not cut anywhere yet: any of its devices may take it";
    EXPECT_EQ(j.started_at, 0);
    EXPECT_EQ(s.device_sheet(dev).state, SheetState::empty);
    EXPECT_EQ(s.device_sheet(dev).last_job, id) << "its owner may say a sheet is loaded";
    EXPECT_FALSE(s.claim_for_device(dev, "sim", confirm))
        << "nothing starts on an empty tray (confirm " << confirm << ")";
    if (confirm) {
      ASSERT_TRUE(s.confirm_sheet(dev).sheet) << "no job holds a sheet there";
    } else {
      EXPECT_TRUE(s.ask_again_for_sheet(dev));
      EXPECT_FALSE(s.ask_again_for_sheet(dev)) << "only an empty tray is asked about";
    }
    EXPECT_EQ(s.claim_for_device(dev, "sim", confirm)->id, id) << "then the job is cut";
  }
  // A job that got strokes out, or was resumed, is not sent back: its sheet was the one taken out.
  const std::int64_t resumed = ready_job(s, "b");
  ASSERT_EQ(s.claim_for_device("b", "sim", false)->id, resumed);
  s.set_progress(resumed, 3);
  EXPECT_FALSE(s.back_for_no_sheet(resumed, "b"));
  EXPECT_EQ(s.get(resumed)->state, JobState::cutting) << "left to its outcome";
  EXPECT_EQ(s.device_sheet("b").state, SheetState::loaded);
}

// A job of two sheets: the first cut, the device's sheet is full and no job (this one included)
// goes on until a fresh one is loaded; one cut short at the first sheet's very end and resumed on its
// own used sheet is not let start the second there either.
TEST_F(Sheets, AFullSheetWaitsForAFreshOneEvenForItsOwnJob) {
  JobStore s(db());
  for (const bool cut_short : {false, true}) {
    NewJob nj{"kiosk", "cards", "a", "sim", "{}"};
    nj.copies = 3;
    const std::int64_t id = *s.insert(nj, 100);
    ASSERT_EQ(s.claim_for_planning()->id, id);
    s.set_planned(id, 18, 5.0, 2, 10);  // sheets of 2 cards, 10 strokes; the last sheet 8
    const Job planned = *s.get(id);
    EXPECT_EQ(planned.sheets(), 2);
    EXPECT_EQ(planned.sheet_of(10), 0);
    EXPECT_EQ(planned.sheet_of(11), 1);
    ASSERT_EQ(s.claim_for_device("a", "sim", true)->id, id);
    s.set_progress(id, 10);
    if (cut_short) {
      s.recover();  // killed after the sheet's last stroke, before its end was recorded
      ASSERT_EQ(s.get(id)->state, JobState::interrupted);
      ASSERT_EQ(s.resume(id), ResumeResult::resumed);
      EXPECT_FALSE(s.claim_for_device("a", "sim", true)) << "its used sheet holds a whole sheet already";
    } else {
      s.sheet_full(id, "a", 10, true);
    }
    const Job j = *s.get(id);
    EXPECT_EQ(j.state, JobState::ready);
    EXPECT_EQ(j.device, "") << "its next sheet may go to any of its devices";
    EXPECT_EQ(j.resume_from, 10);
    EXPECT_EQ(s.device_sheet("a").state, SheetState::full);
    EXPECT_FALSE(s.claim_for_device("a", "sim", true)) << "not onto the full sheet";
    ASSERT_TRUE(s.confirm_sheet("a").sheet) << "no job holds a half-cut sheet there";
    const std::optional<Job> next = s.claim_for_device("a", "sim", true);
    ASSERT_TRUE(next);
    EXPECT_EQ(next->id, id);
    EXPECT_EQ(next->resume_from, 10) << "sheet 2 from its first stroke";
    s.finish(id, JobState::done, "", "");
    ASSERT_TRUE(s.confirm_sheet("a").sheet);
  }
}

}  // namespace

// Pop-up check kept up to date while windows are opened one by one, touching only what a window can change.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "popcut/model/voxel_model.h"

namespace popcut {

// Work done by an IncrementalPopup, for benchmarks and tests.
struct IncrementalPopupStats {
  std::int64_t decisions = 0;         // windows judged
  std::int64_t segments_visited = 0;  // segments re-walked by all decisions together
  std::int64_t full_checks = 0;       // decisions that fell back to the full check_popup
};

// The voxel paper's §3.2 c) flags a window and re-runs the pop-up check (§2.6) each time; over a
// whole card that is rows × cells. This keeps the two walks of check_popup on a coarser graph —
// each slice's strip cut into segments of one face — and, when one slice changes, re-walks only
// the segments whose reach can change: those reachable (in the walk's direction) from the
// segments that changed, before or after the change, not spreading through unchanged start
// segments. Every other segment keeps its reach, because a walk that reaches it from its last
// start segment avoids what changed and uses only edges the change leaves alone. The answer is exactly
// check_popup(make_pattern(model)).pops_up(); when the local walks cannot settle it (a face that
// neither walk reaches, or a floor the back board no longer reaches — both rare) it falls back
// to that full check, and counts it.
class IncrementalPopup {
 public:
  // The model must be valid (require_valid) and must pop up; throws popcut::Error otherwise.
  IncrementalPopup(VoxelModel model, const std::string& source = "");

  const VoxelModel& model() const { return model_; }
  const IncrementalPopupStats& stats() const { return stats_; }

  // Would the card still pop up with isHole(x, z) set to `on`? Leaves the model unchanged; the
  // row must have a front face when turning a window on (z below the column's top).
  bool pops_up_with_window(int x, int z, bool on) { return pops_up_with(Edit::window, x, z, on); }
  // Sets the window when the card still pops up with it; returns whether it did.
  bool try_window(int x, int z, bool on = true) { return try_edit(Edit::window, x, z, on); }
  // The same for leaving out the top face at height z of slice x (§3.3); the slice must have
  // a top face there (VoxelModel::has_top).
  bool pops_up_with_top_dropped(int x, int z, bool on) { return pops_up_with(Edit::dropped_top, x, z, on); }
  bool try_drop_top(int x, int z, bool on = true) { return try_edit(Edit::dropped_top, x, z, on); }

 private:
  enum class Edit { window, dropped_top };
  bool pops_up_with(Edit edit, int x, int z, bool on);
  bool try_edit(Edit edit, int x, int z, bool on);
  bool flag(Edit edit, int x, int z) const;
  void set_flag(Edit edit, int x, int z, bool on);

  struct Segment {
    int lo = 0, hi = 0;  // rows [lo, hi) of the strip
    std::uint32_t face = 0;
    std::uint8_t from_back = 0, from_floor = 0;  // reached by walk (a) / walk (b)
    // Scratch of the decision in progress: epoch marks of the re-walked areas and their result.
    std::uint32_t in_back_area = 0, in_floor_area = 0, in_region = 0;
    std::uint8_t new_back = 0, new_floor = 0;
  };
  using Column = std::vector<Segment>;
  struct Ref {
    int column;
    int index;
  };

  static void cut_into_segments(const std::vector<std::uint32_t>& strip, Column& out);
  bool decide(int x);
  void rebuild();
  bool full_check() const;
  Segment& at(Ref r) { return r.column == changed_ ? pending_[static_cast<std::size_t>(r.index)] : columns_[static_cast<std::size_t>(r.column)][static_cast<std::size_t>(r.index)]; }
  const Column& column(int c) const { return c == changed_ ? pending_ : columns_[static_cast<std::size_t>(c)]; }
  bool fold_below(const Column& col, int index) const;
  template <typename Visit>
  void neighbours(Ref r, bool down, Visit visit) const;
  void closure(bool down, std::vector<Ref>& area);
  void rewalk(bool down, const std::vector<Ref>& area);
  bool in_back_board(Ref r);

  VoxelModel model_;
  std::string source_;
  SheetVoxels sheet_;
  std::vector<Column> columns_;
  std::int64_t neither_ = 0;  // segments that neither walk reaches
  IncrementalPopupStats stats_;

  // The decision in progress: column `changed_` as it would be (the new view of the graph).
  int changed_ = -1;
  Column pending_;
  std::vector<int> old_index_, new_index_;  // unchanged segments: their index in the other view
  std::int64_t pending_neither_ = 0;
  std::vector<std::uint32_t> strip_;
  std::vector<Ref> area_back_, area_floor_, stack_;
  std::uint32_t epoch_ = 0;
};

}  // namespace popcut

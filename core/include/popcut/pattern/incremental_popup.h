// Pop-up check kept up to date while windows are opened one by one, touching only what a window can change.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "popcut/model/voxel_model.h"

namespace popcut {

// Work done by an IncrementalPopup, for benchmarks and tests.
struct IncrementalPopupStats {
  std::int64_t decisions = 0;  // windows judged
  std::int64_t segments_visited =
      0;                         // segments re-labelled plus regions and region folds walked, all decisions together
  std::int64_t full_checks = 0;  // decisions that fell back to the full check_popup
};

// The voxel paper's §3.2 c) flags a window and re-runs the pop-up check (§2.6) each time; over a
// whole card that is rows × cells. The two walks of check_popup (from the back board down across
// folds, from the floor up) move freely inside a face, so they are walks on the card's faces:
// each slice's strip is cut into segments of one face, side steps join segments of the same face
// sharing a row in neighbouring slices, and their components (regions, the pattern's faces) are
// the nodes, joined by the folds between them. A change to one slice re-labels only the regions
// it touches (those of the segments it removes or adds, flooded again across the slices they
// span), updates the fold counts of the re-labelled segments, and walks the region graph, which
// has as many nodes as the pattern has faces: the work per decision follows the faces the change
// touches and the number of faces, not the card's area. The answer is exactly
// check_popup(make_pattern(model)).pops_up(); when the walks cannot settle it (a face that
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
    int region = -1;         // committed region id (-1: a segment the decision in progress adds)
    std::uint32_t seen = 0;  // epoch of the decision that flooded it
    int next_region = -1;    // its region after the change, when flooded
  };
  using Column = std::vector<Segment>;
  struct Ref {
    int column;
    int index;
  };
  struct Region {
    std::uint32_t face = 0;
    std::int64_t size = 0;      // segments; 0 for a free id
    int tops = 0, bottoms = 0;  // strip tops (the back board's edge) and bottoms (the floor's) among them
  };

  static void cut_into_segments(const std::vector<std::uint32_t>& strip, Column& out);
  bool decide(int x);
  void rebuild();
  bool full_check() const;
  Segment& at(Ref r) {
    return r.column == changed_ ? pending_[static_cast<std::size_t>(r.index)]
                                : columns_[static_cast<std::size_t>(r.column)][static_cast<std::size_t>(r.index)];
  }
  const Column& column(int c) const { return c == changed_ ? pending_ : columns_[static_cast<std::size_t>(c)]; }
  bool fold_below(const Column& col, int index) const;
  template <typename Visit>
  void side_steps(const Segment& s, int c, Visit visit) const;
  void flood(Ref seed);
  void new_folds(const Column& col, int index);
  bool walk_regions();
  void start_decision();
  void commit();

  VoxelModel model_;
  std::string source_;
  SheetVoxels sheet_;
  std::vector<Column> columns_;
  std::vector<Region> regions_;
  std::vector<int> free_ids_;
  std::vector<std::vector<int>> down_, up_;  // by region: the regions its folds lead to, down and up
  IncrementalPopupStats stats_;

  // The decision in progress: column `changed_` as it would be (the new view of the graph), the
  // segments flooded into new regions (ids regions_.size() + i), the regions that dissolve.
  int changed_ = -1;  // the column that reads as pending_ (-1: the committed view everywhere)
  int decided_ = -1;  // the column the decision in progress changes
  Column pending_;
  std::vector<int> old_index_, new_index_;  // unchanged segments: their index in the other view
  std::vector<std::uint32_t> strip_;
  std::vector<Ref> flooded_, stack_, seeds_;
  std::vector<Region> fresh_;
  std::vector<int> dead_;
  std::vector<std::uint32_t> dead_mark_;        // by committed id: the epoch that dissolved it
  std::vector<std::pair<int, int>> new_edges_;  // the new regions' folds: (upper, lower)
  std::vector<int> head_, link_, region_stack_, final_id_;
  bool pending_full_ = false;  // the decision in progress needs the full check
  std::vector<std::uint8_t> reach_;
  std::uint32_t epoch_ = 0;
};

}  // namespace popcut

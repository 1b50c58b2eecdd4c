// The pop-up walks on the region graph of strip segments, re-labelled only where one changed slice reaches (see the
// header).
#include "popcut/pattern/incremental_popup.h"

#include <algorithm>

#include "popcut/error.h"
#include "popcut/pattern/popup_check.h"
#include "popcut/pattern/voxel_pattern.h"

namespace popcut {
namespace {

const std::uint32_t kBackWall = CellGrid::pack(FaceKind::vertical, 0);

}  // namespace

IncrementalPopup::IncrementalPopup(VoxelModel model, const std::string& source)
    : model_(std::move(model)), source_(source) {
  require_valid(model_, source_);
  sheet_ = resolve_sheet(model_, source_);
  if (!full_check()) {
    throw Error(ErrorCode::invalid_input, source_, "",
                "the card does not pop up as it is; windows can only be judged on a card that does");
  }
  stats_ = {};
  rebuild();
}

bool IncrementalPopup::full_check() const { return check_popup(make_pattern(model_, source_)).pops_up(); }

// An x-parallel edge is a fold exactly when a VFace t_v and an HFace t_h meet there in 3D:
// t_h - t_v = v (docs/architecture.md, "Geometry"); two VFaces or two HFaces never fold.
bool IncrementalPopup::fold_below(const Column& col, int index) const {
  if (index <= 0 || index >= static_cast<int>(col.size())) return false;
  const Segment& lower = col[static_cast<std::size_t>(index - 1)];
  const Segment& upper = col[static_cast<std::size_t>(index)];
  if (CellGrid::kind_of(lower.face) == CellGrid::kind_of(upper.face)) return false;
  const bool upper_h = CellGrid::kind_of(upper.face) == FaceKind::horizontal;
  const int t_h = CellGrid::t_of(upper_h ? upper.face : lower.face);
  const int t_v = CellGrid::t_of(upper_h ? lower.face : upper.face);
  return t_h - t_v == upper.lo - sheet_.floor;
}

template <typename Visit>
void IncrementalPopup::side_steps(const Segment& s, int c, Visit visit) const {
  for (int c2 : {c - 1, c + 1}) {
    if (c2 < 0 || c2 >= static_cast<int>(columns_.size())) continue;
    const Column& other = column(c2);
    auto it = std::upper_bound(other.begin(), other.end(), s.lo, [](int row, const Segment& o) { return row < o.hi; });
    for (; it != other.end() && it->lo < s.hi; ++it) {
      if (it->face == s.face) visit(Ref{c2, static_cast<int>(it - other.begin())});
    }
  }
}

// Runs of one face in a strip, bottom first.
void IncrementalPopup::cut_into_segments(const std::vector<std::uint32_t>& strip, Column& out) {
  out.clear();
  for (int r = 0; r < static_cast<int>(strip.size()); ++r) {
    if (out.empty() || out.back().face != strip[static_cast<std::size_t>(r)]) {
      out.push_back(Segment{r, r + 1, strip[static_cast<std::size_t>(r)], -1, 0, -1});
    } else {
      out.back().hi = r + 1;
    }
  }
}

// One new region: the side-step component of `seed` in the new view. Committed regions it
// covers dissolve (their other segments are in it, or in another flooded component).
void IncrementalPopup::flood(Ref seed) {
  if (at(seed).seen == epoch_) return;
  const int id = static_cast<int>(regions_.size() + fresh_.size());
  Region info;
  info.face = at(seed).face;
  stack_.assign(1, seed);
  at(seed).seen = epoch_;
  while (!stack_.empty()) {
    const Ref r = stack_.back();
    stack_.pop_back();
    Segment& s = at(r);
    s.next_region = id;
    flooded_.push_back(r);
    ++info.size;
    info.tops += r.index == static_cast<int>(column(r.column).size()) - 1 ? 1 : 0;
    info.bottoms += r.index == 0 ? 1 : 0;
    if (s.region >= 0 && dead_mark_[static_cast<std::size_t>(s.region)] != epoch_) {
      dead_mark_[static_cast<std::size_t>(s.region)] = epoch_;
      dead_.push_back(s.region);
    }
    side_steps(s, r.column, [&](Ref n) {
      Segment& t = at(n);
      if (t.seen == epoch_) return;
      t.seen = epoch_;
      stack_.push_back(n);
    });
  }
  fresh_.push_back(info);
}

// The folds of a flooded segment `index` of `col` in the new view, as (upper, lower) region
// pairs: the one below it always, the one above it unless that segment is flooded too (and
// gives it). Every fold that touches a new region is found this way, as all its segments are
// flooded; every other fold joins two regions the change leaves alone.
void IncrementalPopup::new_folds(const Column& col, int index) {
  const auto label = [&](int i) {
    const Segment& s = col[static_cast<std::size_t>(i)];
    return s.seen == epoch_ ? s.next_region : s.region;
  };
  if (fold_below(col, index)) new_edges_.emplace_back(label(index), label(index - 1));
  if (index + 1 < static_cast<int>(col.size()) && fold_below(col, index + 1) &&
      col[static_cast<std::size_t>(index + 1)].seen != epoch_) {
    new_edges_.emplace_back(label(index + 1), label(index));
  }
}

// Both walks on the region graph of the change in progress: committed folds between regions
// that stay, and the new regions' folds. True when every VFace stands; pending_full_ then says
// whether something is left that only the full check can judge.
bool IncrementalPopup::walk_regions() {
  const std::size_t base = regions_.size(), n = base + fresh_.size();
  const auto info = [&](std::size_t id) -> const Region& { return id < base ? regions_[id] : fresh_[id - base]; };
  const auto live = [&](std::size_t id) { return info(id).size > 0 && (id >= base || dead_mark_[id] != epoch_); };
  // The new folds as linked lists per region, in each walk's direction.
  head_.assign(2 * n, -1);
  link_.resize(2 * new_edges_.size());
  for (std::size_t e = 0; e < new_edges_.size(); ++e) {
    const auto [upper, lower] = new_edges_[e];
    link_[2 * e] = head_[2 * static_cast<std::size_t>(upper)];  // walk (a): upper to lower
    head_[2 * static_cast<std::size_t>(upper)] = static_cast<int>(2 * e);
    link_[2 * e + 1] = head_[2 * static_cast<std::size_t>(lower) + 1];  // walk (b): lower to upper
    head_[2 * static_cast<std::size_t>(lower) + 1] = static_cast<int>(2 * e + 1);
  }
  reach_.assign(n, 0);  // bit 1: walk (a) from the back board down; bit 2: walk (b) from the floor up
  std::int64_t work = static_cast<std::int64_t>(n);
  for (int walk = 0; walk < 2; ++walk) {
    const auto bit = static_cast<std::uint8_t>(1 << walk);
    std::vector<int>& stack = region_stack_;
    stack.clear();
    const auto visit = [&](std::size_t to) {
      if ((reach_[to] & bit) || !live(to)) return;
      reach_[to] |= bit;
      stack.push_back(static_cast<int>(to));
    };
    for (std::size_t id = 0; id < n; ++id) {
      if (live(id) && (walk == 0 ? info(id).tops : info(id).bottoms) > 0) visit(id);
    }
    while (!stack.empty()) {
      const auto id = static_cast<std::size_t>(stack.back());
      stack.pop_back();
      if (id < base) {
        const std::vector<int>& out = walk == 0 ? down_[id] : up_[id];
        work += static_cast<std::int64_t>(out.size());
        for (int to : out) visit(static_cast<std::size_t>(to));
      }
      for (int e = head_[2 * id + static_cast<std::size_t>(walk)]; e >= 0; e = link_[static_cast<std::size_t>(e)]) {
        const auto [upper, lower] = new_edges_[static_cast<std::size_t>(e / 2)];
        visit(static_cast<std::size_t>(walk == 0 ? lower : upper));
        ++work;
      }
    }
  }
  stats_.segments_visited += work;
  std::int64_t neither = 0;
  for (std::size_t id = 0; id < n; ++id) {
    if (!live(id)) continue;
    const Region& r = info(id);
    const bool a = reach_[id] & 1, b = reach_[id] & 2;
    if (!a && !b) neither += r.size;
    // A VFace must be reached by both walks unless it is the back board (walk (a)'s start, the
    // V0 face that holds a strip's top).
    if (CellGrid::kind_of(r.face) == FaceKind::vertical && !(a && b) && !(a && r.face == kBackWall && r.tops > 0))
      return false;
  }
  // Every VFace stands. With every face reached by one walk or the other and the floor reached
  // from the back board, every piece hangs together with both boards. Otherwise (rare) only the
  // full check can tell.
  const Segment& floor = pending_.front();
  const int floor_region = floor.seen == epoch_ ? floor.next_region : floor.region;
  pending_full_ = neither > 0 || !(reach_[static_cast<std::size_t>(floor_region)] & 1);
  return true;
}

void IncrementalPopup::rebuild() {
  changed_ = -1;
  columns_.assign(static_cast<std::size_t>(model_.width + 2 * sheet_.side), {});
  for (std::size_t c = 0; c < columns_.size(); ++c) {
    slice_faces(model_, sheet_, static_cast<int>(c) - sheet_.side, strip_);
    cut_into_segments(strip_, columns_[c]);
  }
  regions_.clear();
  free_ids_.clear();
  dead_mark_.clear();
  start_decision();
  for (std::size_t c = 0; c < columns_.size(); ++c) {
    for (int i = 0; i < static_cast<int>(columns_[c].size()); ++i) flood(Ref{static_cast<int>(c), i});
  }
  down_.clear();
  up_.clear();
  for (std::size_t c = 0; c < columns_.size(); ++c) {
    for (int i = 0; i < static_cast<int>(columns_[c].size()); ++i) new_folds(columns_[c], i);
  }
  commit();
}

void IncrementalPopup::start_decision() {
  if (++epoch_ == 0) {  // after 2^32 decisions: clear the marks once rather than misread them
    for (Column& col : columns_) {
      for (Segment& s : col) s.seen = 0;
    }
    std::fill(dead_mark_.begin(), dead_mark_.end(), 0);
    epoch_ = 1;
  }
  flooded_.clear();
  fresh_.clear();
  dead_.clear();
  new_edges_.clear();
}

bool IncrementalPopup::decide(int x) {
  ++stats_.decisions;
  start_decision();
  const int c = x + sheet_.side;
  decided_ = c;
  slice_faces(model_, sheet_, x, strip_);
  cut_into_segments(strip_, pending_);
  // Segments the change leaves as they were keep their region unless a flood re-labels them.
  const Column& old = columns_[static_cast<std::size_t>(c)];
  old_index_.assign(pending_.size(), -1);
  new_index_.assign(old.size(), -1);
  for (std::size_t i = 0, j = 0; i < old.size() && j < pending_.size();) {
    if (old[i].lo == pending_[j].lo && old[i].hi == pending_[j].hi && old[i].face == pending_[j].face) {
      old_index_[j] = static_cast<int>(i);
      new_index_[i] = static_cast<int>(j);
      pending_[j].region = old[i].region;
    }
    (old[i].hi <= pending_[j].hi ? ++i : ++j);
  }
  // Seeds: the segments added, and the old neighbours of those removed (every piece a removed
  // segment leaves of its region holds one). The removed segments' regions dissolve.
  std::vector<Ref>& seed_list = seeds_;
  seed_list.clear();
  for (std::size_t i = 0; i < old.size(); ++i) {
    if (new_index_[i] >= 0) continue;
    const int region = old[i].region;
    if (dead_mark_[static_cast<std::size_t>(region)] != epoch_) {
      dead_mark_[static_cast<std::size_t>(region)] = epoch_;
      dead_.push_back(region);
    }
    side_steps(old[i], c, [&](Ref n) { seed_list.push_back(n); });
  }
  changed_ = c;
  for (std::size_t j = 0; j < pending_.size(); ++j) {
    if (old_index_[j] < 0) flood(Ref{c, static_cast<int>(j)});
  }
  for (Ref r : seed_list) flood(r);
  stats_.segments_visited += static_cast<std::int64_t>(flooded_.size());
  for (Ref r : flooded_) new_folds(column(r.column), r.index);
  if (!walk_regions()) return false;
  if (pending_full_) {
    ++stats_.full_checks;
    return full_check();
  }
  return true;
}

// Makes the decision in progress the committed state: dissolved regions free their ids, new
// ones take ids, flooded segments their new region, the fold counts their new keys.
void IncrementalPopup::commit() {
  const auto erase = [](std::vector<int>& list, int id) {
    list.erase(std::remove(list.begin(), list.end(), id), list.end());
  };
  for (int id : dead_) {
    const auto d = static_cast<std::size_t>(id);
    for (int other : down_[d]) erase(up_[static_cast<std::size_t>(other)], id);
    for (int other : up_[d]) erase(down_[static_cast<std::size_t>(other)], id);
    down_[d].clear();
    up_[d].clear();
    regions_[d] = {};
    free_ids_.push_back(id);
  }
  const std::size_t base = regions_.size();
  std::vector<int>& final_id = final_id_;
  final_id.resize(fresh_.size());
  for (std::size_t i = 0; i < fresh_.size(); ++i) {
    if (!free_ids_.empty()) {
      final_id[i] = free_ids_.back();
      free_ids_.pop_back();
      regions_[static_cast<std::size_t>(final_id[i])] = fresh_[i];
    } else {
      final_id[i] = static_cast<int>(regions_.size());
      regions_.push_back(fresh_[i]);
    }
  }
  dead_mark_.resize(regions_.size(), 0);
  down_.resize(regions_.size());
  up_.resize(regions_.size());
  const auto remap = [&](int id) {
    return static_cast<std::size_t>(id) < base ? id : final_id[static_cast<std::size_t>(id) - base];
  };
  for (Ref r : flooded_) {
    Segment& s = at(r);
    s.region = remap(s.next_region);
  }
  if (changed_ >= 0) columns_[static_cast<std::size_t>(changed_)] = pending_;
  changed_ = -1;
  // Each new region's folds, once per pair of regions.
  for (auto& [upper, lower] : new_edges_) {
    upper = remap(upper);
    lower = remap(lower);
  }
  std::sort(new_edges_.begin(), new_edges_.end());
  new_edges_.erase(std::unique(new_edges_.begin(), new_edges_.end()), new_edges_.end());
  for (const auto& [upper, lower] : new_edges_) {
    down_[static_cast<std::size_t>(upper)].push_back(lower);
    up_[static_cast<std::size_t>(lower)].push_back(upper);
  }
  fresh_.clear();
  dead_.clear();
  flooded_.clear();
  new_edges_.clear();
}

bool IncrementalPopup::flag(Edit edit, int x, int z) const {
  return edit == Edit::window ? model_.is_window(x, z) : model_.is_top_dropped(x, z);
}

void IncrementalPopup::set_flag(Edit edit, int x, int z, bool on) {
  if (edit == Edit::window) {
    model_.set_window(x, z, on);
  } else {
    model_.set_top_dropped(x, z, on);
  }
}

bool IncrementalPopup::pops_up_with(Edit edit, int x, int z, bool on) {
  const char* field = edit == Edit::window ? "windows" : "dropped_tops";
  const int z_lo = edit == Edit::window ? 0 : 1;
  const int z_hi = edit == Edit::window ? model_.height - 1 : model_.height;
  if (x < 0 || x >= model_.width || z < z_lo || z > z_hi) {
    throw Error(ErrorCode::invalid_input, source_, field,
                "[" + std::to_string(x) + ", " + std::to_string(z) + "] is outside the grid");
  }
  if (flag(edit, x, z) == on) return true;  // no change: the card pops up as it is
  if (on && edit == Edit::window && z >= model_.h(x, 0)) {
    throw Error(ErrorCode::invalid_input, source_, field,
                "row " + std::to_string(z) + " of slice " + std::to_string(x) + " has no front face to open");
  }
  if (on && edit == Edit::dropped_top && !model_.has_top(x, z)) {
    throw Error(ErrorCode::invalid_input, source_, field,
                "slice " + std::to_string(x) + " has no top face at height " + std::to_string(z));
  }
  set_flag(edit, x, z, on);
  const bool ok = decide(x);
  set_flag(edit, x, z, !on);
  changed_ = -1;
  return ok;
}

bool IncrementalPopup::try_edit(Edit edit, int x, int z, bool on) {
  const std::int64_t fallbacks = stats_.full_checks;
  if (!pops_up_with(edit, x, z, on)) return false;
  if (flag(edit, x, z) == on) return true;
  set_flag(edit, x, z, on);
  if (stats_.full_checks != fallbacks) {
    rebuild();  // the full check decided; the segment walks start afresh
    return true;
  }
  // Commit the decision just made (its scratch still describes the change).
  changed_ = x + sheet_.side;
  commit();
  return true;
}

}  // namespace popcut

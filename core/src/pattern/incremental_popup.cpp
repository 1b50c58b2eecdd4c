// The pop-up walks on strip segments, re-walked only where one changed slice can reach (see the header).
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

bool IncrementalPopup::full_check() const {
  return check_popup(make_pattern(model_, source_)).pops_up();
}

// An x-parallel edge is a fold exactly when a VFace t_v and an HFace t_h meet there in 3D:
// t_h - t_v = v (DESIGN.md); two VFaces or two HFaces never fold.
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

// Walk (a) (`down`) crosses folds from the upper segment to the lower one, walk (b) upward; both
// move freely inside a face, which across slices means to a segment of the same face sharing
// at least one row (cells touching at a corner are separate faces, as in the pattern).
template <typename Visit>
void IncrementalPopup::neighbours(Ref r, bool down, Visit visit) const {
  const Column& col = column(r.column);
  if (down) {
    if (fold_below(col, r.index)) visit(Ref{r.column, r.index - 1});
  } else if (fold_below(col, r.index + 1)) {
    visit(Ref{r.column, r.index + 1});
  }
  const Segment& s = col[static_cast<std::size_t>(r.index)];
  for (int c2 : {r.column - 1, r.column + 1}) {
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
      out.push_back(Segment{r, r + 1, strip[static_cast<std::size_t>(r)], 0, 0, 0, 0, 0, 0, 0});
    } else {
      out.back().hi = r + 1;
    }
  }
}

void IncrementalPopup::rebuild() {
  changed_ = -1;
  columns_.assign(static_cast<std::size_t>(model_.width + 2 * sheet_.side), {});
  for (std::size_t c = 0; c < columns_.size(); ++c) {
    slice_faces(model_, sheet_, static_cast<int>(c) - sheet_.side, strip_);
    cut_into_segments(strip_, columns_[c]);
  }
  // Walk (a) from the back board (every strip's top segment), walk (b) from the floor (bottom).
  for (bool down : {true, false}) {
    stack_.clear();
    for (std::size_t c = 0; c < columns_.size(); ++c) {
      Column& col = columns_[c];
      Segment& seed = down ? col.back() : col.front();
      (down ? seed.from_back : seed.from_floor) = 1;
      stack_.push_back(Ref{static_cast<int>(c), down ? static_cast<int>(col.size()) - 1 : 0});
    }
    while (!stack_.empty()) {
      const Ref r = stack_.back();
      stack_.pop_back();
      neighbours(r, down, [&](Ref n) {
        std::uint8_t& flag = down ? at(n).from_back : at(n).from_floor;
        if (!flag) {
          flag = 1;
          stack_.push_back(n);
        }
      });
    }
  }
  neither_ = 0;
  for (const Column& col : columns_) {
    for (const Segment& s : col) neither_ += (!s.from_back && !s.from_floor) ? 1 : 0;
  }
}

// Everything a walk can reach from what changed in the slice, before or after the change,
// without passing a start segment that did not change: the slice's new segments that have no
// identical old one, and whatever the walk reaches from the old segments' neighbours. A segment
// of the slice with the same rows and face before and after is unchanged, with the same edges
// to every other unchanged segment. A segment outside this area keeps its reach: a path to it
// from its last start segment avoids what changed, so it exists before and after.
void IncrementalPopup::closure(bool down, std::vector<Ref>& area) {
  area.clear();
  stack_.clear();
  // A walk's start segments (every strip's top for walk a, bottom for walk b) are reached
  // whatever changes, so a path through one can start afresh there: the area includes them
  // but does not spread from them, unless they changed. Without this, walk (a)'s area would
  // always be the whole card, since every slice's top segment belongs to the back board.
  const auto add = [&](Ref n) {
    std::uint32_t& mark = down ? at(n).in_back_area : at(n).in_floor_area;
    if (mark == epoch_) return;
    mark = epoch_;
    area.push_back(n);
    const int last = static_cast<int>(column(n.column).size()) - 1;
    const bool changed = n.column == changed_ && old_index_[static_cast<std::size_t>(n.index)] < 0;
    if (changed || n.index != (down ? last : 0)) stack_.push_back(n);
  };
  for (int i = 0; i < static_cast<int>(pending_.size()); ++i) {
    if (old_index_[static_cast<std::size_t>(i)] < 0) add(Ref{changed_, i});
  }
  // The old changed segments' neighbours, found with the old slice in place; those in the
  // slice itself are unchanged segments, named by their index in the new slice.
  const int c = changed_;
  changed_ = -1;
  const Column& old = columns_[static_cast<std::size_t>(c)];
  std::vector<Ref> next_to_old;
  for (int i = 0; i < static_cast<int>(old.size()); ++i) {
    if (new_index_[static_cast<std::size_t>(i)] >= 0) continue;
    neighbours(Ref{c, i}, down, [&](Ref n) { next_to_old.push_back(n); });
  }
  changed_ = c;
  for (Ref n : next_to_old) {
    if (n.column != c) {
      add(n);
    } else if (new_index_[static_cast<std::size_t>(n.index)] >= 0) {
      add(Ref{c, new_index_[static_cast<std::size_t>(n.index)]});
    }
  }
  while (!stack_.empty()) {
    const Ref r = stack_.back();
    stack_.pop_back();
    neighbours(r, down, add);
  }
}

// Reach inside `area` after the change: seeded by the boards and by folds entering the area
// from reached segments outside it (whose reach the change cannot alter). No side step enters
// the area from outside: the area is closed under the walk's moves, and side steps go both ways.
void IncrementalPopup::rewalk(bool down, const std::vector<Ref>& area) {
  stack_.clear();
  const auto in_area = [&](Ref n) { return (down ? at(n).in_back_area : at(n).in_floor_area) == epoch_; };
  const auto reach = [&](Ref n) {
    std::uint8_t& flag = down ? at(n).new_back : at(n).new_floor;
    if (flag || !in_area(n)) return;
    flag = 1;
    stack_.push_back(n);
  };
  for (Ref r : area) (down ? at(r).new_back : at(r).new_floor) = 0;
  for (Ref r : area) {
    const Column& col = column(r.column);
    const int last = static_cast<int>(col.size()) - 1;
    bool seed = down ? r.index == last : r.index == 0;
    if (!seed) {
      // The fold into r comes from the segment above (walk a) or below (walk b).
      const Ref from{r.column, down ? r.index + 1 : r.index - 1};
      const bool fold = down ? fold_below(col, r.index + 1) : fold_below(col, r.index);
      seed = fold && !in_area(from) && (down ? at(from).from_back : at(from).from_floor);
    }
    if (seed) reach(r);
  }
  while (!stack_.empty()) {
    const Ref r = stack_.back();
    stack_.pop_back();
    neighbours(r, down, reach);
  }
}

// Is this V0 segment part of the back board (the face of the sheet's top edge)?
bool IncrementalPopup::in_back_board(Ref start) {
  if (at(start).in_region == epoch_) return true;  // flooded before in this decision: it was
  std::vector<Ref> stack{start};
  at(start).in_region = epoch_;
  bool top = false;
  while (!stack.empty()) {
    const Ref r = stack.back();
    stack.pop_back();
    top = top || r.index == static_cast<int>(column(r.column).size()) - 1;
    const Segment& s = at(r);
    for (int c2 : {r.column - 1, r.column + 1}) {
      if (c2 < 0 || c2 >= static_cast<int>(columns_.size())) continue;
      const Column& other = column(c2);
      for (int i = 0; i < static_cast<int>(other.size()); ++i) {
        const Segment& o = other[static_cast<std::size_t>(i)];
        if (o.face != s.face || o.hi <= s.lo || o.lo >= s.hi || o.in_region == epoch_) continue;
        at(Ref{c2, i}).in_region = epoch_;
        stack.push_back(Ref{c2, i});
      }
    }
  }
  return top;
}

bool IncrementalPopup::decide(int x) {
  ++stats_.decisions;
  if (++epoch_ == 0) {  // after 2^32 decisions: clear the marks once rather than misread them
    for (Column& col : columns_) {
      for (Segment& s : col) s.in_back_area = s.in_floor_area = s.in_region = 0;
    }
    epoch_ = 1;
  }
  changed_ = x + sheet_.side;
  slice_faces(model_, sheet_, x, strip_);
  cut_into_segments(strip_, pending_);
  // Segments the change leaves as they were keep their reach until shown otherwise.
  const Column& old = columns_[static_cast<std::size_t>(changed_)];
  old_index_.assign(pending_.size(), -1);
  new_index_.assign(old.size(), -1);
  for (std::size_t i = 0, j = 0; i < old.size() && j < pending_.size();) {
    if (old[i].lo == pending_[j].lo && old[i].hi == pending_[j].hi && old[i].face == pending_[j].face) {
      old_index_[j] = static_cast<int>(i);
      new_index_[i] = static_cast<int>(j);
      pending_[j].from_back = old[i].from_back;
      pending_[j].from_floor = old[i].from_floor;
    }
    (old[i].hi <= pending_[j].hi ? ++i : ++j);
  }
  closure(true, area_back_);
  closure(false, area_floor_);
  rewalk(true, area_back_);
  rewalk(false, area_floor_);
  stats_.segments_visited += static_cast<std::int64_t>(area_back_.size() + area_floor_.size());

  // Segments neither walk reaches: the old slice's go, the new slice's come (those outside the
  // areas with the reach they kept), and the re-walked others change.
  std::int64_t neither = neither_;
  for (const Segment& s : old) neither -= (!s.from_back && !s.from_floor) ? 1 : 0;
  for (const Segment& s : pending_) {
    if (s.in_back_area != epoch_ && s.in_floor_area != epoch_) neither += (!s.from_back && !s.from_floor) ? 1 : 0;
  }
  bool standing = true;
  const auto judge = [&](Ref r) {
    const Segment& s = at(r);
    const bool a = s.in_back_area == epoch_ ? s.new_back : s.from_back;
    const bool b = s.in_floor_area == epoch_ ? s.new_floor : s.from_floor;
    if (r.column != changed_) neither -= (!s.from_back && !s.from_floor) ? 1 : 0;
    neither += (!a && !b) ? 1 : 0;
    // A VFace must be reached by both walks unless it is the back board (which walk (a) starts
    // from, so a V0 segment without walk (a) is never part of it).
    if (CellGrid::kind_of(s.face) == FaceKind::vertical && !(a && b)) {
      if (!(a && s.face == kBackWall && in_back_board(r))) standing = false;
    }
  };
  for (Ref r : area_back_) {
    judge(r);
    if (!standing) return false;
  }
  for (Ref r : area_floor_) {
    if (at(r).in_back_area == epoch_) continue;
    judge(r);
    if (!standing) return false;
  }
  // Every VFace stands. With every segment reached by one walk or the other and the floor
  // reached from the back board, every piece hangs together with both boards: no loose pieces,
  // no split sheet. Otherwise (rare) only the full check can tell.
  pending_neither_ = neither;
  const Segment& floor = pending_.front();
  if (neither > 0 || !(floor.in_back_area == epoch_ ? floor.new_back : floor.from_back)) {
    ++stats_.full_checks;
    return full_check();
  }
  return true;
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
  // Commit the decision just made: the re-walked areas take their new reach.
  changed_ = x + sheet_.side;
  for (Ref r : area_back_) at(r).from_back = at(r).new_back;
  for (Ref r : area_floor_) at(r).from_floor = at(r).new_floor;
  changed_ = -1;
  columns_[static_cast<std::size_t>(x + sheet_.side)] = pending_;
  neither_ = pending_neither_;
  return true;
}

}  // namespace popcut

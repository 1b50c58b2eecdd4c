// The tour's local search: 2-opt, Or-opt and closed-loop starts over a greedy tour of paths.
#pragma once

#include <cstdint>
#include <vector>

#include "plan/path_geometry.h"
#include "popcut/pattern/pattern.h"

namespace popcut::plan_detail {

// Local search over a tour of paths: 2-opt (reverse a run of paths), Or-opt (move a run of one
// to three paths elsewhere, either way round), and each closed loop's start vertex. Candidate
// moves come from each path end's nearest other path ends, so a sweep costs O(n), not O(n²).
// Work is counted (evaluations and elements moved), never timed: one input, one tour.
class TourSearch {
 public:
  TourSearch(std::vector<std::vector<Point2>> tour, Point2 start, std::uint64_t budget);
  // Descends, then kicks and descends again while the budget lasts; the best tour found.
  std::vector<std::vector<Point2>> run();

 private:
  static constexpr double kGain = 1e-9;  // mm: smaller gains are rounding, not improvement
  static constexpr std::size_t kNeighbours = 8;
  static constexpr int kLoopSearchSteps = 30;     // golden-section steps per segment: 1e-6 of its length
  static constexpr double kLoopSplitGain = 0.01;  // mm: a loop starts mid-segment only to save more

  // An anchor is a place a path may be entered or left: an open path's ends, a loop's vertices,
  // and the start (owner -1).
  struct Anchor {
    Point2 at;
    int owner;
    int vertex;  // index into the path's points
  };
  struct Saved {
    std::vector<int> order;
    std::vector<char> flip;
    std::vector<LoopStart> loop_at;
  };

  // The tour as it stands: who is where, and where each path is entered and left.
  int path_at(long i) const { return order_[static_cast<std::size_t>(i)]; }
  Point2 entry(long i) const {
    const int s = path_at(i);
    const auto& p = paths_[static_cast<std::size_t>(s)];
    if (closed_[static_cast<std::size_t>(s)]) return loop_point(p, loop_at_[static_cast<std::size_t>(s)]);
    return flip_[static_cast<std::size_t>(s)] ? p.back() : p.front();
  }
  Point2 exit(long i) const {
    if (i < 0) return start_;
    const int s = path_at(i);
    const auto& p = paths_[static_cast<std::size_t>(s)];
    if (closed_[static_cast<std::size_t>(s)]) return loop_point(p, loop_at_[static_cast<std::size_t>(s)]);
    return flip_[static_cast<std::size_t>(s)] ? p.front() : p.back();
  }
  // Knife-up move into position i (none past the end).
  double link(long i) const { return i < n_ ? dist(exit(i - 1), entry(i)) : 0; }
  // Does anchor `a` (of a path, at its position) currently serve as the entry / the exit?
  bool is_entry(const Anchor& a) const {
    if (a.owner < 0) return false;
    const auto s = static_cast<std::size_t>(a.owner);
    if (closed_[s])
      return static_cast<std::size_t>(a.vertex) == loop_at_[s].seg;  // the anchor before a mid-segment start
    return (a.vertex == 0) != static_cast<bool>(flip_[s]);
  }
  bool is_exit(const Anchor& a) const {
    if (a.owner < 0) return true;
    const auto s = static_cast<std::size_t>(a.owner);
    if (closed_[s])
      return static_cast<std::size_t>(a.vertex) == loop_at_[s].seg;  // the anchor before a mid-segment start
    return (a.vertex == 0) == static_cast<bool>(flip_[s]);
  }
  long position(const Anchor& a) const { return a.owner < 0 ? -1 : pos_[static_cast<std::size_t>(a.owner)]; }

  void build_anchors();
  void build_neighbours();

  // Moves: each gain is counted work; a move re-queues the paths whose links it changed.
  double gain_reverse(long lo, long hi);
  void reverse(long lo, long hi);
  double gain_move(long i, long j, long q, bool rev);
  void move(long i, long j, long q, bool rev);
  bool try_move(long i, long j, long q, bool rev);
  bool try_two_opt(long i, long q, bool a_in, bool a_out, bool c_in, bool c_out);
  bool try_or_opt(long i, long q, bool a_in, bool a_out, bool c_in, bool c_out);
  bool improve_at(long i);
  bool place_loop_start(long i);

  void touch(long i);
  void descend();
  double tour_mm();
  Saved save();
  void restore(const Saved& s);
  void kick(bool bridge, std::uint64_t& seed);
  std::vector<std::vector<Point2>> take_tour();

  std::vector<std::vector<Point2>> paths_;
  Point2 start_;
  std::uint64_t budget_;
  std::uint64_t work_ = 0;
  long n_;
  std::vector<int> order_;          // path ids in cutting order
  std::vector<long> pos_;           // position of each path id
  std::vector<char> flip_;          // open path cut back to front
  std::vector<LoopStart> loop_at_;  // closed loop: where it starts and ends
  std::vector<char> closed_;
  std::vector<Anchor> anchors_;
  std::vector<std::vector<int>> of_path_;  // anchors of each path
  std::vector<std::vector<int>> near_;     // nearest anchors of other paths (or the start)
  std::vector<int> queue_;                 // paths to look at again
  std::vector<char> queued_;
};

}  // namespace popcut::plan_detail

// The tour's local search: 2-opt, Or-opt and loop starts over near path ends, then kicks.
#include "plan/tour_search.h"

#include <algorithm>
#include <array>
#include <numeric>
#include <utility>

#include "popcut/spatial_grid.h"

namespace popcut::plan_detail {

TourSearch::TourSearch(std::vector<std::vector<Point2>> tour, Point2 start, std::uint64_t budget)
    : paths_(std::move(tour)), start_(start), budget_(budget), n_(static_cast<long>(paths_.size())) {
  order_.resize(paths_.size());
  std::iota(order_.begin(), order_.end(), 0);
  pos_.assign(order_.begin(), order_.end());
  flip_.assign(paths_.size(), 0);
  loop_at_.assign(paths_.size(), LoopStart{});
  closed_.resize(paths_.size());
  for (std::size_t s = 0; s < paths_.size(); ++s) closed_[s] = is_closed(paths_[s]);
  build_anchors();
  build_neighbours();
}

std::vector<std::vector<Point2>> TourSearch::run() {
  queued_.assign(paths_.size(), 0);
  for (long i = 0; i < n_; ++i) touch(i);
  descend();
  // Iterated local search: kick the tour (double bridge, or reverse a stretch), descend again,
  // keep the result only if shorter. The kicks come from a fixed-seed generator.
  double best = tour_mm();
  Saved saved = save();
  std::uint64_t seed = 0x9e3779b97f4a7c15ULL;
  const long kicks = n_ >= 3 ? std::max<long>(50, 2 * n_) : 0;
  for (long k = 0; k < kicks && work_ < budget_; ++k) {
    kick(k % 2 == 0, seed);
    descend();
    const double len = tour_mm();
    if (len < best - kGain) {
      best = len;
      saved = save();
    } else {
      restore(saved);
    }
  }
  return take_tour();
}

// The paths in tour order, each turned and each loop rotated as the search left them.
std::vector<std::vector<Point2>> TourSearch::take_tour() {
  std::vector<std::vector<Point2>> out;
  out.reserve(paths_.size());
  for (int s : order_) {
    auto& p = paths_[static_cast<std::size_t>(s)];
    if (closed_[static_cast<std::size_t>(s)]) rotate_loop(p, loop_at_[static_cast<std::size_t>(s)]);
    if (flip_[static_cast<std::size_t>(s)]) std::reverse(p.begin(), p.end());
    out.push_back(std::move(p));
  }
  return out;
}

void TourSearch::build_anchors() {
  for (std::size_t s = 0; s < paths_.size(); ++s) {
    const auto& p = paths_[s];
    const int owner = static_cast<int>(s);
    if (closed_[s]) {
      for (std::size_t k = 0; k + 1 < p.size(); ++k) anchors_.push_back({p[k], owner, static_cast<int>(k)});
    } else {
      anchors_.push_back({p.front(), owner, 0});
      anchors_.push_back({p.back(), owner, static_cast<int>(p.size() - 1)});
    }
  }
  anchors_.push_back({start_, -1, 0});
  of_path_.resize(paths_.size());
  for (std::size_t a = 0; a < anchors_.size(); ++a) {
    if (anchors_[a].owner >= 0) of_path_[static_cast<std::size_t>(anchors_[a].owner)].push_back(static_cast<int>(a));
  }
}

// Each anchor's kNeighbours nearest anchors of other paths (ties: the lower anchor).
void TourSearch::build_neighbours() {
  std::vector<Point2> at;
  for (const Anchor& a : anchors_) at.push_back(a.at);
  SpatialGrid grid(bounds(at), anchors_.size());
  for (std::size_t a = 0; a < anchors_.size(); ++a) grid.insert(static_cast<int>(a), at[a], anchors_[a].owner);
  near_.resize(anchors_.size());
  std::vector<std::pair<double, int>> found;
  for (std::size_t a = 0; a < anchors_.size(); ++a) {
    grid.nearest(at[a], kNeighbours, anchors_[a].owner, found);
    for (const auto& [d, b] : found) near_[a].push_back(b);
  }
}

// Gain of reversing positions lo..hi (each path turned round too).
double TourSearch::gain_reverse(long lo, long hi) {
  ++work_;
  const double before = link(lo) + link(hi + 1);
  const double after = dist(exit(lo - 1), exit(hi)) + (hi + 1 < n_ ? dist(entry(lo), entry(hi + 1)) : 0);
  return before - after;
}

void TourSearch::reverse(long lo, long hi) {
  std::reverse(order_.begin() + lo, order_.begin() + hi + 1);
  for (long k = lo; k <= hi; ++k) {
    flip_[static_cast<std::size_t>(path_at(k))] ^= 1;
    pos_[static_cast<std::size_t>(path_at(k))] = k;
  }
  work_ += static_cast<std::uint64_t>(hi - lo + 1);
  touch(lo);
  touch(hi);
}

// Gain of moving the run i..j to just after position q (q = -1: first), turned round or not.
double TourSearch::gain_move(long i, long j, long q, bool rev) {
  ++work_;
  const double removed = link(i) + link(j + 1) - (j + 1 < n_ ? dist(exit(i - 1), entry(j + 1)) : 0);
  const Point2 in = rev ? exit(j) : entry(i), out = rev ? entry(i) : exit(j);
  const double added = dist(exit(q), in) + (q + 1 < n_ ? dist(out, entry(q + 1)) - link(q + 1) : 0);
  return removed - added;
}

void TourSearch::move(long i, long j, long q, bool rev) {
  // The paths either side of the gap left behind and of the gap filled get new links.
  std::vector<int> near;
  for (long k : {i - 1, j + 1, q, q + 1}) {
    if (k >= 0 && k < n_) near.push_back(path_at(k));
  }
  std::vector<int> run(order_.begin() + i, order_.begin() + j + 1);
  if (rev) {
    std::reverse(run.begin(), run.end());
    for (int s : run) flip_[static_cast<std::size_t>(s)] ^= 1;
  }
  order_.erase(order_.begin() + i, order_.begin() + j + 1);
  const long at = q < i ? q + 1 : q + 1 - (j - i + 1);
  order_.insert(order_.begin() + at, run.begin(), run.end());
  const long lo = std::min(i, at), hi = std::max(j, at + (j - i));
  for (long k = lo; k <= hi; ++k) pos_[static_cast<std::size_t>(path_at(k))] = k;
  // erase and insert each shift the rest of the order
  work_ += static_cast<std::uint64_t>(hi - lo + 1) + 2 * static_cast<std::uint64_t>(n_ - lo);
  for (int p : near) touch(pos_[static_cast<std::size_t>(p)]);
  touch(at);
  touch(at + (j - i));
}

bool TourSearch::try_move(long i, long j, long q, bool rev) {
  if (i < 0 || j >= n_ || i > j || (q >= i - 1 && q <= j) || q < -1 || q >= n_) return false;
  if (gain_move(i, j, q, rev) <= kGain) return false;
  move(i, j, q, rev);
  return true;
}

// 2-opt: exit next to exit, or entry next to entry, by reversing what lies between positions i and q.
bool TourSearch::try_two_opt(long i, long q, bool a_in, bool a_out, bool c_in, bool c_out) {
  if (a_out && c_out) {
    const long lo = std::min(i, q) + 1, hi = std::max(i, q);
    if (lo <= hi && gain_reverse(lo, hi) > kGain) return reverse(lo, hi), true;
  }
  if (a_in && c_in) {
    const long lo = std::min(i, q), hi = std::max(i, q) - 1;
    if (lo <= hi && gain_reverse(lo, hi) > kGain) return reverse(lo, hi), true;
  }
  return false;
}

// Or-opt: a run of one to three paths starting (or ending) with the one at i goes next to q's.
bool TourSearch::try_or_opt(long i, long q, bool a_in, bool a_out, bool c_in, bool c_out) {
  for (long len = 1; len <= 3; ++len) {
    if (a_in && c_out && try_move(i, i + len - 1, q, false)) return true;
    if (a_in && c_in && try_move(i, i + len - 1, q - 1, true)) return true;
    if (a_out && c_in && try_move(i - len + 1, i, q - 1, false)) return true;
    if (a_out && c_out && try_move(i - len + 1, i, q, true)) return true;
  }
  return false;
}

// First improving 2-opt or Or-opt move that makes a knife-up link between a path end at
// position i and one of its near anchors.
bool TourSearch::improve_at(long i) {
  for (int ai : of_path_[static_cast<std::size_t>(path_at(i))]) {
    const Anchor& a = anchors_[static_cast<std::size_t>(ai)];
    const bool a_in = is_entry(a), a_out = is_exit(a);
    if (!a_in && !a_out) continue;
    for (int ci : near_[static_cast<std::size_t>(ai)]) {
      if (work_ >= budget_) return false;
      const Anchor& c = anchors_[static_cast<std::size_t>(ci)];
      const long q = position(c);
      const bool c_in = is_entry(c), c_out = is_exit(c);
      if (q == i || (!c_in && !c_out)) continue;
      if (try_two_opt(i, q, a_in, a_out, c_in, c_out) || try_or_opt(i, q, a_in, a_out, c_in, c_out)) return true;
    }
  }
  // The end of the tour is free: appending costs only the link there.
  for (long len = 1; len <= 3; ++len) {
    for (bool rev : {false, true}) {
      if (try_move(i, i + len - 1, n_ - 1, rev)) return true;
    }
  }
  // Flip this path in place; turn the whole rest of the tour round.
  for (long hi : {i, n_ - 1}) {
    if (gain_reverse(i, hi) > kGain) return reverse(i, hi), true;
  }
  return place_loop_start(i);
}

// A closed loop starts at the point of it nearest to both its knife-up links: a vertex, or a
// point inside a segment (which then becomes a vertex of the stroke) when that saves more than
// kLoopSplitGain. Along a segment the two links' sum is convex: golden-section search.
bool TourSearch::place_loop_start(long i) {
  const auto s = static_cast<std::size_t>(path_at(i));
  if (!closed_[s]) return false;
  const auto& p = paths_[s];
  const Point2 from = exit(i - 1);
  const bool last = i + 1 >= n_;
  const Point2 to = last ? from : entry(i + 1);
  const auto cost = [&](Point2 q) { return dist(from, q) + (last ? 0 : dist(q, to)); };
  LoopStart best = loop_at_[s];
  double best_d = cost(loop_point(p, best));
  for (std::size_t k = 0; k + 1 < p.size(); ++k) {
    if (const double d = cost(p[k]); d < best_d - kGain) best_d = d, best = {k, 0};
    constexpr double kGolden = 0.6180339887498949;
    double lo = 0, hi = 1;
    for (int step = 0; step < kLoopSearchSteps; ++step) {
      const double a = hi - kGolden * (hi - lo), b = lo + kGolden * (hi - lo);
      if (cost(lerp(p[k], p[k + 1], a)) < cost(lerp(p[k], p[k + 1], b)))
        hi = b;
      else
        lo = a;
    }
    const double t = (lo + hi) / 2, len = dist(p[k], p[k + 1]);
    if (t * len <= kLoopSplitGain || (1 - t) * len <= kLoopSplitGain) continue;  // a vertex: tried above
    if (const double d = cost(lerp(p[k], p[k + 1], t)); d < best_d - kLoopSplitGain) best_d = d, best = {k, t};
  }
  work_ += p.size() * (2 * kLoopSearchSteps + 2);
  if (best == loop_at_[s]) return false;
  loop_at_[s] = best;
  touch(i);
  return true;
}

// Paths whose links changed are looked at again; the rest stay settled ("don't look" bits).
void TourSearch::touch(long i) {
  for (long k = std::max(0L, i - 1); k <= std::min(n_ - 1, i + 1); ++k) {
    const auto s = static_cast<std::size_t>(path_at(k));
    if (!queued_[s]) queued_[s] = 1, queue_.push_back(static_cast<int>(s));
  }
}

void TourSearch::descend() {
  for (std::size_t head = 0; head < queue_.size() && work_ < budget_; ++head) {
    const auto s = static_cast<std::size_t>(queue_[head]);
    queued_[s] = 0;
    if (improve_at(pos_[s])) touch(pos_[s]);
  }
  queue_.clear();
  std::fill(queued_.begin(), queued_.end(), 0);
}

double TourSearch::tour_mm() {
  double t = 0;
  for (long i = 0; i < n_; ++i) t += link(i);
  work_ += static_cast<std::uint64_t>(n_);
  return t;
}

TourSearch::Saved TourSearch::save() {
  work_ += static_cast<std::uint64_t>(n_);
  return {order_, flip_, loop_at_};
}

void TourSearch::restore(const Saved& s) {
  order_ = s.order;
  flip_ = s.flip;
  loop_at_ = s.loop_at;
  for (long k = 0; k < n_; ++k) pos_[static_cast<std::size_t>(path_at(k))] = k;
  work_ += static_cast<std::uint64_t>(n_);
}

namespace {

// splitmix64: a fixed sequence on every platform (std distributions are not portable).
std::uint64_t next(std::uint64_t& x) {
  std::uint64_t z = (x += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

}  // namespace

void TourSearch::kick(bool bridge, std::uint64_t& seed) {
  std::array<long, 3> cut{};
  for (long& c : cut) c = static_cast<long>(next(seed) % static_cast<std::uint64_t>(n_ + 1));
  std::sort(cut.begin(), cut.end());
  if (bridge && cut[0] < cut[1] && cut[1] < cut[2]) {
    // A B C D -> A C B D: a move 2-opt and Or-opt cannot undo in one step.
    std::rotate(order_.begin() + cut[0], order_.begin() + cut[1], order_.begin() + cut[2]);
    for (long k = cut[0]; k < cut[2]; ++k) pos_[static_cast<std::size_t>(path_at(k))] = k;
    work_ += static_cast<std::uint64_t>(cut[2] - cut[0]);
    for (long c : {cut[0], cut[0] + cut[2] - cut[1], cut[2] - 1}) touch(c);
  } else {
    const long lo = std::min(cut[0], n_ - 1), hi = std::max(lo, std::min(cut[2], n_ - 1));
    reverse(lo, hi);
  }
}

}  // namespace popcut::plan_detail

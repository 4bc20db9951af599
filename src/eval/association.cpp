#include "asynevo/eval/association.hpp"

#include <algorithm>
#include <tuple>

namespace asynevo::eval {

std::vector<Match> associate(const std::vector<int64_t>& est_t_ns, const std::vector<int64_t>& gt_t_ns,
                             int64_t max_diff_ns) {
  // Candidates: all pairs closer than max_diff (both lists are sorted, so a sliding window over the
  // ground truth finds them without the O(n·m) scan).
  struct Candidate {
    int64_t diff;
    std::size_t est, gt;
  };
  std::vector<Candidate> candidates;
  std::size_t window_begin = 0;
  for (std::size_t i = 0; i < est_t_ns.size(); ++i) {
    const int64_t t = est_t_ns[i];
    while (window_begin < gt_t_ns.size() && gt_t_ns[window_begin] <= t - max_diff_ns) ++window_begin;
    for (std::size_t j = window_begin; j < gt_t_ns.size() && gt_t_ns[j] < t + max_diff_ns; ++j) {
      const int64_t diff = gt_t_ns[j] > t ? gt_t_ns[j] - t : t - gt_t_ns[j];
      if (diff < max_diff_ns) candidates.push_back({diff, i, j});
    }
  }
  // Closest first; ties by estimate index, then ground-truth index (Python's tuple sort).
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    return std::tie(a.diff, a.est, a.gt) < std::tie(b.diff, b.est, b.gt);
  });
  std::vector<bool> est_used(est_t_ns.size(), false), gt_used(gt_t_ns.size(), false);
  std::vector<Match> matches;
  for (const Candidate& c : candidates) {
    if (est_used[c.est] || gt_used[c.gt]) continue;
    est_used[c.est] = true;
    gt_used[c.gt] = true;
    matches.push_back({c.est, c.gt});
  }
  std::sort(matches.begin(), matches.end(),
            [](const Match& a, const Match& b) { return std::tie(a.est, a.gt) < std::tie(b.est, b.gt); });
  return matches;
}

std::vector<Match> associate(const StampedTrajectory& est, const StampedTrajectory& gt, int64_t max_diff_ns) {
  std::vector<int64_t> est_t, gt_t;
  est_t.reserve(est.size());
  gt_t.reserve(gt.size());
  for (const auto& p : est) est_t.push_back(p.t_ns);
  for (const auto& p : gt) gt_t.push_back(p.t_ns);
  return associate(est_t, gt_t, max_diff_ns);
}

}  // namespace asynevo::eval

#include "joins.h"

#include <algorithm>

namespace treeskel::modeling::detail {

using Eigen::Vector3d;

std::pair<Ring, Vector3d> arm_ring(const Arm& arm, double d, const Polyline& line, int sides) {
  Ring ring = ring_at(line, arm.forward ? d : line.length() - d, sides);
  ring.radius *= arm.neck;
  return {ring, arm.forward ? ring.normal : Vector3d(-ring.normal)};
}

std::optional<std::size_t> place_rings(Cluster& cl, double reach, const std::vector<Polyline>& lines,
                                       const std::vector<int>& sides, double eps, std::vector<std::size_t>& partner) {
  const std::size_t k = cl.arms.size();
  for (auto& arm : cl.arms)
    arm.d = std::min(kFirstRingRadii * lines[arm.chain].r[arm.forward ? 0 : lines[arm.chain].r.size() - 1], arm.available);
  for (int it = 0; it < kMaxJunctionIterations; ++it) {
    std::vector<std::pair<Ring, Vector3d>> rings;
    for (const auto& arm : cl.arms) rings.push_back(arm_ring(arm, arm.d, lines[arm.chain], sides[arm.chain]));
    bool moved = false;
    std::vector<double> step(k, 0.0);
    for (std::size_t i = 0; i < k; ++i) {
      double worst = -1e300, worst_cos = 0.0;
      for (std::size_t j = 0; j < k; ++j) {
        if (j == i) continue;
        const double r = reach_beyond(rings[i].first, rings[i].second, rings[j].first);
        if (r > worst) {
          worst = r;
          worst_cos = rings[i].second.dot(rings[j].second);
          partner[i] = j;
        }
      }
      const double margin = kRingClearanceRadii * rings[i].first.radius + eps;
      if (worst + margin > 0.0) {
        step[i] = (worst + margin) / std::max(1.0 - std::max(worst_cos, 0.0), kLeastFacingDivisor);
        moved = true;
      }
    }
    if (!moved) return std::nullopt;
    std::optional<std::size_t> failed;
    double worst_over = 0.0;
    for (std::size_t i = 0; i < k; ++i) {
      cl.arms[i].d += step[i];
      double over = cl.arms[i].d / std::max(std::min(cl.arms[i].available, reach), eps);
      if (cl.arms[i].kind == Arm::leaf) over *= kTwigOverrunWeight;
      if (over > 1.0 && over > worst_over) {
        worst_over = over;
        failed = i;
      }
    }
    if (failed) return failed;
  }
  std::size_t worst = 0;
  for (std::size_t i = 1; i < k; ++i)
    if (cl.arms[i].d / cl.arms[i].available > cl.arms[worst].d / cl.arms[worst].available) worst = i;
  return worst;
}

}  // namespace treeskel::modeling::detail

// control_evaluate: re-simulate the forces with the plain control forward model and
// measure the result against the keyframes (issue 3's report).
#include <cmath>

#include "control_forward_model.h"

namespace pliant::smoke {

ControlMetrics control_evaluate(const ControlModel& m, const FaceSeries& f) {
  using namespace control_detail;
  ForwardOps ops(m, kControlPressureTolerance);
  const SerialBelow serial(ops.cells());
  const std::vector<Vec> fd = to_double(f);
  TrajectoryD t;
  forward_d(m, ops, fd, t);
  ControlMetrics out;
  for (const Vec& fi : fd)
    for (double x : fi) out.control_energy += x * x;
  out.objective = keyframe_error_d(m, t) + m.r * out.control_energy;
  for (const Vec& u : t.u) out.max_divergence = std::max(out.max_divergence, ops.max_divergence(u));
  out.iou_min = m.keyframes.empty() ? 0.0 : 1.0;
  for (const Keyframe& k : m.keyframes) {
    const Vec& r = t.rho[k.frame];
    double diff = 0, norm = 0, tmax = 0;
    for (size_t c = 0; c < r.size(); ++c) {
      diff += (r[c] - k.density[c]) * (r[c] - k.density[c]);
      norm += double(k.density[c]) * k.density[c];
      tmax = std::max(tmax, double(k.density[c]));
    }
    const double thr = 0.5 * tmax;
    size_t inter = 0, uni = 0;
    for (size_t c = 0; c < r.size(); ++c) {
      const bool a = r[c] >= thr, b = k.density[c] >= thr;
      inter += a && b;
      uni += a || b;
    }
    KeyframeMetrics km;
    km.frame = k.frame;
    km.relative_l2 = norm > 0 ? std::sqrt(diff / norm) : std::sqrt(diff);
    km.iou = uni ? double(inter) / double(uni) : 1.0;
    out.iou_min = std::min(out.iou_min, km.iou);
    out.keyframes.push_back(km);
  }
  return out;
}

}  // namespace pliant::smoke

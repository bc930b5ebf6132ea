// Sweep and prune over the filtered body-body pairs (contact.h, PairBroadphase): the
// same pairs reach the bounding-sphere test as in the full scan, in the same order,
// at O(G log G + overlaps) per call instead of O(G^2).
#include <algorithm>
#include <stdexcept>

#include "pliant/articulated/contact.h"

namespace pliant::articulated {

PairBroadphase pair_broadphase(const Model& m, const std::vector<GeomPair>& pairs) {
  PairBroadphase bp;
  const int ng = static_cast<int>(m.geoms.size());
  while (bp.filtered < static_cast<int>(pairs.size()) && !pairs[bp.filtered].explicit_pair &&
         !pairs[bp.filtered].world_sides)
    ++bp.filtered;
  std::vector<int> slot(ng, -1);  // per model geom: its entry in bp.geoms
  bp.first.assign(ng + 1, 0);
  double margin = 0;
  for (int p = 0; p < bp.filtered; ++p) {
    const GeomPair& pr = pairs[p];
    if (p > 0 && (pr.a < pairs[p - 1].a || (pr.a == pairs[p - 1].a && pr.b <= pairs[p - 1].b)))
      throw std::logic_error("pair_broadphase: filtered pairs not grouped by a with b ascending");
    ++bp.first[pr.a + 1];
    margin = std::max(margin, pr.mix.margin);
    for (int g : {pr.a, pr.b})
      if (slot[g] < 0) {
        slot[g] = static_cast<int>(bp.geoms.size());
        bp.geoms.push_back(g);
      }
  }
  for (int g = 0; g < ng; ++g) bp.first[g + 1] += bp.first[g];
  for (int g : bp.geoms) bp.radius.push_back(geom_bounding_radius(m.geoms[g]) + margin);
  const size_t n = bp.geoms.size();
  bp.centre.resize(n);
  bp.lo.resize(n);
  bp.hi.resize(n);
  return bp;
}

namespace contact_internal {

// Fills bp.candidates with the filtered pairs whose geoms' intervals overlap on the
// axis of largest spread and whose spheres of radius R (bounding radius + the largest
// margin) overlap, ascending. |c_a - c_b| < reach <= R_a + R_b for a pair the exact
// sphere test keeps, so none is lost.
void broadphase_candidates(const Model& m, const Kinematics& k, const std::vector<GeomPair>& pairs,
                           PairBroadphase& bp) {
  bp.candidates.clear();
  const size_t n = bp.geoms.size();
  if (n == 0) return;
  Vec3 mean = Vec3::Zero();
  for (size_t i = 0; i < n; ++i) {
    const Geom& g = m.geoms[bp.geoms[i]];
    bp.centre[i] = k.xpos[g.body] + k.xmat[g.body] * g.pos;
    mean += bp.centre[i];
  }
  mean /= static_cast<double>(n);
  Vec3 spread = Vec3::Zero();
  for (size_t i = 0; i < n; ++i) spread += (bp.centre[i] - mean).cwiseAbs2();
  int axis = 0;
  spread.maxCoeff(&axis);
  for (size_t i = 0; i < n; ++i) {
    bp.lo[i] = {bp.centre[i][axis] - bp.radius[i], static_cast<int>(i)};
    bp.hi[i] = bp.centre[i][axis] + bp.radius[i];
  }
  std::sort(bp.lo.begin(), bp.lo.end());
  for (size_t s = 0; s < n; ++s) {
    const int i = bp.lo[s].second;
    const double end = bp.hi[i];
    for (size_t t = s + 1; t < n && bp.lo[t].first < end; ++t) {
      const int j = bp.lo[t].second;
      const double reach = bp.radius[i] + bp.radius[j];
      if ((bp.centre[i] - bp.centre[j]).squaredNorm() >= reach * reach) continue;  // spheres apart
      const int a = std::min(bp.geoms[i], bp.geoms[j]), b = std::max(bp.geoms[i], bp.geoms[j]);
      // Is (a, b) a filtered pair? a's pairs are sorted by b.
      const auto begin = pairs.begin() + bp.first[a], stop = pairs.begin() + bp.first[a + 1];
      const auto it = std::lower_bound(begin, stop, b, [](const GeomPair& p, int v) { return p.b < v; });
      if (it != stop && it->b == b) bp.candidates.push_back(static_cast<int>(it - pairs.begin()));
    }
  }
  std::sort(bp.candidates.begin(), bp.candidates.end());
}

}  // namespace contact_internal
}  // namespace pliant::articulated

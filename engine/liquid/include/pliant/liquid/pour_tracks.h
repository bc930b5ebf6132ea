// Particle streamlines of a pour, recorded frame by frame from the full
// simulation: when each particle leaves the source, its free-flight samples,
// and where it crosses the target's rim height. Used by the objective C_OBJ
// (Eq. 2.6) and by the correction planner (Algorithm 2).
#pragma once
#include <array>
#include <vector>

#include "pliant/liquid/liquid.h"

namespace pliant::liquid {

class PourTracks {
 public:
  explicit PourTracks(const LiquidModel& m, const LiquidState& initial);
  // Call after every frame.
  void record(const LiquidState& s);

  struct Track {
    double leave_time = -1;               // s; -1 = still in the source
    bool landed = false;                  // crossed the rim height going down
    Vec3 landing{0, 0, 0};                // interpolated crossing point (world)
    double landing_time = -1;             // s
    Vec3 landing_offset{0, 0, 0};         // landing minus the opening centre at landing_time
    std::vector<std::array<double, 4>> flight;  // (t, x, y, z) after leaving, until landing
  };
  const std::vector<Track>& tracks() const { return tracks_; }

  // C_OBJ (Eq. 2.6): for each particle whose free flight is well fitted by a
  // parabola (quadratic in t per axis, RMS error < eps, >= 3 samples), the
  // distance from the parabola's crossing of the rim height to the opening
  // centre c (where a moving target is at the crossing time); returns the sum
  // over those particles (Eq. 2.6) and their count.
  double objective(double eps_m, int* useful = nullptr) const;
  // Centre of the target opening (world) at time t.
  Vec3 opening_centre(double t = 0) const;

 private:
  const LiquidModel& m_;
  std::vector<Track> tracks_;
  std::vector<unsigned char> in_source_;
  std::vector<Vec3> last_;
  double last_time_ = 0;
};

}  // namespace pliant::liquid

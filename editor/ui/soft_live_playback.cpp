// Live playback of a soft take's controller: instead of the take's stored frames,
// the viewport shows the engine's realtime simulation (soft_playback_step) of the
// optimised DMP parameters (the take's last checkpoint), one step per 1/dt of UI
// time, and keeps going past the take's end (the DMP is periodic). A push shoves
// the body sideways; Tracking adds the engine's feedback controller (PD on the
// controlled modes toward the open-loop reference, dissertation section 4.6), so an
// animator can watch the gait recover. The model compiles off the UI thread (with
// cubature: seconds on large bodies); the take view is untouched, so turning Live
// off shows the take's frame again.
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "pliant/core/take.h"
#include "ui/app.h"
#include "ui/soft_ui.h"
#include "ui/ui_mark.h"

#ifdef PLIANT_HAVE_SOFT
#include "pliant/core/scene.h"
#include "pliant/soft/soft.h"
#endif

namespace pliant::editor {

using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// Tracking gains (the engine's unit test recovers from a shove with these) and the
// push: 20 m/s^2 on every node for 0.2 s, sideways (+z; the gaits walk along x).
constexpr double kTrackKp = 3, kTrackKd = 0.3;
constexpr double kPushAccel = 20, kPushSeconds = 0.2;
// UI frames slower than the simulation drop the debt beyond this many steps, so a
// stall (window dragged, breakpoint) does not make the body fast-forward.
constexpr int kMaxStepsPerUiFrame = 4;

#ifdef PLIANT_HAVE_SOFT
// Worker thread: compile the take's scene copy, read theta from its last
// checkpoint and roll out the open-loop reference the tracking controller follows.
SoftLiveBuild build_live(const std::string& take_dir, const json& scene, const fs::path& scene_dir) {
  SoftLiveBuild b;
  try {
    Scene s;
    s.file = (scene_dir / "scene.json").string();
    s.dir = scene_dir;
    s.kind = "soft";
    s.doc = scene;
    auto m = std::make_shared<soft::SoftModel>(soft::soft_compile(s));
    soft::soft_bind(*m);
    Eigen::VectorXd theta;
    if (!soft::soft_take_theta(take_dir, *m, &theta)) {
      b.error = "the take has no optimised controller (no checkpoint with theta of size " +
                std::to_string(m->problem.dmp.parameters()) + ")";
      return b;
    }
    b.start = std::make_shared<soft::SoftPlayback>(soft::soft_playback_start(*m, theta));
    b.start->q_ref = soft::soft_reference_q(*m, theta, m->frames);
    b.model = std::move(m);
  } catch (const std::exception& e) {
    b.error = e.what();
  }
  return b;
}
#endif

size_t soft_live_reference_frames(const SoftLive& live) {
#ifdef PLIANT_HAVE_SOFT
  return live.start ? live.start->q_ref.size() : 0;
#else
  (void)live;
  return 0;
#endif
}

double soft_live_dt(const SoftLive& live) {
#ifdef PLIANT_HAVE_SOFT
  return live.model ? live.model->problem.sim.dt_s : 1.0 / 30;
#else
  (void)live;
  return 1.0 / 30;
#endif
}

}  // namespace

bool soft_live_start(App& app) {
  SoftLive& live = soft_ui(app).live;
  live = SoftLive{};
  TakeReader* rd = app.take.reader();
  if (!rd || rd->manifest().kind != "soft") {
    live.error = "open a soft take first (Optimize, or File > Open Take)";
    return false;
  }
#ifdef PLIANT_HAVE_SOFT
  live.on = true;
  live.take_dir = app.take.dir().string();
  live.scene = rd->manifest().scene;
  // Relative paths in the scene copy are relative to the scene file it came from.
  fs::path scene_dir = fs::path(rd->manifest().scene_file).parent_path();
  if (scene_dir.empty()) scene_dir = app.take.dir();
  live.pending = std::async(std::launch::async, build_live, live.take_dir, live.scene, scene_dir);
  return true;
#else
  live.error = "this editor was built without the soft module";
  return false;
#endif
}

void soft_live_stop(App& app) {
  SoftLive& live = soft_ui(app).live;
  if (!live.on) return;
  live.on = false;
  app.viewport.shown_frame = -1;  // the take's frame is uploaded again
}

int SoftLive::frame() const {
#ifdef PLIANT_HAVE_SOFT
  return pb ? pb->state.frame : 0;
#else
  return 0;
#endif
}

void soft_live_restart(SoftLive& live) {
#ifdef PLIANT_HAVE_SOFT
  if (!live.model || !live.start) return;
  live.pb = std::make_shared<soft::SoftPlayback>(*live.start);
  live.clock_s = 0;
  live.push_frames = 0;
  live.shown_frame = -1;
  live.drag_steps = 0;
  live.com.clear();
  const Eigen::Vector3d c = soft::centre_of_mass(live.model->character, live.pb->state);
  live.com.push_back({float(c.x()), float(c.y()), float(c.z())});
  const Eigen::Matrix3d& R = live.pb->state.R;
  live.yaw.assign(1, float(std::atan2(-R(2, 0), R(0, 0))));
#else
  (void)live;
#endif
}

bool soft_live_frame(App& app) {
  SoftLive& live = soft_ui(app).live;
  if (!live.on) return false;
  // A different take shown (a new run, Open Take): live follows the take view.
  if (app.take.dir().string() != live.take_dir) {
    soft_live_stop(app);
    return false;
  }
#ifdef PLIANT_HAVE_SOFT
  if (live.pending.valid()) {
    if (live.pending.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return false;
    SoftLiveBuild b = live.pending.get();
    if (!b.model) {
      live.error = b.error;
      soft_live_stop(app);
      return false;
    }
    live.model = std::move(b.model);
    live.start = std::move(b.start);
    soft_live_restart(live);
  }
  if (!live.pb) return false;
  const soft::SoftModel& m = *live.model;
  const double dt = m.problem.sim.dt_s;
  live.clock_s += ImGui::GetIO().DeltaTime;
  int steps = std::min(int(std::floor(live.clock_s / dt)), kMaxStepsPerUiFrame);
  live.clock_s = std::min(live.clock_s - steps * dt, dt);
  for (; steps > 0; --steps) {
    soft::SoftPlayback& pb = *live.pb;
    pb.track_kp = live.tracking ? kTrackKp : 0;
    pb.track_kd = live.tracking ? kTrackKd : 0;
    if (live.push_frames > 0) {
      pb.push_n = Eigen::Vector3d(0, 0, kPushAccel * m.character.mass_kg);
      --live.push_frames;
    }
    if (live.drag_vertex >= 0) {
      const Eigen::Vector3d f(live.drag_force[0], live.drag_force[1], live.drag_force[2]);
      if (live.drag_whole_body || live.drag_patch.empty())
        pb.push_n += f;
      else
        for (const auto& [v, w] : live.drag_patch) soft::add_vertex_force(m.character.lattice, v, double(w) * f, pb.push_nodal);
      live.drag_steps += f.squaredNorm() > 0;
    }
    try {
      soft::soft_playback_step(m, pb);
    } catch (const std::exception& e) {
      live.error = e.what();
      app.log.error(std::string("live playback: ") + e.what());
      soft_live_stop(app);
      return false;
    }
    const Eigen::Vector3d c = soft::centre_of_mass(m.character, pb.state);
    live.com.push_back({float(c.x()), float(c.y()), float(c.z())});
    live.yaw.push_back(float(std::atan2(-pb.state.R(2, 0), pb.state.R(0, 0))));
  }
  if (live.shown_frame != live.frame()) {
    const Record r = soft::soft_frame_record(m, live.pb->state, live.frame(), /*with_triangles=*/true);
    if (const Field* v = r.find("vertices")) live.vertices = v->data;  // the drag push picks on these
    app.renderer.set_frame(r, &live.scene);
    ++app.viewport.uploads;
    live.shown_frame = live.frame();
  }
  return true;
#else
  return false;
#endif
}

void draw_soft_live_controls(App& app) {
  SoftLive& live = soft_ui(app).live;
  bool on = live.on;
  if (ImGui::Checkbox("Live", &on)) {
    if (on) {
      if (!soft_live_start(app)) app.log.warn("live playback: " + live.error);
    } else {
      soft_live_stop(app);
    }
  }
  ui_mark("soft_live");
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("simulate the take's controller in realtime (past its end too), with pushes and tracking");
  if (!live.on) {
    if (!live.error.empty()) {
      ImGui::SameLine();
      ImGui::TextColored(ImVec4(1, 0.45f, 0.4f, 1), "%s", live.error.c_str());
    }
    return;
  }
  ImGui::SameLine();
  ImGui::Checkbox("Tracking", &live.tracking);
  ui_mark("soft_live_tracking");
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("feedback toward the open-loop gait (PD on the controlled modes, kp %.1f, kd %.1f)", kTrackKp,
                      kTrackKd);
  ImGui::SameLine();
  const bool ready = live.pb != nullptr;
  if (!ready) ImGui::BeginDisabled();
  if (ImGui::SmallButton("Push")) live.push_frames = int(std::lround(kPushSeconds / soft_live_dt(live)));
  ui_mark("soft_live_push");
  ImGui::SameLine();
  if (ImGui::SmallButton("Restart##live")) soft_live_restart(live);
  ui_mark("soft_live_restart");
  if (!ready) ImGui::EndDisabled();
  ImGui::SameLine();
  if (!ready) {
    ImGui::TextDisabled("compiling the body...");
  } else {
    const size_t n = soft_live_reference_frames(live);
    ImGui::TextDisabled("live frame %d (%.2f s)%s", live.frame(), live.frame() * soft_live_dt(live),
                        live.tracking && size_t(live.frame()) >= n ? ", past the tracked reference" : "");
  }
}

}  // namespace pliant::editor

// Soft character workflow (issue 5): UI state that is not document data and
// the pieces the soft panels share (soft_panels.cpp: inspector, jobs, timeline;
// soft_character_view.cpp: the Character edit mode; soft_gizmos.cpp: target,
// heading and jump handles).
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <future>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "doc/soft_scene.h"
#include "render/offscreen_target.h"
#include "render/line_drawer.h"
#include "render/mat4.h"
#include "render/mesh_drawer.h"
#include "render/orbit_camera.h"
#include "render/soft_drawer.h"
#include "ui/kind_panels.h"

namespace pliant::soft {
struct SoftModel;
struct SoftPlayback;
}

namespace pliant::editor {

class App;

// One finished body compile (worker thread -> UI thread).
struct SoftPreviewBuild {
  uint64_t key = 0;
  std::shared_ptr<soft::SoftModel> model;  // null when the compile failed
  std::string error;
  double compile_s = 0;
};

// The body compiled from the document (character + material only: no
// cubature, no objectives), recompiled off the UI thread when those sections
// change (ui/soft_preview_build.cpp): the previous body stays shown until the
// new one is done; a result the document no longer wants is dropped.
struct SoftPreviewModel {
  uint64_t key = 0;  // hash of the sections the shown model was compiled from (0 = none)
  std::shared_ptr<soft::SoftModel> model;  // null when the compile failed
  std::string error;
  double compile_s = 0;
  uint64_t wanted = 0;                     // hash of the document's sections now
  std::future<SoftPreviewBuild> pending;   // the worker's compile, when one runs
  int builds = 0;                          // finished compiles (tests)
  uint64_t frames_while_building = 0;      // UI frames drawn while a compile ran (tests)
  bool building() const { return pending.valid(); }
};

// Live playback (ui/soft_live_playback.cpp): the engine's realtime simulation of
// the shown take's controller, with pushes and tracking, instead of its frames.
struct SoftLiveBuild {  // worker thread -> UI thread
  std::shared_ptr<soft::SoftModel> model;  // null when the compile failed
  std::shared_ptr<soft::SoftPlayback> start;  // frame 0, with the tracked reference
  std::string error;
};
struct SoftLive {
  bool on = false;
  bool tracking = false;
  std::string take_dir;   // the take whose controller plays
  nlohmann::json scene;   // its scene copy (the drawer's take-data key)
  std::future<SoftLiveBuild> pending;
  std::shared_ptr<soft::SoftModel> model;
  std::shared_ptr<soft::SoftPlayback> start, pb;  // pb: null until the build is in
  double clock_s = 0;    // UI time not yet simulated
  int push_frames = 0;   // frames the push still acts
  int shown_frame = -1;  // the frame last handed to the renderer
  std::vector<std::array<float, 3>> com;  // centre of mass per live frame (tests, readout)
  std::string error;
  // Click-and-drag push (ui/soft_live_drag.cpp): the shown frame's surface (xyz,
  // for picking), the picked vertex while the button is held (-1: none), the
  // force the drag asks for (world N, horizontal; acts on every step while held),
  // the view held still meanwhile, and how many steps a drag push acted (tests).
  // The force acts where the body was grabbed: on the surface vertices of
  // drag_patch (the picked one and those within half a lattice cell of it, hat
  // weights summing to one), each carried to its cell's nodes by the embedding
  // weights (soft::add_vertex_force). drag_whole_body: the former push on every
  // node by mass (no moment; tests compare, no widget).
  std::vector<float> vertices;
  int drag_vertex = -1;
  Vec3 drag_force{0, 0, 0};
  OrbitCamera drag_camera;
  int drag_steps = 0;
  std::vector<std::pair<int, float>> drag_patch;
  bool drag_whole_body = false;
  std::vector<float> yaw;  // heading of the body frame about +y per live frame (rad; tests)
  int frame() const;
};

struct SoftUi : KindUiState {
  bool character_mode = false;  // the Character edit mode replaces the result view
  bool show_lattice = true;
  std::vector<float> amplitude_m;  // mode slider values (largest node displacement)
  SoftPreviewModel preview;
  int hovered_vertex = -1;
  std::string last_pick;  // "vertex 12 pinned at frame 5" (shown in the mode's toolbar)
  // Character-mode drawing (own framebuffer; the Renderer shows takes).
  bool gl_ready = false;
  bool gl_failed = false;  // the view's drawers failed to initialise: not shown again
  OffscreenTarget target;
  MeshDrawer mesh;
  LineDrawer lines;
  std::vector<float> drawn_state;
  uint64_t redraws = 0;  // character-mode framebuffer redraws (tests)
  Mat4 world_to_clip = mat4_identity();
  std::vector<float> surface;  // the previewed surface (xyz), for picking
  // Take data handed to the drawer (triangles, trail): the shown take and B.
  struct TakeSync {
    std::string dir;
    size_t frames = 0;
    SoftTakeData data;
  };
  TakeSync shown, compared;
  // Gizmo drag: which handle (0 none, 1 target, 2 heading, 3 jump), merge key,
  // the camera to hold still while dragging, where the drag started.
  int drag_handle = 0;
  uint64_t drag_serial = 0;
  OrbitCamera drag_camera;
  float drag_start_y = 0;
  double drag_start_value = 0;
  // Screen positions of the handles drawn last frame (scripts and tests drag them).
  struct Handle {
    int id = 0;  // 1 target, 2 heading tip, 3 jump, 4 pin target
    float x = 0, y = 0;
    int vertex = -1;  // pin targets: the pinned vertex
  };
  // Pin target drag (handle 4): the pin and its target at the start, where
  // the mouse ray met the target's horizontal plane then, the scene then
  // (each drag frame re-pins from it: one undo step per drag).
  SoftPin drag_pin;
  Vec3 drag_pin_target{0, 0, 0};
  Vec3 drag_start_hit{0, 0, 0};
  nlohmann::json drag_scene;
  std::vector<Handle> handles;
  SoftLive live;
  ~SoftUi() override;
};

SoftUi& soft_ui(App& app);

// Compiles the preview body when the document's character changed (cheap when not).
const SoftPreviewModel& soft_preview_model(App& app);

// The Character view is shown: chosen with the toolbar's checkbox, or no take yet
// (there is no result to show, and an empty viewport tells an animator nothing).
bool soft_character_shown(App& app);

// The Character edit mode (viewport_editor): true when it drew the viewport.
bool soft_character_view(App& app);

// Target, heading and jump handles over an image rectangle whose world -> clip
// matrix is given; drags edit the document (one undo step per drag).
// `base`: the character's centre at the start (heading arrow and jump height
// start there); `size`: its extent (handle lengths).
void soft_gizmos(App& app, const Mat4& world_to_clip, const Vec3& base, float size, float x, float y, int w,
                 int h);

// The pin frame for the shown take frame: clamped to [1, horizon].
int soft_pin_frame(App& app);

// Live playback: start (false with live.error when no soft take is shown), stop,
// back to frame 0; soft_live_frame is the kind's viewport_frame hook (steps at 1/dt
// of UI time, uploads the frame; false when the take's frame should show).
bool soft_live_start(App& app);
void soft_live_stop(App& app);
void soft_live_restart(SoftLive& live);
bool soft_live_frame(App& app);
void draw_soft_live_controls(App& app);
// Live playback's drag push over the result view (image rectangle x, y, w, h;
// world -> clip m): press on the body (the nearest drawn surface vertex within
// 12 px, front-most), drag, release. While held, the body is pushed along the
// drag in the ground plane: from the picked vertex to where the mouse ray meets
// the horizontal plane through it, kDragPushAccel x mass at a drag of one body
// length or more, less in proportion below, acting at the grabbed point (its
// patch of surface vertices, see SoftLive): off the centre of mass it turns the
// body. Drawn as an arrow from the picked vertex.
void soft_live_drag(App& app, const Mat4& m, float x, float y, int w, int h);

// Dropping a mesh file on a soft scene (KindPanels::on_drop): sets
// /character/mesh (relative to the scene's folder when saved), one undo step.
// False for other kinds/extensions.
bool soft_on_drop(App& app, const std::filesystem::path& path);

}  // namespace pliant::editor

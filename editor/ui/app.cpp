#include "ui/app.h"

#include <GL/gl.h>
#include <GL/glext.h>
#include <imgui.h>
#include <imgui_impl_opengl3.h>

#include <cctype>
#include <cstdio>

#include "doc/config_dir.h"
#include "doc/doc_commands.h"
#include "render/screenshot.h"
#include "ui/panels.h"

namespace pliant::editor {

namespace fs = std::filesystem;

namespace {
std::string lower_ext(const std::string& p) {
  std::string e = fs::path(p).extension().string();
  for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
  return e;
}
bool is_image_file(const std::string& p) {
  const std::string e = lower_ext(p);
  return e == ".png" || e == ".jpg" || e == ".jpeg" || e == ".bmp" || e == ".tga";
}
bool is_mesh_file(const std::string& p) {
  const std::string e = lower_ext(p);
  return e == ".obj" || e == ".stl" || e == ".ply" || e == ".off" || e == ".fbx" || e == ".gltf" || e == ".glb";
}
}  // namespace

App::App(AppOptions opt)
    : recent(fs::path()), opt_(std::move(opt)) {
  if (opt_.config_dir.empty()) opt_.config_dir = config_dir();
  recent = RecentFiles(opt_.config_dir / "recent.json");
}

App::~App() { shutdown(false); }

bool App::init(std::unique_ptr<Platform> platform, std::string* err) {
  platform_ = std::move(platform);
  job_threads = opt_.job_threads;
  if (ImGui::GetCurrentContext() == nullptr) {
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    imgui_owned_ = true;
  }
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;  // the layout is fixed; nothing to persist
  ImGui::StyleColorsDark();

  PlatformOptions po;
  po.width = opt_.width;
  po.height = opt_.height;
  po.fixed_dt_s = opt_.fixed_dt_s;
  po.vsync = true;
  if (!platform_->init(po, err)) return false;
  gl_ = platform_->has_gl();
  if (gl_) {
    if (!ImGui_ImplOpenGL3_Init("#version 330 core")) {
      *err = "ImGui OpenGL3 backend failed to initialize";
      return false;
    }
    gl_backend_ = true;
    std::string rerr;
    renderer_ok_ = renderer.init(&rerr);
    if (!renderer_ok_) log.error("renderer: " + rerr);
  } else {
    unsigned char* px;
    int w, h;
    io.Fonts->GetTexDataAsRGBA32(&px, &w, &h);  // ImGui needs a built atlas
  }

  std::error_code ec;
  fs::create_directories(opt_.config_dir, ec);
  recent.load();
  autosave = std::make_unique<Autosave>(opt_.config_dir, opt_.autosave_s);
  if (opt_.check_recovery) recovery = autosave->find_recovery();
  autosave->begin_session();

  if (!opt_.scene.empty()) {
    if (!cmd_open(opt_.scene)) {
      *err = status_;
      return false;
    }
  } else {
    cmd_new();
  }
  if (!opt_.take.empty()) cmd_open_take(opt_.take);
  if (recovery) log.warn("found unsaved work from a session that did not exit cleanly");
  log.info(gl_ ? "OpenGL: " + platform_->gl_description() : "no OpenGL (mock platform)");
  return true;
}

void App::shutdown(bool clean) {
  if (shut_down_) return;
  shut_down_ = true;
  for (auto& j : jobs) j->cancel();
  jobs.clear();  // joins the reader threads
  if (export_run) export_run->wait();
  if (autosave && clean) {
    // Closing a window with unsaved edits keeps them: the autosave stays and the
    // next start offers to recover it. Headless runs are automation: always clean.
    if (doc.dirty() && platform_ && !platform_->headless() && autosave->write_now(doc)) {
      std::fprintf(stderr, "pliant-editor: unsaved changes kept in %s; the next start offers to recover them\n",
                   autosave->autosave_file().c_str());
    } else {
      autosave->end_session();
    }
  }
  if (gl_) {
    viewport.target.release();
    release_canvas_gl(canvas);
    compare.release_gl();
    if (renderer_ok_) renderer.shutdown();
    if (gl_backend_) ImGui_ImplOpenGL3_Shutdown();
  }
  if (platform_) platform_->shutdown();  // before the context: the GLFW backend needs it
  if (imgui_owned_) ImGui::DestroyContext();
  imgui_owned_ = false;
}

bool App::should_quit() const {
  return quit_requested_ || (platform_ && platform_->should_close());
}

const std::string& App::scene_error() {
  if (scene_error_revision_ != doc.revision()) {
    scene_error_ = validate_scene(doc.scene(), doc.path());
    scene_error_revision_ = doc.revision();
  }
  return scene_error_;
}

void App::update_title() {
  std::string t = "Pliant - " + doc.title();
  if (t != last_title_) {
    platform_->set_title(t);
    last_title_ = t;
  }
}

void App::poll_jobs() {
  job_seen_state.resize(jobs.size(), JobState::Starting);
  for (size_t i = 0; i < jobs.size(); ++i) {
    auto& j = *jobs[i];
    std::string src = "job " + std::to_string(j.id);
    for (auto& l : j.take_log()) log.add(parse_log_level(l.level), src, l.message);
    JobStatus st = j.snapshot();
    // Report the end only once the child is reaped (exit code known).
    JobState shown = st.ended() && st.exit_code < 0 ? JobState::Running : st.state;
    if (shown != job_seen_state[i]) {
      job_seen_state[i] = shown;
      std::string msg = "Job " + std::to_string(j.id) + ": " + job_state_name(shown);
      bool failed = shown == JobState::Failed;
      if (failed) msg += ": " + st.error;
      log.add(failed ? LogLevel::Error : LogLevel::Info, src, msg);
      set_status(msg, failed);
    }
  }
}

void App::handle_drops(const std::vector<std::string>& paths) {
  const KindPanels* kp = kind_panels(scene_kind(*this));
  for (const auto& p : paths) {
    std::error_code ec;
    if (kp && kp->on_drop && !fs::is_directory(p, ec) && kp->on_drop(*this, p)) continue;
    if (fs::is_directory(p, ec)) {
      cmd_open_take(p);
    } else if (fs::path(p).extension() == ".json") {
      cmd_open(p);
    } else if (is_image_file(p)) {
      import_image_keyframe(*this, p, /*new_keyframe=*/true);
    } else if (is_mesh_file(p)) {
      import_mesh_keyframe(*this, p);
    } else {
      log.warn("dropped file ignored (not a scene .json, a take folder, an image or a mesh): " + p);
    }
  }
}

void App::frame() {
  platform_->new_frame();
  if (before_frame) before_frame(*this);
  input.apply();
  if (gl_) ImGui_ImplOpenGL3_NewFrame();
  ImGui::NewFrame();
  marks.begin_frame();
  set_ui_marks(&marks);

  handle_drops(platform_->take_dropped_files());
  poll_jobs();
  poll_export();
  take.update(ImGui::GetIO().DeltaTime);
  if (autosave && autosave->tick(doc, std::chrono::steady_clock::now()))
    log.add(LogLevel::Debug, "editor", "autosaved to " + autosave->autosave_file().string());
  handle_hotkeys();
  draw_layout();
  // A released widget ends its merge run: the next drag is a new undo step.
  if (!ImGui::IsAnyItemActive()) doc.history().close_merge();
  update_title();

  ImGui::Render();
  if (gl_) {
    int w = 0, h = 0;
    platform_->framebuffer_size(&w, &h);
    glBindFramebuffer(GL_FRAMEBUFFER, platform_->default_framebuffer());
    glViewport(0, 0, w, h);
    glDisable(GL_SCISSOR_TEST);
    glClearColor(0.06f, 0.06f, 0.07f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  }
  if (after_render) after_render(*this);
  platform_->present();
  set_ui_marks(nullptr);
  ++frames_;
}

void App::draw_layout() {
  draw_menu_bar(*this);
  float menu_h = ImGui::GetFrameHeight();
  ImVec2 ds = ImGui::GetIO().DisplaySize;
  Layout l = compute_layout(ds.x, ds.y, menu_h);
  if (panels.inspector) draw_inspector_panel(*this, l.inspector);
  if (panels.viewport) draw_viewport_panel(*this, l.viewport);
  if (panels.timeline) draw_timeline_panel(*this, l.timeline);
  if (panels.jobs) draw_jobs_panel(*this, l.jobs);
  if (panels.log) draw_log_panel(*this, l.log);
  draw_file_dialog(*this);
  draw_recovery_prompt(*this);
}

Image App::capture_window() const {
  if (!gl_) return {};
  int w = 0, h = 0;
  platform_->framebuffer_size(&w, &h);
  return read_framebuffer(platform_->default_framebuffer(), 0, 0, w, h);
}

Image App::capture_viewport() const {
  if (!gl_ || !viewport.target.fbo) return {};
  return read_framebuffer(viewport.target.fbo, 0, 0, viewport.target.w, viewport.target.h);
}

}  // namespace pliant::editor

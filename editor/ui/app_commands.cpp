// The App's commands: what menus, hotkeys, drops and scripts ask for.
#include <imgui.h>

#include <cstring>

#include "doc/doc_commands.h"
#include "doc/smoke_keyframes.h"
#include "pliant/core/scene.h"
#include "ui/app.h"
#include "ui/hotkeys.h"

namespace pliant::editor {

namespace fs = std::filesystem;

void App::cmd_new() {
  new_document(doc);
  take.close();
  set_status("New scene");
  log.info("new scene from " + (default_scene_path().empty() ? std::string("the built-in template")
                                                             : default_scene_path().string()));
}

bool App::cmd_open(const fs::path& path) {
  std::string err = open_document(doc, path);
  if (!err.empty()) {
    set_status("Open failed: " + err, true);
    log.error("cannot open scene: " + err);
    return false;
  }
  recent.add(path);
  take.close();
  // A keyframe scene opens on its keyframes (there is no result yet to show).
  viewport.show_canvas = has_control(doc.scene());
  set_status("Opened " + path.string());
  log.info(status_);
  return true;
}

bool App::cmd_save() {
  if (!doc.has_path()) {
    open_file_dialog(FileDialog::Mode::SaveAs);
    return false;
  }
  return cmd_save_as(doc.path());
}

bool App::cmd_save_as(const fs::path& path) {
  std::string err = save_document_as(doc, path);
  if (!err.empty()) {
    set_status("Save failed: " + err, true);
    log.error(err);
    return false;
  }
  recent.add(path);
  set_status("Saved " + path.string());
  log.info(status_);
  return true;
}

bool App::cmd_open_take(const fs::path& dir) {
  std::error_code ec;
  if (!fs::exists(dir / "take.json", ec)) {
    set_status("Not a take (no take.json): " + dir.string(), true);
    log.error(status_);
    return false;
  }
  take.open(dir);
  doc.take_dir = dir;
  viewport.show_canvas = false;  // the take is what was asked for
  set_status("Opened take " + dir.string());
  log.info(status_);
  return true;
}

void App::cmd_undo() {
  std::string label = doc.history().undo_label();
  if (doc.undo()) set_status("Undo " + label);
}

void App::cmd_redo() {
  std::string label = doc.history().redo_label();
  if (doc.redo()) set_status("Redo " + label);
}

bool App::cmd_run(const fs::path& take_dir, bool resume) {
  if (const std::string& e = scene_error(); !e.empty()) {
    set_status("Cannot run: " + e, true);
    log.error(status_);
    return false;
  }
  JobSpec spec;
  spec.pliant = opt_.pliant.empty() ? default_pliant_binary() : opt_.pliant;
  spec.take = take_dir.empty() ? default_take_dir(doc.path(), opt_.config_dir) : take_dir;
  spec.threads = job_threads;
  spec.resume = resume;
  // The job runs what the user sees, saved or not: write the scene beside the
  // take (same folder depth as the take, so the job never reads a half-saved file).
  spec.scene = doc.has_path() && !doc.dirty() ? doc.path()
                                              : fs::path(spec.take.string() + ".scene.json");
  try {
    std::error_code ec;
    fs::create_directories(spec.take.parent_path(), ec);
    if (spec.scene != doc.path()) {
      // Relative asset paths (meshes, images, models) still mean the document's folder.
      nlohmann::json copy = doc.scene();
      const fs::path base = doc.has_path() ? doc.path().parent_path() : default_scene_path().parent_path();
      if (copy.is_object() && !copy.contains("asset_dir") && !base.empty())
        copy["asset_dir"] = fs::absolute(base).lexically_normal().string();
      save_json_atomic(spec.scene, copy);
    }
  } catch (const std::exception& e) {
    set_status(std::string("Cannot run: ") + e.what(), true);
    log.error(status_);
    return false;
  }
  auto job = std::make_unique<JobProcess>();
  job->id = ++job_counter_;
  std::string err;
  if (!job->start(spec, &err)) {
    set_status("Cannot run: " + err, true);
    log.error(status_);
    return false;
  }
  set_status("Job " + std::to_string(job->id) + " started: " + spec.take.string());
  log.info(status_);
  jobs.push_back(std::move(job));
  job_seen_state.push_back(JobState::Starting);
  take.open(spec.take);
  doc.take_dir = spec.take;
  viewport.show_canvas = false;  // watch the run (the Keyframes button goes back)
  return true;
}

bool App::cmd_resume() {
  JobProcess* j = newest_job();
  if (!j || !j->snapshot().ended()) {
    set_status("Nothing to resume: no ended job", true);
    log.error(status_);
    return false;
  }
  return cmd_run(j->spec().take, /*resume=*/true);
}

void App::cmd_cancel(size_t i) {
  if (i >= jobs.size()) return;
  jobs[i]->cancel();
  set_status("Cancelling job " + std::to_string(jobs[i]->id));
  log.info(status_);
}

void App::open_file_dialog(FileDialog::Mode mode) {
  file_dialog.mode = mode;
  file_dialog.open_requested = true;
  file_dialog.error.clear();
  std::string init;
  if (mode == FileDialog::Mode::SaveAs && doc.has_path()) init = doc.path().string();
  if (mode == FileDialog::Mode::OpenTake && !doc.take_dir.empty()) init = doc.take_dir.string();
  if (!take.dir().empty()) {
    if (mode == FileDialog::Mode::ExportPng) init = take.dir().string() + "-png";
    if (mode == FileDialog::Mode::ExportMp4) init = take.dir().string() + "-mp4";
    if (mode == FileDialog::Mode::ExportVdb) init = take.dir().string() + "-vdb";
    if (mode == FileDialog::Mode::ExportParticles) init = take.dir().string() + "-particles";
    if (mode == FileDialog::Mode::ExportObj) init = take.dir().string() + "-obj";
    if (mode == FileDialog::Mode::ExportCsv) init = take.dir().string() + "-csv";
  }
  std::snprintf(file_dialog.path, sizeof file_dialog.path, "%s", init.c_str());
}

void App::recover(bool accept) {
  if (!recovery) return;
  if (accept) {
    nlohmann::json on_disk;
    bool have_disk = false;
    if (!recovery->file.empty()) {
      try {
        on_disk = load_scene(recovery->file).doc;
        have_disk = true;
      } catch (const std::exception&) {
      }
    }
    // The recovered scene is unsaved work: dirty against what the file holds.
    nlohmann::json empty = nlohmann::json::object();
    doc.reset(recovery->scene, have_disk ? recovery->file : fs::path(),
              have_disk ? &on_disk : &empty);
    take.close();
    set_status("Recovered unsaved work" +
               (recovery->file.empty() ? std::string() : " of " + recovery->file.string()));
  } else {
    set_status("Discarded the autosave of session " + std::to_string(recovery->pid));
  }
  log.info(status_);
  Autosave::forget(*recovery);
  recovery.reset();
}

void App::handle_hotkeys() {
  const ImGuiIO& io = ImGui::GetIO();
  bool text = io.WantTextInput;
  if (io.KeyCtrl && key_pressed_code(kKeyS)) {
    if (io.KeyShift) open_file_dialog(FileDialog::Mode::SaveAs);
    else cmd_save();
  }
  if (io.KeyCtrl && key_pressed_code(kKeyO)) open_file_dialog(FileDialog::Mode::Open);
  if (!text && io.KeyCtrl && key_pressed_named(ImGuiKey_Z)) {
    if (io.KeyShift) cmd_redo();
    else cmd_undo();
  }
  if (!text && io.KeyCtrl && key_pressed_named(ImGuiKey_Y)) cmd_redo();
  if (key_pressed_code(kKeyF1 + 4)) cmd_run();  // F5
  if (!text && !io.KeyCtrl) {
    if (key_pressed_named(ImGuiKey_Space)) take.playing = !take.playing;
    if (key_pressed_named(ImGuiKey_LeftArrow)) take.step(-1);
    if (key_pressed_named(ImGuiKey_RightArrow)) take.step(+1);
  }
}

}  // namespace pliant::editor

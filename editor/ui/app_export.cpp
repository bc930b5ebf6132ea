// Export of the shown take: PNG sequence and OpenVDB through the exporter plugins
// (`pliant export`), MP4 as the PNG sequence encoded by ffmpeg when installed.
// The commands run on a thread (ExportRun); the UI polls it every frame.
#include <GL/gl.h>
#include <GL/glext.h>

#include <cstdio>

#include "doc/export_run.h"
#include "render/screenshot.h"
#include "ui/app.h"

namespace pliant::editor {

namespace fs = std::filesystem;

// Takes drawn by a kind drawer (particles, meshes, bodies) have no exporter
// plugin that can draw them: their PNGs are the viewport's own rendering of
// every frame, with the current camera, at the viewport's size. GL lives on the
// UI thread, so this runs synchronously (tens of ms per frame).
bool App::export_rendered_frames(const fs::path& dir, std::string* err) {
  TakeReader* rd = take.reader();
  if (!gl_ || !renderer_ok_ || !rd) {
    *err = "rendered export needs the OpenGL viewport and an open take";
    return false;
  }
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) {
    *err = "cannot create " + dir.string() + ": " + ec.message();
    return false;
  }
  const int w = viewport.target.w > 15 ? viewport.target.w : 960;
  const int h = viewport.target.h > 15 ? viewport.target.h : 540;
  OffscreenTarget target;
  target.ensure(w, h);
  GLint prev = 0;
  glGetIntegerv(GL_FRAMEBUFFER_BINDING, &prev);
  bool ok = true;
  const size_t n = rd->frame_count();
  for (size_t i = 0; i < n && ok; ++i) {
    try {
      renderer.set_take_frame(*rd, i);
    } catch (const std::exception& e) {
      *err = "frame " + std::to_string(i) + ": " + e.what();
      ok = false;
      break;
    }
    target.bind();
    renderer.render(viewport.camera, viewport.settings, w, h);
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05zu.png", i);
    ok = write_png((dir / name).string(), read_framebuffer(target.fbo, 0, 0, w, h), err);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, GLuint(prev));
  target.release();
  viewport.shown_frame = -1;  // the viewport re-uploads its own frame
  ++viewport.uploads;
  return ok;
}

bool App::cmd_export(const std::string& format, const fs::path& out) {
  auto refuse = [&](const std::string& why) {
    set_status("Export failed: " + why, true);
    log.error(status_);
    return false;
  };
  if (export_run && !export_run->done()) return refuse("an export is already running");
  if (take.dir().empty() || take.frame_count() == 0) return refuse("no take with frames is shown");
  if (out.empty()) return refuse("no output folder");
  const std::string pliant = (opt_.pliant.empty() ? default_pliant_binary() : opt_.pliant).string();
  std::vector<std::vector<std::string>> cmds;
  auto plugin_export = [&](const std::string& name, const fs::path& dir) {
    cmds.push_back({pliant, "export", take.dir().string(), "--format", name, "--out", dir.string()});
  };
  // Kind drawers' takes: rendered frames now, then (MP4) ffmpeg on the thread.
  const bool rendered = !renderer.drawer_name().empty() && (format == "png" || format == "mp4");
  if (rendered) {
    std::string err;
    if (!export_rendered_frames(format == "png" ? out : out / "frames", &err)) return refuse(err);
  }
  if (format == "png") {
    if (!rendered) plugin_export("png", out);
  } else if (format == "vdb" || format == "particles" || format == "obj" || format == "csv") {
    plugin_export(format, out);
  } else if (format == "mp4") {
    const std::string ffmpeg = find_ffmpeg();
    if (ffmpeg.empty()) return refuse("MP4 needs ffmpeg, which is not installed (apt-get install ffmpeg)");
    if (!rendered) plugin_export("png", out / "frames");
    // Nearest-neighbour upscale to at least 512 px high (grids are small), even sizes for yuv420p.
    cmds.push_back({ffmpeg, "-y", "-loglevel", "error", "-framerate", std::to_string(int(take.fps)),
                    "-i", (out / "frames" / "frame_%05d.png").string(), "-vf",
                    "scale=-2:'max(512,trunc(ih/2)*2)':flags=neighbor", "-pix_fmt", "yuv420p",
                    (out / "take.mp4").string()});
  } else {
    return refuse("unknown format '" + format + "' (png, mp4, vdb, particles, obj, csv)");
  }
  if (export_run) export_run->wait();
  export_run = std::make_unique<ExportRun>(std::move(cmds), out);
  export_reported_ = false;
  set_status("Exporting " + format + " to " + out.string() + "...");
  log.info(status_);
  return true;
}

void App::poll_export() {
  if (!export_run || export_reported_ || !export_run->done()) return;
  export_reported_ = true;
  if (export_run->ok()) {
    set_status("Export done: " + export_run->message());
    log.info(status_);
  } else {
    set_status("Export failed: " + export_run->message(), true);
    log.error(status_);
  }
}

}  // namespace pliant::editor

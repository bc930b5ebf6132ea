// Export of the shown take: PNG sequence and OpenVDB through the exporter plugins
// (`pliant export`), MP4 as the PNG sequence encoded by ffmpeg when installed.
// The commands run on a thread (ExportRun); the UI polls it every frame.
#include "doc/export_run.h"
#include "ui/app.h"

namespace pliant::editor {

namespace fs = std::filesystem;

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
  if (format == "png") {
    plugin_export("png", out);
  } else if (format == "vdb") {
    plugin_export("vdb", out);
  } else if (format == "mp4") {
    const std::string ffmpeg = find_ffmpeg();
    if (ffmpeg.empty()) return refuse("MP4 needs ffmpeg, which is not installed (apt-get install ffmpeg)");
    plugin_export("png", out / "frames");
    // Nearest-neighbour upscale to at least 512 px high (grids are small), even sizes for yuv420p.
    cmds.push_back({ffmpeg, "-y", "-loglevel", "error", "-framerate", std::to_string(int(take.fps)),
                    "-i", (out / "frames" / "frame_%05d.png").string(), "-vf",
                    "scale=-2:'max(512,trunc(ih/2)*2)':flags=neighbor", "-pix_fmt", "yuv420p",
                    (out / "take.mp4").string()});
  } else {
    return refuse("unknown format '" + format + "' (png, mp4, vdb)");
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

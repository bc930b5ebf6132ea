// Articulated jobs started by the panels: Simulate, and "Compare integrators"
// (one `pliant run` per integrator on scene variants written beside their
// takes), with the runs' total energy read back from the takes frame by frame.
#include <algorithm>
#include <cmath>
#include <system_error>

#include "doc/config_dir.h"
#include "doc/job_process.h"
#include "pliant/core/scene.h"
#include "pliant/core/take.h"
#include "ui/app.h"
#include "ui/articulated_panels.h"

namespace pliant::editor {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

fs::path scene_folder(const App& app) {
  std::error_code ec;
  return app.doc.has_path() ? fs::absolute(app.doc.path(), ec).parent_path() : fs::current_path(ec);
}

// The document's scene with a relative model path made absolute, so the
// variant resolves the model wherever it is written.
json rebased_scene(const App& app) {
  json s = app.doc.scene();
  if (s.is_object() && s.contains("model") && s["model"].is_string()) {
    const fs::path rel = s["model"].get<std::string>();
    if (rel.is_relative()) s["model"] = (scene_folder(app) / rel).lexically_normal().string();
  }
  return s;
}

fs::path take_base(const App& app) {
  const fs::path cfg = app.options().config_dir.empty() ? config_dir() : app.options().config_dir;
  return default_take_dir(app.doc.path(), cfg);
}

// Writes `scene` to TAKE.scene.json and starts `pliant run` on it; the job joins
// app.jobs (the jobs panel shows its progress and Cancel).
JobProcess* start_job(App& app, const json& scene, const fs::path& take, std::string* err) {
  JobSpec spec;
  spec.pliant = app.options().pliant.empty() ? default_pliant_binary() : app.options().pliant;
  spec.take = take;
  spec.threads = app.job_threads;
  spec.scene = fs::path(take.string() + ".scene.json");
  try {
    std::error_code ec;
    fs::create_directories(take.parent_path(), ec);
    save_json_atomic(spec.scene, scene);
  } catch (const std::exception& e) {
    *err = e.what();
    return nullptr;
  }
  auto job = std::make_unique<JobProcess>();
  job->id = app.next_job_id();
  if (!job->start(spec, err)) return nullptr;
  JobProcess* p = job.get();
  app.jobs.push_back(std::move(job));
  app.job_seen_state.push_back(JobState::Starting);
  return p;
}

}  // namespace

const std::vector<std::string>& articulated_integrators() {
  static const std::vector<std::string> k = {"pbad2", "pbad3", "pbad4", "euler", "rk4"};
  return k;
}

double IntegratorRun::drift_percent() const {
  if (total.size() < 2) return -1;
  float kmax = 0, pmin = potential.front(), pmax = potential.front(), dmax = 0;
  for (size_t i = 0; i < total.size(); ++i) {
    kmax = std::max(kmax, kinetic[i]);
    pmin = std::min(pmin, potential[i]);
    pmax = std::max(pmax, potential[i]);
    dmax = std::max(dmax, std::fabs(total[i] - total.front()));
  }
  const double scale = std::max<double>({kmax, pmax - pmin, 1e-12});
  return 100.0 * dmax / scale;
}

bool articulated_compare_integrators(App& app, const std::vector<std::string>& integrators) {
  ArticulatedUiState& st = app.kind_ui.get<ArticulatedUiState>("articulated");
  st.compare_error.clear();
  if (const std::string& e = app.scene_error(); !e.empty()) {
    st.compare_error = "fix the scene first: " + e;
    app.set_status("Cannot compare: " + e, true);
    return false;
  }
  if (integrators.empty()) {
    st.compare_error = "pick at least one integrator";
    return false;
  }
  const json base_scene = rebased_scene(app);
  // default_take_dir is unique for its own name only: two comparisons in the
  // same second would share "<stamp>-<integrator>", so number them.
  const fs::path stamp = take_base(app);
  fs::path base = stamp;
  auto taken = [&](const fs::path& b) {
    std::error_code ec;
    for (const std::string& name : integrators)
      if (fs::exists(b.string() + "-" + name, ec)) return true;
    return false;
  };
  for (int n = 2; taken(base); ++n) base = fs::path(stamp.string() + "-" + std::to_string(n));
  std::vector<IntegratorRun> runs;
  for (const std::string& name : integrators) {
    IntegratorRun run;
    run.integrator = name;
    run.take = fs::path(base.string() + "-" + name);
    json variant = base_scene;
    variant["integrator"] = name;
    std::string err;
    run.job = start_job(app, variant, run.take, &err);
    if (!run.job) {
      st.compare_error = name + ": " + err;
      app.set_status("Cannot compare: " + st.compare_error, true);
      app.log.error(app.status());
      st.runs = std::move(runs);
      return false;
    }
    runs.push_back(std::move(run));
  }
  st.runs = std::move(runs);
  // Show the run of the scene's own integrator (else the first), like Run does.
  const std::string own = app.doc.scene().value("integrator", std::string("pbad3"));
  const IntegratorRun* shown = &st.runs.front();
  for (const IntegratorRun& r : st.runs)
    if (r.integrator == own) shown = &r;
  app.take.open(shown->take);
  app.doc.take_dir = shown->take;
  app.set_status("Comparing " + std::to_string(integrators.size()) + " integrators: " + base.string() + "-*");
  app.log.info(app.status());
  return true;
}

void articulated_poll_compare(App& app) {
  ArticulatedUiState& st = app.kind_ui.get<ArticulatedUiState>("articulated");
  for (IntegratorRun& run : st.runs) {
    std::error_code ec;
    if (!run.reader) {
      if (!fs::exists(run.take / "take.json", ec)) continue;
      try {
        run.reader = std::make_shared<TakeReader>(run.take);
      } catch (const std::exception&) {
        continue;  // the manifest is being replaced: next frame
      }
    }
    try {
      run.reader->refresh();
      const size_t n = run.reader->frame_count();
      for (; run.frames_read < n; ++run.frames_read) {
        const Record r = run.reader->read_frame_at(run.frames_read);
        const Field* e = r.find("energy");
        if (!e || e->data.size() != 3) continue;
        run.time_s.push_back(static_cast<float>(r.time_s));
        run.kinetic.push_back(e->data[0]);
        run.potential.push_back(e->data[1]);
        run.total.push_back(e->data[2]);
        for (float v : e->data) run.finite = run.finite && std::isfinite(v);
      }
    } catch (const std::exception&) {
      // A frame being written: read it on the next UI frame.
    }
  }
}

bool articulated_simulate(App& app) {
  const json& s = app.doc.scene();
  const bool relative_model = s.is_object() && s.contains("model") && s["model"].is_string() &&
                              fs::path(s["model"].get<std::string>()).is_relative();
  // A saved, clean document runs from its own file, where relative paths resolve.
  if (!relative_model || (app.doc.has_path() && !app.doc.dirty())) return app.cmd_run();
  if (const std::string& e = app.scene_error(); !e.empty()) {
    app.set_status("Cannot run: " + e, true);
    app.log.error(app.status());
    return false;
  }
  const fs::path take = take_base(app);
  std::string err;
  JobProcess* job = start_job(app, rebased_scene(app), take, &err);
  if (!job) {
    app.set_status("Cannot run: " + err, true);
    app.log.error(app.status());
    return false;
  }
  app.set_status("Job " + std::to_string(job->id) + " started: " + take.string());
  app.log.info(app.status());
  app.take.open(take);
  app.doc.take_dir = take;
  return true;
}

}  // namespace pliant::editor

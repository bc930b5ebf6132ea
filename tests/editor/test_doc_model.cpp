// Document model without any UI: undo stack, dirty state, recent files,
// autosave/recovery files, job-line parsing, script parse errors.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <thread>

#include "doc/autosave.h"
#include "doc/document.h"
#include "doc/job_process.h"
#include "doc/recent_files.h"
#include "editor_harness.h"
#include "ui/ui_script.h"

namespace pliant::editor::test {

using nlohmann::json;

TEST(UndoStack, MergesOneWidgetRunAndClearsRedo) {
  Document d;
  d.reset(json{{"a", 1}, {"b", 1}}, {});
  d.set("/a", 2, 7);
  d.set("/a", 3, 7);  // same widget still active: merges
  d.set("/a", 4, 7);
  EXPECT_EQ(d.history().size(), 1u);
  d.history().close_merge();
  d.set("/a", 5, 7);  // released and grabbed again: a new step
  EXPECT_EQ(d.history().size(), 2u);
  d.set("/b", 9);
  EXPECT_EQ(d.history().size(), 3u);
  ASSERT_TRUE(d.undo());
  ASSERT_TRUE(d.undo());
  EXPECT_EQ(d.scene(), (json{{"a", 4}, {"b", 1}}));
  ASSERT_TRUE(d.undo());
  EXPECT_EQ(d.scene(), (json{{"a", 1}, {"b", 1}}));
  EXPECT_FALSE(d.dirty());  // back at the loaded state
  EXPECT_FALSE(d.undo());
  ASSERT_TRUE(d.redo());
  EXPECT_EQ(d.scene()["a"], 4);
  EXPECT_TRUE(d.dirty());
  d.set("/b", 2);  // a new edit drops the redo side
  EXPECT_FALSE(d.history().can_redo());
}

TEST(UndoStack, LimitDropsOldestSteps) {
  UndoStack s(5);
  for (int i = 0; i < 12; ++i) s.push("step", json(i), json(i + 1));
  EXPECT_EQ(s.size(), 5u);
  json last;
  while (s.can_undo()) last = s.undo();
  EXPECT_EQ(last, json(7));  // steps 7..11 survive
}

TEST(RecentFiles, NewestFirstNoDuplicatesAtMostTen) {
  EditorHarness h("recent");
  fs::path f = h.dir / "recent.json";
  {
    RecentFiles r(f);
    for (int i = 0; i < 13; ++i) r.add(h.dir / (std::string("s") += std::to_string(i) + ".json"));  // (+=: GCC 12 -Wrestrict)
    r.add(h.dir / "s5.json");
  }
  RecentFiles r(f);
  r.load();
  ASSERT_EQ(r.items().size(), RecentFiles::kMax);
  EXPECT_EQ(fs::path(r.items()[0]).filename(), "s5.json");
  EXPECT_EQ(fs::path(r.items()[1]).filename(), "s12.json");
  EXPECT_EQ(std::count(r.items().begin(), r.items().end(), r.items()[0]), 1);
}

TEST(JobProcess, ParsesProtocolLines) {
  JobStatus st;
  std::vector<JobLogLine> log;
  JobProcess::apply_line(R"({"event":"start","kind":"smoke","take":"t","frames":40})", st, log);
  EXPECT_EQ(st.state, JobState::Running);
  EXPECT_EQ(st.frames_expected, 40);
  JobProcess::apply_line(R"({"event":"progress","stage":"admm","iter":3,"of":20,"objective":0.5,"eta_s":41})", st, log);
  JobProcess::apply_line(R"({"event":"progress","stage":"admm","iter":4,"of":20,"objective":0.25})", st, log);
  EXPECT_EQ(st.stage, "admm");
  EXPECT_EQ(st.iter, 4);
  EXPECT_EQ(st.of, 20);
  ASSERT_EQ(st.objective.size(), 2u);
  EXPECT_FLOAT_EQ(st.objective[1], 0.25f);
  JobProcess::apply_line(R"({"event":"frame","index":0})", st, log);
  JobProcess::apply_line(R"({"event":"frame","index":1})", st, log);
  EXPECT_EQ(st.frames_seen, 2);
  EXPECT_EQ(st.last_frame, 1);
  JobProcess::apply_line("not json at all", st, log);
  JobProcess::apply_line(R"({"event":"error","message":"scene.json: /grid: bad"})", st, log);
  EXPECT_EQ(st.state, JobState::Failed);
  EXPECT_EQ(st.error, "scene.json: /grid: bad");
  ASSERT_EQ(log.size(), 2u);
  EXPECT_EQ(log[0].message, "not json at all");
  EXPECT_EQ(log[1].level, "error");
}

// Coarse-to-fine solves report one stage per grid level; the objective curve
// restarts on a new level and continues from ADMM into its polish.
TEST(JobProcess, ObjectiveCurveRestartsPerGridLevel) {
  JobStatus st;
  std::vector<JobLogLine> log;
  auto progress = [&](const char* stage, double f) {
    JobProcess::apply_line(std::string(R"({"event":"progress","stage":")") + stage +
                               R"(","iter":1,"of":5,"objective":)" + std::to_string(f) + "}",
                           st, log);
  };
  progress("admm 32x32", 10);
  progress("admm 32x32", 8);
  ASSERT_EQ(st.objective.size(), 2u);
  progress("admm 64x64", 40);
  ASSERT_EQ(st.objective.size(), 1u);
  EXPECT_FLOAT_EQ(st.objective[0], 40.0f);
  progress("admm", 160);
  progress("admm", 120);
  progress("lbfgs", 110);  // the polish on the same grid
  ASSERT_EQ(st.objective.size(), 3u);
  EXPECT_FLOAT_EQ(st.objective[2], 110.0f);
  EXPECT_EQ(st.stage, "lbfgs");
}

TEST(JobProcess, MissingBinaryFailsWithoutBlocking) {
  EditorHarness h("nobin");
  JobProcess j;
  JobSpec s{h.dir / "no-such-pliant", h.dir / "x.json", h.dir / "take", 0};
  std::string err;
  EXPECT_FALSE(j.start(s, &err));
  EXPECT_NE(err.find("no-such-pliant"), std::string::npos) << err;
}

// A pid that surely belongs to no process: a child we started and reaped.
int dead_pid() {
  pid_t p = ::fork();
  if (p == 0) ::_exit(0);
  int st;
  ::waitpid(p, &st, 0);
  return p;
}

TEST(Autosave, WritesWhenDirtyAndIsFoundAfterADeadSession) {
  EditorHarness h("autosave");
  fs::path cfg = h.dir / "config";
  Autosave a(cfg, 0.01);
  a.begin_session();
  EXPECT_TRUE(fs::exists(a.lock_file()));
  Document d;
  d.reset(json{{"pliant", 1}, {"x", 1}}, h.dir / "scene.json");
  auto t0 = std::chrono::steady_clock::now();
  EXPECT_FALSE(a.tick(d, t0));  // clean: nothing to save
  d.set("/x", 2);
  EXPECT_TRUE(a.tick(d, t0 + std::chrono::milliseconds(50)));
  EXPECT_FALSE(a.tick(d, t0 + std::chrono::milliseconds(100)));  // unchanged since
  std::ifstream in(a.autosave_file());
  json saved = json::parse(in);
  EXPECT_EQ(saved["scene"]["x"], 2);
  EXPECT_EQ(saved["file"], (h.dir / "scene.json").string());
  // Our own live session is never offered for recovery...
  EXPECT_FALSE(a.find_recovery().has_value());
  // ...but the same files under a dead pid are.
  int pid = dead_pid();
  fs::copy_file(a.autosave_file(), cfg / "autosave" / (std::to_string(pid) + ".json"));
  std::ofstream(cfg / "sessions" / (std::to_string(pid) + ".lock")) << pid;
  auto rc = a.find_recovery();
  ASSERT_TRUE(rc.has_value());
  EXPECT_EQ(rc->pid, pid);
  EXPECT_EQ(rc->scene["x"], 2);
  Autosave::forget(*rc);
  EXPECT_FALSE(a.find_recovery().has_value());
  a.end_session();
  EXPECT_FALSE(fs::exists(a.lock_file()));
  EXPECT_FALSE(fs::exists(a.autosave_file()));
}

TEST(UiScript, ParseErrorsNameTheLine) {
  const char* text = "# comment\nwait 2\n\nclick_item Run\nfrobnicate 3\n";
  try {
    parse_script(text, "demo.txt", ".");
    FAIL() << "expected a ScriptError";
  } catch (const ScriptError& e) {
    EXPECT_STREQ(e.what(), "demo.txt:5: unknown command 'frobnicate'");
  }
  EXPECT_THROW(parse_script("wait two\n", "d.txt", "."), ScriptError);
  try {
    parse_script("move 1 2\ndrag 1 2 3\n", "d.txt", ".");
    FAIL();
  } catch (const ScriptError& e) {
    EXPECT_NE(std::string(e.what()).find("d.txt:2: drag: expected 4 to 6 arguments, got 3"),
              std::string::npos)
        << e.what();
  }
  Script s = parse_script("type hello world\nexpect \"Job 1: done\"\nkey CTRL+Z\n", "ok.txt", "/x");
  ASSERT_EQ(s.commands.size(), 3u);
  EXPECT_EQ(s.commands[0].args[0], "hello world");
  EXPECT_EQ(s.commands[1].args[0], "Job 1: done");
  EXPECT_EQ(s.commands[2].line, 3);
}

}  // namespace pliant::editor::test

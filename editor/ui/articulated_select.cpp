// Body selection in the articulated viewport and the "Selected body" inspector
// section (see the header). The joint values are recovered from the take's
// body poses by Gauss-Newton on the engine's forward kinematics, frame after
// frame from the scene's initial state (frame 0), so hinge angles past +-pi
// stay unwrapped like the engine's qpos; solved frames are cached per take.
#include "ui/articulated_select.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "pliant/core/scene.h"
#include "pliant/core/take.h"
#include "render/articulated_drawer.h"
#include "render/articulated_pick.h"
#include "render/screen_ray.h"
#include "ui/app.h"
#include "ui/articulated_panels.h"
#include "ui/ui_mark.h"

#ifdef PLIANT_HAVE_ARTICULATED
#include "pliant/articulated/articulated.h"
#endif

namespace pliant::editor {

namespace fs = std::filesystem;
using nlohmann::json;

#ifdef PLIANT_HAVE_ARTICULATED
struct ArticulatedSelectionSolver {
  std::string key;  // take folder + its scene copy
  bool ok = false;
  std::string error;
  articulated::ArticulatedScene scene;
  ArticulatedGeometry geometry;  // the drawn geoms (contact sides)
  articulated::Kinematics kin;
  std::map<int, Eigen::VectorXd> qpos;  // solved frames
};
#else
struct ArticulatedSelectionSolver {};
#endif

namespace {

ArticulatedUiState& ui_state(App& app) { return app.kind_ui.get<ArticulatedUiState>("articulated"); }

#ifdef PLIANT_HAVE_ARTICULATED
// Body poses of a take frame, [0] the world.
bool frame_poses(const Record& r, std::vector<Vec3>* pos, std::vector<Quat4>* quat) {
  const Field* f = r.find("body_pose");
  if (!f || f->shape.size() != 2 || f->shape[1] != 7 || f->data.size() != size_t(f->shape[0]) * 7) return false;
  const size_t nb = f->shape[0];
  pos->assign(nb + 1, Vec3{0, 0, 0});
  quat->assign(nb + 1, Quat4{1, 0, 0, 0});
  for (size_t b = 0; b < nb; ++b) {
    const float* p = f->data.data() + 7 * b;
    (*pos)[b + 1] = {p[0], p[1], p[2]};
    (*quat)[b + 1] = {p[3], p[4], p[5], p[6]};
  }
  return true;
}

fs::path take_scene_dir(App& app, TakeReader& rd) {
  std::error_code ec;
  if (!rd.manifest().scene_file.empty())
    return fs::absolute(fs::path(rd.manifest().scene_file), ec).parent_path();
  return app.doc.has_path() ? fs::absolute(app.doc.path(), ec).parent_path() : fs::current_path(ec);
}

using articulated::Model;
using Vec3d = Eigen::Vector3d;
using Quatd = Eigen::Quaterniond;

// Rotation residuals are weighted by this length (m per rad) against positions.
constexpr double kRotationLength = 0.1;

// r = per body (position error; kRotationLength * rotation error) of qpos q
// against the take's poses.
void pose_residual(const Model& m, const Eigen::VectorXd& q, const std::vector<Vec3>& pos,
                   const std::vector<Quat4>& quat, articulated::Kinematics* k, Eigen::VectorXd* r) {
  articulated::kinematics(m, q, k, /*poses_only=*/true);
  const int nb = int(m.bodies.size()) - 1;
  r->resize(6 * nb);
  for (int b = 1; b <= nb; ++b) {
    const Vec3d p(pos[b][0], pos[b][1], pos[b][2]);
    Quatd t(quat[b][0], quat[b][1], quat[b][2], quat[b][3]);
    t.normalize();
    Quatd d = t.conjugate() * k->xquat[b];
    if (d.w() < 0) d.coeffs() *= -1;
    r->segment<3>(6 * (b - 1)) = k->xpos[b] - p;
    r->segment<3>(6 * (b - 1) + 3) = 2 * kRotationLength * d.vec();
  }
}

// Levenberg-Marquardt on the pose residual from q (a nearby frame's solution),
// finite-difference Jacobian through qpos_integrate (quaternion joints stay unit).
Eigen::VectorXd solve_qpos(const Model& m, const std::vector<Vec3>& pos, const std::vector<Quat4>& quat,
                           Eigen::VectorXd q, articulated::Kinematics* k, double* residual) {
  Eigen::VectorXd r, rp, dv(m.nv);
  pose_residual(m, q, pos, quat, k, &r);
  Eigen::MatrixXd J(r.size(), m.nv);
  double lambda = 1e-9;
  const double h = 1e-7;
  for (int it = 0; it < 50 && m.nv > 0 && r.norm() > 1e-10; ++it) {
    for (int i = 0; i < m.nv; ++i) {
      dv.setZero();
      dv[i] = h;
      Eigen::VectorXd qp = q;
      articulated::qpos_integrate(m, qp, dv, 1.0);
      pose_residual(m, qp, pos, quat, k, &rp);
      J.col(i) = (rp - r) / h;
    }
    const Eigen::MatrixXd A = J.transpose() * J;
    const Eigen::VectorXd g = J.transpose() * r;
    bool improved = false;
    for (int tries = 0; tries < 8 && !improved; ++tries) {
      Eigen::MatrixXd Ad = A;
      Ad.diagonal().array() += lambda * (1 + A.diagonal().array());
      dv = -Ad.ldlt().solve(g);
      Eigen::VectorXd qn = q;
      articulated::qpos_integrate(m, qn, dv, 1.0);
      pose_residual(m, qn, pos, quat, k, &rp);
      if (rp.norm() < r.norm()) {
        q = qn;
        r = rp;
        lambda = std::max(lambda / 10, 1e-12);
        improved = true;
      } else {
        lambda *= 100;
      }
    }
    if (!improved || dv.norm() < 1e-12) break;
  }
  if (residual) *residual = r.size() ? r.cwiseAbs().maxCoeff() : 0;
  return q;
}

ArticulatedSelectionSolver& solver_for(App& app, TakeReader& rd, std::shared_ptr<ArticulatedSelectionSolver>* slot) {
  const std::string key = rd.dir().string() + "\n" + rd.manifest().scene.dump();
  if (!*slot || (*slot)->key != key) {
    auto s = std::make_shared<ArticulatedSelectionSolver>();
    s->key = key;
    Scene sc;
    sc.file = "scene";
    sc.dir = take_scene_dir(app, rd);
    sc.kind = "articulated";
    sc.doc = rd.manifest().scene;
    try {
      s->scene = articulated::articulated_compile(sc);
      std::string err;
      s->ok = articulated_scene_geometry(sc.doc, sc.dir, &s->geometry, &err);
      if (!s->ok) s->error = err;
    } catch (const std::exception& e) {
      s->error = e.what();
    }
    *slot = std::move(s);
  }
  return **slot;
}

// qpos at frame f: from the nearest solved frame before it (frame 0 from the
// scene's initial state, which is what the take's frame 0 shows), frame by frame.
const Eigen::VectorXd* qpos_at(ArticulatedSelectionSolver& s, TakeReader& rd, int f, double* residual) {
  const Model& m = s.scene.model;
  if (auto it = s.qpos.find(f); it != s.qpos.end()) return &it->second;
  int g = -1;
  Eigen::VectorXd q = s.scene.initial.qpos;
  if (auto it = s.qpos.upper_bound(f); it != s.qpos.begin()) {
    --it;
    g = it->first;
    q = it->second;
  }
  std::vector<Vec3> pos;
  std::vector<Quat4> quat;
  for (int i = g + 1; i <= f; ++i) {
    if (!frame_poses(rd.read_frame_at(size_t(i)), &pos, &quat) || int(pos.size()) != int(m.bodies.size()))
      return nullptr;
    q = solve_qpos(m, pos, quat, q, &s.kin, residual);
    s.qpos[i] = q;
  }
  return &s.qpos[f];
}

const char* joint_type_name(articulated::JointType t) {
  switch (t) {
    case articulated::JointType::Hinge: return "hinge";
    case articulated::JointType::Slide: return "slide";
    case articulated::JointType::Ball: return "ball";
    case articulated::JointType::Free: return "free";
  }
  return "?";
}

const char* shape_name(ArticulatedGeom::Shape s) {
  switch (s) {
    case ArticulatedGeom::Plane: return "plane";
    case ArticulatedGeom::Sphere: return "sphere";
    case ArticulatedGeom::Capsule: return "capsule";
    case ArticulatedGeom::Box: return "box";
    case ArticulatedGeom::Mesh: return "mesh";
  }
  return "geom";
}

// Fills `sel` for body sel.body at frame sel.frame of the shown take.
void compute_selection(App& app, TakeReader& rd, ArticulatedSelection& sel) {
  ArticulatedSelectionSolver& s = solver_for(app, rd, &sel.solver);
  if (!s.error.empty()) {
    sel.error = s.error;
    return;
  }
  const Model& m = s.scene.model;
  const int b = sel.body, f = sel.frame, n = int(rd.frame_count());
  if (b < 1 || b >= int(m.bodies.size())) {
    sel.error = "no body " + std::to_string(b) + " in the take's model";
    return;
  }
  const articulated::Body& body = m.bodies[b];
  sel.body_name = body.name.empty() ? "body " + std::to_string(b) : body.name;
  sel.mass = body.mass;
  const Record rec = rd.read_frame_at(size_t(f));
  std::vector<Vec3> pos;
  std::vector<Quat4> quat;
  if (!frame_poses(rec, &pos, &quat) || pos.size() != m.bodies.size()) {
    sel.error = "the frame's body_pose does not fit the model";
    return;
  }
  sel.world_pos = pos[b];
  // Joints: qpos at f, qvel by central differences (one-sided at the ends).
  const Eigen::VectorXd* qf = qpos_at(s, rd, f, &sel.ik_residual);
  if (!qf) {
    sel.error = "cannot read the take's body poses";
    return;
  }
  const Eigen::VectorXd q = *qf;
  const int f0 = std::max(f - 1, 0), f1 = std::min(f + 1, n - 1);
  Eigen::VectorXd v = Eigen::VectorXd::Zero(m.nv);
  const Eigen::VectorXd* q0 = qpos_at(s, rd, f0, nullptr);
  const Eigen::VectorXd* q1 = q0 ? qpos_at(s, rd, f1, nullptr) : nullptr;
  if (q0 && q1 && f1 > f0) {
    const double dt = rd.read_frame_at(size_t(f1)).time_s - rd.read_frame_at(size_t(f0)).time_s;
    if (dt > 0) v = articulated::qpos_difference(m, *q1, *q0) / dt;
  }
  for (int j : body.joints) {
    const articulated::Joint& jt = m.joints[j];
    ArticulatedJointInfo info;
    info.name = jt.name.empty() ? "joint " + std::to_string(j) : jt.name;
    info.type = joint_type_name(jt.type);
    for (int i = 0; i < articulated::joint_nq(jt.type); ++i) info.qpos.push_back(q[jt.qadr + i]);
    for (int i = 0; i < articulated::joint_nv(jt.type); ++i) info.qvel.push_back(v[jt.vadr + i]);
    info.limited = jt.limited;
    info.range_min = jt.range_min;
    info.range_max = jt.range_max;
    sel.joints.push_back(std::move(info));
  }
  // Contacts touching the body: the take's point and force; depth = |f| / k.
  const Field* c = rec.find("contacts");
  if (!c || c->shape.size() != 2 || c->shape[1] != 6) return;
  const double k = s.scene.options.contact.stiffness;
  for (size_t i = 0; i < c->shape[0]; ++i) {
    const float* d = c->data.data() + 6 * i;
    ArticulatedContactInfo ci;
    ci.point = {d[0], d[1], d[2]};
    ci.force = {d[3], d[4], d[5]};
    ci.magnitude = std::sqrt(double(d[3]) * d[3] + double(d[4]) * d[4] + double(d[5]) * d[5]);
    ci.depth = k > 0 ? ci.magnitude / k : -1;
    const ContactSides sides =
        articulated_contact_sides(s.geometry, pos, quat, ci.point, std::max(ci.depth, 0.0));
    int other = -1, other_geom = -1;
    if (sides.body == b) other = sides.other_body, other_geom = sides.other_geom;
    else if (sides.other_body == b) other = sides.body, other_geom = sides.geom;
    else continue;
    if (other > 0) ci.other = m.bodies[other].name.empty() ? "body " + std::to_string(other) : m.bodies[other].name;
    else if (other_geom >= 0) ci.other = std::string(shape_name(s.geometry.geoms[other_geom].shape)) + " obstacle";
    else ci.other = "?";
    sel.contacts.push_back(std::move(ci));
  }
}

int body_named(const ArticulatedSelectionSolver& s, const std::string& name) {
  const Model& m = s.scene.model;
  for (int b = int(m.bodies.size()) - 1; b >= 1; --b)
    if (m.bodies[b].name == name) return b;
  return 0;
}
#endif

// World ray through window pixel (px, py) of the image rectangle (x, y, w, h).
bool click_ray(const ArticulatedView& v, float px, float py, float x, float y, int w, int h, Vec3* o, Vec3* d) {
  Vec3 far_pt;
  if (!screen_ray(v.world_to_clip, px, py, x, y, float(w), float(h), o, &far_pt)) return false;
  for (int i = 0; i < 3; ++i) (*d)[i] = far_pt[i] - (*o)[i];
  return true;
}

}  // namespace

bool articulated_select_body(App& app, int body) {
  ArticulatedUiState& st = ui_state(app);
  if (body <= 0) {
    st.selected_body = 0;
    st.selected_name.clear();
    if (st.selection) st.selection->body = 0;
    return true;
  }
#ifdef PLIANT_HAVE_ARTICULATED
  TakeReader* rd = app.take.reader();
  if (!rd || rd->manifest().kind != "articulated") return false;
  if (!st.selection) st.selection = std::make_shared<ArticulatedSelection>();
  ArticulatedSelectionSolver& s = solver_for(app, *rd, &st.selection->solver);
  if (!s.error.empty() || body >= int(s.scene.model.bodies.size())) return false;
  st.selected_body = body;
  st.selected_name = s.scene.model.bodies[body].name;
  st.selection->frame = -1;  // recompute
  return true;
#else
  return false;
#endif
}

void articulated_viewport_pick(App& app, float x, float y, int w, int h) {
  ArticulatedUiState& st = ui_state(app);
  const ImGuiIO& io = ImGui::GetIO();
  if (st.selected_body > 0 && !io.WantTextInput && ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape), false))
    articulated_select_body(app, 0);
  // A click: released where it was pressed (orbiting drags do not pick).
  if (!ImGui::IsMouseReleased(ImGuiMouseButton_Left) || !ImGui::IsWindowHovered()) return;
  if (io.MouseDragMaxDistanceSqr[0] > 9) return;
  auto inside = [&](const ImVec2& p) { return p.x >= x && p.y >= y && p.x < x + w && p.y < y + h; };
  if (!inside(io.MousePos) || !inside(io.MouseClickedPos[0])) return;
  const ArticulatedView* v = articulated_primary_view();
  Vec3 o, d;
  if (!v || !v->model || !click_ray(*v, io.MousePos.x, io.MousePos.y, x, y, w, h, &o, &d)) return;
  const ArticulatedPick hit = articulated_pick(*v->model, v->pos, v->quat, o, d);
  if (hit.body < 1 || !articulated_select_body(app, hit.body)) articulated_select_body(app, 0);
}

const ArticulatedSelection* articulated_selection(App& app) {
  ArticulatedUiState& st = ui_state(app);
  const ArticulatedSelection* out = nullptr;
#ifdef PLIANT_HAVE_ARTICULATED
  TakeReader* rd = app.take.reader();
  if (st.selected_body > 0 && rd && rd->manifest().kind == "articulated" && app.take.frame_count() > 0) {
    if (!st.selection) st.selection = std::make_shared<ArticulatedSelection>();
    ArticulatedSelection& sel = *st.selection;
    ArticulatedSelectionSolver& s = solver_for(app, *rd, &sel.solver);
    // Another take shown: the body of the same name, or none.
    if (s.error.empty() && (st.selected_body >= int(s.scene.model.bodies.size()) ||
                            s.scene.model.bodies[st.selected_body].name != st.selected_name))
      st.selected_body = body_named(s, st.selected_name);
    const int f = std::clamp(app.take.frame, 0, int(app.take.frame_count()) - 1);
    if (st.selected_body > 0 && (sel.take_dir != rd->dir().string() || sel.frame != f ||
                                 sel.body != st.selected_body || sel.take_frames != rd->frame_count())) {
      auto solver = sel.solver;
      sel = ArticulatedSelection{};
      sel.solver = std::move(solver);
      sel.take_dir = rd->dir().string();
      sel.frame = f;
      sel.body = st.selected_body;
      sel.take_frames = rd->frame_count();
      try {
        compute_selection(app, *rd, sel);
      } catch (const std::exception& e) {
        sel.error = e.what();
      }
    }
    if (st.selected_body > 0) out = &sel;
  }
#endif
  if (articulated_drawer_set_highlight(out ? st.selected_body : 0)) app.viewport.shown_frame = -1;
  return out;
}

void draw_selected_body(App& app) {
  const ArticulatedSelection* sel = articulated_selection(app);
  if (!sel) return;
  if (!ImGui::CollapsingHeader("Selected body", ImGuiTreeNodeFlags_DefaultOpen)) return;
  if (!sel->error.empty()) {
    ImGui::TextColored(ImVec4(1, 0.45f, 0.4f, 1), "%s", sel->error.c_str());
    return;
  }
  ImGui::Text("%s  (body %d, %.4g kg), frame %d", sel->body_name.c_str(), sel->body, sel->mass, sel->frame);
  ui_mark("selected_body");
  ImGui::SameLine();
  if (ImGui::SmallButton("Clear")) articulated_select_body(app, 0);
  ui_mark("selected_body_clear");
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("or Esc, or click empty space in the viewport");
  ImGui::Text("frame origin (%.4f, %.4f, %.4f) m", sel->world_pos[0], sel->world_pos[1], sel->world_pos[2]);
  auto values = [](const std::vector<double>& v) {
    std::string s;
    char b[32];
    for (size_t i = 0; i < v.size(); ++i) {
      std::snprintf(b, sizeof b, "%s%.5g", i ? ", " : "", v[i]);
      s += b;
    }
    return s;
  };
  if (sel->joints.empty()) ImGui::TextDisabled("no joints (welded to its parent)");
  for (const ArticulatedJointInfo& j : sel->joints) {
    ImGui::Text("%s (%s)", j.name.c_str(), j.type.c_str());
    ImGui::Indent();
    if (j.type == "hinge" && j.qpos.size() == 1)
      ImGui::Text("qpos %.5g rad (%.2f deg)", j.qpos[0], j.qpos[0] * 180 / 3.14159265358979);
    else
      ImGui::Text("qpos %s", values(j.qpos).c_str());
    ImGui::Text("qvel %s", values(j.qvel).c_str());
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("central difference of the neighbouring frames' qpos");
    if (j.limited) ImGui::Text("range [%.4g, %.4g]", j.range_min, j.range_max);
    else ImGui::TextDisabled("no limits");
    ImGui::Unindent();
  }
  if (sel->ik_residual > 1e-5)
    ImGui::TextDisabled("qpos recovered from the poses up to %.2g m", sel->ik_residual);
  ImGui::Text("%zu contact%s", sel->contacts.size(), sel->contacts.size() == 1 ? "" : "s");
  for (size_t i = 0; i < sel->contacts.size(); ++i) {
    const ArticulatedContactInfo& c = sel->contacts[i];
    ImGui::BulletText("with %s at (%.3f, %.3f, %.3f)", c.other.c_str(), c.point[0], c.point[1], c.point[2]);
    ImGui::Indent();
    ImGui::Text("|f| %.4g N  f (%.3g, %.3g, %.3g)", c.magnitude, c.force[0], c.force[1], c.force[2]);
    if (c.depth >= 0) ImGui::Text("depth %.3g mm", 1000 * c.depth);
    ImGui::Unindent();
  }
}

}  // namespace pliant::editor

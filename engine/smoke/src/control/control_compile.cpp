// The scene's "control" section -> ControlModel. The grid, time step and boundary
// come from the usual smoke fields (smoke_compile on a copy without "control");
// keyframe targets are rasterised by engine/geom.
//
//   "control": {"method": "admm"|"lbfgs", "r": >0, "max_iterations", "tolerance",
//     "admm": {"penalty", "ao_iterations", "nso_vcycles", "nso_skip_gap" (0..1), "polish_iterations",
//              "coarse_polish_iterations" (-1: polish_iterations), "balance_mu" (0 or > 1), "balance_tau" (> 1), "relaxation" (0..2), "switch_progress" (0..1)},
//     "progressive_preview",
//     "coarse_iterations" (outer iterations per coarse level of the progressive preview,
//     default max_iterations), "lbfgs_chunk" (L-BFGS iterations between checkpoints; the
//     quasi-Newton memory is kept within a chunk, default 20), "coarse_admm_levels" (ADMM:
//     only the coarsest N levels run ADMM, the finer coarse levels polish; -1 all, default),
//     "initial_density": [TARGET], "obstacles": [TARGET],
//     "keyframes": [{"frame": 1..T (one keyframe per frame), "weight": >0,
//                    "target": TARGET or "targets": [TARGET] (their union)}],
//     "sequence": {"images": "dir/" or "pattern%03d.png", "first_frame", "every",
//                  "weight", + the placement fields of an image TARGET}}
//   TARGET: {"type": circle|sphere|box|square|mask|image|text|mesh|painted, placement
//     ("center" fraction of the domain or "center_m", "scale", "rotation_deg",
//     3D "rotation_axis" [x, y, z]: rotation_deg about that axis, default +z;
//     right-handed (counter-clockwise seen from the axis tip), any 3D orientation is
//     one axis-angle pair; 2D accepts +z only),
//     "supersample", and per type: radius|radius_m; half_size|half_size_m;
//     file, channel (luma|alpha), threshold, height|height_m, depth|depth_m;
//     text, font, height|height_m, threshold; file, size|size_m (mesh);
//     painted: size [w, h(, d)], data (geom/painted_grid.h; covers the domain)}
// Fractions are of the smallest domain extent (sizes) or of each axis (center).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "pliant/core/json_reader.h"
#include "pliant/geom/keyframe_raster.h"
#include "pliant/geom/painted_grid.h"
#include "pliant/smoke/control.h"

namespace pliant::smoke {
namespace {

struct Ctx {
  const Scene& scene;
  geom::RasterGrid grid;
  double min_extent() const {
    double e = grid.extent_m(0);
    for (int a = 1; a < grid.dim; ++a) e = std::min(e, grid.extent_m(a));
    return e;
  }
};

// A length given either in metres (`key_m`) or as a fraction of the smallest extent.
double length(JsonReader& r, const Ctx& c, const std::string& key, double def_fraction, bool required) {
  const std::string km = key + "_m";
  if (r.has(km)) {
    const double v = r.number(km, 0);
    if (!(v > 0)) r.fail(km, "expected a number > 0 (metres)");
    return v;
  }
  if (!r.has(key) && required)
    r.fail(key, "missing required field; expected \"" + key + "\" (fraction of the domain) or \"" + km + "\" (metres)");
  const double f = r.number(key, def_fraction);
  if (!(f > 0)) r.fail(key, "expected a number > 0 (fraction of the domain)");
  return f * c.min_extent();
}

geom::Placement placement(JsonReader& r, const Ctx& c) {
  geom::Placement p;
  const int dim = c.grid.dim;
  for (int a = 0; a < dim; ++a) p.center_m[a] = 0.5 * c.grid.extent_m(a);
  if (r.has("center_m")) {
    const auto v = r.numbers("center_m", {}, dim, dim);
    for (int a = 0; a < dim; ++a) p.center_m[a] = v[a];
  } else if (r.has("center")) {
    const auto v = r.numbers("center", {}, dim, dim);
    for (int a = 0; a < dim; ++a) p.center_m[a] = v[a] * c.grid.extent_m(a);
  }
  p.scale = r.number("scale", 1.0);
  if (!(p.scale > 0)) r.fail("scale", "expected a number > 0");
  p.rotation_deg = r.number("rotation_deg", 0.0);
  // Axis-angle: rotation_deg about rotation_axis (default +z, the only axis in 2D).
  if (r.has("rotation_axis")) {
    const auto v = r.numbers("rotation_axis", {}, 3, 3);
    if (!(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] > 0)) r.fail("rotation_axis", "expected a non-zero vector");
    if (dim == 2 && (v[0] != 0 || v[1] != 0 || !(v[2] > 0)))
      r.fail("rotation_axis", "2D targets turn about +z only ([0, 0, 1]); use rotation_deg");
    p.rotation_axis = {v[0], v[1], v[2]};
  }
  return p;
}

geom::ImageChannel channel(JsonReader& r) {
  return r.choice("channel", "luma", {"luma", "alpha"}) == "alpha" ? geom::ImageChannel::Alpha
                                                                    : geom::ImageChannel::Luma;
}

// An image file placed by the reader's fields (mask: binarised at threshold).
std::vector<float> image_target(JsonReader& r, const Ctx& c, const std::string& file_rel, bool binarise,
                                int ss, std::string* source) {
  geom::CoverageImage img = geom::load_coverage_image(c.scene.asset_path(file_rel), file_rel, channel(r));
  const double thr = r.number("threshold", 0.5, 0.0, 1.0);
  if (binarise || r.has("threshold")) geom::threshold_coverage(img, thr, file_rel);
  const geom::Placement p = placement(r, c);
  const double height = length(r, c, "height", 0.6, false);
  const double depth = c.grid.dim == 3 ? length(r, c, "depth", 0.3, false) : 0.0;
  *source = (binarise ? "mask " : "image ") + file_rel;
  return geom::raster_image(c.grid, img, p, height, depth, ss);
}

std::vector<float> target(JsonReader& r, const Ctx& c, std::string* source) {
  const std::string type =
      r.choice("type", "", {"circle", "sphere", "box", "square", "mask", "image", "text", "mesh", "painted"});
  if (type.empty())
    r.fail("type", "missing required field; expected circle, sphere, box, square, mask, image, text, mesh or painted");
  const int ss = int(r.integer("supersample", c.grid.dim == 3 ? 2 : 4, 1, 16));
  std::vector<float> d;
  try {
    if (type == "circle" || type == "sphere") {
      const double radius = length(r, c, "radius", 0, true);
      d = geom::raster_sphere(c.grid, placement(r, c), radius, ss);
      *source = type;
    } else if (type == "box" || type == "square") {
      std::array<double, 3> half{0, 0, 0};
      const int dim = c.grid.dim;
      if (r.has("half_size_m")) {
        const auto v = r.numbers("half_size_m", {}, dim, dim, 1e-300);
        for (int a = 0; a < dim; ++a) half[a] = v[a];
      } else if (r.has("half_size")) {
        const auto v = r.numbers("half_size", {}, dim, dim, 1e-300);
        for (int a = 0; a < dim; ++a) half[a] = v[a] * c.min_extent();
      } else {
        r.fail("half_size", "missing required field; expected \"half_size\" (fractions) or \"half_size_m\"");
      }
      d = geom::raster_box(c.grid, placement(r, c), half, ss);
      *source = type;
    } else if (type == "mask" || type == "image") {
      const std::string file = r.required_string("file");
      d = image_target(r, c, file, type == "mask", ss, source);
    } else if (type == "text") {
      const std::string text = r.required_string("text");
      std::string font_label = "assets/fonts/DejaVuSans-Bold.ttf";
      std::filesystem::path font = geom::default_font_path(c.scene.dir);
      if (r.has("font")) {
        font_label = r.string("font", "");
        font = c.scene.asset_path(font_label);
      }
      geom::CoverageImage img = geom::render_text(text, font, font_label, 128);
      if (r.has("threshold")) geom::threshold_coverage(img, r.number("threshold", 0.5, 0.0, 1.0), "text \"" + text + "\"");
      const geom::Placement p = placement(r, c);
      const double height = length(r, c, "height", 0.6, false);
      const double depth = c.grid.dim == 3 ? length(r, c, "depth", 0.3, false) : 0.0;
      d = geom::raster_image(c.grid, img, p, height, depth, ss);
      *source = "text \"" + text + "\"";
    } else if (type == "painted") {
      const int dim = c.grid.dim;
      const auto size = r.numbers("size", {}, dim, dim, 1, 4096);
      std::array<int, 3> n{1, 1, 1};
      for (int a = 0; a < dim; ++a) {
        if (size[a] != std::floor(size[a])) r.fail("size", "expected whole cell counts");
        n[a] = int(size[a]);
      }
      const std::string data = r.required_string("data");
      try {
        d = geom::raster_painted(c.grid, geom::decode_painted(data, dim, n));
      } catch (const geom::GeomError& e) {
        throw InputError(c.scene.file, r.child_pointer("data"), e.what());
      }
      *source = "painted keyframe";
    } else {  // mesh
      if (c.grid.dim != 3) r.fail("type", "mesh targets need a 3D grid (resolution [nx, ny, nz])");
      const std::string file = r.required_string("file");
      const geom::TriangleMesh mesh = geom::load_mesh(c.scene.asset_path(file), file);
      const geom::Placement p = placement(r, c);
      d = geom::raster_mesh(c.grid, mesh, p, length(r, c, "size", 0.6, false), ss);
      *source = "mesh " + file;
    }
  } catch (const geom::GeomError& e) {
    const std::string key = r.has("file") ? "file" : (r.has("text") ? "text" : (r.has("font") ? "font" : "type"));
    throw InputError(c.scene.file, r.child_pointer(key), e.what());
  }
  r.finish();
  double sum = 0;
  for (float v : d) sum += v;
  if (!(sum > 0)) throw InputError(c.scene.file, r.pointer(), *source + ": target is empty on this grid (nothing of it lies inside the domain)");
  return d;
}

int frame_in_range(JsonReader& r, const std::string& key, int T, bool required, int def) {
  if (!r.has(key)) {
    if (required) r.fail(key, "missing required field; expected a frame in 1.." + std::to_string(T));
    return def;
  }
  const nlohmann::json& v = r.value().at(key);
  if (!v.is_number_integer()) r.fail(key, "expected a frame in 1.." + std::to_string(T) + ", got " + v.dump());
  const long long f = v.get<long long>();
  r.accept(key);
  if (f < 1 || f > T) r.fail(key, "expected a frame in 1.." + std::to_string(T) + ", got " + std::to_string(f));
  return int(f);
}

// Files of a sequence: a printf pattern with the frame number, or a folder's images in name order.
std::vector<std::pair<int, std::string>> sequence_files(JsonReader& s, const Scene& scene, int T) {
  const std::string images = s.required_string("images");
  const int first = frame_in_range(s, "first_frame", T, false, 1);
  const int every = int(s.integer("every", 1, 1, 1000000));
  std::vector<std::pair<int, std::string>> out;
  if (images.find('%') != std::string::npos) {
    for (int f = first; f <= T; f += every) {
      char buf[1024];
      std::snprintf(buf, sizeof buf, images.c_str(), f);
      if (!std::filesystem::exists(scene.asset_path(buf))) break;
      out.push_back({f, buf});
    }
    if (out.empty())
      s.fail("images", "no image matches the pattern for frame " + std::to_string(first) + " (" + images + ")");
    return out;
  }
  const std::filesystem::path dir = scene.asset_path(images);
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    s.fail("images", "expected a folder of images or a pattern like \"frames/%03d.png\"; " + images + " is neither");
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
    std::string ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    if (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp" || ext == ".tga")
      names.push_back(e.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  if (names.empty()) s.fail("images", "folder " + images + " has no images (png, jpg, bmp, tga)");
  int f = first;
  for (const std::string& n : names) {
    if (f > T) break;
    out.push_back({f, (std::filesystem::path(images) / n).string()});
    f += every;
  }
  return out;
}

}  // namespace

ControlModel control_compile(const Scene& scene) {
  ControlModel m;
  {
    Scene plain = scene;
    plain.doc.erase("control");
    m.sim = smoke_compile(plain);
  }
  JsonReader root(scene.doc, scene.file);
  auto cr = root.object("control");
  if (!cr) root.fail("control", "missing required field; expected the keyframe-control section");
  JsonReader& c = *cr;
  const int T = m.sim.frames;
  Ctx ctx{scene, {}};
  ctx.grid.dim = m.sim.dim;
  ctx.grid.n = m.sim.n;
  if (m.sim.dim == 2) ctx.grid.n[2] = 1;
  ctx.grid.cell_size_m = m.sim.cell_size_m;
  const size_t cells = ctx.grid.cells();

  m.method = c.choice("method", "admm", {"admm", "lbfgs"}) == "lbfgs" ? ControlMethod::Lbfgs : ControlMethod::Admm;
  m.r = c.number("r", m.r);
  if (!(m.r > 0)) c.fail("r", "expected a number > 0 (ghost-force regularisation)");
  // 0 is allowed for ADMM with a polish: the fine level then only polishes what the
  // coarse levels found (see coarse_iterations).
  m.max_iterations = int(c.integer("max_iterations", m.max_iterations, 0, 1000000));
  m.tolerance = c.number("tolerance", m.tolerance);
  if (!(m.tolerance > 0 && m.tolerance < 1)) c.fail("tolerance", "expected a number in (0, 1)");
  if (auto a = c.object("admm")) {
    m.admm_penalty = a->number("penalty", m.admm_penalty);
    if (!(m.admm_penalty > 0)) a->fail("penalty", "expected a number > 0");
    m.ao_iterations = int(a->integer("ao_iterations", m.ao_iterations, 1, 100000));
    m.nso_vcycles = int(a->integer("nso_vcycles", m.nso_vcycles, 1, 100000));
    m.nso_skip_gap = a->number("nso_skip_gap", m.nso_skip_gap);
    if (!(m.nso_skip_gap >= 0 && m.nso_skip_gap < 1)) a->fail("nso_skip_gap", "expected a number in [0, 1)");
    m.polish_iterations = int(a->integer("polish_iterations", m.polish_iterations, 0, 1000000));
    m.coarse_polish_iterations = int(a->integer("coarse_polish_iterations", m.coarse_polish_iterations, -1, 1000000));
    m.admm_balance_mu = a->number("balance_mu", m.admm_balance_mu);
    if (!(m.admm_balance_mu == 0 || m.admm_balance_mu > 1))
      a->fail("balance_mu", "expected 0 (penalty continuation) or a number > 1 (residual balancing)");
    m.admm_balance_tau = a->number("balance_tau", m.admm_balance_tau);
    if (!(m.admm_balance_tau > 1 && m.admm_balance_tau <= 100)) a->fail("balance_tau", "expected a number in (1, 100]");
    m.admm_relaxation = a->number("relaxation", m.admm_relaxation);
    if (!(m.admm_relaxation > 0 && m.admm_relaxation < 2)) a->fail("relaxation", "expected a number in (0, 2)");
    m.admm_switch_progress = a->number("switch_progress", m.admm_switch_progress);
    if (!(m.admm_switch_progress >= 0 && m.admm_switch_progress < 1))
      a->fail("switch_progress", "expected a number in [0, 1)");
    a->finish();
  }
  m.progressive_preview = c.boolean("progressive_preview", m.progressive_preview);
  m.coarse_iterations = int(c.integer("coarse_iterations", m.coarse_iterations, -1, 1000000));
  m.lbfgs_chunk = int(c.integer("lbfgs_chunk", m.lbfgs_chunk, 1, 1000000));
  m.coarse_admm_levels = int(c.integer("coarse_admm_levels", m.coarse_admm_levels, -1, 16));
  if (m.max_iterations == 0 && !(m.method == ControlMethod::Admm && m.polish_iterations > 0))
    c.fail("max_iterations", "expected >= 1 (0 only for ADMM with admm.polish_iterations > 0)");

  std::string source;
  if (c.has("initial_density")) {
    m.initial_density.assign(cells, 0.0f);
    for (JsonReader& t : c.objects("initial_density")) {
      const auto d = target(t, ctx, &source);
      for (size_t i = 0; i < cells; ++i) m.initial_density[i] = std::min(1.0f, m.initial_density[i] + d[i]);
    }
  } else {
    m.initial_density = smoke_init(m.sim).density;  // the smoke "initial_density" shapes
  }
  if (c.has("obstacles")) {
    m.solid.assign(cells, 0);
    for (JsonReader& t : c.objects("obstacles")) {
      const auto d = target(t, ctx, &source);
      for (size_t i = 0; i < cells; ++i) m.solid[i] = m.solid[i] || d[i] >= 0.5f;
    }
  }
  for (JsonReader& k : c.objects("keyframes")) {
    Keyframe kf;
    kf.frame = frame_in_range(k, "frame", T, true, 0);
    kf.weight = k.number("weight", 1.0);
    if (!(kf.weight > 0)) k.fail("weight", "expected a number > 0");
    if (k.has("targets")) {  // several shapes at one frame: their union (summed, clamped to 1)
      if (k.has("target")) k.fail("target", "give either \"target\" or \"targets\", not both");
      kf.density.assign(cells, 0.0f);
      std::string part;
      for (JsonReader& t : k.objects("targets")) {
        const auto d = target(t, ctx, &part);
        for (size_t i = 0; i < cells; ++i) kf.density[i] = std::min(1.0f, kf.density[i] + d[i]);
        kf.source += (kf.source.empty() ? "" : " + ") + part;
      }
      if (kf.source.empty()) k.fail("targets", "expected at least one target");
    } else {
      auto t = k.object("target");
      if (!t) k.fail("target", "missing required field; expected a target object with \"type\" (or \"targets\")");
      kf.density = target(*t, ctx, &kf.source);
    }
    for (const Keyframe& other : m.keyframes)
      if (other.frame == kf.frame)
        k.fail("frame", "frame " + std::to_string(kf.frame) +
                            " already has a keyframe; put several shapes in one keyframe's \"targets\"");
    k.finish();
    m.keyframes.push_back(std::move(kf));
  }
  if (auto s = c.object("sequence")) {
    const double weight = s->number("weight", 1.0);
    if (!(weight > 0)) s->fail("weight", "expected a number > 0");
    const bool binarise = s->boolean("binarise", true);
    const int ss = int(s->integer("supersample", 2, 1, 16));
    for (const auto& [frame, file] : sequence_files(*s, scene, T)) {
      for (const Keyframe& other : m.keyframes)
        if (other.frame == frame)
          s->fail("images", "frame " + std::to_string(frame) + " (" + file + ") already has a keyframe");
      Keyframe kf;
      kf.frame = frame;
      kf.weight = weight;
      try {
        kf.density = image_target(*s, ctx, file, binarise, ss, &kf.source);
      } catch (const geom::GeomError& e) {
        throw InputError(scene.file, s->child_pointer("images"), e.what());
      }
      m.keyframes.push_back(std::move(kf));
    }
    s->finish();
  }
  if (m.keyframes.empty())
    c.fail("keyframes", "expected at least one keyframe (\"keyframes\" or \"sequence\")");
  std::stable_sort(m.keyframes.begin(), m.keyframes.end(),
                   [](const Keyframe& a, const Keyframe& b) { return a.frame < b.frame; });
  c.finish();
  return m;
}

}  // namespace pliant::smoke

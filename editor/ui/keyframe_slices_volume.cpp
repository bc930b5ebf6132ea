// Volume view of the 3D keyframe being edited (see keyframe_slices.h). Renders
// only when the volume, the size or the camera changed: ray marching on a
// software GL is too slow to repeat every UI frame.
#include <GL/gl.h>
#include <GL/glext.h>
#include <imgui.h>

#include <algorithm>

#include "render/mat4.h"
#include "ui/app.h"
#include "ui/keyframe_slices.h"
#include "ui/panel_window.h"

namespace pliant::editor {

void release_volume_view(KeyframeVolumeView& v) {
  v.target.release();
  if (v.ready) v.renderer.shutdown();
  v.ready = false;
  v.uploaded_version = ~uint64_t(0);
  v.dirty = true;
}

namespace {

}  // namespace

void draw_keyframe_volume(KeyframeVolumeView& v, App& app, const geom::PaintedGrid& volume, uint64_t version,
                          SliceAxis axis, int slice, float x, float y, int w, int h) {
  ImGui::SetCursorScreenPos(ImVec2(x, y));
  ImGui::InvisibleButton("slice_volume", ImVec2(float(w), float(h)));
  ui_mark("slice_volume");
  if (ImGui::IsItemActive() && ImGui::IsMouseDragging(ImGuiMouseButton_Left)) {
    const ImVec2 d = ImGui::GetIO().MouseDelta;
    if (d.x != 0 || d.y != 0) {
      v.camera.orbit(d.x, d.y);
      v.dirty = true;
    }
  }
  ImDrawList* dl = ImGui::GetWindowDrawList();
  if (!app.has_gl() || w < 16 || h < 16 || volume.dim != 3 || volume.cells() == 0) return;
  if (!v.ready) {
    v.ready = v.renderer.init(&v.error);
    if (!v.ready) {
      dl->AddText(ImVec2(x + 8, y + 8), IM_COL32(255, 120, 100, 255), v.error.c_str());
      return;
    }
  }
  if (v.uploaded_version != version) {
    Record rec;
    Field f;
    f.name = "density";
    f.shape = {uint32_t(volume.n[2]), uint32_t(volume.n[1]), uint32_t(volume.n[0])};
    f.data.resize(volume.cells());
    for (size_t c = 0; c < volume.cells(); ++c) f.data[c] = volume.value[c] / 255.0f;
    rec.fields.push_back(std::move(f));
    v.renderer.set_frame(rec);
    v.uploaded_version = version;
    v.dirty = true;
  }
  if (v.target.ensure(w, h)) v.dirty = true;
  if (v.dirty) {
    GLint prev = 0;
    glGetIntegerv(GL_FRAMEBUFFER_BINDING, &prev);
    v.target.bind();
    ViewSettings view;
    view.density_scale = 1.5f;  // keyframes are mostly 0/1: a little denser reads better
    v.renderer.render(v.camera, view, w, h);
    glBindFramebuffer(GL_FRAMEBUFFER, GLuint(prev));
    v.dirty = false;
  }
  dl->AddImage(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(v.target.color_tex)), ImVec2(x, y),
               ImVec2(x + w, y + h), ImVec2(0, 1), ImVec2(1, 0));
  // The painted slice: its outline in the volume (the renderer frames the domain
  // centred at the origin with the longest side 1).
  const auto e = v.renderer.domain_extent();
  const auto corners = slice_outline(volume.n, axis, slice, e);
  const Mat4 vp = mat4_mul(v.camera.projection(float(w) / float(h)), v.camera.view());
  ImVec2 pts[4];
  for (int i = 0; i < 4; ++i) {
    const auto c = mat4_apply(vp, {corners[i][0], corners[i][1], corners[i][2], 1.0f});
    const float iw = c[3] != 0 ? 1.0f / c[3] : 0.0f;
    pts[i] = ImVec2(x + (0.5f + 0.5f * c[0] * iw) * w, y + (0.5f - 0.5f * c[1] * iw) * h);
  }
  dl->AddPolyline(pts, 4, IM_COL32(255, 170, 60, 220), ImDrawFlags_Closed, 2.0f);
  dl->AddRect(ImVec2(x, y), ImVec2(x + w, y + h), IM_COL32(120, 125, 140, 200));
  dl->AddText(ImVec2(x + 6, y + 4), IM_COL32(220, 220, 230, 255), "volume (drag to orbit)");
}

}  // namespace pliant::editor

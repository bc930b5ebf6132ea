// Slice view of 3D smoke keyframes: the selected slot's raster (through the
// engine's control_compile, so meshes appear voxelised) one z slice at a time.
// Painting is 2D only; 3D keyframes come from meshes (drop one on the window)
// and the scene's target fields.
#include <GL/gl.h>
#include <GL/glext.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "ui/app.h"
#include "ui/keyframe_canvas.h"
#include "ui/panel_window.h"

namespace pliant::editor {

void draw_keyframe_slices(App& app) {
  KeyframeCanvasState& s = app.canvas;
  const nlohmann::json& scene = app.doc.scene();
  if (!has_control(scene)) {
    ImGui::TextDisabled("No keyframe control in this scene (Jobs > Keyframe solve > Add keyframe control)");
    return;
  }
  std::string label = s.slot == kInitialDensitySlot ? "Initial density" : "Keyframe ?";
  for (const auto& k : list_keyframes(scene))
    if (k.index == s.slot) label = "Keyframe " + std::to_string(k.frame) + " (" + k.type + ")";
  ImGui::SetNextItemWidth(200);
  if (ImGui::BeginCombo("##slot3d", label.c_str())) {
    if (ImGui::Selectable("Initial density", s.slot == kInitialDensitySlot)) s.slot = kInitialDensitySlot;
    for (const auto& k : list_keyframes(scene)) {
      std::string l = "Keyframe " + std::to_string(k.frame) + " (" + k.type + ")##" + std::to_string(k.index);
      if (ImGui::Selectable(l.c_str(), s.slot == k.index)) s.slot = k.index;
    }
    ImGui::EndCombo();
  }
  ui_mark("slice_slot");
  if (s.volume_revision != app.doc.revision() || s.volume_slot != s.slot) {
    s.volume = rasterize_slot_density(scene, app.doc.has_path() ? app.doc.path().parent_path() : std::filesystem::path(),
                                      s.slot, &s.volume_dims, &s.error);
    s.volume_revision = app.doc.revision();
    s.volume_slot = s.slot;
    s.shown_slice = -2;
  }
  const int nx = s.volume_dims[0], ny = s.volume_dims[1], nz = s.volume_dims[2];
  if (s.volume.empty() || nx <= 0) {
    ImGui::TextColored(kWarnColor, "%s", s.error.c_str());
    return;
  }
  if (s.slice < 0 || s.slice >= nz) s.slice = nz / 2;
  ImGui::SameLine();
  ImGui::SetNextItemWidth(160);
  ImGui::SliderInt("z slice", &s.slice, 0, nz - 1);
  ui_mark("slice_z");
  ImGui::SameLine();
  ImGui::TextDisabled("%dx%dx%d; drop a mesh to add a keyframe", nx, ny, nz);

  ImVec2 avail = ImGui::GetContentRegionAvail();
  const float cell = std::max(1.0f, std::min(avail.x / nx, avail.y / ny));
  ImVec2 p0 = ImGui::GetCursorScreenPos();
  p0.x += 0.5f * (avail.x - cell * nx);
  const ImVec2 p1(p0.x + cell * nx, p0.y + cell * ny);
  ImGui::SetCursorScreenPos(p0);
  ImGui::Dummy(ImVec2(cell * nx, cell * ny));
  ui_mark("slice_view");
  if (!app.has_gl()) return;
  if (s.shown_slice != s.slice || !s.texture) {
    std::vector<uint8_t> rgba(size_t(nx) * ny * 4);
    const size_t off = size_t(s.slice) * nx * ny;
    for (size_t c = 0; c < size_t(nx) * ny; ++c) {
      const float v = std::clamp(s.volume[off + c], 0.0f, 1.0f);
      rgba[c * 4 + 0] = uint8_t(std::lround(26 + v * (255 - 26)));
      rgba[c * 4 + 1] = uint8_t(std::lround(28 + v * (255 - 28)));
      rgba[c * 4 + 2] = uint8_t(std::lround(36 + v * (255 - 36)));
      rgba[c * 4 + 3] = 255;
    }
    if (!s.texture) glGenTextures(1, &s.texture);
    glBindTexture(GL_TEXTURE_2D, s.texture);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, nx, ny, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glBindTexture(GL_TEXTURE_2D, 0);
    s.shown_slice = s.slice;
    s.texture_key = {~0ull, 0, 0};  // the 2D canvas must re-upload if shown next
  }
  ImDrawList* dl = ImGui::GetWindowDrawList();
  dl->AddImage(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(s.texture)), p0, p1, ImVec2(0, 1), ImVec2(1, 0));
  dl->AddRect(p0, p1, IM_COL32(190, 195, 210, 200));
}

}  // namespace pliant::editor

// Keyframe list edits on the scene JSON and rasterising targets (editor/doc/smoke_keyframes).
#include "doc/smoke_keyframes.h"

#include <gtest/gtest.h>

#include <cmath>

#include "doc/paint_ops.h"

namespace pliant::editor {
namespace {

using nlohmann::json;

json scene() {
  return json::parse(R"({"pliant": 1, "kind": "smoke", "name": "t",
    "grid": {"resolution": [24, 16], "cell_size_m": 0.05},
    "time": {"dt_s": 0.05, "frames": 30}, "advection": "upwind", "buoyancy_m_per_s2": 0.0})");
}

TEST(SmokeKeyframes, AddKeepsThemSortedAndMoveRefusesAnOccupiedFrame) {
  json s = scene();
  EXPECT_TRUE(is_smoke_2d(s));
  EXPECT_FALSE(has_control(s));
  int i = -1;
  s = with_keyframe_added(s, 20, &i);
  EXPECT_EQ(i, 0);
  s = with_keyframe_added(s, 10, &i);
  EXPECT_EQ(i, 0);
  s = with_keyframe_added(s, 99, &i);  // clamped to T
  EXPECT_EQ(i, 2);
  auto ks = list_keyframes(s);
  ASSERT_EQ(ks.size(), 3u);
  EXPECT_EQ(ks[0].frame, 10);
  EXPECT_EQ(ks[1].frame, 20);
  EXPECT_EQ(ks[2].frame, 30);
  EXPECT_EQ(ks[0].type, "painted");
  json same = with_keyframe_added(s, 20, &i);
  EXPECT_EQ(same, s);
  EXPECT_EQ(i, 1);
  // Moving 10 past 20 re-sorts; moving onto 30 is refused.
  int w = -1;
  json moved = with_keyframe_moved(s, 0, 25, &w);
  EXPECT_EQ(w, 1);
  EXPECT_EQ(list_keyframes(moved)[1].frame, 25);
  EXPECT_EQ(with_keyframe_moved(s, 0, 30, &w), s);
  json removed = with_keyframe_removed(s, 1);
  ASSERT_EQ(list_keyframes(removed).size(), 2u);
  EXPECT_EQ(list_keyframes(removed)[1].frame, 30);
}

TEST(SmokeKeyframes, PaintedSlotRoundTripsBitForBit) {
  json s = scene();
  int i = 0;
  s = with_keyframe_added(s, 5, &i);
  geom::PaintedGrid g = make_painted_grid(24, 16);
  paint_dab(g, 7.3, 5.1, Brush{4, 0.3, false});
  s = with_painted_slot(s, i, g);
  // Through text, as save/reopen does.
  json back = json::parse(s.dump(2));
  std::string err;
  geom::PaintedGrid r = rasterize_slot(back, ".", i, &err);
  EXPECT_EQ(err, "");
  EXPECT_EQ(r.value, g.value);
}

TEST(SmokeKeyframes, RasterisesAnalyticTargetsAndTheInitialDensity) {
  json s = scene();
  s["control"] = default_control_section();
  s["control"]["initial_density"] = json::array({{{"type", "circle"}, {"center", {0.5, 0.5}}, {"radius", 0.25}}});
  s["control"]["keyframes"] = json::array(
      {{{"frame", 3}, {"target", {{"type", "square"}, {"center", {0.5, 0.5}}, {"half_size", {0.25, 0.25}}}}}});
  std::string err;
  geom::PaintedGrid init = rasterize_slot(s, ".", kInitialDensitySlot, &err);
  EXPECT_EQ(err, "");
  // Radius 0.25 of the smallest extent (16 cells) = 4 cells: area ~ 50 cells.
  double m = 0;
  for (uint8_t v : init.value) m += v / 255.0;
  EXPECT_NEAR(m, M_PI * 16, 4);
  geom::PaintedGrid sq = rasterize_slot(s, ".", 0, &err);
  m = 0;
  for (uint8_t v : sq.value) m += v / 255.0;
  EXPECT_NEAR(m, 64, 3);  // 8 x 8 cells
  // A broken target reports its error instead of throwing.
  s["control"]["keyframes"][0]["target"] = {{"type", "mask"}, {"file", "missing.png"}};
  rasterize_slot(s, ".", 0, &err);
  EXPECT_NE(err.find("missing.png"), std::string::npos) << err;
}

}  // namespace
}  // namespace pliant::editor

// The frame's decoration drawn in pixels over the rendered scene with
// MuJoCo's 2D calls (mjr_text, mjr_rectangle), as renders/offscreen_renderer.h
// draws it: the overlay's text panel, the legend (the swimming direction's
// arrow and the trails' colours) and the scale bar; and the grid spacing
// that both the scene's grid and the scale bar follow.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <mujoco/mujoco.h>

namespace ipmc {

// Trail colours per tip (tip1, tip2, tip3, then repeated), rgb in [0, 1].
inline constexpr float kTrailColors[][3] = {
    {0.95f, 0.60f, 0.05f}, {0.15f, 0.65f, 0.25f}, {0.85f, 0.15f, 0.15f}, {0.55f, 0.25f, 0.75f}};
inline constexpr int kTrailColorCount = sizeof(kTrailColors) / sizeof(kTrailColors[0]);

// The series 1, 2, 5 x 10^k [m]: the value at or above `at_least_m`.
double NextInSeries(double at_least_m);
// The grid's minor spacing [m] for px_per_m: 1 mm while that is 8 to 80 px,
// else the coarsest of 1, 2, 5 x 10^k above 8 px (or the finest below
// 80 px); *major_every: 5, or 2 for 5 x 10^k.
double GridSpacing(double px_per_m, int* major_every);

// Where the decoration is drawn: MuJoCo's GL context (its font), the
// image's size [px] and its lower left corner in the framebuffer [px]
// (a panel of a window holding several images).
struct DecorCanvas {
  const mjrContext* con = nullptr;
  int width_px = 0;
  int height_px = 0;
  int left_px = 0;
  int bottom_px = 0;
};

// Width [px] of `text` in the context's normal font.
int TextWidth_px(const DecorCanvas& canvas, const std::string& text);
// The rows (label, value) in a light panel at the top left (top right
// with `right`).
void DrawTable(const DecorCanvas& canvas, const std::vector<std::array<std::string, 2>>& rows,
               bool right = false);
// A light panel at the bottom left: an arrow in the direction the body
// swims when it goes "+ along" (world -x, as `camera` sees it), and the
// colour of each of `trails` tips' trails.
void DrawLegend(const DecorCanvas& canvas, const mjvCamera& camera, int trails);
// A bar one major grid spacing long at the bottom right with its length
// above it (none if it does not fit the width).
void DrawScaleBar(const DecorCanvas& canvas, double px_per_m);
// The legend's label of tip k's (0-based) trail.
std::string TipTrailLabel(int k);

}  // namespace ipmc

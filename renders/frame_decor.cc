#include "renders/frame_decor.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <GL/gl.h>

#include "sim/base/numbers.h"

namespace ipmc {
namespace {

constexpr double kDegToRad = kPi / 180.0;
constexpr float kScaleBar[3] = {0.15f, 0.15f, 0.15f};
// The overlay's panels: dark text on a light, opaque panel, legible over
// any part of the scene. WCAG 2 contrast ratios (L1 + 0.05) / (L2 + 0.05)
// with relative luminances from the sRGB values: text 16.3, labels 7.4
// (tests/render_test.cc measures them on a frame).
constexpr float kPanel[3] = {0.97f, 0.97f, 0.97f};
constexpr float kPanelText[3] = {0.08f, 0.08f, 0.08f};
constexpr float kPanelLabel[3] = {0.30f, 0.30f, 0.32f};
// Grid: 1 mm spacing unless that is closer than kMinGridSpacing_px or
// wider than kMaxGridSpacing_px.
constexpr double kPreferredGridSpacing_m = 1e-3;
constexpr double kMinGridSpacing_px = 8.0;
constexpr double kMaxGridSpacing_px = 80.0;
// Scale bar: thickness and margins from the image corner [px].
constexpr int kScaleBarThickness_px = 4;
constexpr int kScaleBarMargin_px = 16;

std::string FormatLength(double metres) {
  char text[32];
  const double mm = metres * 1e3;
  std::snprintf(text, sizeof(text), mm >= 1.0 ? "%g mm" : "%g um", mm >= 1.0 ? mm : mm * 1e3);
  return text;
}

// The GL viewport on the whole image: mjr_text places its text relative to
// the current viewport, which mjr_rectangle leaves on its rectangle.
void ViewportOnImage(const DecorCanvas& canvas) {
  glViewport(canvas.left_px, canvas.bottom_px, canvas.width_px, canvas.height_px);
}

// A rectangle of the image (pixels from its lower left corner) filled with rgb.
void FillRect(const DecorCanvas& canvas, mjrRect rect, const float rgb[3]) {
  rect.left += canvas.left_px;
  rect.bottom += canvas.bottom_px;
  mjr_rectangle(rect, rgb[0], rgb[1], rgb[2], 1.0f);
}

// Text whose box starts at pixel (x, y from the bottom) of the image.
void DrawText(const DecorCanvas& canvas, const std::string& text, int x_px, int y_px,
              const float rgb[3]) {
  ViewportOnImage(canvas);
  mjr_text(mjFONT_NORMAL, text.c_str(), canvas.con, static_cast<float>(x_px) / canvas.width_px,
           static_cast<float>(y_px) / canvas.height_px, rgb[0], rgb[1], rgb[2]);
}

}  // namespace

double NextInSeries(double at_least_m) {
  const double decade = std::pow(10.0, std::floor(std::log10(at_least_m)));
  for (double factor : {1.0, 2.0, 5.0}) {
    if (factor * decade >= at_least_m * (1.0 - 1e-12)) return factor * decade;
  }
  return 10.0 * decade;
}

double GridSpacing(double px_per_m, int* major_every) {
  double spacing = kPreferredGridSpacing_m;
  if (spacing * px_per_m < kMinGridSpacing_px) {
    spacing = NextInSeries(kMinGridSpacing_px / px_per_m);
  } else if (spacing * px_per_m > kMaxGridSpacing_px) {
    spacing = NextInSeries(kMaxGridSpacing_px / px_per_m);
    if (spacing * px_per_m > kMaxGridSpacing_px) spacing = NextInSeries(0.45 * spacing);
  }
  const double leading = spacing / std::pow(10.0, std::floor(std::log10(spacing) + 1e-9));
  *major_every = std::abs(leading - 5.0) < 1e-6 ? 2 : 5;
  return spacing;
}

void DrawScaleBar(const DecorCanvas& canvas, double px_per_m) {
  int major_every = 5;
  const double spacing = GridSpacing(px_per_m, &major_every);
  const double bar_m = spacing * major_every;
  const int length_px = static_cast<int>(std::lround(bar_m * px_per_m));
  if (length_px + 2 * kScaleBarMargin_px > canvas.width_px) return;
  const mjrRect bar = {canvas.width_px - kScaleBarMargin_px - length_px, kScaleBarMargin_px, length_px,
                       kScaleBarThickness_px};
  const std::string label = FormatLength(bar_m);
  const int text_px = TextWidth_px(canvas, label);
  DrawText(canvas, label, bar.left + (length_px - text_px) / 2, bar.bottom + bar.height + 4,
           kScaleBar);
  FillRect(canvas, bar, kScaleBar);
}

int TextWidth_px(const DecorCanvas& canvas, const std::string& text) {
  int width = 0;
  for (unsigned char ch : text) width += ch < 127 ? canvas.con->charWidth[ch] : 0;
  return width;
}

// Labels in one column, values in the next, dark on light.
void DrawTable(const DecorCanvas& canvas, const std::vector<std::array<std::string, 2>>& rows,
               bool right) {
  const int width_ = canvas.width_px, height_ = canvas.height_px;
  const int line = canvas.con->charHeight;
  int label_px = 0, value_px = 0;
  for (const auto& row : rows) {
    label_px = std::max(label_px, TextWidth_px(canvas, row[0]));
    value_px = std::max(value_px, TextWidth_px(canvas, row[1]));
  }
  const int pad = line / 2;
  const int panel_w = std::min(width_, 3 * pad + label_px + value_px + pad);
  const int panel_h = std::min(height_, static_cast<int>(rows.size()) * line + 2 * pad);
  const int left = right ? width_ - panel_w : 0;
  FillRect(canvas, {left, height_ - panel_h, panel_w, panel_h}, kPanel);
  for (size_t k = 0; k < rows.size(); ++k) {
    // mjr_text's y is the bottom of the text's box.
    const int y = height_ - pad - static_cast<int>(k + 1) * line;
    DrawText(canvas, rows[k][0], left + pad, y, kPanelLabel);
    DrawText(canvas, rows[k][1], left + 2 * pad + label_px + pad, y, kPanelText);
  }
}

void DrawLegend(const DecorCanvas& canvas, const mjvCamera& camera, int trails) {
  const int width_ = canvas.width_px, height_ = canvas.height_px;
  const int line = canvas.con->charHeight;
  const int pad = line / 2;
  const int arrow_px = 3 * line;
  const std::string along = "+ along";
  int text_px = TextWidth_px(canvas, along);
  for (int k = 0; k < trails; ++k) text_px = std::max(text_px, TextWidth_px(canvas, TipTrailLabel(k)));
  const int panel_w = 3 * pad + arrow_px + text_px;
  const int panel_h = (1 + trails) * line + 2 * pad;
  if (panel_w > width_ / 2 || panel_h > height_ / 2) return;
  FillRect(canvas, {0, 0, panel_w, panel_h}, kPanel);

  // The screen direction of world -x: its components on the camera's
  // right and up vectors, as MuJoCo's free camera sets them from azimuth
  // and elevation (up = d forward / d elevation, right = forward x up).
  const double el = camera.elevation * kDegToRad, az = camera.azimuth * kDegToRad;
  const double forward[3] = {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                             std::sin(el)};
  const double up[3] = {-std::sin(el) * std::cos(az), -std::sin(el) * std::sin(az), std::cos(el)};
  const double right_x = forward[1] * up[2] - forward[2] * up[1];
  const double norm = std::hypot(right_x, up[0]);
  // (none when the camera looks along the swimming axis)
  const double dir_x = norm > 1e-6 ? -right_x / norm : 0.0;
  const double dir_y = norm > 1e-6 ? -up[0] / norm : 0.0;
  const int row0 = pad + trails * line;  // bottom of the arrow's row
  const double cx = pad + 0.5 * arrow_px, cy = row0 + 0.5 * line;
  const double half = 0.5 * (arrow_px - 4);
  const int dot = std::max(2, line / 8);
  // Shaft and head as small squares (mjr_rectangle is all GL offers here).
  const auto square = [&](double x, double y) {
    FillRect(canvas,
             {static_cast<int>(std::lround(x - 0.5 * dot)),
              static_cast<int>(std::lround(y - 0.5 * dot)), dot, dot},
             kPanelText);
  };
  const double tip_x = cx + half * dir_x, tip_y = cy + half * dir_y;
  const double head = 0.35 * arrow_px;
  if (norm > 1e-6) {
    for (double t = -half; t <= half; t += 0.5 * dot) square(cx + t * dir_x, cy + t * dir_y);
    for (const double angle : {kPi * 5.0 / 6.0, -kPi * 5.0 / 6.0}) {
      const double hx = dir_x * std::cos(angle) - dir_y * std::sin(angle);
      const double hy = dir_x * std::sin(angle) + dir_y * std::cos(angle);
      for (double t = 0.0; t <= head; t += 0.5 * dot) square(tip_x + t * hx, tip_y + t * hy);
    }
  }
  const int text_x = 2 * pad + arrow_px;
  DrawText(canvas, along, text_x, row0 + (line - canvas.con->charHeight) / 2, kPanelText);
  for (int k = 0; k < trails; ++k) {
    const float* color = kTrailColors[k % kTrailColorCount];
    const int y = pad + (trails - 1 - k) * line;
    FillRect(canvas, {pad, y + line / 4, arrow_px, line / 2}, color);
    DrawText(canvas, TipTrailLabel(k), text_x, y + (line - canvas.con->charHeight) / 2, kPanelText);
  }
}

std::string TipTrailLabel(int k) { return "tip " + std::to_string(k + 1) + " trail"; }

}  // namespace ipmc

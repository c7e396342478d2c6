// Off-screen rendering of a flagellum model with OSMesa (no display
// needed): the body on a light background with a millimetre grid, a faint
// ghost of a reference shape, the trails of the link tips, and an overlay
// with the time, the wave cycle, caller-given rows and the net
// displacement.
//
// Camera. A MuJoCo free camera looks at a point of the x-y plane, by
// default straight down (-z) with +x to the right and +y up in the image.
// It follows the root body's subtree centre of mass (the swimmer's centre
// of mass, the point SwimMeter measures) or stays at a fixed point. The
// image spans `view_width_m` at the look-at point, or, if that is 0, the
// body's rest length L (the span of its geoms at qpos0, 32 mm for the
// paper's flagellum with its 1 mm head) over `body_fill`:
//   distance = W / (2 tan(fovy / 2) aspect),   aspect = width / height,
// with a narrow fovy of 3 deg (0.77 m for W = 53 mm at 4:3), so the view
// is nearly orthographic. PixelsPerMetre gives the scale at the look-at
// point.
//
// The strip. Its 3 mm width lies along z, so from above it shows its
// 250 um edge. The renderer's copy of the model draws every box thinner
// than `strip_thickness_m` in the bending plane (and every capsule or
// cylinder of smaller radius) that thick instead, so the bending reads at
// a glance; the caller's model, and so the physics, keeps its geometry.
// The root body (the head, standing for the electrode clamp) is drawn
// dark and 2.5 times as thick. Sites are hidden. Seen from straight above,
// boxes are drawn flat (10 um along the view), so that the perspective
// shows no sides off the image centre: each box shows its footprint.
//
// Decor, from the bottom up (all under the body's lowest face, so the body
// covers them): a light background, grid lines, the ghost, the trails.
// Each decor point is moved along its camera ray to its layer's height, so
// it is drawn where its point of the plane z = 0 (the body's mid-plane)
// would be: the grid is a true ruler at the body's plane.
//   Grid: minor lines (1 px GL lines) every millimetre (or, where that is
//   closer than 8 px or wider than 80 px, every 0.1, 0.2, 0.5, 2, 5, 10,
//   ... mm), and darker major lines every 5 minor ones (2 for a spacing of
//   5 x 10^k). Top-down views also get a scale bar one major
//   spacing long (bottom right).
//   Ghost: the polyline `ghost_m` (world points, e.g. the ideal wave in
//   the head's frame) as pale capsules as thick as the drawn strip.
//   Trails: every Frame() appends the world positions of the sites
//   tip1..tipN (the link tips; tip1..tip(N-1) sit 0.25 mm from hinges
//   j2..jN, so they also trace the joints) to a ring of `trail_length`
//   frames per site, drawn as GL lines (0.2 mm wide for a 32 mm body)
//   between consecutive positions, one colour per tip, fading into the
//   background with age. (Lines cost a tenth of what capsules do.)
//
// Overlay (top left): time, cycle (given the wave period), the caller's
// rows, and the net displacement of the centre of mass along the swimming
// axis -x (positive = head first) and across it (+y).
//
// Lighting. The renderer works on its own copy of the model (so the
// caller's model may be freed or changed meanwhile) with the view settings
// changed there: a headlight with more ambient light than MuJoCo's
// default, the model's lights dimmed, a faint glow on the body's geoms
// (so their sides stay blue), the fovy above, coarser spheres and
// capsules (they are a few pixels across), and shadows off.
//
// Frames are 8-bit RGB, rows from top to bottom (width x height x 3 bytes).
//
// In a window (RendererOptions::window) the same scene is drawn into the
// current GL context's framebuffer instead, so that a viewer shows what a
// film's frame shows.
//
// An OSMesa context is current per thread: a renderer is used from one
// thread at a time; Frame() makes its own context current, so several
// renderers can take turns in one thread.
#pragma once

#include <mujoco/mujoco.h>

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "renders/frame_decor.h"

namespace ipmc {

struct CameraSetup {
  bool follow = true;               // look at the swimmer's centre of mass
  double lookat_m[3] = {0, 0, 0};   // when !follow
  double follow_offset_m[2] = {0, 0};  // when follow: added to the centre of mass (x, y)
  double body_fill = 0.6;           // rest length / image width, in (0, 10]; used if view_width_m == 0
  double view_width_m = 0.0;        // > 0: the image width at the look-at point [m]
  double azimuth_deg = 90.0;        // 90 with elevation -90: +x right, +y up
  double elevation_deg = -90.0;     // -90: straight down; in [-90, -5]
};

struct OverlaySetup {
  bool show = true;
  double period_s = 0.0;  // > 0: show the cycle, floor(t / period) + 1
  // Rows shown after the cycle: label, value.
  std::vector<std::array<std::string, 2>> rows;
  // Net displacement of the centre of mass from this point (x, y) [m],
  // shown along the swimming axis -x (positive = head first) and across it
  // (+y) in mm. Unset: from the centre of mass at the first frame since the
  // renderer was made or Reset().
  std::optional<std::array<double, 2>> origin_m;
};

struct FrameSetup {
  CameraSetup camera;
  OverlaySetup overlay;
  bool grid = true;                          // grid lines (and scale bar) on the background
  std::vector<std::array<double, 3>> ghost_m;  // polyline drawn faintly under the body; empty: none
};

struct RendererOptions {
  int trail_length = 50;  // frames kept per tip site; 0: no trails
  // Drawn thickness of the strip in the bending plane [m], in [0, 0.01];
  // 0 keeps the model's geometry. Unset: 2 % of the body's rest length
  // (0.64 mm for the paper's flagellum).
  std::optional<double> strip_thickness_m;
  // Draw into the framebuffer of the GL context current on the calling
  // thread (a window's: renders/viewer.h) instead of an OSMesa buffer of
  // the renderer's own, with the image's lower left corner at (left_px,
  // bottom_px) of it; the model's offscreen buffer does not limit the
  // image's size then. That context must be current whenever the renderer
  // is made, used or destroyed.
  bool window = false;
  int left_px = 0, bottom_px = 0;
};

class OffscreenRenderer {
 public:
  // Copies m and creates the OSMesa and MuJoCo contexts. width and height
  // must be positive and fit the model's offscreen buffer
  // (<visual><global offwidth offheight>); throws FieldError naming the
  // field (width, height, trail_length, strip_thickness_m) otherwise, std::runtime_error if OSMesa or MuJoCo
  // cannot provide an offscreen buffer.
  OffscreenRenderer(const mjModel* m, int width, int height, RendererOptions options = {});
  ~OffscreenRenderer();
  OffscreenRenderer(const OffscreenRenderer&) = delete;
  OffscreenRenderer& operator=(const OffscreenRenderer&) = delete;

  // Renders the state of d (data of the model given to the constructor, or
  // of a model of identical sizes; FieldError "data" otherwise). Only
  // d->qpos, the mocap poses and d->time are read: the kinematics are
  // recomputed on a private copy, so the picture matches d->qpos even right
  // after mj_step. Appends the tip positions to the trails.
  std::vector<unsigned char> Frame(const mjData* d, const FrameSetup& setup = {});
  // Frame() without reading the image back (a window's frame).
  void Draw(const mjData* d, const FrameSetup& setup = {});
  // Appends the tip positions of the state d->qpos to the trails, as a
  // Frame() of it would, without drawing.
  void AppendTrail(const mjData* d);

  // Forgets the trails and the first frame's centre of mass.
  void Reset();

  // The x-y bounding box (x_min, x_max, y_min, y_max) [m] of the body as
  // drawn (strip thickened) in the state d->qpos.
  std::array<double, 4> DrawnBounds(const mjData* d);
  // Height of one overlay text line [px].
  int overlay_line_height_px() const;
  // Where the image is drawn, for more decoration over it
  // (renders/frame_decor.h).
  DecorCanvas Canvas() const;
  // Throws FieldError ("width" or "height") naming the limit unless
  // width x height is positive and fits m's offscreen buffer.
  static void CheckImageSize(const mjModel* m, int width, int height);

  // Image pixels per metre at the camera's look-at point.
  double PixelsPerMetre(const CameraSetup& camera) const;
  // Throws FieldError naming the field (body_fill, elevation_deg, ...) if
  // a camera value is out of range.
  static void ValidateCamera(const CameraSetup& camera);

  int width() const { return width_; }
  int height() const { return height_; }
  double body_length_m() const { return body_length_m_; }
  double strip_thickness_m() const { return strip_thickness_m_; }  // as drawn
  // The scene of the last frame (scene().camera[0..1]: the OpenGL cameras).
  const mjvScene& scene() const;

 private:
  struct Context;  // OSMesa and MuJoCo resources, destroyed in reverse order
  struct Layers;   // heights of the decor layers
  void ThickenStrip(mjModel* copy, double thickness_m);
  void AddDecor(const FrameSetup& setup);
  void AddBackgroundAndGrid(const double eye[3], double px_per_m);
  void AddGhost(const FrameSetup& setup, const double eye[3]);
  void AddTrailGeoms(const double eye[3], double px_per_m);
  // The overlay: its rows and the legend (renders/frame_decor.h).
  void DrawOverlay(const FrameSetup& setup);
  // Copies d's state to the scratch data and computes its kinematics.
  void PoseScratch(const mjData* d);
  void AppendTrailPoints();  // from the scratch data's kinematics

  int width_, height_;
  bool window_ = false;
  int left_px_ = 0, bottom_px_ = 0;
  double body_length_m_ = 0.0;
  double body_half_height_m_ = 0.0;  // half the body's extent along z at rest
  double strip_thickness_m_ = 0.0;   // as drawn
  int root_body_ = 1;  // the first body below the world: the head, free or welded
  std::vector<int> tip_sites_;
  int trail_length_;
  std::vector<std::vector<float>> trails_;  // per site: ring of xyz
  int trail_count_ = 0, trail_next_ = 0;
  std::optional<std::array<double, 2>> first_com_m_;
  std::unique_ptr<Context> context_;
};

}  // namespace ipmc

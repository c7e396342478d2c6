// Off-screen rendering of a flagellum model with OSMesa (no display
// needed): a camera that follows the swimmer from above, the trails of the
// link tips, and an overlay with the time, the wave cycle and the net
// displacement.
//
// Camera. A MuJoCo free camera looks straight down (-z) at the x-y plane,
// +x to the right and +y up in the image, at the root body's subtree centre
// of mass (the swimmer's centre of mass; the same point SwimMeter
// measures). Its distance is set so that the body's rest length L (the span
// of its geoms at qpos0, 32 mm for the paper's flagellum with its 1 mm
// head) fills the fraction `body_fill` of the image width:
//   distance = L / (2 body_fill tan(fovy / 2) aspect),   aspect = width / height,
// with a narrow fovy of 10 deg (0.23 m at 60 % and 4:3), so the view is
// nearly orthographic. The strip's 3 mm width lies along z, so from above
// it shows its 250 um edge: about 3 px wide at 640 x 480.
//
// Trails. Every Frame() appends the world positions of the sites tip1..tipN
// (the link tips; tip1..tip(N-1) sit 0.25 mm from hinges j2..jN, so they
// also trace the joints) to a ring of `trail_length` frames per site, drawn
// as capsules between consecutive positions (one colour per tip, darkening
// with age); they lie in the mid-plane z = 0, under the strip's top face.
//
// Overlay (top left): time, cycle (given the wave period) and the net
// displacement of the centre of mass.
//
// Lighting. The renderer works on its own copy of the model (so the
// caller's model may be freed or changed meanwhile) with the view settings
// changed there: a brighter headlight than MuJoCo's default, the fovy
// above, coarser spheres and capsules (they are a few pixels across), and
// shadows off. The model's directional light is kept; the background is
// MuJoCo's plain black.
//
// Frames are 8-bit RGB, rows from top to bottom (width x height x 3 bytes).
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

namespace ipmc {

struct CameraSetup {
  bool follow = true;               // look at the swimmer's centre of mass
  double lookat_m[3] = {0, 0, 0};   // when !follow
  double body_fill = 0.6;           // rest length / image width, in (0, 10]
  double azimuth_deg = 90.0;        // 90 with elevation -90: +x right, +y up
  double elevation_deg = -90.0;     // -90: straight down
};

struct OverlaySetup {
  bool show = true;
  double period_s = 0.0;  // > 0: show the cycle, floor(t / period) + 1
  // Net displacement of the centre of mass from this point (x, y) [m],
  // shown along the swimming axis -x (positive = head first) and across it
  // (+y) in mm. Unset: from the centre of mass at the first frame since the
  // renderer was made or Reset().
  std::optional<std::array<double, 2>> origin_m;
};

struct FrameSetup {
  CameraSetup camera;
  OverlaySetup overlay;
};

struct RendererOptions {
  int trail_length = 50;  // frames kept per tip site; 0: no trails
};

class OffscreenRenderer {
 public:
  // Copies m and creates the OSMesa and MuJoCo contexts. width and height
  // must be positive and fit the model's offscreen buffer
  // (<visual><global offwidth offheight>); throws std::invalid_argument
  // naming the limit otherwise, std::runtime_error if OSMesa or MuJoCo
  // cannot provide an offscreen buffer.
  OffscreenRenderer(const mjModel* m, int width, int height, RendererOptions options = {});
  ~OffscreenRenderer();
  OffscreenRenderer(const OffscreenRenderer&) = delete;
  OffscreenRenderer& operator=(const OffscreenRenderer&) = delete;

  // Renders the state of d (data of the model given to the constructor, or
  // of a model of identical sizes; std::invalid_argument otherwise). Only
  // d->qpos, the mocap poses and d->time are read: the kinematics are
  // recomputed on a private copy, so the picture matches d->qpos even right
  // after mj_step. Appends the tip positions to the trails.
  std::vector<unsigned char> Frame(const mjData* d, const FrameSetup& setup = {});

  // Forgets the trails and the first frame's centre of mass.
  void Reset();

  int width() const { return width_; }
  int height() const { return height_; }
  double body_length_m() const { return body_length_m_; }
  // The scene of the last frame (scene().camera[0..1]: the OpenGL cameras).
  const mjvScene& scene() const;

 private:
  struct Context;  // OSMesa and MuJoCo resources, destroyed in reverse order
  void AddTrailGeoms();
  void DrawOverlay(const FrameSetup& setup);

  int width_, height_;
  double body_length_m_ = 0.0;
  int root_body_ = 1;  // the first body below the world: the head, free or welded
  std::vector<int> tip_sites_;
  int trail_length_;
  std::vector<std::vector<float>> trails_;  // per site: ring of xyz
  int trail_count_ = 0, trail_next_ = 0;
  std::optional<std::array<double, 2>> first_com_m_;
  std::unique_ptr<Context> context_;
};

}  // namespace ipmc

#include "renders/offscreen_renderer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "sim/base/error.h"
#include "sim/base/numbers.h"
#include "renders/frame_decor.h"
#include "renders/offscreen_context.h"
#include "sim/core/simulation.h"

namespace ipmc {
namespace {

constexpr double kDegToRad = kPi / 180.0;
// Room in the scene for what mjv_updateScene adds besides the model's geoms
// and sites (decor: frames, labels, lights' markers).
constexpr int kSceneMargin = 100;
// Lights. Headlight (MuJoCo's default is ambient 0.1, diffuse 0.4,
// specular 0.5) and the model's lights, whose diffuse part is scaled to
// kModelLightDiffuse and specular part to kModelLightSpecular; the body's
// geoms also glow with kBodyEmission. An upward face then gets 1.15 times
// its colour from a light straight above (0.5 + 0.3 + 0.1 + 0.25), so the
// blue strip keeps its colour, and a vertical face 0.8 times (emission and
// ambient): the strip's sides read as a darker blue, not black.
constexpr float kHeadlightAmbient = 0.3f;
constexpr float kHeadlightDiffuse = 0.1f;
constexpr float kHeadlightSpecular = 0.0f;
constexpr float kModelLightDiffuse = 0.25f;
constexpr float kModelLightSpecular = 0.1f;
constexpr float kBodyEmission = 0.5f;
// Tessellation of MuJoCo's built-in spheres and capsules (default 28 x 16):
// the ghost's capsules are a few pixels across (render rate at 640 x 480
// with 300 capsules: 21 frames/s at the default, 94 at 8 x 4).
constexpr int kSlices = 8;
constexpr int kStacks = 4;
// Vertical field of view (MuJoCo's default is 45 deg): a narrow one puts the
// camera far away (0.77 m for a 53 mm wide view at 4:3), so the view is
// nearly orthographic: from above, the strip's 3 mm tall sides show as
// less than a third of a pixel.
constexpr float kFovy_deg = 3.0f;
// Multisampling of the offscreen buffer (MuJoCo's default is 4): without
// it a frame costs about half the CPU time (llvmpipe shades every sample;
// 29 against 52 ms per 640x480 frame, encoding included), and the H.264
// encoding softens the strip's stepped edges anyway; lines are drawn
// smooth by GL either way.
constexpr int kMultisamples = 0;
// Half-height along the view of boxes seen from straight above.
constexpr float kFlatBoxHalfHeight_m = 1e-5f;
constexpr double kMinElevation_deg = -90.0, kMaxElevation_deg = -5.0;
// Default drawn strip thickness, relative to the body's rest length.
constexpr double kStripThicknessPerLength = 0.02;
constexpr double kMaxStripThickness_m = 0.01;
// The head (clamp) is drawn this many times as thick as the strip.
constexpr double kClampThicknessRatio = 2.5;

// Colours (rgb in [0, 1]) as they should appear on screen (decor geoms
// glow: OffscreenRenderer::Context::FlatRgba, renders/offscreen_context.h).
constexpr float kBackground[3] = {0.965f, 0.965f, 0.950f};
constexpr float kGridMinor[3] = {0.855f, 0.860f, 0.870f};
constexpr float kGridMajor[3] = {0.700f, 0.715f, 0.735f};
constexpr float kGhost[3] = {0.780f, 0.815f, 0.900f};
constexpr float kClamp[3] = {0.20f, 0.20f, 0.24f};
// The oldest part of a trail (colours: kTrailColors, renders/frame_decor.h)
// is this far from the background towards its colour.
constexpr float kTrailOldestStrength = 0.15f;
// Trails: half their width relative to the body length (0.1 mm for 32 mm).
constexpr double kTrailRadiusPerLength = 0.003;
// Grid (spacing: GridSpacing, renders/frame_decor.h): line widths [px].
constexpr double kMinorLine_px = 1.0;
constexpr double kMajorLine_px = 2.0;
constexpr int kMaxGridLines = 400;
constexpr int kMaxGhostPoints = 400;

std::string Size(int width, int height) {
  return std::to_string(width) + "x" + std::to_string(height);
}

struct Box3 {
  double lo[3] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                  std::numeric_limits<double>::infinity()};
  double hi[3] = {-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                  -std::numeric_limits<double>::infinity()};
  bool any = false;
};

// The bounding box of the model's non-world geoms; d holds the kinematics.
Box3 GeomBox(const mjModel* m, const mjData* d) {
  Box3 box;
  for (int g = 0; g < m->ngeom; ++g) {
    if (m->geom_bodyid[g] == 0) continue;
    const mjtNum* pos = d->geom_xpos + 3 * g;
    const mjtNum* mat = d->geom_xmat + 9 * g;
    for (int i = 0; i < 3; ++i) {
      double half = 0.0;
      if (m->geom_type[g] == mjGEOM_BOX) {
        for (int k = 0; k < 3; ++k) half += std::abs(mat[3 * i + k]) * m->geom_size[3 * g + k];
      } else {
        half = m->geom_rbound[g];
      }
      box.lo[i] = std::min(box.lo[i], pos[i] - half);
      box.hi[i] = std::max(box.hi[i], pos[i] + half);
    }
    box.any = true;
  }
  return box;
}

// The point on the ray from eye through (x, y, 0) at height z: drawn there,
// it covers the pixel of (x, y, 0).
void OnRayAtHeight(const double eye[3], double x, double y, double z, mjtNum out[3]) {
  const double s = (eye[2] - z) / eye[2];
  out[0] = eye[0] + (x - eye[0]) * s;
  out[1] = eye[1] + (y - eye[1]) * s;
  out[2] = z;
}

}  // namespace

// Heights of the decor layers, below the body's lowest face: trails, then
// the ghost (whose top is at the trails' centre), the grid inside the
// ghost's capsules, and the background just under the grid.
struct OffscreenRenderer::Layers {
  double trail_radius, trail_z, ghost_radius, ghost_z, grid_z, grid_half_thickness, background_z;
  Layers(double body_half_height, double strip_thickness, double body_length) {
    trail_radius = kTrailRadiusPerLength * body_length;
    ghost_radius = 0.5 * strip_thickness;
    trail_z = -body_half_height - 2.0 * trail_radius;
    ghost_z = trail_z - ghost_radius;
    grid_z = ghost_z;
    grid_half_thickness = 0.02 * ghost_radius;
    background_z = grid_z - 0.2 * ghost_radius;
  }
};

void OffscreenRenderer::ValidateCamera(const CameraSetup& cam) {
  const auto fail = [](const std::string& field, const std::string& range, double value) {
    std::ostringstream msg;
    msg << "renderer: camera " << field << " must be " << range << " (got " << value << ")";
    throw FieldError(msg.str(), field, range);
  };
  if (!(cam.body_fill > 0.0 && cam.body_fill <= 10.0)) fail("body_fill", "in (0, 10]", cam.body_fill);
  if (!(cam.view_width_m >= 0.0 && cam.view_width_m <= 10.0)) {
    fail("view_width_m", "in [0, 10] (0: from body_fill)", cam.view_width_m);
  }
  if (!(cam.elevation_deg >= kMinElevation_deg && cam.elevation_deg <= kMaxElevation_deg)) {
    fail("elevation_deg", "in [-90, -5]", cam.elevation_deg);
  }
  if (!(std::abs(cam.azimuth_deg) <= 360.0)) fail("azimuth_deg", "in [-360, 360]", cam.azimuth_deg);
  for (double v : cam.lookat_m) {
    if (!std::isfinite(v)) fail("lookat_m", "finite", v);
  }
  for (double v : cam.follow_offset_m) {
    if (!std::isfinite(v)) fail("follow_offset_m", "finite", v);
  }
}

OffscreenRenderer::OffscreenRenderer(const mjModel* m, int width, int height,
                                     RendererOptions options)
    : width_(width),
      height_(height),
      window_(options.window),
      left_px_(options.left_px),
      bottom_px_(options.bottom_px),
      trail_length_(options.trail_length) {
  if (!m) throw FieldError("renderer: no model", "model", "a model");
  if (window_) {
    if (width <= 0 || height <= 0) {
      throw FieldError("renderer: image size must be positive (got " + Size(width, height) + ")",
                       width <= 0 ? "width" : "height", "> 0");
    }
  } else {
    CheckImageSize(m, width, height);
  }
  if (trail_length_ < 0) {
    throw FieldError("renderer: trail_length must be >= 0 (got " + std::to_string(trail_length_) +
                         ")",
                     "trail_length", ">= 0");
  }
  if (options.strip_thickness_m &&
      !(*options.strip_thickness_m >= 0.0 && *options.strip_thickness_m <= kMaxStripThickness_m)) {
    std::ostringstream msg;
    msg << "renderer: strip_thickness_m must be in [0, 0.01] (got " << *options.strip_thickness_m
        << ")";
    throw FieldError(msg.str(), "strip_thickness_m", "in [0, 0.01]");
  }
  if (m->nbody < 2) {
    throw FieldError("renderer: the model has no body to follow", "model", "a model with a body");
  }

  ModelPtr copy(mj_copyModel(nullptr, m));
  if (!copy) throw std::runtime_error("renderer: cannot copy the model");
  copy->vis.headlight.active = 1;
  std::fill_n(copy->vis.headlight.ambient, 3, kHeadlightAmbient);
  std::fill_n(copy->vis.headlight.diffuse, 3, kHeadlightDiffuse);
  std::fill_n(copy->vis.headlight.specular, 3, kHeadlightSpecular);
  for (int l = 0; l < copy->nlight; ++l) {
    float* diffuse = copy->light_diffuse + 3 * l;
    const float brightest = std::max({diffuse[0], diffuse[1], diffuse[2]});
    if (brightest > 0.0f) {
      for (int i = 0; i < 3; ++i) diffuse[i] *= kModelLightDiffuse / brightest;
    }
    std::fill_n(copy->light_specular + 3 * l, 3, kModelLightSpecular);
  }
  copy->vis.global.fovy = kFovy_deg;
  copy->vis.quality.offsamples = kMultisamples;
  copy->vis.quality.numslices = kSlices;
  copy->vis.quality.numstacks = kStacks;

  for (int k = 1;; ++k) {
    const int site = mj_name2id(copy.get(), mjOBJ_SITE, ("tip" + std::to_string(k)).c_str());
    if (site < 0) break;
    tip_sites_.push_back(site);
  }
  trails_.assign(tip_sites_.size(), std::vector<float>(3 * static_cast<size_t>(trail_length_)));
  const int trail_geoms = static_cast<int>(tip_sites_.size()) * std::max(0, trail_length_ - 1);
  const int maxgeom = copy->ngeom + copy->nsite + trail_geoms + kMaxGridLines + kMaxGhostPoints +
                      1 + kSceneMargin;
  const int fontscale = height >= 720 ? mjFONTSCALE_150 : mjFONTSCALE_100;
  context_ = std::make_unique<Context>(std::move(copy), maxgeom, width, height, fontscale, window_);

  mjModel* model = context_->model.get();
  mjData* scratch = context_->scratch.get();
  mj_kinematics(model, scratch);
  const Box3 rest = GeomBox(model, scratch);
  if (rest.any) {
    body_length_m_ = std::max(rest.hi[0] - rest.lo[0], rest.hi[1] - rest.lo[1]);
    body_half_height_m_ = 0.5 * (rest.hi[2] - rest.lo[2]);
  } else {
    body_length_m_ = model->stat.extent;
    body_half_height_m_ = 0.0;
  }
  ThickenStrip(model, options.strip_thickness_m.value_or(kStripThicknessPerLength * body_length_m_));

  context_->scene.scn.flags[mjRND_SHADOW] = 0;
  const mjrContext& con = context_->render.con;
  if (window_) {
    mjr_setBuffer(mjFB_WINDOW, &context_->render.con);
    return;
  }
  mjr_setBuffer(mjFB_OFFSCREEN, &context_->render.con);
  if (con.currentBuffer != mjFB_OFFSCREEN) {
    throw std::runtime_error("renderer: MuJoCo could not make an offscreen framebuffer");
  }
  if (con.offWidth < width || con.offHeight < height) {
    throw std::runtime_error("renderer: offscreen framebuffer is " +
                             Size(con.offWidth, con.offHeight) + ", smaller than " +
                             Size(width, height));
  }
}

OffscreenRenderer::~OffscreenRenderer() = default;

void OffscreenRenderer::CheckImageSize(const mjModel* m, int width, int height) {
  if (width <= 0 || height <= 0) {
    throw FieldError("renderer: image size must be positive (got " + Size(width, height) + ")",
                     width <= 0 ? "width" : "height", "> 0");
  }
  if (width > m->vis.global.offwidth || height > m->vis.global.offheight) {
    throw FieldError(
        "renderer: image " + Size(width, height) + " exceeds the model's offscreen buffer " +
            Size(m->vis.global.offwidth, m->vis.global.offheight) +
            " (<visual><global offwidth offheight> in the MJCF)",
        width > m->vis.global.offwidth ? "width" : "height",
        "at most " + Size(m->vis.global.offwidth, m->vis.global.offheight));
  }
}

std::array<double, 4> OffscreenRenderer::DrawnBounds(const mjData* d) {
  const mjModel* m = context_->model.get();
  mjData* s = context_->scratch.get();
  mju_copy(s->qpos, d->qpos, m->nq);
  mj_kinematics(m, s);
  const Box3 box = GeomBox(m, s);
  if (!box.any) return {0, 0, 0, 0};
  return {box.lo[0], box.hi[0], box.lo[1], box.hi[1]};
}

int OffscreenRenderer::overlay_line_height_px() const { return context_->render.con.charHeight; }

// Boxes: the local axis lying in the x-y plane at rest with the smallest
// half-size is widened to half the thickness; capsules and cylinders get
// at least that radius. The root body's geoms are the clamp: dark and
// kClampThicknessRatio times as thick.
void OffscreenRenderer::ThickenStrip(mjModel* copy, double thickness_m) {
  const mjData* rest = context_->scratch.get();
  double drawn = 0.0;
  for (int g = 0; g < copy->ngeom; ++g) {
    const int body = copy->geom_bodyid[g];
    if (body == 0) continue;
    const bool clamp = body == root_body_;
    const double half = 0.5 * thickness_m * (clamp ? kClampThicknessRatio : 1.0);
    mjtNum* size = copy->geom_size + 3 * g;
    if (copy->geom_type[g] == mjGEOM_BOX) {
      const mjtNum* mat = rest->geom_xmat + 9 * g;
      int thin = -1;
      for (int k = 0; k < 3; ++k) {
        if (std::abs(mat[6 + k]) > 0.5) continue;  // local axis k points out of the plane
        if (thin < 0 || size[k] < size[thin]) thin = k;
      }
      if (thin >= 0) {
        size[thin] = std::max<mjtNum>(size[thin], half);
        if (!clamp) drawn = std::max(drawn, 2.0 * size[thin]);
      }
    } else if (copy->geom_type[g] == mjGEOM_CAPSULE || copy->geom_type[g] == mjGEOM_CYLINDER) {
      size[0] = std::max<mjtNum>(size[0], half);
      if (!clamp) drawn = std::max(drawn, 2.0 * size[0]);
    }
    if (clamp) {
      copy->geom_matid[g] = -1;
      std::copy(kClamp, kClamp + 3, copy->geom_rgba + 4 * g);
      copy->geom_rgba[4 * g + 3] = 1.0f;
    }
  }
  strip_thickness_m_ = drawn > 0.0 ? drawn : thickness_m;
}

const mjvScene& OffscreenRenderer::scene() const { return context_->scene.scn; }

void OffscreenRenderer::Reset() {
  trail_count_ = 0;
  trail_next_ = 0;
  first_com_m_.reset();
}

double OffscreenRenderer::PixelsPerMetre(const CameraSetup& camera) const {
  const double view_width_m =
      camera.view_width_m > 0.0 ? camera.view_width_m : body_length_m_ / camera.body_fill;
  return width_ / view_width_m;
}

void OffscreenRenderer::PoseScratch(const mjData* d) {
  Context& c = *context_;
  mjModel* m = c.model.get();
  mjData* s = c.scratch.get();
  if (!d || d->nbuffer != s->nbuffer || d->nstack != s->nstack) {
    throw FieldError("renderer: mjData does not belong to the rendered model", "data",
                     "an mjData of the rendered model");
  }
  s->time = d->time;
  mju_copy(s->qpos, d->qpos, m->nq);
  mju_copy(s->mocap_pos, d->mocap_pos, 3 * m->nmocap);
  mju_copy(s->mocap_quat, d->mocap_quat, 4 * m->nmocap);
  mj_kinematics(m, s);
}

void OffscreenRenderer::AppendTrailPoints() {
  if (trail_length_ <= 0) return;
  const mjData* s = context_->scratch.get();
  for (size_t k = 0; k < tip_sites_.size(); ++k) {
    for (int i = 0; i < 3; ++i) {
      trails_[k][3 * trail_next_ + i] = static_cast<float>(s->site_xpos[3 * tip_sites_[k] + i]);
    }
  }
  trail_next_ = (trail_next_ + 1) % trail_length_;
  trail_count_ = std::min(trail_count_ + 1, trail_length_);
}

void OffscreenRenderer::AppendTrail(const mjData* d) {
  PoseScratch(d);
  AppendTrailPoints();
}

std::vector<unsigned char> OffscreenRenderer::Frame(const mjData* d, const FrameSetup& setup) {
  Draw(d, setup);
  Context& c = *context_;
  const mjrRect viewport = {left_px_, bottom_px_, width_, height_};
  mjr_readPixels(c.pixels.data(), nullptr, viewport, &c.render.con);
  std::vector<unsigned char> rgb(c.pixels.size());
  const size_t row = static_cast<size_t>(width_) * 3;
  for (int y = 0; y < height_; ++y) {
    std::memcpy(rgb.data() + row * y, c.pixels.data() + row * (height_ - 1 - y), row);
  }
  return rgb;
}

void OffscreenRenderer::Draw(const mjData* d, const FrameSetup& setup) {
  Context& c = *context_;
  mjModel* m = c.model.get();
  mjData* s = c.scratch.get();
  const CameraSetup& cam = setup.camera;
  ValidateCamera(cam);
  PoseScratch(d);
  mj_comPos(m, s);
  mj_camlight(m, s);
  if (!first_com_m_) {
    first_com_m_ = {s->subtree_com[3 * root_body_], s->subtree_com[3 * root_body_ + 1]};
  }
  AppendTrailPoints();

  // Free camera: forward = (cos el cos az, cos el sin az, sin el), the eye
  // `distance` behind the look-at point.
  const double aspect = static_cast<double>(width_) / height_;
  const double half_fovy = 0.5 * m->vis.global.fovy * kDegToRad;
  const double distance = width_ / PixelsPerMetre(cam) / (2.0 * std::tan(half_fovy) * aspect);
  c.camera.type = mjCAMERA_FREE;
  c.camera.azimuth = cam.azimuth_deg;
  c.camera.elevation = cam.elevation_deg;
  c.camera.distance = distance;
  for (int i = 0; i < 3; ++i) {
    c.camera.lookat[i] = cam.follow ? s->subtree_com[3 * root_body_ + i] : cam.lookat_m[i];
    if (cam.follow && i < 2) c.camera.lookat[i] += cam.follow_offset_m[i];
  }
  // Clipping planes around the body: the depth buffer resolves the decor
  // layers (a few tenths of a millimetre apart) at any distance.
  m->vis.map.znear = static_cast<float>(0.25 * distance / m->stat.extent);
  m->vis.map.zfar = static_cast<float>(50.0 * distance / m->stat.extent);

  mjv_updateScene(m, s, &c.option, &c.perturb, &c.camera, mjCAT_ALL, &c.scene.scn);
  const bool top_down = cam.elevation_deg <= kMinElevation_deg + 1e-9;
  for (int g = 0; g < c.scene.scn.ngeom; ++g) {
    mjvGeom& geom = c.scene.scn.geoms[g];
    if (geom.objtype != mjOBJ_GEOM) continue;
    geom.emission = std::max(geom.emission, kBodyEmission);
    // From straight above, a box's extent along the view (the strip's
    // 3 mm width) cannot be seen, but the perspective would show its sides
    // off the image centre (up to a few pixels, varying as the links
    // turn): flattened, each box shows exactly its footprint.
    if (top_down && geom.type == mjGEOM_BOX) {
      for (int k = 0; k < 3; ++k) {
        if (std::abs(geom.mat[6 + k]) > 0.99f) geom.size[k] = std::min(geom.size[k], kFlatBoxHalfHeight_m);
      }
    }
  }
  AddDecor(setup);

  c.render.MakeCurrent();
  const int buffer = window_ ? mjFB_WINDOW : mjFB_OFFSCREEN;
  mjr_setBuffer(buffer, &c.render.con);
  if (c.render.con.currentBuffer != buffer) {
    throw std::runtime_error("renderer: offscreen framebuffer not available");
  }
  const mjrRect viewport = {left_px_, bottom_px_, width_, height_};
  mjr_render(viewport, &c.scene.scn, &c.render.con);
  // The scale bar: top-down views only (elsewhere the scale varies across
  // the image).
  if (setup.grid && setup.camera.elevation_deg <= kMinElevation_deg + 1e-9) {
    DrawScaleBar(Canvas(), PixelsPerMetre(setup.camera));
  }
  DrawOverlay(setup);
}

DecorCanvas OffscreenRenderer::Canvas() const {
  return {&context_->render.con, width_, height_, left_px_, bottom_px_};
}

void OffscreenRenderer::AddDecor(const FrameSetup& setup) {
  const mjvCamera& camera = context_->camera;
  const double el = camera.elevation * kDegToRad, az = camera.azimuth * kDegToRad;
  const double forward[3] = {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
  double eye[3];
  for (int i = 0; i < 3; ++i) eye[i] = camera.lookat[i] - camera.distance * forward[i];
  if (setup.grid) {
    AddBackgroundAndGrid(eye, PixelsPerMetre(setup.camera));
  } else {
    AddBackgroundAndGrid(eye, 0.0);
  }
  AddGhost(setup, eye);
  AddTrailGeoms(eye, PixelsPerMetre(setup.camera));
}

// The background box, and with px_per_m > 0 the grid lines over the view
// (for oblique views, over a wider patch of the plane).
void OffscreenRenderer::AddBackgroundAndGrid(const double eye[3], double px_per_m) {
  Context& c = *context_;
  const Layers layers(body_half_height_m_, strip_thickness_m_, body_length_m_);
  const double* lookat = c.camera.lookat;
  const double width_m = 2.0 * c.camera.distance * std::tan(0.5 * kFovy_deg * kDegToRad) *
                         static_cast<double>(width_) / height_;
  {
    const mjtNum size[3] = {50.0 * width_m, 50.0 * width_m, 0.1 * layers.ghost_radius};
    const mjtNum pos[3] = {lookat[0], lookat[1], layers.background_z - size[2]};
    c.AddDecorGeom(mjGEOM_BOX, kBackground, size, pos);
  }
  if (px_per_m <= 0.0) return;

  int major_every = 5;
  const double sine = std::max(0.3, std::abs(std::sin(c.camera.elevation * kDegToRad)));
  double half_extent = 0.75 * width_m / sine;
  double spacing = GridSpacing(px_per_m, &major_every);
  while (4.0 * half_extent / spacing + 4.0 > kMaxGridLines) {
    spacing = NextInSeries(1.01 * spacing);  // the next coarser spacing
    major_every = spacing / std::pow(10.0, std::floor(std::log10(spacing) + 1e-9)) > 4.0 ? 2 : 5;
  }
  const long first_x = static_cast<long>(std::floor((lookat[0] - half_extent) / spacing));
  const long last_x = static_cast<long>(std::ceil((lookat[0] + half_extent) / spacing));
  const long first_y = static_cast<long>(std::floor((lookat[1] - half_extent) / spacing));
  const long last_y = static_cast<long>(std::ceil((lookat[1] + half_extent) / spacing));
  const double z = layers.grid_z;
  for (int along = 0; along < 2; ++along) {  // 0: lines of constant x, 1: of constant y
    const long first = along == 0 ? first_x : first_y;
    const long last = along == 0 ? last_x : last_y;
    for (long k = first; k <= last; ++k) {
      const bool major = k % major_every == 0;
      const double width_px = major ? kMajorLine_px : kMinorLine_px;
      const double at = k * spacing;
      mjtNum a[3], b[3];
      if (along == 0) {
        OnRayAtHeight(eye, at, lookat[1] - half_extent, z, a);
        OnRayAtHeight(eye, at, lookat[1] + half_extent, z, b);
      } else {
        OnRayAtHeight(eye, lookat[0] - half_extent, at, z, a);
        OnRayAtHeight(eye, lookat[0] + half_extent, at, z, b);
      }
      if (!c.AddDecorLine(major ? kGridMajor : kGridMinor, a, b, width_px)) return;
    }
  }
}

void OffscreenRenderer::AddGhost(const FrameSetup& setup, const double eye[3]) {
  Context& c = *context_;
  const Layers layers(body_half_height_m_, strip_thickness_m_, body_length_m_);
  const size_t points = std::min<size_t>(setup.ghost_m.size(), kMaxGhostPoints);
  for (size_t k = 0; k + 1 < points; ++k) {
    mjtNum a[3], b[3];
    OnRayAtHeight(eye, setup.ghost_m[k][0], setup.ghost_m[k][1], layers.ghost_z, a);
    OnRayAtHeight(eye, setup.ghost_m[k + 1][0], setup.ghost_m[k + 1][1], layers.ghost_z, b);
    // Capsules, not lines: GL lines this wide are not drawn at full width.
    mjvGeom* geom = c.AddDecorGeom(mjGEOM_CAPSULE, kGhost);
    if (!geom) return;
    mjv_makeConnector(geom, mjGEOM_CAPSULE, layers.ghost_radius, a[0], a[1], a[2], b[0], b[1], b[2]);
  }
}

void OffscreenRenderer::AddTrailGeoms(const double eye[3], double px_per_m) {
  if (trail_count_ < 2) return;
  Context& c = *context_;
  const Layers layers(body_half_height_m_, strip_thickness_m_, body_length_m_);
  for (size_t k = 0; k < trails_.size(); ++k) {
    const float* color = kTrailColors[k % kTrailColorCount];
    const std::vector<float>& ring = trails_[k];
    // Oldest to newest: segment j joins positions j and j + 1.
    const int oldest = (trail_next_ - trail_count_ + trail_length_) % trail_length_;
    for (int j = 0; j + 1 < trail_count_; ++j) {
      const float* pa = &ring[3 * ((oldest + j) % trail_length_)];
      const float* pb = &ring[3 * ((oldest + j + 1) % trail_length_)];
      // From kTrailOldestStrength of the colour over the background
      // (oldest) to the full colour (newest).
      const float age = static_cast<float>(j + 1) / (trail_count_ - 1);
      const float strength = kTrailOldestStrength + (1.0f - kTrailOldestStrength) * age;
      float shade[3];
      for (int i = 0; i < 3; ++i) shade[i] = kBackground[i] + (color[i] - kBackground[i]) * strength;
      mjtNum a[3], b[3];
      OnRayAtHeight(eye, pa[0], pa[1], layers.trail_z, a);
      OnRayAtHeight(eye, pb[0], pb[1], layers.trail_z, b);
      if (!c.AddDecorLine(shade, a, b, 2.0 * layers.trail_radius * px_per_m)) return;
    }
  }
}

void OffscreenRenderer::DrawOverlay(const FrameSetup& setup) {
  const OverlaySetup& overlay = setup.overlay;
  if (!overlay.show) return;
  const mjData* s = context_->scratch.get();
  const std::array<double, 2> origin = overlay.origin_m ? *overlay.origin_m : *first_com_m_;
  const double dx_mm = (s->subtree_com[3 * root_body_] - origin[0]) * 1e3;
  const double dy_mm = (s->subtree_com[3 * root_body_ + 1] - origin[1]) * 1e3;
  std::vector<std::array<std::string, 2>> rows;
  char buffer[256];
  std::snprintf(buffer, sizeof(buffer), "%.2f s", s->time);
  rows.push_back({"time", buffer});
  if (overlay.period_s > 0.0) {
    const long cycle = static_cast<long>(std::floor(s->time / overlay.period_s + 1e-9)) + 1;
    rows.push_back({"cycle", std::to_string(cycle)});
  }
  for (const auto& row : overlay.rows) rows.push_back(row);
  // (+ 0.0 turns a -0 into 0)
  std::snprintf(buffer, sizeof(buffer), "%+.4f mm along, %+.4f mm across", -dx_mm + 0.0,
                dy_mm + 0.0);
  rows.push_back({"net displacement", buffer});
  const DecorCanvas canvas = Canvas();
  DrawTable(canvas, rows);
  DrawLegend(canvas, context_->camera, trail_length_ > 1 ? static_cast<int>(tip_sites_.size()) : 0);
}

}  // namespace ipmc

#include "renders/offscreen_renderer.h"

#include <GL/osmesa.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "sim/core/simulation.h"
#include "sim/io/numbers.h"

namespace ipmc {
namespace {

// Room in the scene for what mjv_updateScene adds besides the model's geoms
// and sites (decor: frames, labels, lights' markers).
constexpr int kSceneMargin = 100;
// Headlight (MuJoCo's default is ambient 0.1, diffuse 0.4, specular 0.5):
// enough ambient light that the strip's thin edge stays visible however it
// faces, little specular so the blue keeps its colour.
constexpr float kHeadlightAmbient = 0.3f;
constexpr float kHeadlightDiffuse = 0.5f;
constexpr float kHeadlightSpecular = 0.1f;
// Trail capsules: radius relative to the body length (0.1 mm for 32 mm) and
// colours per tip (tip1, tip2, tip3, then repeated).
constexpr double kTrailRadiusPerLength = 0.003;
constexpr float kTrailColors[][3] = {
    {1.00f, 0.75f, 0.20f}, {0.30f, 0.90f, 0.40f}, {1.00f, 0.35f, 0.35f}, {0.80f, 0.50f, 1.00f}};
constexpr float kTrailOldestBrightness = 0.15f;
// Tessellation of MuJoCo's built-in spheres and capsules (default 28 x 16):
// the sites and trail capsules are a few pixels across, and the hundreds of
// trail capsules are most of the drawing work (render rate at 640 x 480 with
// 300 capsules: 21 frames/s at the default, 94 at 8 x 4).
constexpr int kSlices = 8;
constexpr int kStacks = 4;
// Vertical field of view (MuJoCo's default is 45 deg): a narrow one puts the
// camera far away (0.23 m for 60 % fill at 4:3), so the view is nearly
// orthographic and the strip's 3 mm tall sides barely show off-centre.
constexpr float kFovy_deg = 10.0f;

std::string Size(int width, int height) {
  return std::to_string(width) + "x" + std::to_string(height);
}

// The span of the model's non-world geoms at qpos0 (largest side of their
// bounding box in the x-y plane); d holds the kinematics at qpos0.
double RestLength(const mjModel* m, const mjData* d) {
  double lo[3] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                  std::numeric_limits<double>::infinity()};
  double hi[3] = {-lo[0], -lo[1], -lo[2]};
  bool any = false;
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
      lo[i] = std::min(lo[i], pos[i] - half);
      hi[i] = std::max(hi[i], pos[i] + half);
    }
    any = true;
  }
  if (!any) return m->stat.extent;
  return std::max(hi[0] - lo[0], hi[1] - lo[1]);
}

}  // namespace

// Each resource is its own member, so a constructor that throws halfway
// releases what it made; members are destroyed in reverse order of
// declaration: MuJoCo's GL context (with its OSMesa context current), the
// OSMesa context, the scene, the scratch data, the model copy.
struct OffscreenRenderer::Context {
  struct Scene {
    mjvScene scn;
    Scene(const mjModel* m, int maxgeom) {
      mjv_defaultScene(&scn);
      mjv_makeScene(m, &scn, maxgeom);
    }
    ~Scene() { mjv_freeScene(&scn); }
  };
  struct Osmesa {
    OSMesaContext context = nullptr;
    std::vector<unsigned char> buffer;  // the context's own framebuffer (unused: we draw off-screen)
    int width, height;
    Osmesa(int w, int h) : buffer(static_cast<size_t>(w) * h * 4), width(w), height(h) {
      context = OSMesaCreateContextExt(OSMESA_RGBA, 24, 8, 0, nullptr);
      if (!context) throw std::runtime_error("renderer: OSMesaCreateContextExt failed");
    }
    ~Osmesa() { OSMesaDestroyContext(context); }
    void MakeCurrent() {
      if (OSMesaGetCurrentContext() == context) return;
      if (!OSMesaMakeCurrent(context, buffer.data(), GL_UNSIGNED_BYTE, width, height)) {
        throw std::runtime_error("renderer: OSMesaMakeCurrent failed");
      }
    }
  };
  struct Render {
    Osmesa& osmesa;
    mjrContext con;
    Render(const mjModel* m, Osmesa& gl, int fontscale) : osmesa(gl) {
      mjr_defaultContext(&con);
      osmesa.MakeCurrent();  // before mjr_makeContext, which loads the GL functions
      mjr_makeContext(m, &con, fontscale);
    }
    ~Render() {
      try {
        osmesa.MakeCurrent();
      } catch (const std::exception&) {
        return;  // no current context: freeing GL objects would touch another context
      }
      mjr_freeContext(&con);
    }
  };

  ModelPtr model;
  DataPtr scratch;
  Scene scene;
  Osmesa osmesa;
  Render render;
  mjvCamera camera;
  mjvOption option;
  mjvPerturb perturb;
  std::vector<unsigned char> pixels;  // bottom row first, as OpenGL reads them

  Context(ModelPtr m, int maxgeom, int width, int height, int fontscale)
      : model(std::move(m)),
        scratch(mj_makeData(model.get())),
        scene(model.get(), maxgeom),
        osmesa(width, height),
        render(model.get(), osmesa, fontscale),
        pixels(static_cast<size_t>(width) * height * 3) {
    if (!scratch) throw std::runtime_error("renderer: cannot allocate mjData");
    mjv_defaultCamera(&camera);
    mjv_defaultOption(&option);
    mjv_defaultPerturb(&perturb);
  }
};

OffscreenRenderer::OffscreenRenderer(const mjModel* m, int width, int height,
                                     RendererOptions options)
    : width_(width), height_(height), trail_length_(options.trail_length) {
  if (!m) throw std::invalid_argument("renderer: no model");
  if (width <= 0 || height <= 0) {
    throw std::invalid_argument("renderer: image size must be positive (got " +
                                Size(width, height) + ")");
  }
  if (width > m->vis.global.offwidth || height > m->vis.global.offheight) {
    throw std::invalid_argument(
        "renderer: image " + Size(width, height) + " exceeds the model's offscreen buffer " +
        Size(m->vis.global.offwidth, m->vis.global.offheight) +
        " (<visual><global offwidth offheight> in the MJCF)");
  }
  if (trail_length_ < 0) {
    throw std::invalid_argument("renderer: trail_length must be >= 0 (got " +
                                std::to_string(trail_length_) + ")");
  }
  if (m->nbody < 2) throw std::invalid_argument("renderer: the model has no body to follow");

  ModelPtr copy(mj_copyModel(nullptr, m));
  if (!copy) throw std::runtime_error("renderer: cannot copy the model");
  copy->vis.headlight.active = 1;
  std::fill_n(copy->vis.headlight.ambient, 3, kHeadlightAmbient);
  std::fill_n(copy->vis.headlight.diffuse, 3, kHeadlightDiffuse);
  std::fill_n(copy->vis.headlight.specular, 3, kHeadlightSpecular);
  copy->vis.global.fovy = kFovy_deg;
  copy->vis.quality.numslices = kSlices;
  copy->vis.quality.numstacks = kStacks;

  for (int k = 1;; ++k) {
    const int site = mj_name2id(copy.get(), mjOBJ_SITE, ("tip" + std::to_string(k)).c_str());
    if (site < 0) break;
    tip_sites_.push_back(site);
  }
  trails_.assign(tip_sites_.size(), std::vector<float>(3 * static_cast<size_t>(trail_length_)));
  const int trail_geoms = static_cast<int>(tip_sites_.size()) * std::max(0, trail_length_ - 1);
  const int maxgeom = copy->ngeom + copy->nsite + trail_geoms + kSceneMargin;
  const int fontscale = height >= 720 ? mjFONTSCALE_150 : mjFONTSCALE_100;
  context_ = std::make_unique<Context>(std::move(copy), maxgeom, width, height, fontscale);

  const mjModel* model = context_->model.get();
  mjData* scratch = context_->scratch.get();
  mj_kinematics(model, scratch);
  body_length_m_ = RestLength(model, scratch);

  const mjrContext& con = context_->render.con;
  mjr_setBuffer(mjFB_OFFSCREEN, &context_->render.con);
  if (con.currentBuffer != mjFB_OFFSCREEN) {
    throw std::runtime_error("renderer: MuJoCo could not make an offscreen framebuffer");
  }
  if (con.offWidth < width || con.offHeight < height) {
    throw std::runtime_error("renderer: offscreen framebuffer is " +
                             Size(con.offWidth, con.offHeight) + ", smaller than " +
                             Size(width, height));
  }
  context_->scene.scn.flags[mjRND_SHADOW] = 0;
}

OffscreenRenderer::~OffscreenRenderer() = default;

const mjvScene& OffscreenRenderer::scene() const { return context_->scene.scn; }

void OffscreenRenderer::Reset() {
  trail_count_ = 0;
  trail_next_ = 0;
  first_com_m_.reset();
}

std::vector<unsigned char> OffscreenRenderer::Frame(const mjData* d, const FrameSetup& setup) {
  Context& c = *context_;
  const mjModel* m = c.model.get();
  mjData* s = c.scratch.get();
  if (!d || d->nbuffer != s->nbuffer || d->nstack != s->nstack) {
    throw std::invalid_argument("renderer: mjData does not belong to the rendered model");
  }
  const CameraSetup& cam = setup.camera;
  if (!(cam.body_fill > 0.0 && cam.body_fill <= 10.0)) {
    throw std::invalid_argument("renderer: camera body_fill must be in (0, 10]");
  }

  s->time = d->time;
  mju_copy(s->qpos, d->qpos, m->nq);
  mju_copy(s->mocap_pos, d->mocap_pos, 3 * m->nmocap);
  mju_copy(s->mocap_quat, d->mocap_quat, 4 * m->nmocap);
  mj_kinematics(m, s);
  mj_comPos(m, s);
  mj_camlight(m, s);
  if (!first_com_m_) {
    first_com_m_ = {s->subtree_com[3 * root_body_], s->subtree_com[3 * root_body_ + 1]};
  }

  if (trail_length_ > 0) {
    for (size_t k = 0; k < tip_sites_.size(); ++k) {
      for (int i = 0; i < 3; ++i) {
        trails_[k][3 * trail_next_ + i] = static_cast<float>(s->site_xpos[3 * tip_sites_[k] + i]);
      }
    }
    trail_next_ = (trail_next_ + 1) % trail_length_;
    trail_count_ = std::min(trail_count_ + 1, trail_length_);
  }

  const double aspect = static_cast<double>(width_) / height_;
  const double half_fovy = 0.5 * m->vis.global.fovy * kPi / 180.0;
  c.camera.type = mjCAMERA_FREE;
  c.camera.azimuth = cam.azimuth_deg;
  c.camera.elevation = cam.elevation_deg;
  c.camera.distance = body_length_m_ / (2.0 * cam.body_fill * std::tan(half_fovy) * aspect);
  for (int i = 0; i < 3; ++i) {
    c.camera.lookat[i] = cam.follow ? s->subtree_com[3 * root_body_ + i] : cam.lookat_m[i];
  }

  mjv_updateScene(m, s, &c.option, &c.perturb, &c.camera, mjCAT_ALL, &c.scene.scn);
  AddTrailGeoms();

  c.osmesa.MakeCurrent();
  mjr_setBuffer(mjFB_OFFSCREEN, &c.render.con);
  if (c.render.con.currentBuffer != mjFB_OFFSCREEN) {
    throw std::runtime_error("renderer: offscreen framebuffer not available");
  }
  const mjrRect viewport = {0, 0, width_, height_};
  mjr_render(viewport, &c.scene.scn, &c.render.con);
  DrawOverlay(setup);
  mjr_readPixels(c.pixels.data(), nullptr, viewport, &c.render.con);

  std::vector<unsigned char> rgb(c.pixels.size());
  const size_t row = static_cast<size_t>(width_) * 3;
  for (int y = 0; y < height_; ++y) {
    std::memcpy(rgb.data() + row * y, c.pixels.data() + row * (height_ - 1 - y), row);
  }
  return rgb;
}

void OffscreenRenderer::AddTrailGeoms() {
  if (trail_count_ < 2) return;
  mjvScene& scn = context_->scene.scn;
  const double radius = kTrailRadiusPerLength * body_length_m_;
  for (size_t k = 0; k < trails_.size(); ++k) {
    const float* color = kTrailColors[k % (sizeof(kTrailColors) / sizeof(kTrailColors[0]))];
    const std::vector<float>& ring = trails_[k];
    // Oldest to newest: segment j joins positions j and j + 1.
    const int oldest = (trail_next_ - trail_count_ + trail_length_) % trail_length_;
    for (int j = 0; j + 1 < trail_count_; ++j) {
      if (scn.ngeom >= scn.maxgeom) return;
      const float* a = &ring[3 * ((oldest + j) % trail_length_)];
      const float* b = &ring[3 * ((oldest + j + 1) % trail_length_)];
      // Fade from kTrailOldestBrightness (oldest) to 1 (newest) towards black.
      const float age = static_cast<float>(j + 1) / (trail_count_ - 1);
      const float brightness = kTrailOldestBrightness + (1.0f - kTrailOldestBrightness) * age;
      const float rgba[4] = {color[0] * brightness, color[1] * brightness, color[2] * brightness, 1};
      mjvGeom* geom = scn.geoms + scn.ngeom;
      mjv_initGeom(geom, mjGEOM_CAPSULE, nullptr, nullptr, nullptr, rgba);
      mjv_makeConnector(geom, mjGEOM_CAPSULE, radius, a[0], a[1], a[2], b[0], b[1], b[2]);
      geom->category = mjCAT_DECOR;
      geom->emission = 0.5f;
      ++scn.ngeom;
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
  std::string labels = "time";
  char values[256];
  int n = std::snprintf(values, sizeof(values), "%.2f s", s->time);
  if (overlay.period_s > 0.0) {
    labels += "\ncycle";
    const long cycle = static_cast<long>(std::floor(s->time / overlay.period_s + 1e-9)) + 1;
    n += std::snprintf(values + n, sizeof(values) - n, "\n%ld", cycle);
  }
  labels += "\nnet displacement";
  std::snprintf(values + n, sizeof(values) - n, "\n%+.4f mm along, %+.4f mm across", -dx_mm,
                dy_mm);
  const mjrRect viewport = {0, 0, width_, height_};
  mjr_overlay(mjFONT_NORMAL, mjGRID_TOPLEFT, viewport, labels.c_str(), values,
              &context_->render.con);
}

}  // namespace ipmc

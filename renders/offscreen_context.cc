#include "renders/offscreen_context.h"

#include <algorithm>
#include <utility>

namespace ipmc {
namespace {

// Decor geoms glow (emission kDecorEmission) besides being lit like the
// body, so that rounded ones (ghost, trails) look nearly flat; FlatRgba
// divides by the emission plus the light that falls on an upward face so
// an upward face appears as given.
constexpr float kDecorEmission = 4.0f;

// Light falling on an upward face: the headlight's ambient and diffuse
// plus, for each directional model light, its ambient and its diffuse
// times the cosine to +z.
float UpwardLight(const mjModel* m) {
  float light = m->vis.headlight.ambient[0] + m->vis.headlight.diffuse[0];
  for (int l = 0; l < m->nlight; ++l) {
    if (!m->light_active[l]) continue;
    const double cosine = std::max(0.0, -m->light_dir[3 * l + 2]);
    light += m->light_ambient[3 * l] + m->light_diffuse[3 * l] * static_cast<float>(cosine);
  }
  return std::max(light, 0.05f);
}

}  // namespace

OffscreenRenderer::Context::Context(ModelPtr m, int maxgeom, int width, int height, int fontscale,
                                    bool window)
    : model(std::move(m)),
      scratch(mj_makeData(model.get())),
      scene(model.get(), maxgeom),
      osmesa(window ? nullptr : std::make_unique<Osmesa>(width, height)),
      render(model.get(), osmesa.get(), fontscale),
      pixels(static_cast<size_t>(width) * height * 3) {
  if (!scratch) throw std::runtime_error("renderer: cannot allocate mjData");
  mjv_defaultCamera(&camera);
  mjv_defaultOption(&option);
  mjv_defaultPerturb(&perturb);
  std::fill_n(option.sitegroup, mjNGROUP, 0);
  upward_light = UpwardLight(model.get());
}

void OffscreenRenderer::Context::FlatRgba(const float rgb[3], float out[4]) const {
  for (int i = 0; i < 3; ++i) out[i] = rgb[i] / (kDecorEmission + upward_light);
  out[3] = 1.0f;
}

mjvGeom* OffscreenRenderer::Context::AddDecorGeom(int type, const float rgb[3], const mjtNum* size,
                                                  const mjtNum* pos) {
  mjvScene& scn = scene.scn;
  if (scn.ngeom >= scn.maxgeom) return nullptr;
  float rgba[4];
  FlatRgba(rgb, rgba);
  mjvGeom* geom = scn.geoms + scn.ngeom++;
  mjv_initGeom(geom, type, size, pos, nullptr, rgba);
  geom->category = mjCAT_DECOR;
  geom->emission = kDecorEmission;
  geom->specular = 0.0f;
  return geom;
}

bool OffscreenRenderer::Context::AddDecorLine(const float rgb[3], const mjtNum a[3],
                                              const mjtNum b[3], double width_px) {
  mjvScene& scn = scene.scn;
  if (scn.ngeom >= scn.maxgeom) return false;
  const float rgba[4] = {rgb[0], rgb[1], rgb[2], 1.0f};  // lines are drawn unlit
  mjvGeom* geom = scn.geoms + scn.ngeom++;
  mjv_initGeom(geom, mjGEOM_LINE, nullptr, nullptr, nullptr, rgba);
  geom->category = mjCAT_DECOR;
  mjv_makeConnector(geom, mjGEOM_LINE, std::max(1.0, width_px), a[0], a[1], a[2], b[0], b[1], b[2]);
  return true;
}

}  // namespace ipmc

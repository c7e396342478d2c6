// The resources behind an OffscreenRenderer (renders/offscreen_renderer.h):
// the OSMesa context (or, in a window, the caller's GL context), MuJoCo's
// GL context, the scene, the scratch data and the model copy, and the
// appenders of the decor geoms that the renderer adds to the scene.
// Included only by the renderer's source files.
#pragma once

#include <GL/osmesa.h>
#include <mujoco/mujoco.h>

#include <memory>
#include <stdexcept>
#include <vector>

#include "renders/offscreen_renderer.h"
#include "sim/core/simulation.h"

namespace ipmc {

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
  // MuJoCo's GL context, on the OSMesa context or (osmesa null) on the
  // window's context, which the caller keeps current.
  struct Render {
    Osmesa* osmesa;
    mjrContext con;
    Render(const mjModel* m, Osmesa* gl, int fontscale) : osmesa(gl) {
      mjr_defaultContext(&con);
      if (osmesa) osmesa->MakeCurrent();  // before mjr_makeContext, which loads the GL functions
      mjr_makeContext(m, &con, fontscale);
    }
    ~Render() {
      try {
        if (osmesa) osmesa->MakeCurrent();
      } catch (const std::exception&) {
        return;  // no current context: freeing GL objects would touch another context
      }
      mjr_freeContext(&con);
    }
    void MakeCurrent() {
      if (osmesa) osmesa->MakeCurrent();
    }
  };

  ModelPtr model;
  DataPtr scratch;
  Scene scene;
  std::unique_ptr<Osmesa> osmesa;  // null in a window
  Render render;
  mjvCamera camera;
  mjvOption option;
  mjvPerturb perturb;
  float upward_light = 1.0f;
  std::vector<unsigned char> pixels;  // bottom row first, as OpenGL reads them

  Context(ModelPtr m, int maxgeom, int width, int height, int fontscale, bool window);

  // rgba of a decor geom (emission kDecorEmission) that appears as `rgb`
  // on an upward face.
  void FlatRgba(const float rgb[3], float out[4]) const;
  // Appends a decor geom of the given type and flat colour to the scene
  // (nullptr if the scene is full); size, pos, mat as in mjv_initGeom.
  mjvGeom* AddDecorGeom(int type, const float rgb[3], const mjtNum* size = nullptr,
                        const mjtNum* pos = nullptr);
  // Appends a line from a to b, width_px pixels wide (at least 1), drawn
  // flat in colour rgb; false if the scene is full.
  bool AddDecorLine(const float rgb[3], const mjtNum a[3], const mjtNum b[3], double width_px);
};

}  // namespace ipmc

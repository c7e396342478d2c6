// Models for the plugin's unit tests, loaded by MuJoCo alone (without the
// program's layers): MJCF text through MuJoCo's virtual file system, or a
// file of the source tree, with the userdata the coupling keeps its state
// in reserved (ipmc_swim.h, "State"), as a program that attaches them does.
#pragma once

#include <mujoco/mujoco.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>

#include "ipmc_swim/ipmc_swim.h"

namespace ipmc::testing {

// The model of MJCF `xml`, with UserdataSize(m) userdata values for a model
// with ipmc_* fields (none for malformed fields: Attach reports them).
// Throws std::runtime_error with MuJoCo's message.
inline ModelPtr LoadXml(const std::string& xml) {
  const auto vfs = std::make_unique<mjVFS>();  // megabytes: not on the stack
  mj_defaultVFS(vfs.get());
  const char* name = "plugin_test_model.xml";
  if (mj_makeEmptyFileVFS(vfs.get(), name, static_cast<int>(xml.size())) != 0) {
    mj_deleteVFS(vfs.get());
    throw std::runtime_error("inline model: too large for MuJoCo's virtual file");
  }
  std::memcpy(vfs->filedata[0], xml.data(), xml.size());
  char error[1024] = "";
  mjModel* m = mj_loadXML(name, vfs.get(), error, sizeof(error));
  mj_deleteVFS(vfs.get());
  if (!m) throw std::runtime_error(std::string("inline model: ") + error);
  ModelPtr model(m);
  int needed = 0;
  try {
    needed = UserdataSize(m);
  } catch (const std::invalid_argument&) {
    // Malformed ipmc_* fields: the test's Attach meets them.
  }
  if (model->nuserdata < needed) model->nuserdata += needed;
  return model;
}

// The text of `path`, relative to the source tree (IPMC_SWIM_SOURCE_DIR,
// tests/test_paths.h).
inline std::string SourceFileText(const std::string& path) {
  std::ifstream in(std::string(IPMC_SWIM_SOURCE_DIR) + "/" + path);
  if (!in) throw std::runtime_error(path + ": cannot open it");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The generated flagellum with 16 sub-segments per link
// (tests/strip_keys_test.cc checks that the file is what the generator
// writes).
inline ModelPtr FlexibleFlagellum() {
  return LoadXml(SourceFileText("plugin/tests/flexible_flagellum.xml"));
}

// A model of the source tree's models/ folder ("flagellum3.xml").
inline ModelPtr LoadSourceModel(const std::string& name) {
  return LoadXml(SourceFileText("models/" + name));
}

// A strip of three 10 mm links of `segments_per_link` sub-segments each
// (boxes 3 mm wide and 0.25 mm thick, each hinged about z at its root to
// the one before: stiffness E I / length with the paper's E = 0.25 GPa,
// damping 6.25e-7 N m s), behind a 1 mm head on planar root joints
// (root_x, root_y, root_yaw; free) or hinged to the world (clamped), in
// water under Gray & Hancock's RFT (a = 0.8125 mm, lambda = 32 mm), no
// gravity and no contacts (as the Stokes step wants). `custom` adds
// <custom> fields.
inline std::string SubSegmentedStrip(int segments_per_link, bool clamped,
                                     const std::string& custom = "") {
  const int segments = 3 * segments_per_link;
  const double length_m = 10e-3 / segments_per_link;
  const double bending_N_m2 = 0.25e9 * 3e-3 * 250e-6 * 250e-6 * 250e-6 / 12;  // E I
  std::ostringstream xml;
  xml.precision(17);
  xml << "<mujoco><option gravity=\"0 0 0\"><flag contact=\"disable\"/></option>"
         "<custom><numeric name=\"ipmc_rft_viscosity_Pa_s\" data=\"0.001\"/>"
         "<numeric name=\"ipmc_rft_equivalent_radius_m\" data=\"0.0008125\"/>"
         "<numeric name=\"ipmc_rft_wavelength_m\" data=\"0.032\"/>"
         "<numeric name=\"ipmc_strip_width_m\" data=\"0.003\"/>"
      << custom << "</custom><worldbody>";
  if (!clamped) {
    xml << "<body name=\"head\"><joint name=\"root_x\" type=\"slide\" axis=\"1 0 0\"/>"
           "<joint name=\"root_y\" type=\"slide\" axis=\"0 1 0\"/>"
           "<joint name=\"root_yaw\" type=\"hinge\" axis=\"0 0 1\"/>"
           "<geom type=\"box\" pos=\"-0.0005 0 0\" size=\"0.0005 0.000125 0.0015\"/>";
  }
  for (int k = 0; k < segments; ++k) {
    xml << "<body pos=\"" << (k == 0 ? 0.0 : length_m) << " 0 0\"><joint type=\"hinge\" "
        << "axis=\"0 0 1\" stiffness=\"" << bending_N_m2 / length_m
        << "\" damping=\"6.25e-07\"/><geom type=\"box\" pos=\"" << length_m / 2
        << " 0 0\" size=\"" << length_m / 2 << " 0.000125 0.0015\"/>";
  }
  for (int k = 0; k < segments; ++k) xml << "</body>";
  if (!clamped) xml << "</body>";
  xml << "</worldbody></mujoco>";
  return xml.str();
}

inline DataPtr MakeData(const mjModel* m) { return DataPtr(mj_makeData(m)); }

// SubSegmentedStrip's hinges (not the root's) turned off straight and
// pushed, each by its own amount, so that the shape and a dense fluid's
// resistance change over the steps.
inline void DriveHingesOffStraight(const mjModel* m, mjData* d) {
  for (int j = 0; j < m->njnt; ++j) {
    if (m->jnt_type[j] == mjJNT_HINGE && m->jnt_bodyid[j] != 1) {
      d->qpos[m->jnt_qposadr[j]] = 0.05 * std::sin(0.7 * j);
      d->qfrc_applied[m->jnt_dofadr[j]] = 1e-7 * std::cos(1.3 * j);
    }
  }
}

}  // namespace ipmc::testing

// The fluid models' unit tests' fixture: the paper's model
// (models/flagellum3.xml, or MJCF `xml`) in its reference pose (straight
// along x), its RFT segments and its fluid under `overrides`.
#pragma once

#include <mujoco/mujoco.h>

#include <memory>
#include <string>

#include "plugin/fluid/fluid_model.h"
#include "plugin/fluid/rft_drag.h"
#include "plugin/tests/test_model.h"

namespace ipmc::testing {

struct Paper {
  explicit Paper(const RftDragOverrides& overrides, const std::string& xml = "")
      : model(xml.empty() ? LoadSourceModel("flagellum3.xml") : LoadXml(xml)),
        data(MakeData(model.get())),
        segments(model.get(), *RftDragConfig::FromModel(model.get(), overrides)),
        fluid(MakeFluid(model.get(), segments, overrides)) {
    mj_forward(model.get(), data.get());
  }
  ModelPtr model;
  DataPtr data;
  RftDrag segments;
  std::unique_ptr<Fluid> fluid;
};

}  // namespace ipmc::testing

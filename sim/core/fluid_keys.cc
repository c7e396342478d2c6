#include "sim/core/fluid_keys.h"

#include <string>

#include "plugin/fluid/plate_fluid.h"
#include "plugin/fluid/regularized_stokeslets.h"
#include "plugin/fluid/ribbon_fluid.h"
#include "sim/core/key_builder.h"
#include "sim/core/scenario.h"

namespace ipmc {
namespace {

// The selector of the Stokeslets' keys and the value they apply under.
constexpr char kFluidModel[] = "fluid.model";
constexpr char kStokeslets[] = "stokeslets";
constexpr char kRibbon[] = "ribbon";
constexpr char kPlates[] = "plates";

// The fluid and the model that computes its drag: viscosity, RFT coefficients, wall.
std::vector<KeySpec> RftKeys() {
  using T = KeyType;
  return {
      Key("fluid.viscosity_Pa_s", T::kNumber, "Pa s", "> 0",
          "the model's `ipmc_rft_viscosity_Pa_s`",
          "Dynamic viscosity of the fluid, overriding the model's")
          .Example("1e-3")
          .Refused("0")
          .Above(0.0)
          .Reads([](const KeyValue& v, ScenarioConfig& c) { c.fluid.viscosity_Pa_s = v.Number(); })
          .Writes([](const ScenarioConfig& c) {
            return c.fluid.viscosity_Pa_s ? TomlFloat(*c.fluid.viscosity_Pa_s) : kLeftOut;
          }),
      Key("fluid.rft_coefficients", T::kChoice, "", "", "the model's `ipmc_rft_coefficients`",
          "RFT drag coefficients (plugin/fluid/rft_drag.h), overriding the model's; "
          "gray_hancock and lighthill follow fluid.rft_wavelength_mm; ribbon is calibrated at "
          "set-up on the converged flat plates of the model's own straight strip, per segment: "
          "its share of the broadside and axial drag per length and its own rotational drag "
          "(plugin/fluid/ribbon_coefficients.h, docs/FLUIDS.md); ribbon_fitted is ribbon with "
          "the broadside drag x 1.14 and the rotational drag x 0.85, fitted to the plates' swim "
          "and fluid power in the paper's default job (for that strip and gait)")
          .Example("\"lighthill\"")
          .Refused("\"direct\"")
          .Choices(kRftCoefficientNames)
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            c.fluid.rft_coefficients = ChoiceValue(kRftCoefficientNames, v.Choice());
          })
          .Writes([](const ScenarioConfig& c) {
            return c.fluid.rft_coefficients
                       ? TomlString(ChoiceText(kRftCoefficientNames, *c.fluid.rft_coefficients))
                       : kLeftOut;
          }),
      Key("fluid.rft_wavelength_mm", T::kNumber, "mm", "finite and > 0", "waveform.wavelength_mm",
          "Wavelength in the Gray-Hancock and Lighthill coefficients, over the model's "
          "`ipmc_rft_wavelength_m`")
          .Example("32.0")
          .Refused("0")
          .Above(0.0)
          .Reads(
              [](const KeyValue& v, ScenarioConfig& c) { c.fluid.rft_wavelength_mm = v.Number(); })
          .Writes([](const ScenarioConfig& c) {
            return c.fluid.rft_wavelength_mm ? TomlFloat(*c.fluid.rft_wavelength_mm) : kLeftOut;
          }),
      Key("fluid.wall_gap_mm", T::kNumber, "mm", "> 0", "no wall",
          "A no-slip plane wall this far below the strip's lower edge (the centreline is the "
          "gap plus half the width above it), parallel to the plane the strip beats in: RFT takes "
          "the near-wall coefficients of Katz, Blake & Paveri-Fontana (1975) in place of "
          "fluid.rft_coefficients, Stokeslets and plates the wall's image system; slender-ribbon "
          "theory is free space only")
          .Example("2.0")
          .Refused("0")
          .Above(0.0)
          .Reads([](const KeyValue& v, ScenarioConfig& c) { c.fluid.wall_gap_mm = v.Number(); })
          .Writes([](const ScenarioConfig& c) {
            return c.fluid.wall_gap_mm ? TomlFloat(*c.fluid.wall_gap_mm) : kLeftOut;
          }),
      Key(kFluidModel, T::kChoice, "", "", "\"rft\"",
          "The fluid model (plugin/fluid/fluid_model.h, docs/FLUIDS.md): local RFT, "
          "regularized Stokeslets along the segments' centrelines, whose segments interact "
          "(with the wall's image system when fluid.wall_gap_mm is set), or slender-ribbon "
          "theory, the strip as one flat ribbon with kinks (free space only), or flat plates, "
          "each link a rectangle of regularized Stokeslets by the nearest-neighbour method "
          "(with the wall's image system when fluid.wall_gap_mm is set)")
          .Default("\"rft\"")
          .Example("\"stokeslets\"")
          .Refused("\"bem\"")
          .Choices(kFluidModelNames)
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            c.fluid.model = ChoiceValue(kFluidModelNames, v.Choice());
          })
          .Writes([](const ScenarioConfig& c) {
            return TomlString(ChoiceText(kFluidModelNames, c.fluid.model));
          }),
  };
}

// The regularized Stokeslets' points and blob (fluid.model = "stokeslets").
std::vector<KeySpec> StokesletKeys() {
  using T = KeyType;
  return {
      Key("fluid.stokeslet_width_points", T::kInteger, "", "[1, 16]", "1",
          "Stokeslet points across the strip's width (ipmc_strip_width_m): 1 puts them on the "
          "centreline; k > 1 makes the strip a sheet, a square grid w / k apart with the blob "
          "0.7 w / k (docs/FLUIDS.md, \"Ribbon calibration\")")
          .Default("1")
          .Example("4")
          .Refused("0")
          .AtLeast(1)
          .AtMost(kMaxWidthPoints)
          .Only(kFluidModel, kStokeslets)
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            c.fluid.stokeslets.width_points = static_cast<int>(v.Integer());
          })
          .Writes([](const ScenarioConfig& c) {
            return c.fluid.stokeslets.width_points == 1
                       ? kLeftOut
                       : TomlInteger(c.fluid.stokeslets.width_points);
          }),
      Key("fluid.stokeslet_points_per_mm", T::kNumber, "1/mm", "> 0",
          "one per blob (1 / fluid.stokeslet_blob_mm)",
          "Stokeslet points per mm along each segment's centreline (each segment gets the "
          "smallest whole number of equal intervals at least this dense)")
          .Example("2.0")
          .Refused("0")
          .Above(0.0)
          .Only(kFluidModel, kStokeslets)
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            c.fluid.stokeslets.points_per_mm = v.Number();
          })
          .Writes([](const ScenarioConfig& c) {
            return c.fluid.stokeslets.points_per_mm ? TomlFloat(*c.fluid.stokeslets.points_per_mm)
                                                    : kLeftOut;
          }),
      Key("fluid.stokeslet_blob_mm", T::kNumber, "mm", "> 0",
          "sqrt(e) a = 1.340 mm for the paper's strip (a the RFT equivalent radius)",
          "Blob size eps of the regularized Stokeslets; sqrt(e) a makes the line of points the "
          "slender cylinder of radius a")
          .Example("1.0")
          .Refused("0")
          .Above(0.0)
          .Only(kFluidModel, kStokeslets)
          .Reads(
              [](const KeyValue& v, ScenarioConfig& c) { c.fluid.stokeslets.blob_mm = v.Number(); })
          .Writes([](const ScenarioConfig& c) {
            return c.fluid.stokeslets.blob_mm ? TomlFloat(*c.fluid.stokeslets.blob_mm) : kLeftOut;
          }),
      Key("fluid.stokeslet_shape_tolerance_rad", T::kNumber, "rad", ">= 0", "1e-3",
          "The Stokeslet resistance is recomputed when a joint has moved more than this since "
          "it was last computed (0: every evaluation)")
          .Default("1e-3")
          .Example("1e-4")
          .Refused("-1")
          .AtLeast(0.0)
          .Only(kFluidModel, kStokeslets)
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            c.fluid.stokeslets.shape_tolerance_rad = v.Number();
          })
          .Writes([](const ScenarioConfig& c) {
            return c.fluid.stokeslets.shape_tolerance_rad == 1e-3
                       ? kLeftOut
                       : TomlFloat(c.fluid.stokeslets.shape_tolerance_rad);
          }),
  };
}

// Slender-ribbon theory's resolution (fluid.model = "ribbon").
std::vector<KeySpec> RibbonKeys() {
  using T = KeyType;
  return {
      Key("fluid.ribbon_modes", T::kInteger, "", "[1, 9]", "8",
          "Legendre modes of each component of the ribbon's force density along the whole "
          "strip (slender-ribbon theory; from 10 on they resolve wavelengths near the strip's "
          "width, where the theory's resistance stops being positive: docs/FLUIDS.md)")
          .Default("8")
          .Example("6")
          .Refused("10")
          .AtLeast(1)
          .AtMost(kMaxRibbonModes)
          .Only(kFluidModel, kRibbon)
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            c.fluid.ribbon.modes = static_cast<int>(v.Integer());
          })
          .Writes([](const ScenarioConfig& c) {
            return c.fluid.ribbon.modes == kDefaultRibbonModes ? kLeftOut
                                                               : TomlInteger(c.fluid.ribbon.modes);
          }),
  };
}

// The flat plates' resolution (fluid.model = "plates").
std::vector<KeySpec> PlateKeys() {
  using T = KeyType;
  return {
      Key("fluid.plate_points_across", T::kInteger, "", "[1, 16]", "4",
          "Force points across the strip's width on each plate (square cells along its "
          "length; the blob is half their spacing): the plate model's resolution "
          "(docs/FLUIDS.md, \"Flat plates\")")
          .Default("4")
          .Example("6")
          .Refused("0")
          .AtLeast(1)
          .AtMost(kMaxPlatePointsAcross)
          .Only(kFluidModel, kPlates)
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            c.fluid.plates.points_across = static_cast<int>(v.Integer());
          })
          .Writes([](const ScenarioConfig& c) {
            return c.fluid.plates.points_across == 4 ? kLeftOut
                                                     : TomlInteger(c.fluid.plates.points_across);
          }),
      Key("fluid.plate_quadrature_refinement", T::kInteger, "", "[1, 8]", "4",
          "Quadrature points per force point along each side of its cell (the nearest-neighbour "
          "method's finer grid)")
          .Default("4")
          .Example("6")
          .Refused("0")
          .AtLeast(1)
          .AtMost(kMaxPlateQuadratureRefinement)
          .Only(kFluidModel, kPlates)
          .Reads([](const KeyValue& v, ScenarioConfig& c) {
            c.fluid.plates.quadrature_refinement = static_cast<int>(v.Integer());
          })
          .Writes([](const ScenarioConfig& c) {
            return c.fluid.plates.quadrature_refinement == 4
                       ? kLeftOut
                       : TomlInteger(c.fluid.plates.quadrature_refinement);
          }),
      Key("fluid.plate_richardson", T::kBoolean, "", "true or false", "true",
          "Richardson extrapolation in the blob: 2 R(eps / 2) - R(eps), which removes the "
          "regularization's error, linear in eps (two solves per resistance)")
          .Default("true")
          .Example("false")
          .Only(kFluidModel, kPlates)
          .Reads(
              [](const KeyValue& v, ScenarioConfig& c) { c.fluid.plates.richardson = v.Boolean(); })
          .Writes([](const ScenarioConfig& c) {
            return c.fluid.plates.richardson ? kLeftOut : TomlBool(false);
          }),
  };
}

}  // namespace

std::vector<KeySpec> FluidKeys() {
  std::vector<KeySpec> keys = RftKeys();
  for (const std::vector<KeySpec>& part : {StokesletKeys(), RibbonKeys(), PlateKeys()}) {
    keys.insert(keys.end(), part.begin(), part.end());
  }
  return keys;
}

}  // namespace ipmc

#include "sim/optimize/retune.h"

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/identify/controller_design.h"
#include "sim/runs/closed_loop_run.h"

namespace ipmc {
namespace {

void RetunePid(const std::vector<IpmcLinkParams>& plants, ScenarioConfig* scenario) {
  ControllerScenario::LinkGains& gains = scenario->controller.link_gains;
  gains.kp.clear(), gains.ki.clear(), gains.kd.clear();
  const double reference_gain = PaperLinkParams(3, IpmcModelKind::kG1).a0_mm_per_V;
  for (const IpmcLinkParams& params : plants) {
    const double scale = reference_gain / params.a0_mm_per_V;
    PidTuningOptions options;
    options.starts = {{scenario->controller.pid.kp * scale, scenario->controller.pid.ki * scale,
                       scenario->controller.pid.kd * scale}};
    const PidGains tuned = TunePid(AccurateLinkPlant(params), options).gains;
    gains.kp.push_back(tuned.kp);
    gains.ki.push_back(tuned.ki);
    gains.kd.push_back(tuned.kd);
  }
}

void RetuneFractional(const std::vector<IpmcLinkParams>& plants, ScenarioConfig* scenario) {
  if (scenario->controller.fractional.realisation != FractionalRealisation::kOustaloup) {
    throw std::invalid_argument("the eq. 15 realisation has the paper's fixed order; retuning "
                                "needs controller.realisation = \"oustaloup\"");
  }
  ControllerScenario::LinkGains& gains = scenario->controller.link_gains;
  gains.gain.clear(), gains.order.clear();
  for (const IpmcLinkParams& params : plants) {
    const FractionalIntegratorDesign design = DesignFractionalIntegrator(
        [params](double w) { return LinkResponseExact(params, w); }, kRetuneCrossover_rad_s,
        kRetunePhaseMargin_deg);
    gains.gain.push_back(design.gain);
    gains.order.push_back(design.order);
  }
}

}  // namespace

ScenarioConfig RetunedControllers(const ScenarioConfig& scenario) {
  ScenarioConfig retuned = scenario;
  const std::vector<IpmcLinkParams> plants = ScenarioLinkPlants(scenario);
  try {
    if (scenario.controller.kind == ControllerKind::kPid) {
      RetunePid(plants, &retuned);
    } else {
      RetuneFractional(plants, &retuned);
    }
  } catch (const std::exception& failure) {
    throw std::runtime_error(scenario.source + ": retuning the controllers failed: " +
                             failure.what());
  }
  return retuned;
}

}  // namespace ipmc

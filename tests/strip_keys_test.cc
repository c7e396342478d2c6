// The strip and its plants as scenario keys (sim/core/strip_keys.h): each
// key changed and its effect checked against a simple estimate (beam
// theory, the PID loop's steady state, RFT's coefficients), the generated
// flagellum of the paper's values against the shipped model, and the
// keys' errors and includes.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ipmc_swim/fields.h"
#include "ipmc_swim/ipmc_swim.h"
#include "sim/base/error.h"
#include "sim/base/numbers.h"
#include "sim/core/model_generator.h"
#include "sim/core/scenario.h"
#include "sim/core/scenario_simulation.h"
#include "sim/core/strip_keys.h"
#include "sim/io/files.h"
#include "sim/optimize/optimize_run.h"
#include "sim/runs/closed_loop_run.h"
#include "tests/cli_util.h"

namespace ipmc {
namespace {

namespace fs = std::filesystem;

std::string Paper() { return (fs::path(IPMC_SWIM_SOURCE_DIR) / "scenarios" / "paper.toml").string(); }

// The paper's scenario with `keys` (TOML lines) over its own.
ScenarioConfig PaperWith(const std::string& keys) {
  return ParseScenario("include = \"" + Paper() + "\"\n" + keys,
                       (fs::path(IPMC_SWIM_SOURCE_DIR) / "scenarios" / "with_keys.toml").string());
}

// Hinge j1's stiffness [N m/rad] of the scenario's model.
double RootStiffness(const ScenarioConfig& scenario) {
  std::string source;
  const ModelPtr m = LoadScenarioModel(scenario, &source);
  return m->jnt_stiffness[mj_name2id(m.get(), mjOBJ_JOINT, "j1")];
}

// The drag's normal resistance per length xi_n [N s/m^2] of the scenario's
// model, as its coupling applies it: the straight body's broadside drag
// (its root_y slide's diagonal of the drag matrix) over the length of the
// segments the drag acts on (resistive-force theory's drag is local: a
// segment of length l moving broadside at v takes xi_n l v).
double NormalResistance_N_s_m2(const ScenarioConfig& scenario) {
  const std::unique_ptr<Simulation> sim = LoadScenarioSimulation(scenario);
  const mjModel* m = sim->model();
  const mjData* d = sim->data();
  for (int i = 0; i < m->nq; ++i) EXPECT_EQ(d->qpos[i], m->qpos0[i]) << "qpos " << i;
  const std::vector<double> drag = DragMatrix(m, d);
  const int dof = m->jnt_dofadr[mj_name2id(m, mjOBJ_JOINT, "root_y")];
  double length_m = 0;
  for (double segment_m : FluidOf(d).segment_length_m) length_m += segment_m;
  return drag[static_cast<size_t>(dof) * m->nv + dof] / length_m;
}

// The sperm number Sp = L (xi_n omega / (E I))^(1/4) of a link of the
// scenario (E I = k s, s = L / 2 the root hinge's share; xi_n of its drag).
double SpermNumber(const ScenarioConfig& scenario) {
  std::string source;
  const ModelPtr m = LoadScenarioModel(scenario, &source);
  const double length_m = 10e-3;
  const double bending_N_m2 = m->jnt_stiffness[mj_name2id(m.get(), mjOBJ_JOINT, "j1")] * 0.5 * length_m;
  const double xi_n = NormalResistance_N_s_m2(scenario);
  const double omega_rad_s = 2 * kPi * scenario.waveform.frequency_Hz;
  return length_m * std::pow(xi_n * omega_rad_s / bending_N_m2, 0.25);
}

TEST(StripKeysTest, ThePapersStripAndPlantGenerateTheShippedModel) {
  // Every key stated with the paper's value generates models/flagellum3.xml
  // byte for byte, so the keys change nothing but what they are set to.
  const ScenarioConfig scenario = PaperWith(
      "[strip]\nwidth_mm = 3.0\nthickness_um = 250.0\nyoungs_modulus_Pa = 0.25e9\n"
      "density_kg_m3 = 2000.0\n");
  ASSERT_TRUE(scenario.model.Generated());
  const std::string shipped =
      ReadTextFile((fs::path(IPMC_SWIM_SOURCE_DIR) / "models" / "flagellum3.xml").string(), "model");
  EXPECT_EQ(GenerateFlagellumMjcf(ScenarioFlagellumSpec(scenario.model)), shipped);
  // plant.model = "g1" is the default: no key, the model file.
  EXPECT_FALSE(PaperWith("[plant]\nmodel = \"g1\"\n").model.Generated());
}

TEST(StripKeysTest, ThePluginTestsFlexibleFlagellumIsTheGenerators) {
  // The plugin's unit tests load the generated flagellum with 16
  // sub-segments per link from a file (they do not link the generator):
  // `ipmc-swim generate --segments-per-link 16` writes it byte for byte.
  FlagellumSpec spec;
  spec.segments_per_link = 16;
  const std::string file = ReadTextFile(
      (fs::path(IPMC_SWIM_SOURCE_DIR) / "plugin" / "tests" / "flexible_flagellum.xml").string(),
      "model");
  EXPECT_EQ(GenerateFlagellumMjcf(spec), file);
}

TEST(StripKeysTest, BendingStiffnessScalesAsThicknessCubedAndYoungsModulus) {
  // E I = E w h^3 / 12 (the hinge's k = E I / s): doubling h gives 8 k.
  const double base = RootStiffness(PaperWith("[strip]\nthickness_um = 250.0\n"));
  EXPECT_NEAR(RootStiffness(PaperWith("[strip]\nthickness_um = 500.0\n")) / base, 8.0, 1e-8);
  EXPECT_NEAR(RootStiffness(PaperWith("[strip]\nyoungs_modulus_Pa = 0.75e9\n")) / base, 3.0, 1e-8);
  EXPECT_NEAR(RootStiffness(PaperWith("[strip]\nwidth_mm = 6.0\n")) / base, 2.0, 1e-8);
}

TEST(StripKeysTest, SpermNumberFallsAsThicknessToTheMinusThreeQuarters) {
  // Sp ~ (E I)^(-1/4) ~ h^(-3/4) at a fixed xi_n; xi_n moves only through
  // ln(2 lambda / a) with a = (w + h) / 4 (2.3 % from 250 to 500 um, so
  // 0.6 % on Sp): the estimate holds within 1 %.
  const double base = SpermNumber(PaperWith("[strip]\nthickness_um = 250.0\n"));
  const double thick = SpermNumber(PaperWith("[strip]\nthickness_um = 500.0\n"));
  EXPECT_NEAR(thick / base / std::pow(2.0, -0.75), 1.0, 0.01);
}

TEST(StripKeysTest, DragFollowsTheEquivalentRadiusAndMassTheDensity) {
  for (const double width_mm : {3.0, 5.0}) {
    const ScenarioConfig scenario =
        PaperWith("[strip]\nwidth_mm = " + std::to_string(width_mm) + "\nthickness_um = 200.0\n");
    std::string source;
    const ModelPtr m = LoadScenarioModel(scenario, &source);
    // Batchelor's flat strip: a = (w + h) / 4.
    const double radius_m = 0.25 * (width_mm * 1e-3 + 200e-6);
    const std::optional<double> field_m = FindCustomScalar(m.get(), kAttrEquivalentRadius);
    ASSERT_TRUE(field_m.has_value());
    EXPECT_NEAR(*field_m / radius_m, 1.0, 1e-9);
    // Gray and Hancock: xi_n = 4 pi mu / (ln(2 lambda / a) + 1/2).
    const double xi_n = 4 * kPi * 1e-3 / (std::log(2 * 32e-3 / radius_m) + 0.5);
    EXPECT_NEAR(NormalResistance_N_s_m2(scenario) / xi_n, 1.0, 1e-6);
  }
  std::string source;
  const ModelPtr light = LoadScenarioModel(PaperWith("[strip]\ndensity_kg_m3 = 1000.0\n"), &source);
  const ModelPtr heavy = LoadScenarioModel(PaperWith("[strip]\ndensity_kg_m3 = 3000.0\n"), &source);
  const int link = mj_name2id(light.get(), mjOBJ_BODY, "link2");
  EXPECT_NEAR(heavy->body_mass[link] / light->body_mass[link], 3.0, 1e-8);
}

TEST(StripKeysTest, PlantKeysGiveEachLinkItsPlant) {
  const std::unique_ptr<Simulation> sim = LoadScenarioSimulation(PaperWith(
      "[plant]\na0_mm_per_V = 0.5\nb1 = 0.03\nlink_b2_s2 = [0.002, 0.003, 0.004]\n"));
  const std::vector<IpmcLinkParams> links = AttachedLinkPlants(sim->data());
  ASSERT_EQ(links.size(), 3u);
  for (int q = 0; q < 3; ++q) {
    EXPECT_EQ(links[q].kind, IpmcModelKind::kG1);
    EXPECT_DOUBLE_EQ(links[q].a0_mm_per_V, 0.5);
    EXPECT_DOUBLE_EQ(links[q].b1, 0.03);
    EXPECT_DOUBLE_EQ(links[q].b2_s2, 0.002 + 0.001 * q);
  }
  const std::unique_ptr<Simulation> g2 =
      LoadScenarioSimulation(PaperWith("[plant]\nmodel = \"g2\"\nalpha = 1.7\n"));
  for (const IpmcLinkParams& link : AttachedLinkPlants(g2->data())) {
    EXPECT_EQ(link.kind, IpmcModelKind::kG2);
    EXPECT_DOUBLE_EQ(link.alpha, 1.7);
  }
}

TEST(StripKeysTest, RmsVoltageFallsAsOneOverA0) {
  // The loop tracks the wave closely at 0.05 Hz (its error is under 1 % of
  // the reference), so the voltage is the reference over the plant's gain:
  // V ~ 1 / a0. a0 at 2.7 and 5.3 times eq. 7's keeps every link off the
  // clamp (at 0.05 Hz, |s^-0.5| is 2.2 times smaller than at 0.01 Hz).
  const std::string run = "cycles = 1\n[waveform]\nfrequency_Hz = 0.05\n";
  const ClosedLoopResult low = SimulateScenario(PaperWith(run + "[plant]\na0_mm_per_V = 1.0\n"));
  const ClosedLoopResult high = SimulateScenario(PaperWith(run + "[plant]\na0_mm_per_V = 2.0\n"));
  for (std::size_t q = 0; q < low.links.size(); ++q) {
    SCOPED_TRACE(q);
    EXPECT_EQ(low.links[q].clamped_fraction, 0.0);
    EXPECT_NEAR(high.links[q].rms_voltage_V / low.links[q].rms_voltage_V, 0.5, 0.01);
  }
}

TEST(StripKeysTest, BadKeysAreOneLineErrorsNamingTheKey) {
  const auto message = [](const std::string& keys) {
    try {
      PaperWith(keys);
    } catch (const InputError& error) {
      EXPECT_EQ(std::string(error.what()).find('\n'), std::string::npos);
      return std::string(error.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("[plant]\nlink_a0_mm_per_V = [0.5, 0.4]\n")
                .find("plant.link_a0_mm_per_V: a0_mm_per_V must hold one value per link (3; got 2)"),
            std::string::npos);
  EXPECT_NE(message("[plant]\nalpha = 1.5\n").find("plant.alpha applies only to model = \"g2\""),
            std::string::npos);
  EXPECT_NE(message("[plant]\nmodel = \"g2\"\nalpha = 2.0\n").find("plant.alpha must be < 2"),
            std::string::npos);
  EXPECT_NE(message("[strip]\nthickness_um = -1.0\n").find("strip.thickness_um must be > 0"),
            std::string::npos);
}

TEST(StripKeysTest, IncludedKeysGiveTheSameScenarioAsTheKeysThemselves) {
  const fs::path dir = testing::FreshDir("strip_keys_include");
  testing::WriteFile(dir / "plant.toml", "[plant]\na0_mm_per_V = 0.45\nb2_s2 = 0.003\n");
  testing::WriteFile(dir / "run.toml", "include = [\"" + Paper() + "\", \"plant.toml\"]\n"
                                       "cycles = 2\n[plant]\nb2_s2 = 0.0025\n");
  const ScenarioConfig included = LoadScenario((dir / "run.toml").string());
  const ScenarioConfig direct = PaperWith("cycles = 2\n[plant]\na0_mm_per_V = 0.45\nb2_s2 = 0.0025\n");
  EXPECT_EQ(ResolvedScenarioToml(included), ResolvedScenarioToml(direct));
  // An error of an included file names that file and its line.
  testing::WriteFile(dir / "bad.toml", "[plant]\n\na0_mm_per_V = 0.0\n");
  testing::WriteFile(dir / "uses_bad.toml", "include = \"bad.toml\"\nmodel = \"" +
                                                (fs::path(IPMC_SWIM_SOURCE_DIR) / "models" /
                                                 "flagellum3.xml").string() + "\"\n");
  try {
    LoadScenario((dir / "uses_bad.toml").string());
    ADD_FAILURE() << "bad.toml was taken";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("bad.toml:3: plant.a0_mm_per_V must be > 0"),
              std::string::npos)
        << error.what();
  }
  testing::WriteFile(dir / "loop.toml", "include = \"loop.toml\"\n");
  EXPECT_THROW(LoadScenario((dir / "loop.toml").string()), InputError);
}

// A model file and keys that generate the flagellum never compete in
// silence: generating keys given with the model or over it win, with a
// note; a model given over them (the including file's over an included
// strip or plant) is refused, naming both.
TEST(StripKeysTest, AModelAndGeneratingKeysNeverCompeteSilently) {
  const fs::path dir = testing::FreshDir("strip_keys_model_competition");
  const std::string model =
      (fs::path(IPMC_SWIM_SOURCE_DIR) / "models" / "flagellum3.xml").string();
  testing::WriteFile(dir / "strip.toml",
                     "link_lengths_mm = [12.0, 12.0]\n[strip]\nwidth_mm = 5.0\n");
  testing::WriteFile(dir / "plant.toml", "[plant]\na0_mm_per_V = 0.45\n");
  // The includer's model over an included strip or plant.
  for (const char* included : {"strip.toml", "plant.toml"}) {
    testing::WriteFile(dir / "run.toml", "include = [\"" + std::string(included) +
                                             "\"]\nmodel = \"" + model + "\"\n");
    try {
      LoadScenario((dir / "run.toml").string());
      ADD_FAILURE() << "the model over " << included << " was taken";
    } catch (const InputError& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find("run.toml:2: model = "), std::string::npos) << message;
      EXPECT_NE(message.find(included), std::string::npos) << message;
      EXPECT_NE(message.find("give one or the other"), std::string::npos) << message;
    }
  }
  // Generating keys over an included model: the generated flagellum, said.
  testing::WriteFile(dir / "over.toml", "include = [\"" + Paper() + "\", \"plant.toml\"]\n");
  const ScenarioConfig over = LoadScenario((dir / "over.toml").string());
  EXPECT_TRUE(over.model.Generated());
  ASSERT_EQ(over.notes.size(), 1u);
  EXPECT_NE(over.notes[0].find("generated from plant.a0_mm_per_V"), std::string::npos)
      << over.notes[0];
  EXPECT_NE(over.notes[0].find("flagellum3.xml"), std::string::npos) << over.notes[0];
  // Both in one file: the generated one wins (docs/SCENARIO_KEYS.md), said.
  const ScenarioConfig same = ParseScenario(
      "model = \"" + model + "\"\nsegments_per_link = 2\n", (dir / "same.toml").string());
  ASSERT_EQ(same.notes.size(), 1u);
  EXPECT_NE(same.notes[0].find("generated from segments_per_link"), std::string::npos)
      << same.notes[0];
  // Without competition, no note.
  EXPECT_TRUE(LoadScenario(Paper()).notes.empty());
}

// optimize over the strip's thickness and a plant's gain: two starts of
// two short evaluations of the generated flagellum at 0.5 Hz.
TEST(StripKeysTest, OptimizeTakesThicknessAndA0) {
  for (const char* key : {"strip.thickness_um", "plant.a0_mm_per_V"}) {
    SCOPED_TRACE(key);
    const bool thickness = std::string(key) == "strip.thickness_um";
    const fs::path dir = testing::FreshDir("strip_keys_optimize");
    testing::WriteFile(dir / "base.toml", testing::OneCycleScenario(0.5));
    testing::WriteFile(
        dir / "opt.toml",
        "base = \"base.toml\"\n[[variable]]\nkey = \"" + std::string(key) + "\"\n" +
            (thickness ? "lower = 150.0\nupper = 350.0\ninitial = 250.0\n"
                       : "lower = 0.3\nupper = 0.6\ninitial = 0.4\n") +
            "[objective]\nmetric = \"last_cycle_com_along_mm\"\nsense = \"maximize\"\n"
            "[algorithm]\nname = \"cobyla\"\nmax_evaluations = 2\nmultistart = 1\n");
    OptimizeCommand command;
    command.file = (dir / "opt.toml").string();
    command.out = (dir / "out").string();
    const OptimizeOutcome outcome = RunOptimizeCommand(PlanOptimizeCommand(command));
    EXPECT_EQ(outcome.evaluations, 4);  // 2 starts (multistart = 1) of 2
    const std::string history = testing::ReadFile(dir / "out" / "history.csv");
    EXPECT_NE(history.find(key), std::string::npos) << history;
  }
}

}  // namespace
}  // namespace ipmc

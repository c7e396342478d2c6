#include "sim/core/generate_command.h"

#include "sim/io/files.h"

namespace ipmc {
namespace {

using G = GenerateCommand;

OptionTable<GenerateCommand> MakeGenerateOptions() {
  OptionTable<GenerateCommand> table("generate", "Write the MJCF of an N-link flagellum");
  OptionInfo links{"link_lengths_mm", "mm", "each > 0", "Link lengths, one per link"};
  links.aliases = {"links_mm"};
  table.Add<std::vector<double>>(links, [](G& s) -> std::vector<double>& { return s.link_lengths_mm; });
  table.Add<int>({"segments_per_link", "", ">= 1", "Rigid sub-segments per link (1: rigid links)"},
                 [](G& s) -> int& { return s.segments_per_link; });
  table.Add<double>({"gap_mm", "mm", ">= 0", "Gap between links"},
                    [](G& s) -> double& { return s.gap_mm; });
  table.Add<double>({"width_mm", "mm", "> 0", "Strip width"},
                    [](G& s) -> double& { return s.width_mm; });
  table.Add<double>({"thickness_um", "um", "> 0", "Strip thickness"},
                    [](G& s) -> double& { return s.thickness_um; });
  OptionInfo head{"head_length_mm", "mm", ">= 0", "Head (clamp) length, 0 for none"};
  head.aliases = {"head_mm"};
  table.Add<double>(head, [](G& s) -> double& { return s.head_length_mm; });
  OptionInfo density{"density_kg_m3", "kg/m^3", "> 0", "Strip density"};
  density.aliases = {"density"};
  table.Add<double>(density, [](G& s) -> double& { return s.density_kg_m3; });
  OptionInfo modulus{"bending_modulus_Pa", "Pa", "> 0", "Bending modulus E"};
  modulus.aliases = {"modulus_pa"};
  table.Add<double>(modulus, [](G& s) -> double& { return s.bending_modulus_Pa; });
  table.Add<double>({"hinge_damping_ratio", "", ">= 0", "Hinge damping ratio zeta_h"},
                    [](G& s) -> double& { return s.hinge_damping_ratio; });
  table.Add<bool>({"clamped", "", "", "Weld the root (test bench)"},
                  [](G& s) -> bool& { return s.clamped; });
  table.Add<double>({"timestep_s", "s", "> 0", "Time step"},
                    [](G& s) -> double& { return s.timestep_s; });
  OptionInfo integrator{"integrator", "", "", "MuJoCo integrator"};
  integrator.allowed = "Euler | implicit | RK4";
  table.Add<std::string>(integrator, [](G& s) -> std::string& { return s.integrator; });
  table.Add<double>({"viscosity_Pa_s", "Pa s", "> 0", "Viscosity"},
                    [](G& s) -> double& { return s.viscosity_Pa_s; });
  OptionInfo coefficients{"coefficients", "", "", "RFT drag coefficients"};
  coefficients.allowed = "gray_hancock | lighthill | direct";
  table.Add<std::string>(coefficients, [](G& s) -> std::string& { return s.coefficients; });
  table.Add<double>({"wavelength_mm", "mm", "> 0", "Wavelength for the RFT coefficients"},
                    [](G& s) -> double& { return s.wavelength_mm; });
  table.Add<double>({"equivalent_radius_mm", "mm", ">= 0",
                     "RFT equivalent radius; 0: (w + h) / 4, Batchelor's flat strip"},
                    [](G& s) -> double& { return s.equivalent_radius_mm; });
  OptionInfo xi_n{"xi_normal_N_s_m2", "N s/m^2", "> 0, only with coefficients direct",
                  "Direct xi_n"};
  xi_n.aliases = {"xi_normal"};
  xi_n.default_text = "none";
  table.Add<double>(xi_n, [](G& s) -> double& { return s.xi_normal_N_s_m2; });
  OptionInfo xi_t{"xi_tangential_N_s_m2", "N s/m^2", "> 0, only with coefficients direct",
                  "Direct xi_t"};
  xi_t.aliases = {"xi_tangential"};
  xi_t.default_text = "none";
  table.Add<double>(xi_t, [](G& s) -> double& { return s.xi_tangential_N_s_m2; });
  table.Add<double>({"fluid_density_kg_m3", "kg/m^3", "> 0", "Fluid density"},
                    [](G& s) -> double& { return s.fluid_density_kg_m3; });
  table.Add<bool>({"ipmc_actuators", "", "", "IPMC actuators on every link (Table 2)"},
                  [](G& s) -> bool& { return s.ipmc_actuators; });
  OptionInfo plants{"plants", "", "",
                    "uniform (every link eq. 7's plant) | table2 (Table 2's row per link)"};
  plants.allowed = "uniform | table2";
  table.Add<std::string>(plants, [](G& s) -> std::string& { return s.plants; });
  OptionInfo model{"ipmc_model", "", "", "IPMC link model: g1 (eq. 5) | g2 (eq. 6)"};
  model.allowed = "g1 | g2";
  table.Add<std::string>(model, [](G& s) -> std::string& { return s.ipmc_model; });
  const auto plant = [&table](const char* name, const char* unit, const char* meaning,
                              std::vector<double> G::*field) {
    OptionInfo info{name, unit, "one value per link", meaning};
    info.default_text = "none: the assigned plant's";
    table.Add<std::vector<double>>(info, [field](G& s) -> std::vector<double>& { return s.*field; });
  };
  plant("a0_mm_per_V", "mm/V", "Each link's static gain a0 of G, over the assigned plant's",
        &G::a0_mm_per_V);
  plant("b1", "s or s^alpha", "Each link's b1 of G", &G::b1);
  plant("b2_s2", "s^2", "Each link's b2 of G1", &G::b2_s2);
  plant("alpha", "", "Each link's order alpha of G2", &G::alpha);
  OptionInfo actuation{"actuation", "", "", "distributed | single"};
  actuation.allowed = "distributed | single";
  table.Add<std::string>(actuation, [](G& s) -> std::string& { return s.actuation; });
  table.Add<std::string>({"name", "", "", "Model name"},
                         [](G& s) -> std::string& { return s.name; });
  OptionInfo out{"out", "", "a file", "Output MJCF file (command line default: stdout)"};
  out.aliases = {"o"};
  table.AddPath(out, [](G& s) -> std::string& { return s.out; });
  return table;
}

}  // namespace

const OptionTable<GenerateCommand>& GenerateOptions() {
  static const OptionTable<GenerateCommand> table = MakeGenerateOptions();
  return table;
}

std::string RunGenerateCommand(const GenerateCommand& command) {
  if (!command.out.empty()) RequireWritableParent(command.out);  // a file, where it can be
  const std::string xml = GenerateFlagellumMjcf(command);
  if (!command.out.empty()) WriteFileAtomically(command.out, xml);
  return xml;
}

}  // namespace ipmc

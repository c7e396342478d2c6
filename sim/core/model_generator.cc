#include "sim/core/model_generator.h"

#include <algorithm>
#include <cctype>

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "ipmc_swim/fields.h"
#include "sim/linear/ipmc_link_model.h"
#include "sim/base/error.h"
#include "sim/base/numbers.h"

namespace ipmc {
namespace {

constexpr double kMmToM = 1e-3;
constexpr double kUmToM = 1e-6;

void RequirePositive(double value, const char* field) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    std::ostringstream msg;
    msg << "flagellum spec: " << field << " must be finite and > 0 (got " << value << ")";
    throw FieldError(msg.str(), field, "finite and > 0");
  }
}

void RequireNonNegative(double value, const char* field) {
  if (!(value >= 0.0) || !std::isfinite(value)) {
    std::ostringstream msg;
    msg << "flagellum spec: " << field << " must be finite and >= 0 (got " << value << ")";
    throw FieldError(msg.str(), field, "finite and >= 0");
  }
}

// Numbers in the MJCF: 10 significant digits.
std::string Num(double value) { return FormatDouble(value, 10); }

double EquivalentRadius_m(const FlagellumSpec& spec) {
  if (spec.equivalent_radius_mm > 0.0) return spec.equivalent_radius_mm * kMmToM;
  // Batchelor (1970): a slender body of elliptical section with semi-axes
  // a, b has the resistance of a circular one of radius (a + b) / 2; a flat
  // strip w x h is taken as the ellipse a = w/2, b = h/2.
  return 0.25 * (spec.width_mm * kMmToM + spec.thickness_um * kUmToM);
}

// Where link q's root hinge sits in the gap before it, from the gap's
// start [m]: at its middle for rigid links (the paper's joints), at the
// strip's root for flexible ones, whose root hinge carries the strip's
// curvature next to the root (elsewhere it would shift the rest of the
// body by that angle times the offset, an error of first order in l).
double HingeInGap_m(const FlagellumSpec& spec) {
  return (spec.segments_per_link == 1 ? 0.5 : 1.0) * spec.gap_mm * kMmToM;
}

// Local x offset of link q's geometry from its hinge [m].
double LinkStartOffset_m(const FlagellumSpec& spec, int q) {
  return q == 0 ? 0.0 : spec.gap_mm * kMmToM - HingeInGap_m(spec);
}

void WriteCustomFields(const FlagellumSpec& spec, std::ostringstream& xml) {
  // Field names as the plugin reads them.
  const auto numeric = [&xml](const char* name, const std::string& data) {
    xml << "    <numeric name=\"" << name << "\" data=\"" << data << "\"/>\n";
  };
  const auto text = [&xml](const char* name, const std::string& data) {
    xml << "    <text name=\"" << name << "\" data=\"" << data << "\"/>\n";
  };
  xml << "  <custom>\n";
  numeric(kAttrViscosity, Num(spec.viscosity_Pa_s));
  text(kAttrCoefficients, spec.coefficients);
  numeric(kAttrEquivalentRadius, Num(EquivalentRadius_m(spec)));
  numeric(kAttrWavelength, Num(spec.wavelength_mm * kMmToM));
  numeric(kAttrFluidDensity, Num(spec.fluid_density_kg_m3));
  if (spec.coefficients == "direct") {
    numeric(kAttrXiNormal, Num(spec.xi_normal_N_s_m2));
    numeric(kAttrXiTangential, Num(spec.xi_tangential_N_s_m2));
  }
  numeric(kStripWidthField, Num(spec.width_mm * kMmToM));
  if (spec.ipmc_actuators) {  // with a head or a clamp (Validate)
    std::string links;
    for (int q = 1; q <= spec.Links(); ++q) links += (q > 1 ? " j" : "j") + std::to_string(q);
    text(kAttrLinks, links);
    if (spec.segments_per_link > 1) numeric(kAttrSegments, std::to_string(spec.segments_per_link));
    text(kAttrPlants, spec.plants);
    text(kAttrModel, spec.ipmc_model);
    text(kAttrActuation, spec.actuation);
    const std::pair<const char*, const std::vector<double>*> plant[] = {
        {kAttrA0, &spec.a0_mm_per_V}, {kAttrB1, &spec.b1}, {kAttrB2, &spec.b2_s2},
        {kAttrAlpha, &spec.alpha}};
    for (const auto& [name, values] : plant) {
      std::string data;
      for (double value : *values) data += (data.empty() ? "" : " ") + Num(value);
      if (!data.empty()) numeric(name, data);
    }
  }
  xml << "  </custom>\n";
}

void WriteRootJoints(std::ostringstream& xml, const std::string& indent) {
  xml << indent << "<joint name=\"root_x\" type=\"slide\" axis=\"1 0 0\"/>\n"
      << indent << "<joint name=\"root_y\" type=\"slide\" axis=\"0 1 0\"/>\n"
      << indent << "<joint name=\"root_yaw\" type=\"hinge\" axis=\"0 0 1\"/>\n";
}

}  // namespace

void FlagellumSpec::Validate() const {
  if (link_lengths_mm.empty()) {
    throw FieldError("flagellum spec: link_lengths_mm must list at least one link",
                     "link_lengths_mm", "1 to " + std::to_string(kMaxGeneratedLinks) + " links");
  }
  for (double length : link_lengths_mm) RequirePositive(length, "link_lengths_mm");
  if (link_lengths_mm.size() > kMaxGeneratedLinks) {
    throw FieldError("flagellum spec: link_lengths_mm must list at most " +
                         std::to_string(kMaxGeneratedLinks) + " links (got " +
                         std::to_string(link_lengths_mm.size()) + ")",
                     "link_lengths_mm", "1 to " + std::to_string(kMaxGeneratedLinks) + " links");
  }
  for (char c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-' && c != '.') {
      throw FieldError("flagellum spec: name must hold only letters, digits, '_', "
                       "'-' and '.' (got '" + name + "')",
                       "name", "letters, digits, '_', '-' and '.'");
    }
  }
  RequireNonNegative(gap_mm, "gap_mm");
  RequirePositive(width_mm, "width_mm");
  RequirePositive(thickness_um, "thickness_um");
  RequireNonNegative(head_length_mm, "head_length_mm");
  RequirePositive(density_kg_m3, "density_kg_m3");
  RequireNonNegative(bending_modulus_Pa, "bending_modulus_Pa");
  RequireNonNegative(hinge_damping_ratio, "hinge_damping_ratio");
  RequirePositive(timestep_s, "timestep_s");
  if (integrator != "Euler" && integrator != "implicit" && integrator != "RK4") {
    throw FieldError("flagellum spec: integrator must be Euler, implicit or RK4 (got '" +
                         integrator + "')",
                     "integrator", "Euler, implicit or RK4");
  }
  RequirePositive(viscosity_Pa_s, "viscosity_Pa_s");
  if (coefficients != "gray_hancock" && coefficients != "lighthill" && coefficients != "direct") {
    throw FieldError(
        "flagellum spec: coefficients must be gray_hancock, lighthill or direct (got '" +
            coefficients + "')",
        "coefficients", "gray_hancock, lighthill or direct");
  }
  RequirePositive(wavelength_mm, "wavelength_mm");
  RequireNonNegative(equivalent_radius_mm, "equivalent_radius_mm");
  if (coefficients == "direct") {
    RequirePositive(xi_normal_N_s_m2, "xi_normal_N_s_m2");
    RequirePositive(xi_tangential_N_s_m2, "xi_tangential_N_s_m2");
  }
  RequireNonNegative(fluid_density_kg_m3, "fluid_density_kg_m3");
  if (segments_per_link < 1 || segments_per_link > kMaxSegmentsPerLink) {
    throw FieldError("flagellum spec: segments_per_link must be in [1, " +
                         std::to_string(kMaxSegmentsPerLink) + "] (got " +
                         std::to_string(segments_per_link) + ")",
                     "segments_per_link", "[1, " + std::to_string(kMaxSegmentsPerLink) + "]");
  }
  const bool head = head_length_mm > 0.0;
  if (segments_per_link > MaxSegmentsPerLink(Links(), head)) {
    throw FieldError(
        "flagellum spec: segments_per_link must be <= " +
            std::to_string(MaxSegmentsPerLink(Links(), head)) + " for " +
            std::to_string(Links()) + " links" + (head ? " and a head" : "") + " (got " +
            std::to_string(segments_per_link) + "): MuJoCo 2.2 reads at most " +
            std::to_string(kMaxNestedBodies) + " nested bodies",
        "segments_per_link", "[1, " + std::to_string(MaxSegmentsPerLink(Links(), head)) + "]");
  }
  if (!ParsePlantAssignment(plants)) {
    throw FieldError("flagellum spec: plants must be uniform or table2 (got '" + plants + "')",
                     "plants", "uniform or table2");
  }
  const std::pair<const char*, const std::vector<double>*> plant[] = {
      {"a0_mm_per_V", &a0_mm_per_V}, {"b1", &b1}, {"b2_s2", &b2_s2}, {"alpha", &alpha}};
  for (const auto& [field, values] : plant) {
    if (!values->empty() && values->size() != link_lengths_mm.size()) {
      throw FieldError("flagellum spec: " + std::string(field) + " must hold one value per link (" +
                           std::to_string(Links()) + "; got " + std::to_string(values->size()) +
                           ")",
                       field, "one value per link");
    }
  }
  if (ipmc_model != "g1" && ipmc_model != "g2") {
    throw FieldError("flagellum spec: ipmc_model must be g1 or g2 (got '" + ipmc_model + "')",
                     "ipmc_model", "g1 or g2");
  }
  if (actuation != "distributed" && actuation != "single") {
    throw FieldError(
        "flagellum spec: actuation must be distributed or single (got '" + actuation + "')",
        "actuation", "distributed or single");
  }
  if (ipmc_actuators && head_length_mm == 0.0 && !clamped) {
    // Link q's IPMC drives the hinge at its root; without a head or a
    // clamp, link 1 is the free root and has none.
    throw FieldError("flagellum spec: head_length_mm = 0 leaves link 1 no hinge for its IPMC "
                     "actuator: give a head (head_length_mm > 0), clamp the chain (clamped), "
                     "or set ipmc_actuators false for a passive chain",
                     "head_length_mm", "> 0 with ipmc_actuators and not clamped");
  }
  if (clamped && head_length_mm == 0.0 && Links() < 1) {
    throw FieldError("flagellum spec: a clamped model needs at least one link", "link_lengths_mm",
                     "at least one link when clamped");
  }
  // The drag the loader makes of the written fields must accept them: the
  // wavelength must be long against the equivalent radius.
  if (coefficients != "direct") {
    const double radius_m = EquivalentRadius_m(*this);
    try {
      CheckRftSegment(coefficients == "lighthill" ? "lighthill" : "gray_hancock", radius_m,
                      wavelength_mm * kMmToM);
    } catch (const std::invalid_argument& error) {
      throw FieldError("flagellum spec: wavelength_mm = " + FormatShortest(wavelength_mm) +
                           " is too short for the equivalent radius " +
                           FormatShortest(radius_m / kMmToM) + " mm (" + error.what() + ")",
                       "wavelength_mm", "long against the equivalent radius");
    }
  }
}

int MaxSegmentsPerLink(int links, bool head) {
  return links < 1 ? kMaxSegmentsPerLink
                   : std::min(kMaxSegmentsPerLink, (kMaxNestedBodies - (head ? 1 : 0)) / links);
}

SegmentMechanics ComputeSegmentMechanics(const FlagellumSpec& spec, int q, int segment) {
  // n >= 2: n - 1 sub-segments of l = L / (n - 1/2) and a last one of
  // l / 2, so that every hinge sits at the middle of its share of the
  // strip and the shares l / 2, l, ..., l add up to L.
  const int n = spec.segments_per_link;
  const double full_m = spec.link_lengths_mm.at(q) * kMmToM / (n == 1 ? 1.0 : n - 0.5);
  const double length_m = n > 1 && segment == n - 1 ? 0.5 * full_m : full_m;
  const double width_m = spec.width_mm * kMmToM;
  const double thickness_m = spec.thickness_um * kUmToM;
  SegmentMechanics mech{};
  mech.length_m = length_m;
  mech.mass_kg = spec.density_kg_m3 * length_m * width_m * thickness_m;
  mech.inertia_about_hinge_kg_m2 = mech.mass_kg * length_m * length_m / 3.0;
  mech.hinge_share_m = segment == 0 ? 0.5 * full_m : full_m;
  const double second_moment_m4 = width_m * thickness_m * thickness_m * thickness_m / 12.0;
  mech.stiffness_N_m_rad = spec.bending_modulus_Pa * second_moment_m4 / mech.hinge_share_m;
  mech.damping_N_m_s_rad = 2.0 * spec.hinge_damping_ratio *
                           std::sqrt(mech.stiffness_N_m_rad * mech.inertia_about_hinge_kg_m2);
  return mech;
}

// Names of link q's (0-based) sub-segment s: "link2", "link2_2", ...; its
// hinge "j2", "j2_2", ...
std::string SegmentSuffix(int q, int s) {
  return std::to_string(q + 1) + (s == 0 ? "" : "_" + std::to_string(s + 1));
}

std::string GenerateFlagellumMjcf(const FlagellumSpec& spec) {
  spec.Validate();
  const double half_width_m = 0.5 * spec.width_mm * kMmToM;
  const double half_thickness_m = 0.5 * spec.thickness_um * kUmToM;
  const bool has_head = spec.head_length_mm > 0.0;
  const int links = spec.Links();

  std::ostringstream xml;
  xml << "<mujoco model=\"" << spec.name << "\">\n"
      << "  <!-- Generated by ipmc-swim. SI units: m, kg, s, N m. -->\n"
      << "  <compiler angle=\"radian\" inertiafromgeom=\"true\"/>\n"
      << "  <option timestep=\"" << Num(spec.timestep_s) << "\" integrator=\"" << spec.integrator
      << "\" gravity=\"0 0 0\">\n"
      << "    <flag contact=\"disable\"/>\n"
      << "  </option>\n"
      << "  <visual><global offwidth=\"1280\" offheight=\"720\"/></visual>\n";
  WriteCustomFields(spec, xml);
  xml << "  <worldbody>\n"
      << "    <light name=\"top\" pos=\"0.015 0 0.2\" dir=\"0 0 -1\" directional=\"true\"/>\n";

  std::string indent = "    ";
  int open_bodies = 0;
  if (has_head) {
    const double head_m = spec.head_length_mm * kMmToM;
    xml << indent << "<body name=\"head\" pos=\"0 0 0\">\n";
    indent += "  ";
    ++open_bodies;
    if (!spec.clamped) WriteRootJoints(xml, indent);
    xml << indent << "<geom name=\"head\" type=\"box\" pos=\"" << Num(-0.5 * head_m)
        << " 0 0\" size=\"" << Num(0.5 * head_m) << " " << Num(half_thickness_m) << " "
        << Num(half_width_m) << "\" density=\"" << Num(spec.density_kg_m3)
        << "\" rgba=\"0.35 0.35 0.4 1\"/>\n"
        << indent << "<site name=\"head_tip\" pos=\"" << Num(-head_m) << " 0 0\" size=\"0.0003\"/>\n";
  }
  double body_pos_m = 0.0;
  for (int q = 0; q < links; ++q) {
    const std::string n = std::to_string(q + 1);
    for (int seg = 0; seg < spec.segments_per_link; ++seg) {
      const SegmentMechanics mech = ComputeSegmentMechanics(spec, q, seg);
      const double start_m = seg == 0 ? LinkStartOffset_m(spec, q) : 0.0;
      const std::string suffix = SegmentSuffix(q, seg);
      xml << indent << "<body name=\"link" << suffix << "\" pos=\"" << Num(body_pos_m)
          << " 0 0\">\n";
      indent += "  ";
      ++open_bodies;
      const bool is_free_root = (q == 0 && seg == 0 && !has_head && !spec.clamped);
      if (is_free_root) {
        WriteRootJoints(xml, indent);
      } else {
        xml << indent << "<joint name=\"j" << suffix
            << "\" type=\"hinge\" axis=\"0 0 1\" stiffness=\"" << Num(mech.stiffness_N_m_rad)
            << "\" damping=\"" << Num(mech.damping_N_m_s_rad) << "\"/>\n";
      }
      xml << indent << "<geom name=\"link" << suffix << "\" type=\"box\" pos=\""
          << Num(start_m + 0.5 * mech.length_m) << " 0 0\" size=\"" << Num(0.5 * mech.length_m)
          << " " << Num(half_thickness_m) << " " << Num(half_width_m) << "\" density=\""
          << Num(spec.density_kg_m3) << "\" rgba=\"0.15 0.45 0.8 1\"/>\n";
      body_pos_m = start_m + mech.length_m;
    }
    xml << indent << "<site name=\"tip" << n << "\" pos=\"" << Num(body_pos_m)
        << " 0 0\" size=\"0.0003\"/>\n";
    body_pos_m += HingeInGap_m(spec);
  }
  for (; open_bodies > 0; --open_bodies) {
    indent.resize(indent.size() - 2);
    xml << indent << "</body>\n";
  }
  xml << "  </worldbody>\n";

  // Hinges that can be driven: every link with a hinge of its own (its root
  // hinge, then its interior hinges).
  std::vector<std::string> root_hinges, hinges;
  for (int q = 0; q < links; ++q) {
    for (int seg = 0; seg < spec.segments_per_link; ++seg) {
      if (q == 0 && seg == 0 && !has_head && !spec.clamped) continue;
      hinges.push_back("j" + SegmentSuffix(q, seg));
      if (seg == 0) root_hinges.push_back(hinges.back());
    }
  }
  xml << "  <actuator>\n";
  for (const std::string& joint : hinges) {
    // Active IPMC moment k theta0 [N m] (plugin/actuators/ipmc_actuators.h).
    xml << "    <motor name=\"" << IpmcMotorName(joint) << "\" joint=\"" << joint << "\" gear=\"1\"/>\n";
  }
  for (const std::string& joint : root_hinges) {
    // Prescribed-gait servo; its gains are set at run time (sim/core/gait.h).
    xml << "    <general name=\"servo_" << joint << "\" joint=\"" << joint
        << "\" gaintype=\"fixed\" biastype=\"affine\" gainprm=\"0\" biasprm=\"0 0 0\"/>\n";
  }
  xml << "  </actuator>\n  <sensor>\n";
  for (const std::string& joint : hinges) {
    xml << "    <jointpos name=\"angle_" << joint << "\" joint=\"" << joint << "\"/>\n";
  }
  for (int q = 0; q < links; ++q) {
    const std::string n = std::to_string(q + 1);
    xml << "    <framepos name=\"tip" << n << "_pos\" objtype=\"site\" objname=\"tip" << n
        << "\"/>\n";
  }
  xml << "  </sensor>\n</mujoco>\n";
  return xml.str();
}

}  // namespace ipmc

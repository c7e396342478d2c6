// Drag on the geometry a model declares (plugin/fluid/rft_drag.h,
// geom_resistance.h): a sphere, prolate and oblate ellipsoids, a capsule
// and a box towed and turned through RFT match their analytic drags;
// tapered links drag as their widths say; a geom the fluid cannot
// represent is refused by name; MuJoCo's own fluid beside the library's is
// refused; a chain built along y swims as the same chain along x turned by
// 90 degrees, in both dynamics.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <sstream>
#include <string>

#include "ipmc_swim/ipmc_swim.h"
#include "sim/base/numbers.h"
#include "sim/core/model_generator.h"
#include "sim/core/simulation.h"
#include "tests/oberbeck_drag.h"
#include "tests/test_util.h"

namespace ipmc::testing {
namespace {

constexpr double kMu = 1e-3;  // [Pa s]

// One free body at the origin carrying `geoms`, in a fluid of viscosity kMu;
// `custom` adds <custom> fields.
std::string FreeBody(const std::string& geoms, const std::string& custom = "") {
  return "<mujoco><custom><numeric name=\"ipmc_rft_viscosity_Pa_s\" data=\"0.001\"/>" + custom +
         "</custom><worldbody><body name=\"b\"><freejoint/>" + geoms +
         "</body></worldbody></mujoco>";
}

// The wrench [force; torque about the body's origin, body = world axes]
// the model's RFT drag puts on its free body moving with [v; w]: minus the
// drag matrix the coupling applies (ipmc::DragMatrix) times [v; w].
Eigen::Matrix<double, 6, 1> Drag(const mjModel* m, const Eigen::Vector3d& v,
                                 const Eigen::Vector3d& w) {
  Simulation sim(ModelPtr(mj_copyModel(nullptr, m)), "free body");
  const std::vector<double> drag = DragMatrix(sim.model(), sim.data());
  Eigen::Matrix<double, 6, 1> velocity;
  velocity << v, w;
  return -Eigen::Map<const Eigen::Matrix<double, 6, 6, Eigen::RowMajor>>(drag.data()) * velocity;
}

// Attaches the coupling to a new mjData of m and detaches it; throws as
// Attach does.
void AttachOnce(const mjModel* m) {
  const DataPtr data(mj_makeData(m));
  Attach(m, data.get());
  Detach(data.get());
}

const Eigen::Vector3d kZero = Eigen::Vector3d::Zero();

// Gray & Hancock's coefficients (1955) [N s/m^2] of a segment of radius a
// in a wave of length lambda, in a fluid of viscosity mu:
//   xi_n = 4 pi mu / (ln(2 lambda / a) + 1/2),  xi_t = 2 pi mu / (ln(2 lambda / a) - 1/2).
struct DragCoefficients {
  double normal_N_s_m2, tangential_N_s_m2;
};
DragCoefficients GrayHancockCoefficients(double mu, double radius_m, double wavelength_m) {
  const double log_term = std::log(2 * wavelength_m / radius_m);
  return {4 * kPi * mu / (log_term + 0.5), 2 * kPi * mu / (log_term - 0.5)};
}

TEST(GeomDragTest, SphereHasStokesDrag) {
  // Stokes (1851): F = -6 pi mu a U, T = -8 pi mu a^3 Omega.
  const double a = 1.5e-3;
  const ModelPtr m = LoadModelString(FreeBody("<geom type=\"sphere\" size=\"0.0015\"/>"));
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d e = Eigen::Vector3d::Unit(i);
    const auto towed = Drag(m.get(), 1e-3 * e, kZero);
    EXPECT_NEAR(towed[i] / (-6 * kPi * kMu * a * 1e-3), 1.0, 1e-12);
    EXPECT_NEAR(towed.norm(), std::abs(towed[i]), 1e-20);
    const auto turned = Drag(m.get(), kZero, 2.0 * e);
    EXPECT_NEAR(turned[3 + i] / (-8 * kPi * kMu * a * a * a * 2.0), 1.0, 1e-12);
  }
}

TEST(GeomDragTest, ProlateAndOblateEllipsoidsHaveOberbecksDrag) {
  // Prolate spheroid of semi-axes (3, 1, 1) mm along x, closed forms (Chwang
  // & Wu, J. Fluid Mech. 67, 787, 1975; e the eccentricity, L = ln((1+e)/(1-e))):
  //   along the axis  F = 16 pi mu a e^3 U / ((1 + e^2) L - 2 e),
  //   across it       F = 32 pi mu a e^3 U / (2 e + (3 e^2 - 1) L).
  const double a = 3e-3, e = std::sqrt(1.0 - 1.0 / 9.0);
  const double log_term = std::log((1 + e) / (1 - e));
  const ModelPtr prolate =
      LoadModelString(FreeBody("<geom type=\"ellipsoid\" size=\"0.003 0.001 0.001\"/>"));
  const double along = 16 * kPi * kMu * a * e * e * e / ((1 + e * e) * log_term - 2 * e);
  const double across = 32 * kPi * kMu * a * e * e * e / (2 * e + (3 * e * e - 1) * log_term);
  EXPECT_NEAR(-Drag(prolate.get(), Eigen::Vector3d(1, 0, 0), kZero)[0] / along, 1.0, 1e-12);
  EXPECT_NEAR(-Drag(prolate.get(), Eigen::Vector3d(0, 0, 1), kZero)[2] / across, 1.0, 1e-12);
  // Both ellipsoids, every axis, against Oberbeck's integrals by quadrature
  // (tests/oberbeck_drag.h), turned too.
  for (const Eigen::Vector3d& semi_axes :
       {Eigen::Vector3d(3e-3, 1e-3, 1e-3), Eigen::Vector3d(3e-3, 3e-3, 1e-3)}) {
    std::ostringstream geom;
    geom << "<geom type=\"ellipsoid\" size=\"" << semi_axes[0] << " " << semi_axes[1] << " "
         << semi_axes[2] << "\"/>";
    const ModelPtr m = LoadModelString(FreeBody(geom.str()));
    const OberbeckEllipsoid exact(semi_axes, kMu);
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d unit = Eigen::Vector3d::Unit(i);
      EXPECT_NEAR(-Drag(m.get(), unit, kZero)[i] / exact.Drag_N_s_m(i), 1.0, 1e-9);
      EXPECT_NEAR(-Drag(m.get(), kZero, unit)[3 + i] / exact.RotationalDrag_N_m_s(i), 1.0, 1e-9);
    }
  }
  // A flat oblate ellipsoid tends to the disk of radius a: 16 mu a U
  // broadside and 32/3 mu a U edgewise (Kim & Karrila 1991, sec. 3.3),
  // within O(c/a) = 1e-4 here.
  const ModelPtr disk =
      LoadModelString(FreeBody("<geom type=\"ellipsoid\" size=\"0.003 0.003 3e-7\"/>"));
  EXPECT_NEAR(-Drag(disk.get(), Eigen::Vector3d(0, 0, 1), kZero)[2] / (16 * kMu * a), 1.0, 1e-3);
  EXPECT_NEAR(-Drag(disk.get(), Eigen::Vector3d(1, 0, 0), kZero)[0] / (32.0 / 3 * kMu * a), 1.0,
              1e-3);
}

TEST(GeomDragTest, CapsuleTakesItsOwnRadius) {
  // Gray & Hancock's coefficients (lambda = 32 mm, the default) from the
  // capsule's own radius 0.4 mm; length 2 size[1] = 10 mm.
  const ModelPtr m =
      LoadModelString(FreeBody("<geom type=\"capsule\" size=\"0.0004 0.005\"/>"));
  const DragCoefficients xi = GrayHancockCoefficients(kMu, 0.4e-3, 32e-3);
  EXPECT_NEAR(-Drag(m.get(), Eigen::Vector3d(0, 0, 1), kZero)[2] / (xi.tangential_N_s_m2 * 1e-2),
              1.0, 1e-12);
  EXPECT_NEAR(-Drag(m.get(), Eigen::Vector3d(1, 0, 0), kZero)[0] / (xi.normal_N_s_m2 * 1e-2),
              1.0, 1e-12);
  // The model's global radius, where it sets one, is every segment's.
  const ModelPtr global = LoadModelString(
      FreeBody("<geom type=\"capsule\" size=\"0.0004 0.005\"/>",
               "<numeric name=\"ipmc_rft_equivalent_radius_m\" data=\"0.0008125\"/>"));
  const DragCoefficients paper = GrayHancockCoefficients(kMu, 0.8125e-3, 32e-3);
  EXPECT_NEAR(-Drag(global.get(), Eigen::Vector3d(0, 0, 1), kZero)[2] /
                  (paper.tangential_N_s_m2 * 1e-2),
              1.0, 1e-12);
}

TEST(GeomDragTest, BoxIsARibbonOfItsWidthAlongItsLongestSide) {
  // 10 mm x 3 mm x 0.25 mm, built along x and along y: a = (w + h) / 4 =
  // 0.8125 mm (Batchelor 1970), the axis the longest side.
  const DragCoefficients xi = GrayHancockCoefficients(kMu, 0.8125e-3, 32e-3);
  const ModelPtr along_x =
      LoadModelString(FreeBody("<geom type=\"box\" size=\"0.005 0.000125 0.0015\"/>"));
  const ModelPtr along_y =
      LoadModelString(FreeBody("<geom type=\"box\" size=\"0.0015 0.005 0.000125\"/>"));
  EXPECT_NEAR(-Drag(along_x.get(), Eigen::Vector3d(1, 0, 0), kZero)[0] /
                  (xi.tangential_N_s_m2 * 1e-2), 1.0, 1e-12);
  EXPECT_NEAR(-Drag(along_y.get(), Eigen::Vector3d(0, 1, 0), kZero)[1] /
                  (xi.tangential_N_s_m2 * 1e-2), 1.0, 1e-12);
  EXPECT_NEAR(-Drag(along_y.get(), Eigen::Vector3d(1, 0, 0), kZero)[0] /
                  (xi.normal_N_s_m2 * 1e-2), 1.0, 1e-12);
  // A cube has no axis: refused by name.
  const ModelPtr cube = LoadModelString(FreeBody("<geom name=\"cube\" type=\"box\" size=\"0.001 0.001 0.001\"/>"));
  ExpectInvalidArgument([&] { AttachOnce(cube.get()); },
                        "geom 'cube' is a box centred on its body with two equal longest sides");
}

TEST(GeomDragTest, TaperedLinksDragAsTheirWidthsSay) {
  // Four 8 mm links 3, 2.5, 2 and 1.5 mm wide, 0.25 mm thick, along x: the
  // axial drag is the sum of each link's xi_t(a_k) L_k, a_k = (w_k + h) / 4.
  std::ostringstream geoms;
  const double widths_mm[] = {3.0, 2.5, 2.0, 1.5};
  double expected_N = 0.0;
  for (int k = 0; k < 4; ++k) {
    geoms << "<geom type=\"box\" pos=\"" << (4e-3 + 8e-3 * k) << " 0 0\" size=\"0.004 0.000125 "
          << widths_mm[k] * 0.5e-3 << "\"/>";
    const double radius_m = (widths_mm[k] + 0.25) * 1e-3 / 4;
    expected_N += GrayHancockCoefficients(kMu, radius_m, 32e-3).tangential_N_s_m2 * 8e-3 * 1e-3;
  }
  const ModelPtr m = LoadModelString(FreeBody(geoms.str()));
  EXPECT_NEAR(-Drag(m.get(), Eigen::Vector3d(1e-3, 0, 0), kZero)[0] / expected_N, 1.0, 1e-12);
  // And not as four 3 mm links: the taper lowers the drag.
  const DragCoefficients widest = GrayHancockCoefficients(kMu, 3.25e-3 / 4, 32e-3);
  EXPECT_LT(expected_N, 0.97 * widest.tangential_N_s_m2 * 32e-3 * 1e-3);
}

TEST(GeomDragTest, GeomsTheFluidCannotRepresentAreRefusedByName) {
  const ModelPtr plane = LoadModelString(
      "<mujoco><custom><numeric name=\"ipmc_rft_viscosity_Pa_s\" data=\"0.001\"/>"
      "<text name=\"ipmc_rft_geoms\" data=\"fin\"/></custom><worldbody>"
      "<geom name=\"fin\" type=\"plane\" size=\"1 1 1\"/>"
      "<body><freejoint/><geom type=\"box\" size=\"0.005 0.0001 0.001\"/></body>"
      "</worldbody></mujoco>");
  ExpectInvalidArgument([&] { AttachOnce(plane.get()); },
                        "geom 'fin' is a plane");
  // A sphere near a wall: its drag there is not the free-space one.
  const ModelPtr wall = LoadModelString(FreeBody(
      "<geom name=\"head\" type=\"sphere\" size=\"0.001\"/>",
      "<numeric name=\"ipmc_rft_equivalent_radius_m\" data=\"0.0008125\"/>"
      "<text name=\"ipmc_rft_coefficients\" data=\"near_wall\"/>"
      "<numeric name=\"ipmc_rft_wall_distance_m\" data=\"0.002\"/>"));
  ExpectInvalidArgument([&] { AttachOnce(wall.get()); },
                        "geom 'head' is a sphere");
  // The dense models do not represent a head.
  const ModelPtr head = LoadModelString(FreeBody(
      "<geom name=\"head\" type=\"sphere\" size=\"0.001\"/>"
      "<geom name=\"tail\" type=\"capsule\" fromto=\"0.001 0 0 0.02 0 0\" size=\"0.0002\"/>",
      "<text name=\"ipmc_fluid_model\" data=\"stokeslets\"/>"));
  ExpectInvalidArgument([&] { AttachOnce(head.get()); },
                        "fluid model stokeslets: geom 'head' is a sphere");
}

TEST(GeomDragTest, MujocosOwnFluidBesideTheLibrarysIsRefused) {
  const std::string body = "<body><freejoint/><geom type=\"box\" size=\"0.005 0.0001 0.001\"/>"
                           "</body>";
  const ModelPtr m = LoadModelString(
      "<mujoco><option viscosity=\"0.001\"/><custom>"
      "<numeric name=\"ipmc_rft_viscosity_Pa_s\" data=\"0.001\"/></custom><worldbody>" + body +
      "</worldbody></mujoco>");
  mjData* d = mj_makeData(m.get());
  ExpectInvalidArgument([&] { ipmc::Attach(m.get(), d); },
                        "turns on MuJoCo's own fluid forces");
  mj_deleteData(d);
}

// The generated two-link swimmer turned by +90 degrees about z: every
// position (x, y, z) becomes (-y, x, z), a box's sides along x and y swap,
// the slides along x and y become slides along y and -x.
std::string TurnedAlongY(const std::string& xml) {
  std::string turned;
  const std::regex triple("(pos|size)=\"([-0-9.e]+) ([-0-9.e]+) ([-0-9.e]+)\"");
  std::sregex_iterator it(xml.begin(), xml.end(), triple), end;
  size_t last = 0;
  for (; it != end; ++it) {
    const std::smatch& match = *it;
    turned += xml.substr(last, match.position() - last);
    const std::string x = match[2], y = match[3], z = match[4];
    if (match[1] == "pos") {
      const std::string minus_y = y[0] == '-' ? y.substr(1) : (y == "0" ? y : "-" + y);
      turned += "pos=\"" + minus_y + " " + x + " " + z + "\"";
    } else {
      turned += "size=\"" + y + " " + x + " " + z + "\"";
    }
    last = match.position() + match.length();
  }
  turned += xml.substr(last);
  turned = std::regex_replace(turned, std::regex("axis=\"1 0 0\""), "axis=\"0 1 0 X\"");
  turned = std::regex_replace(turned, std::regex("axis=\"0 1 0\""), "axis=\"-1 0 0\"");
  return std::regex_replace(turned, std::regex("axis=\"0 1 0 X\""), "axis=\"0 1 0\"");
}

// The head's position (x, y) [m] after `steps` steps of the links driven
// by travelling sine voltages.
Eigen::Vector2d SwimHead(const std::string& xml, int steps) {
  const ModelPtr m = LoadModelString(xml);
  m->nuserdata = ipmc::UserdataSize(m.get());
  mjData* d = mj_makeData(m.get());
  EXPECT_TRUE(ipmc::Attach(m.get(), d));
  for (int step = 0; step < steps; ++step) {
    const double phase = kTwoPi * 5.0 * d->time;  // 5 Hz
    const double voltage_V[2] = {2.0 * std::sin(phase), 2.0 * std::sin(phase - kPi / 2)};
    ipmc::SetVoltages(d, voltage_V, 2);
    EXPECT_TRUE(ipmc::Step(m.get(), d)) << ipmc::LastError(d);
  }
  const int head = mj_name2id(m.get(), mjOBJ_BODY, "head");
  const Eigen::Vector2d position(d->xpos[3 * head], d->xpos[3 * head + 1]);
  ipmc::Detach(d);
  mj_deleteData(d);
  return position;
}

TEST(GeomDragTest, AChainAlongYSwimsAsTheChainAlongXTurned) {
  FlagellumSpec spec;
  spec.link_lengths_mm = {10.0, 10.0};
  spec.ipmc_actuators = true;
  for (const char* dynamics : {"inertial", "stokes"}) {
    SCOPED_TRACE(dynamics);
    std::string along_x = GenerateFlagellumMjcf(spec);
    if (std::string(dynamics) == "stokes") {
      along_x = std::regex_replace(along_x, std::regex("<custom>"),
                                   "<custom>\n    <text name=\"ipmc_dynamics\" data=\"stokes\"/>");
    }
    const std::string along_y = TurnedAlongY(along_x);
    ASSERT_NE(along_y, along_x);
    const Eigen::Vector2d x = SwimHead(along_x, 2000);  // 0.2 s, one cycle
    const Eigen::Vector2d y = SwimHead(along_y, 2000);
    ASSERT_GT(x.norm(), 1e-6);  // it swam (more than 1 um)
    // Turned back by -90 degrees: (x, y) = (y_y, -y_x); rounding only.
    EXPECT_NEAR(y[1], x[0], 1e-9 * 1e-3 + 1e-6 * x.norm());
    EXPECT_NEAR(-y[0], x[1], 1e-9 * 1e-3 + 1e-6 * x.norm());
  }
}

}  // namespace
}  // namespace ipmc::testing

// The generator's nesting limit (sim/core/model_generator.h,
// kMaxNestedBodies) is MuJoCo 2.2's: a chain of that many nested bodies
// loads and one more does not, so `generate` never writes a model that the
// loader rejects, and segments_per_link beyond it is refused in one line
// before any work.
#include <gtest/gtest.h>

#include <sstream>
#include <stdexcept>
#include <string>

#include "sim/core/model_generator.h"
#include "sim/core/simulation.h"
#include "tests/test_util.h"

namespace ipmc::testing {
namespace {

// <mujoco><worldbody> and `bodies` nested bodies, each with a hinge and a
// box: the generator's nesting.
std::string NestedChain(int bodies) {
  std::ostringstream xml;
  xml << "<mujoco><option><flag contact=\"disable\"/></option><worldbody>\n";
  for (int b = 0; b < bodies; ++b) {
    xml << "<body pos=\"0.001 0 0\"><joint type=\"hinge\" axis=\"0 0 1\"/>"
        << "<geom type=\"box\" size=\"0.0005 0.001 0.001\"/>\n";
  }
  for (int b = 0; b < bodies; ++b) xml << "</body>";
  xml << "</worldbody></mujoco>\n";
  return xml.str();
}

TEST(NestingLimitTest, IsMuJoCosOwn) {
  EXPECT_NO_THROW(LoadModelString(NestedChain(kMaxNestedBodies)));
  ExpectThrowMentioning<std::runtime_error>(
      [] { LoadModelString(NestedChain(kMaxNestedBodies + 1)); }, "inline model: ");
}

TEST(NestingLimitTest, GeneratorStopsAtIt) {
  FlagellumSpec spec;  // three links and a head
  EXPECT_EQ(MaxSegmentsPerLink(3, true), 31);
  EXPECT_EQ(MaxSegmentsPerLink(3, false), 32);
  EXPECT_EQ(MaxSegmentsPerLink(2, false), 48);
  EXPECT_EQ(MaxSegmentsPerLink(1, false), 64);  // ipmc_segments_per_link's own limit
  spec.segments_per_link = 31;
  EXPECT_NO_THROW(LoadModelString(GenerateFlagellumMjcf(spec)));
  spec.segments_per_link = 32;
  ExpectInvalidArgument(
      [&] { spec.Validate(); },
      "flagellum spec: segments_per_link must be <= 31 for 3 links and a head (got 32): "
      "MuJoCo 2.2 reads at most 96 nested bodies");
  spec.head_length_mm = 0;
  spec.clamped = true;
  EXPECT_NO_THROW(LoadModelString(GenerateFlagellumMjcf(spec)));
  spec.link_lengths_mm = {15.0, 16.0};
  spec.clamped = false;
  spec.ipmc_actuators = false;  // link 1 is the free root: no hinge for its IPMC
  spec.segments_per_link = 48;
  EXPECT_NO_THROW(LoadModelString(GenerateFlagellumMjcf(spec)));
}

}  // namespace
}  // namespace ipmc::testing

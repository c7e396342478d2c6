// sim/io/result_files.h: MATLAB names and units from column names, and
// the two file formats' signatures and refusals. Octave reading a run's
// run.mat (tests/octave) and scipy/h5py reading run.mat/run.h5
// (tests/python/test_result_files.py) check the contents.
#include "sim/io/result_files.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace ipmc {
namespace {

using Json = nlohmann::ordered_json;

TEST(ResultFilesTest, MatlabNamesAreIdentifiers) {
  EXPECT_EQ(MatlabName("com_x_mm"), "com_x_mm");
  EXPECT_EQ(MatlabName("waveform.wavelength_mm"), "waveform_wavelength_mm");
  EXPECT_EQ(MatlabName("1st"), "x1st");
  EXPECT_EQ(MatlabName("_private"), "x_private");
  EXPECT_EQ(MatlabName(""), "x");
  EXPECT_EQ(MatlabName(std::string(80, 'a')).size(), 63u);  // MATLAB's namelengthmax
}

TEST(ResultFilesTest, UnitsComeFromTheNamesSuffix) {
  EXPECT_EQ(UnitOfName("com_x_mm"), "mm");
  EXPECT_EQ(UnitOfName("time_s"), "s");
  EXPECT_EQ(UnitOfName("voltage2_V"), "V");
  EXPECT_EQ(UnitOfName("yaw_rad"), "rad");
  EXPECT_EQ(UnitOfName("w_rad_s"), "rad/s");
  EXPECT_EQ(UnitOfName("mean_speed_along_mm_s"), "mm/s");
  EXPECT_EQ(UnitOfName("iae_mm_s"), "mm s");
  EXPECT_EQ(UnitOfName("itae_mm_s2"), "mm s^2");
  EXPECT_EQ(UnitOfName("viscosity_Pa_s"), "Pa s");
  EXPECT_EQ(UnitOfName("c1_um_per_mm"), "um/mm");
  EXPECT_EQ(UnitOfName("reynolds_tip"), "");
  EXPECT_EQ(UnitOfName("controller"), "");
}

TEST(ResultFilesTest, FilesStartWithTheirFormatsSignature) {
  const Json tree = {{"t_s", {0.0, 0.5, 1.0}},
                     {"name", "pid"},
                     {"clamped", true},
                     {"none", nullptr},
                     {"links", Json::array({{{"link", 1}, {"iae_mm_s", 2.5}},
                                            {{"link", 2}, {"iae_mm_s", 3.5}}})},
                     {"keys", {"a", "b"}},
                     {"nested", {{"x_mm", 1.0}}}};
  // MAT-file 5: a 116-byte text header that starts "MATLAB 5.0 MAT-file".
  const std::string mat = MatFileBytes("run", tree);
  EXPECT_EQ(mat.rfind("MATLAB 5.0 MAT-file", 0), 0u) << mat.substr(0, 40);
  // HDF5: the 8-byte signature \211HDF\r\n\032\n.
  const std::string h5 = Hdf5FileBytes(tree);
  EXPECT_EQ(h5.substr(0, 8), std::string("\211HDF\r\n\032\n", 8));
}

TEST(ResultFilesTest, ValuesWithoutAPlaceAreRefusedNamingTheirKey) {
  // Rows of unequal length make no matrix (equal ones do: a swept list).
  const Json nested = {{"grid", Json::array({Json::array({1.0, 2.0}), Json::array({3.0})})}};
  EXPECT_NO_THROW(MatFileBytes("run", {{"grid", {{1.0, 2.0}, {3.0, 4.0}}}}));
  try {
    MatFileBytes("run", nested);
    FAIL() << "nested arrays accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_EQ(std::string(error.what()).rfind("run.grid: ", 0), 0u) << error.what();
  }
  EXPECT_THROW(Hdf5FileBytes(nested), std::invalid_argument);
  const Json ragged = {{"rows", Json::array({{{"a", 1}}, {{"b", 2}}})}};
  EXPECT_THROW(MatFileBytes("run", ragged), std::invalid_argument);
}

}  // namespace
}  // namespace ipmc

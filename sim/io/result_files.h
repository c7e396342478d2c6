// Results as one file for MATLAB/GNU Octave (MAT-file, libmatio) or for
// HDF5 readers (h5py, MATLAB's h5read, HDFView; the HDF5 C library).
//
// Both write the same tree, given as JSON (object keys in order):
//   object                       MAT: struct (1x1)        HDF5: group
//   number                       MAT: double (1x1)        HDF5: scalar double
//   true / false                 MAT: logical (1x1)       HDF5: scalar uint8
//   string                       MAT: char row            HDF5: scalar string
//   array of numbers             MAT: double column       HDF5: 1-D double
//   array of strings             MAT: cell column         HDF5: 1-D strings
//   array of number arrays of    MAT: double matrix       HDF5: 2-D double
//   one length (a row each)
//   array of objects with the    MAT: struct of columns   HDF5: group of
//   same keys (a table; a null   (a field per key)        datasets
//   cell is NaN, [NaN...] or "";
//   flags are 1 and 0)
//   null                         MAT: [] (0x0 double)     HDF5: empty dataset
// Keys become MATLAB names (MatlabName); in HDF5 every dataset whose name
// ends in a unit (UnitOfName) carries it as the attribute "units".
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace ipmc {

// A valid MATLAB identifier for `key`: characters other than letters,
// digits and '_' become '_', a name that does not start with a letter gets
// "x" before it, and it is cut at MATLAB's 63 characters.
// "waveform.wavelength_mm" -> "waveform_wavelength_mm".
std::string MatlabName(const std::string& key);

// The unit a name ends in, as text ("mm", "mm/s", "V", "rad", "mm s"), or
// "" if it names none: "_mm" mm, "_s" s, "_rad" rad, "_V" V, "_Hz" Hz,
// "_deg" deg, "_dB" dB, "_mm_s" mm/s for speeds and mm s for integrals
// (iae_mm_s), "_mm_s2" mm s^2, "_rad_s" rad/s, "_Pa_s" Pa s, "_kg_m3"
// kg/m^3, "_N_s_m2" N s/m^2, "_um_per_mm" um/mm, "_mm_per_V" mm/V.
std::string UnitOfName(const std::string& name);

// The bytes of a MAT-file (version 5, zlib-compressed: MATLAB 7 and later,
// GNU Octave and scipy.io.loadmat read it) holding one variable, the
// struct `tree` named `variable`. Throws std::invalid_argument naming the
// key of a value the mapping above has no place for (nested arrays, a
// table whose rows differ), std::runtime_error if libmatio fails.
std::string MatFileBytes(const std::string& variable, const nlohmann::ordered_json& tree);

// The bytes of an HDF5 file whose root group holds `tree`; throws as
// MatFileBytes does.
std::string Hdf5FileBytes(const nlohmann::ordered_json& tree);

}  // namespace ipmc

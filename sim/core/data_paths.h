// Where the models and scenarios that ship with the program are: beside an
// installed program, <prefix>/share/ipmc_swim/{models,scenarios}; in a build
// tree, the source tree it was built from.
#pragma once

#include <string>

namespace ipmc {

std::string ModelsDir();
std::string ScenariosDir();

// The program's version, as `ipmc-swim --version` prints it: the library's
// Version(), the CMake project version.
const char* ProgramVersion();

}  // namespace ipmc

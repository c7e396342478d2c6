// The source tree and the program of the build that the tests belong to,
// as IPMC_SWIM_SOURCE_DIR and IPMC_SWIM_CLI (const char*). Every test is
// compiled with this header included first (tests/CMakeLists.txt); the
// paths themselves are in one object, test_paths.cc, so that every test's
// own object is the same whatever folder the tree is in, and the compiler
// cache serves it to a clone in another folder (scripts/setup.sh).
#pragma once

namespace ipmc::test_paths {

extern const char kSourceDir[];
extern const char kCli[];

}  // namespace ipmc::test_paths

#define IPMC_SWIM_SOURCE_DIR (::ipmc::test_paths::kSourceDir)
#define IPMC_SWIM_CLI (::ipmc::test_paths::kCli)

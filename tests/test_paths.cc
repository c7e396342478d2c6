#include "tests/test_paths.h"

namespace ipmc::test_paths {

const char kSourceDir[] = IPMC_SWIM_SOURCE_DIR_TEXT;
const char kCli[] = IPMC_SWIM_CLI_TEXT;

}  // namespace ipmc::test_paths

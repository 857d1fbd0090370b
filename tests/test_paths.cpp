// Where the unit tests find the checkout and the shared test data. The two
// absolute paths are compiled into this file alone: on every test's command
// line they would make ccache miss in any other clone (CMakeLists.txt, base_dir).
#include <gtest/gtest.h>

#include <string>

#include "test_util.h"

namespace voxtest {

std::string sourceDir() { return VOX_SOURCE_DIR; }

std::string sharedDataDir() { return VOX_SHARED_DATA_DIR; }

}  // namespace voxtest

// Inputs nobody here wrote (webOAcard's demos, the FOLD examples), read in place from the shared
// test data beside the checkout (../shared/testdata) or from -DPOPCUT_SHARED_TESTDATA=DIR.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace popcut::testing {

inline std::string shared_testdata(const std::string& relative) {
  return std::string(POPCUT_SHARED_TESTDATA) + "/" + relative;
}

inline bool have_shared_testdata() { return std::filesystem::is_directory(POPCUT_SHARED_TESTDATA); }

}  // namespace popcut::testing

// Skips the test, saying where the data was looked for, in a checkout without the shared data
// (a clone outside the workspace); never silently passes on an empty directory.
#define POPCUT_NEEDS_SHARED_TESTDATA()                             \
  if (!popcut::testing::have_shared_testdata())                    \
  GTEST_SKIP() << "no shared test data at " POPCUT_SHARED_TESTDATA \
                  " (clone beside it, or configure with -DPOPCUT_SHARED_TESTDATA=DIR)"

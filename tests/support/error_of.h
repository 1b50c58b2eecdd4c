// The popcut::Error a call throws, for tests of messages and codes (a failure when it throws none).
#pragma once

#include <gtest/gtest.h>

#include <functional>

#include "popcut/error.h"

namespace popcut::testing {

inline Error error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "no error";
  return Error(ErrorCode::internal, "", "", "");
}

}  // namespace popcut::testing

// Order-independent comparison of two patterns (lines, faces, check results), for equivalence tests.
#pragma once

#include <string>

#include "popcut/pattern/pattern.h"

namespace popcut::testing {

// Empty when the patterns have the same lines (as maximal segments, either direction), the same
// faces (kind, t and rings up to starting vertex), and the same pop-up verdict and problem faces;
// otherwise says the first difference.
std::string compare_patterns(const Pattern& a, const Pattern& b);

}  // namespace popcut::testing

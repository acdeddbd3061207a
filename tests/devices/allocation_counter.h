#pragma once
// Counts heap allocations through operator new, program-wide, so that a test can assert that a
// code path (one meant for the 1 kHz loop) makes none.

#include <cstddef>

namespace incise::devices::testing {

// Allocations so far; compare before and after the code under test.
std::size_t allocation_count();

}  // namespace incise::devices::testing

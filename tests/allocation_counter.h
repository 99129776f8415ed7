// Counts heap allocations in a test binary: linking allocation_counter.cpp replaces the global
// operator new, so only binaries that ask for it (the steady-state allocation tests) are affected.
#pragma once

namespace hapticut::test {

/// Allocations made through operator new since the program started.
long allocationCount();

}  // namespace hapticut::test

// The memory a real-time thread's own allocations come from, faulted in before it starts its clock.
#pragma once

#include <cstddef>

namespace hapticut {

/// Makes about `bytes` of the calling thread's malloc arena ready: allocated, written and freed, so
/// that what the thread allocates later comes from pages already mapped instead of faulting new ones
/// in. A cut on the haptic thread allocates its new vertices' lists of faces and springs: a scalpel
/// stroke across the 1,000,000-triangle heart faulted about 40 pages in that way, each inside a cut
/// event, and on a virtual machine a fault can hold the thread for up to a few hundred microseconds.
/// The memory stays with the thread's arena until it ends. With glibc's malloc; elsewhere harmless.
void prefaultThreadHeap(std::size_t bytes);

}  // namespace hapticut

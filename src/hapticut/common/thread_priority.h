// Keeping the haptic loop ahead of other work in the process when the machine has few cores.
#pragma once

#include <string>
#include <vector>

namespace hapticut {

/// Lowers the scheduling priority (raises the nice value to `niceness`) of every thread of this
/// process except the calling one, and returns their names. For the viewer, called once the OpenGL
/// context exists and before the haptic loop starts: a software renderer (Mesa's llvmpipe) then runs a
/// worker per core that takes time slices of several milliseconds from the haptic thread, which misses
/// its deadlines and ramps its force back in after each stall. Raising a nice value needs no privilege;
/// threads started later by the calling thread keep its priority.
std::vector<std::string> deprioritiseOtherThreads(int niceness);

/// The nice value of a thread of this process, by its kernel id; 0 where it cannot be read.
int threadNiceness(long tid);

}  // namespace hapticut

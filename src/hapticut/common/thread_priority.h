// Keeping the haptic loop ahead of other work when the machine has few cores: other threads yield to it,
// and its own thread asks for real-time scheduling.
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

/// What a thread got when it asked for real-time scheduling.
struct RealtimeScheduling {
    bool granted = false;
    int error = 0;  // why not, when refused: an errno value
};

/// Puts the calling thread under SCHED_FIFO at `priority` (1-99), so that it runs the moment it wakes
/// and no normal thread takes its core from it. Needs CAP_SYS_NICE or an rtprio limit of at least
/// `priority` (limits.conf); refused otherwise, and the thread keeps its scheduling.
RealtimeScheduling scheduleRealtime(int priority);

/// Puts the calling thread back under the normal time-sharing scheduler.
void scheduleNormally();

}  // namespace hapticut

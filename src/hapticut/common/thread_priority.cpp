// Nice values of the other threads of the process (through /proc and setpriority), and real-time
// scheduling of the calling thread (pthread_setschedparam).
#include "hapticut/common/thread_priority.h"

#include <pthread.h>
#include <sched.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <system_error>

namespace hapticut {

int threadNiceness(long tid) {
    errno = 0;
    const int nice = getpriority(PRIO_PROCESS, static_cast<id_t>(tid));
    return errno == 0 ? nice : 0;
}

std::vector<std::string> deprioritiseOtherThreads(int niceness) {
    std::vector<std::string> names;
    const long self = syscall(SYS_gettid);
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator("/proc/self/task", ec)) {
        const std::string id = entry.path().filename().string();
        long tid = 0;
        if (std::from_chars(id.data(), id.data() + id.size(), tid).ec != std::errc()) continue;
        if (tid == self || threadNiceness(tid) >= niceness) continue;
        // On Linux a thread's nice value is its own; setpriority with a thread id sets that thread's.
        if (setpriority(PRIO_PROCESS, static_cast<id_t>(tid), niceness) != 0) continue;
        std::string name;
        std::getline(std::ifstream(entry.path() / "comm"), name);
        names.push_back(name);
    }
    return names;
}

RealtimeScheduling scheduleRealtime(int priority) {
    sched_param param{};
    param.sched_priority = priority;
    const int error = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
    return {error == 0, error};
}

void scheduleNormally() {
    sched_param param{};
    pthread_setschedparam(pthread_self(), SCHED_OTHER, &param);
}

}  // namespace hapticut

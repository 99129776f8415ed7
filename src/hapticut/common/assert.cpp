// The assert handler.
#include "hapticut/common/assert.h"

#include <atomic>
#include <cstdio>
#include <cstdlib>

namespace hapticut {

namespace {
void printAndAbort(const char* file, int line, const char* condition) {
    std::fprintf(stderr, "%s:%d: assertion failed: %s\n", file, line, condition);
    std::abort();
}
std::atomic<AssertHandler> handler{printAndAbort};
}  // namespace

AssertHandler setAssertHandler(AssertHandler h) { return handler.exchange(h ? h : printAndAbort); }

void assertFailed(const char* file, int line, const char* condition) { handler.load()(file, line, condition); }

}  // namespace hapticut

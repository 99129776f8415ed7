// HAPTICUT_ASSERT: checks that can only fail if the code is wrong (never user input). On in Debug builds
// and wherever HAPTICUT_ENABLE_ASSERTS is defined (the HAPTICUT_ASSERTS and sanitizer builds); off in
// Release. A failure calls the assert handler: by default it prints "file:line: assertion failed:
// condition" and aborts; tests and embedding programs may set their own.
#pragma once

namespace hapticut {

using AssertHandler = void (*)(const char* file, int line, const char* condition);

/// Sets what a failed assertion does and returns the previous handler. A handler that returns lets the
/// program go on past the failed check; one that throws unwinds from it.
AssertHandler setAssertHandler(AssertHandler handler);

/// Called by HAPTICUT_ASSERT on failure.
void assertFailed(const char* file, int line, const char* condition);

}  // namespace hapticut

#if !defined(NDEBUG) || defined(HAPTICUT_ENABLE_ASSERTS)
#define HAPTICUT_ASSERT(cond)                                             \
    do {                                                                  \
        if (!(cond)) ::hapticut::assertFailed(__FILE__, __LINE__, #cond); \
    } while (0)
#else
#define HAPTICUT_ASSERT(cond) ((void)0)
#endif

// HAPTICUT_ASSERT: checks that can only fail if the code is wrong (never user input).
#pragma once

#include <cstdio>
#include <cstdlib>

#if !defined(NDEBUG) || defined(HAPTICUT_ENABLE_ASSERTS)
#define HAPTICUT_ASSERT(cond)                                                                  \
    do {                                                                                       \
        if (!(cond)) {                                                                         \
            std::fprintf(stderr, "%s:%d: assertion failed: %s\n", __FILE__, __LINE__, #cond); \
            std::abort();                                                                      \
        }                                                                                      \
    } while (0)
#else
#define HAPTICUT_ASSERT(cond) ((void)0)
#endif

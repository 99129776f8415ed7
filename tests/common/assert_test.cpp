// HAPTICUT_ASSERT calls a settable handler with the file, line and condition; asserts are compiled in
// here whatever the build type, as in the Debug, HAPTICUT_ASSERTS and sanitizer builds.
#define HAPTICUT_ENABLE_ASSERTS 1
#include "hapticut/common/assert.h"

#include <gtest/gtest.h>

#include <string>

namespace hapticut {
namespace {

struct Failed {
    std::string file, condition;
    int line;
};

void throwFailure(const char* file, int line, const char* condition) { throw Failed{file, condition, line}; }

TEST(Assert, AFailedCheckCallsTheHandlerWithWhereAndWhat) {
    const AssertHandler previous = setAssertHandler(throwFailure);
    const int n = 3;
    HAPTICUT_ASSERT(n == 3);  // holds: no call
    int line = 0;
    try {
        line = __LINE__ + 1;
        HAPTICUT_ASSERT(n == 4);
        ADD_FAILURE() << "the handler was not called";
    } catch (const Failed& f) {
        EXPECT_NE(f.file.find("assert_test.cpp"), std::string::npos);
        EXPECT_EQ(f.condition, "n == 4");
        EXPECT_EQ(f.line, line);
    }
    EXPECT_EQ(setAssertHandler(previous), throwFailure);
}

TEST(AssertDeathTest, TheDefaultHandlerNamesTheCheckAndAborts) {
    EXPECT_DEATH(HAPTICUT_ASSERT(1 + 1 == 3), "assertion failed: 1 \\+ 1 == 3");
}

}  // namespace
}  // namespace hapticut

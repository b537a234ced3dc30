// GoogleTest main for every suite: a broken SLUICE_ASSERT becomes a failed test, not an abort.
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "sluice/format/support/Assert.h"

namespace {
struct AssertionFailure : std::runtime_error {
    using std::runtime_error::runtime_error;
};

void throwingHandler(const char* expr, const char* msg, const char* file, int line) {
    throw AssertionFailure(std::string(file) + ":" + std::to_string(line) +
                           ": SLUICE_ASSERT(" + expr + ") failed: " + msg);
}
} // namespace

int main(int argc, char** argv) {
    testing::InitGoogleTest(&argc, argv);
    sluice::setAssertHandler(&throwingHandler);
    return RUN_ALL_TESTS();
}

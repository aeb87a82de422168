#pragma once
// A test fixture with one headless OpenGL 4.5 core context (OSMesa) for the suite. Tests are
// skipped, not failed, where no such context can be made.
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "base/Error.h"
#include "visibility/gl/HeadlessContext.h"

namespace sightline::test {

class GlContextTest : public ::testing::Test {
protected:
    static void SetUpTestSuite()
    {
        if (context)
            return;
        try {
            context = gl::HeadlessContext::create(gl::Backend::OSMesa);
        } catch (const Error& e) {
            reason = e.what();
        }
    }
    void SetUp() override
    {
        if (!context)
            GTEST_SKIP() << "no OpenGL 4.5 core context: " << reason;
        context->makeCurrent();
    }

    static inline std::unique_ptr<gl::HeadlessContext> context;
    static inline std::string reason;
};

} // namespace sightline::test

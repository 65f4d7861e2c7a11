// A test fixture with a headless llvmpipe context: the emulation models
// llvmpipe, so the tests that hold it against a real GL skip (with the
// reason, never silently) where no EGL context can be made or the context is
// another driver.
#pragma once

#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <string>

#include "nearcap/error.hpp"
#include "nearcap/render/egl_context.hpp"

namespace nearcap::test {

class LlvmpipeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    try {
      context_ = std::make_unique<render::EglContext>();
    } catch (const Error& e) {
      GTEST_SKIP() << "no headless OpenGL here: " << e.what();
    }
    if (context_->renderer().find("llvmpipe") == std::string::npos)
      GTEST_SKIP() << "the emulation models llvmpipe; this context is " << context_->renderer();
    std::printf("[ context  ] %s, %s (%s)\n", context_->renderer().c_str(), context_->version().c_str(),
                context_->platform().c_str());
  }
  std::unique_ptr<render::EglContext> context_;
};

}  // namespace nearcap::test

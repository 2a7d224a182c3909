// A GoogleTest fixture for GPU tests: a Context on the best device (lavapipe
// in CI) with the Khronos validation layer and synchronization validation on.
// Any validation message during the test fails it.
#pragma once

#include <gtest/gtest.h>

#include <memory>

#include "gpu/context.h"

namespace bounce::testing {

class GpuTest : public ::testing::Test {
 protected:
  void SetUp() override {
    gpu::ContextOptions options;
    options.validation = true;
    options.printValidationMessages = false;
    context_ = std::make_unique<gpu::Context>(options);
  }
  void TearDown() override {
    if (!context_) return;
    vkDeviceWaitIdle(context_->device());
    for (const std::string& message : context_->validationMessages()) ADD_FAILURE() << message;
  }
  gpu::Context& context() { return *context_; }

  std::unique_ptr<gpu::Context> context_;
};

}  // namespace bounce::testing

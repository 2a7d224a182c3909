// gpu/ logic that needs no device: shader reflection and timing statistics.
#include <gtest/gtest.h>

#include <spirv/unified1/spirv.hpp>

#include "gpu/embedded_shaders.h"
#include "gpu/error.h"
#include "gpu/spirv_reflect.h"
#include "gpu/timing.h"
#include "render/analytic_scene_types.glsl"

namespace bounce::testing {
namespace {

TEST(Reflection, ReadsNamesBindingsKindsFormatsAccessAndSizes) {
  gpu::ShaderReflection r = gpu::reflectShader(gpu::findShader("render/direct_sun"), "render/direct_sun");
  ASSERT_EQ(r.bindings.size(), 5u);
  EXPECT_EQ(r.bindings[0].name, "gIn_Scene");
  EXPECT_EQ(r.bindings[0].kind, gpu::ResourceKind::StorageBuffer);
  EXPECT_FALSE(r.bindings[0].writable);
  EXPECT_EQ(r.bindings[1].name, "gIn_ViewZ");
  EXPECT_EQ(r.bindings[1].spirvImageFormat, std::uint32_t(spv::ImageFormatR32f));
  EXPECT_FALSE(r.bindings[1].writable);
  EXPECT_EQ(r.bindings[4].name, "gOut_Radiance");
  EXPECT_EQ(r.bindings[4].binding, 4u);
  EXPECT_EQ(r.bindings[4].spirvImageFormat, std::uint32_t(spv::ImageFormatRgba16f));
  EXPECT_FALSE(r.bindings[4].readable);
  EXPECT_TRUE(r.bindings[4].writable);
  EXPECT_EQ(r.pushConstantSize, sizeof(shared::AnalyticSceneParams));
  EXPECT_EQ(r.localSize[0], 8u);
  EXPECT_EQ(r.localSize[1], 8u);
}

TEST(Reflection, RejectsGarbage) {
  std::vector<std::uint32_t> words = {0x12345678u, 0, 0, 0, 0};
  EXPECT_THROW(gpu::reflectShader(words, "garbage"), gpu::GpuError);
  std::span<const std::uint32_t> real = gpu::findShader("render/direct_sun");
  std::vector<std::uint32_t> truncated(real.begin(), real.begin() + long(real.size() / 2));
  truncated.push_back(0xffff0000u | spv::OpName);  // an instruction claiming more words than remain
  EXPECT_THROW(gpu::reflectShader(truncated, "truncated"), gpu::GpuError);
}

TEST(Timing, MedianShareAndOrder) {
  gpu::TimingStats stats;
  for (double ms : {3.0, 1.0, 2.0, 100.0}) stats.add("b.second", ms);
  for (double ms : {1.0, 1.0, 1.0, 1.0}) stats.add("a.first", ms);
  stats.add("c.third", 0.5);
  auto rows = stats.summary();
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].pass, "b.second") << "rows keep the order passes first ran";
  EXPECT_DOUBLE_EQ(rows[0].medianMs, 2.5) << "median is robust to the 100 ms outlier";
  EXPECT_DOUBLE_EQ(rows[0].maxMs, 100.0);
  EXPECT_EQ(rows[2].samples, 1u);
  std::string table = stats.table();
  EXPECT_NE(table.find("b.second"), std::string::npos);
  EXPECT_NE(table.find("62.5%"), std::string::npos) << table;  // 2.5 of 4.0 ms
  EXPECT_NE(table.find("total"), std::string::npos);
}

}  // namespace
}  // namespace bounce::testing

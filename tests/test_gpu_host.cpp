// gpu/ logic that needs no device: shader reflection and timing statistics.
#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <string>

#include <spirv/unified1/spirv.hpp>

#include "gi/gi_shaders.h"
#include "gpu/constants_layout.h"
#include "gpu/embedded_shaders.h"
#include "gpu/error.h"
#include "gpu/spirv_reflect.h"
#include "gpu/timing.h"
#include "render/render_shaders.h"

namespace bounce::testing {
namespace {

const gpu::ReflectedBinding& bindingNamed(const gpu::ShaderReflection& r, const std::string& name) {
  for (const gpu::ReflectedBinding& b : r.bindings)
    if (b.name == name) return b;
  throw std::runtime_error("no binding " + name);
}

// A block of 40 members (the old macro's ceiling was 32; blocks of 24 and
// more exist): every member listed, in order, with the compiler's offsets.
struct FortyMembers {
  float m0;
  std::uint32_t m1;
  float m2;
  std::int32_t m3;
  float m4;
  std::uint32_t m5;
  float m6;
  std::int32_t m7;
  float m8;
  std::uint32_t m9;
  float m10;
  std::int32_t m11;
  float m12;
  std::uint32_t m13;
  float m14;
  std::int32_t m15;
  float m16;
  std::uint32_t m17;
  float m18;
  std::int32_t m19;
  float m20;
  std::uint32_t m21;
  float m22;
  std::int32_t m23;
  float m24;
  std::uint32_t m25;
  float m26;
  std::int32_t m27;
  float m28;
  std::uint32_t m29;
  float m30;
  std::int32_t m31;
  float m32;
  std::uint32_t m33;
  float m34;
  std::int32_t m35;
  float m36;
  std::uint32_t m37;
  float m38;
  std::int32_t m39;
};

TEST(ConstantsLayout, ListsEveryMemberOfALongBlockInOrder) {
  const gpu::ConstantsDecl decl = BOUNCE_CONSTANTS_LAYOUT(
      "gIn_Long", FortyMembers, m0, m1, m2, m3, m4, m5, m6, m7, m8, m9, m10, m11, m12, m13, m14, m15, m16, m17, m18,
      m19, m20, m21, m22, m23, m24, m25, m26, m27, m28, m29, m30, m31, m32, m33, m34, m35, m36, m37, m38, m39);
  EXPECT_EQ(decl.binding, "gIn_Long");
  EXPECT_EQ(decl.type, "FortyMembers");
  EXPECT_EQ(decl.size, sizeof(FortyMembers));
  ASSERT_EQ(decl.members.size(), 40u);
  for (std::size_t i = 0; i < decl.members.size(); ++i) {
    const std::string expected = std::string("m").append(std::to_string(i));
    EXPECT_EQ(decl.members[i].name, expected);
    EXPECT_EQ(decl.members[i].offset, 4 * i);
    EXPECT_EQ(decl.members[i].size, 4u);
  }
}

TEST(Reflection, ReadsNamesBindingsKindsFormatsAccessAndSizes) {
  gpu::ShaderReflection r =
      gpu::reflectShader(gpu::findShader(render::shaders(), "render/direct_light"), "render/direct_light");
  const gpu::ReflectedBinding& frame = bindingNamed(r, "gIn_Frame");
  EXPECT_EQ(frame.kind, gpu::ResourceKind::UniformBuffer);
  EXPECT_EQ(frame.binding, 0u);
  // The variant for CPU drivers has the same constant block as a read-only storage buffer.
  const gpu::ShaderReflection storage =
      gpu::reflectShader(gpu::findShader(render::shaders(), "render/direct_light", true), "storage");
  EXPECT_EQ(bindingNamed(storage, "gIn_Frame").kind, gpu::ResourceKind::StorageBuffer);
  EXPECT_FALSE(bindingNamed(storage, "gIn_Frame").writable);
  EXPECT_EQ(bindingNamed(storage, "gIn_Frame").binding, 0u);
  EXPECT_EQ(storage.bindings.size(), r.bindings.size());
  const gpu::ReflectedBinding& lights = bindingNamed(r, "gIn_Lights");
  EXPECT_EQ(lights.kind, gpu::ResourceKind::StorageBuffer);
  EXPECT_FALSE(lights.writable);
  const gpu::ReflectedBinding& viewZ = bindingNamed(r, "gIn_ViewZ");
  EXPECT_EQ(viewZ.kind, gpu::ResourceKind::StorageImage);
  EXPECT_EQ(viewZ.spirvImageFormat, std::uint32_t(spv::ImageFormatR32f));
  EXPECT_FALSE(viewZ.writable);
  EXPECT_EQ(bindingNamed(r, "gIn_Environment").kind, gpu::ResourceKind::SampledImage);
  const gpu::ReflectedBinding& radiance = bindingNamed(r, "gOut_Radiance");
  EXPECT_EQ(radiance.binding, 23u);
  EXPECT_EQ(radiance.spirvImageFormat, std::uint32_t(spv::ImageFormatRgba16f));
  EXPECT_FALSE(radiance.readable);
  EXPECT_TRUE(radiance.writable);
  EXPECT_EQ(bindingNamed(r, "gIn_BvhNodes").binding, 6u) << "BVH_FIRST_BINDING";
  EXPECT_EQ(r.pushConstantSize, 0u);
  EXPECT_EQ(r.localSize[0], 8u);
  EXPECT_EQ(r.localSize[1], 8u);

  // Block layouts, member by member: push constants, and a uniform block
  // whose one member is a struct (described by that struct's members).
  const gpu::ShaderReflection spatial =
      gpu::reflectShader(gpu::findShader(gi::shaders(), "gi/diffuse/spatial_reuse"), "gi/diffuse/spatial_reuse");
  EXPECT_EQ(spatial.pushConstantSize, 16u);
  ASSERT_EQ(spatial.pushConstantMembers.size(), 4u);
  EXPECT_EQ(spatial.pushConstantMembers[1].name, "samples");
  EXPECT_EQ(spatial.pushConstantMembers[1].offset, 4u);
  EXPECT_EQ(spatial.pushConstantMembers[2].name, "passIndex");
  EXPECT_EQ(spatial.pushConstantMembers[2].size, 4u);
  EXPECT_EQ(spatial.pushConstantMembers[3].name, "slotsPerPixel");
  EXPECT_EQ(spatial.pushConstantMembers[3].offset, 12u);
  const gpu::ReflectedBinding& frameBlock = bindingNamed(spatial, "gIn_Frame");
  ASSERT_GE(frameBlock.members.size(), 3u);
  EXPECT_EQ(frameBlock.members[0].name, "view");
  EXPECT_EQ(frameBlock.members[1].name, "previousView");
  EXPECT_EQ(frameBlock.members[1].offset, frameBlock.members[0].size);
  EXPECT_EQ(frameBlock.members[2].name, "renderSize");
  EXPECT_EQ(frameBlock.members[2].size, 8u);
}

TEST(Reflection, RejectsGarbage) {
  std::vector<std::uint32_t> words = {0x12345678u, 0, 0, 0, 0};
  EXPECT_THROW(gpu::reflectShader(words, "garbage"), gpu::GpuError);
  std::span<const std::uint32_t> real = gpu::findShader(render::shaders(), "render/direct_light");
  // Walk to the first instruction boundary past the middle, and to an
  // instruction of several words, so the cuts below land where intended.
  std::size_t boundary = 5, longInstruction = 0;
  while (boundary < real.size() / 2) {
    const std::size_t words = real[boundary] >> 16;
    if (words > 2 && longInstruction == 0) longInstruction = boundary;
    boundary += words;
  }
  std::vector<std::uint32_t> overlong(real.begin(), real.begin() + long(boundary));
  overlong.push_back(0xffff0000u | spv::OpName);  // an instruction claiming more words than remain
  EXPECT_THROW(gpu::reflectShader(overlong, "overlong"), gpu::GpuError);
  ASSERT_GT(longInstruction, 0u);
  std::vector<std::uint32_t> cut(real.begin(), real.begin() + long(longInstruction + 1));
  EXPECT_THROW(gpu::reflectShader(cut, "cut inside an instruction"), gpu::GpuError);
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

TEST(Timing, MemoryIsBoundedOverLongRunsAndTheSummaryStaysTrue) {
  gpu::TimingStats stats;
  // A million frames of one pass: 1 ms mostly, with a 0.25 ms minimum and a
  // 50 ms maximum once each, and every tenth frame 3 ms (the median stays 1).
  constexpr std::size_t kFrames = 1000000;
  for (std::size_t i = 0; i < kFrames; ++i)
    stats.add("p", i == 10 ? 0.25 : i == 777777 ? 50.0 : i % 10 == 0 ? 3.0 : 1.0);
  const auto rows = stats.summary();
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].samples, kFrames) << "the count is exact";
  EXPECT_EQ(stats.keptSamples("p"), gpu::TimingStats::kMaxSamples) << "memory does not grow with the frame count";
  EXPECT_DOUBLE_EQ(rows[0].minMs, 0.25) << "the extremes are exact however rare";
  EXPECT_DOUBLE_EQ(rows[0].maxMs, 50.0);
  EXPECT_DOUBLE_EQ(rows[0].medianMs, 1.0);
  // A late change of speed reaches the kept sample: after a million more
  // frames at 2 ms, about half the kept times are 2 ms, so the median moves.
  for (std::size_t i = 0; i < 2 * kFrames; ++i) stats.add("p", 2.0);
  EXPECT_DOUBLE_EQ(stats.summary()[0].medianMs, 2.0);
}

}  // namespace
}  // namespace bounce::testing

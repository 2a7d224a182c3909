// Tests of src/render/texture_atlas: packing, mip chains, and sampling on the
// GPU (shaders/render/texture_atlas.glsl) against the CPU's mip chains.
#include "render/texture_atlas.h"

#include <gtest/gtest.h>

#include <cmath>

#include "gpu/constants_layout.h"
#include "gpu/pass.h"
#include "gpu/recorder.h"
#include "gpu/transfer.h"
#include "gpu_test.h"
#include "shared/color.glsl"
#include "test_shaders.h"

namespace bounce::render {
namespace {

// The push constants of the check shader: how many queries it answers.
struct CheckParams {
  std::uint32_t count;
};

scene::Texture randomTexture(int width, int height, bool srgb, unsigned seed) {
  scene::Texture t;
  t.name = "random";
  t.width = width;
  t.height = height;
  t.srgb = srgb;
  std::uint32_t state = seed * 747796405u + 1u;
  for (int i = 0; i < width * height * 4; ++i) {
    state = state * 747796405u + 2891336453u;
    t.rgba8.push_back(std::uint8_t(state >> 24));
  }
  return t;
}

TEST(TextureAtlas, PackedRectanglesAreInsideTheirPageAndDisjoint) {
  std::vector<glm::uvec2> sizes;
  for (unsigned i = 0; i < 40; ++i) sizes.emplace_back(3 + i % 6, 2 + (i * 7) % 7);
  const AtlasLayout layout = packAtlas(sizes, 1024);
  ASSERT_EQ(layout.entries.size(), sizes.size());
  struct Box { std::uint32_t page, x0, y0, x1, y1; };
  std::vector<Box> boxes;
  for (const AtlasEntry& e : layout.entries) {
    const std::uint32_t w = 1u << e.log2Width, h = 1u << e.log2Height;
    const Box box{e.page, e.x, e.y, e.x + w + std::max(1u, w / 2), e.y + h};
    EXPECT_LE(box.x1, layout.pageSize);
    EXPECT_LE(box.y1, layout.pageSize);
    EXPECT_LT(box.page, layout.pageCount);
    for (const Box& other : boxes)
      EXPECT_TRUE(other.page != box.page || other.x1 <= box.x0 || box.x1 <= other.x0 || other.y1 <= box.y0 ||
                  box.y1 <= other.y0);
    boxes.push_back(box);
  }
}

TEST(TextureAtlas, SidesArePowersOfTwoCapped) {
  EXPECT_EQ(atlasSide(1000, 2048), 1024u);
  EXPECT_EQ(atlasSide(1024, 2048), 1024u);
  EXPECT_EQ(atlasSide(3000, 2048), 2048u);
  EXPECT_EQ(atlasSide(1, 2048), 1u);
}

TEST(TextureAtlas, MipChainAveragesInLinearLight) {
  scene::Texture t{"checker", 2, 2, true, {0, 0, 0, 255, 255, 255, 255, 255, 255, 255, 255, 255, 0, 0, 0, 255}};
  const auto chain = buildMipChain(t, 2, 2);
  ASSERT_EQ(chain.size(), 2u);
  // Half black, half white averages to linear 0.5: sRGB byte 188, not 128.
  EXPECT_NEAR(int(chain[1][0]), int(std::lround(shared::srgbEncode(0.5f) * 255.0f)), 1);
  EXPECT_EQ(chain[1][3], 255);
}

class TextureAtlasGpu : public testing::GpuTest {};

TEST_F(TextureAtlasGpu, SamplesMatchTheCpuMipChains) {
  std::vector<scene::Texture> textures = {randomTexture(16, 8, false, 1), randomTexture(5, 7, true, 2),
                                          randomTexture(32, 32, false, 3)};
  TextureAtlas atlas(context(), textures);

  // Texel centres of a few mip levels: the bilinear weights are exact there,
  // so the GPU must return the CPU's texel (sRGB decoded) at that level.
  struct Query { std::uint32_t texture, level, x, y; };
  std::vector<Query> queries;
  std::vector<glm::vec4> gpuQueries;
  for (std::uint32_t t = 0; t < textures.size(); ++t) {
    const AtlasEntry& e = atlas.layout().entries[t];
    for (std::uint32_t level = 0; level < e.mipCount; ++level) {
      const std::uint32_t w = std::max(1u, (1u << e.log2Width) >> level);
      const std::uint32_t h = std::max(1u, (1u << e.log2Height) >> level);
      for (std::uint32_t k = 0; k < 5; ++k) {
        const std::uint32_t x = (k * 7) % w, y = (k * 5) % h;
        queries.push_back({t, level, x, y});
        // footprint such that texel lod == level exactly
        const float footprint = float(level) - 0.5f * float(e.log2Width + e.log2Height);
        gpuQueries.emplace_back(float(t), (float(x) + 0.5f) / float(w), (float(y) + 0.5f) / float(h), footprint);
      }
    }
  }
  gpu::Buffer input(context(), "queries", gpuQueries.size() * sizeof(glm::vec4), gpu::BufferUsage::DeviceLocal);
  gpu::uploadBuffer(context(), input, gpuQueries.data(), gpuQueries.size() * sizeof(glm::vec4));
  gpu::Buffer output(context(), "results", gpuQueries.size() * sizeof(glm::vec4), gpu::BufferUsage::DeviceLocal);
  gpu::ComputePass pass(context(),
                        {.name = "tests.atlas_sample_check",
                         .shader = "tests/atlas_sample_check",
                         .shaders = tests::shaders(),
                         .resources = {{"gIn_TextureAtlas", gpu::Access::Read, VK_FORMAT_UNDEFINED, "atlas",
                                        gpu::ResourceKind::SampledImage},
                                       {"gIn_TextureAtlasEntries", gpu::Access::Read, VK_FORMAT_UNDEFINED, "entries",
                                        gpu::ResourceKind::StorageBuffer},
                                       {"gIn_Queries", gpu::Access::Read, VK_FORMAT_UNDEFINED, "queries",
                                        gpu::ResourceKind::StorageBuffer},
                                       {"gOut_Results", gpu::Access::Write, VK_FORMAT_UNDEFINED, "results",
                                        gpu::ResourceKind::StorageBuffer}},
                         .constants = {BOUNCE_CONSTANTS_LAYOUT("", CheckParams, count)}});
  const std::uint32_t count = std::uint32_t(gpuQueries.size());
  context().submitAndWait([&](gpu::Recorder& r) {
    r.dispatch(pass, count, 1,
               {{"gIn_TextureAtlas", atlas.pages(), context().nearestSampler()},
                {"gIn_TextureAtlasEntries", atlas.entries()},
                {"gIn_Queries", input},
                {"gOut_Results", output}},
               count);
  });
  const std::vector<std::uint8_t> bytes = gpu::readbackBuffer(context(), output);
  const auto* results = reinterpret_cast<const glm::vec4*>(bytes.data());

  for (std::size_t q = 0; q < queries.size(); ++q) {
    const Query& query = queries[q];
    const AtlasEntry& e = atlas.layout().entries[query.texture];
    const auto chain = buildMipChain(textures[query.texture], 1u << e.log2Width, 1u << e.log2Height);
    const std::uint32_t w = std::max(1u, (1u << e.log2Width) >> query.level);
    const std::uint8_t* texel = &chain[query.level][(std::size_t(query.y) * w + query.x) * 4];
    for (int c = 0; c < 4; ++c) {
      float expected = float(texel[c]) / 255.0f;
      if (c < 3 && textures[query.texture].srgb) expected = shared::srgbDecode(expected);
      EXPECT_NEAR(results[q][c], expected, 2e-3f) << "texture " << query.texture << " level " << query.level << " ("
                                                   << query.x << "," << query.y << ") channel " << c;
    }
  }
}

}  // namespace
}  // namespace bounce::render

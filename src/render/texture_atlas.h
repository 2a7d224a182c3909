// All scene textures in one array image, with their mip chains, sampled by
// hand in shaders (shaders/render/texture_atlas.glsl).
//
// Why an atlas rather than one Vulkan image per texture: a compute shader can
// only index many textures through descriptor indexing, and lavapipe (our
// test device) has neither descriptor indexing nor more than 32 samplers per
// stage, while Sponza has ~70 textures. An atlas works everywhere, and manual
// filtering inside each texture's rectangle has no bleeding between
// neighbours and wraps (REPEAT) exactly.
//
// Layout: every texture is resized to power-of-two sides (at most
// maxTextureSize) and stored with its mip chain in one rectangle of a page
// (layer): mip 0 at the left, mip k >= 1 stacked in a column to its right at
// y = h - (h >> (k - 1)). Pages are square, at most 4096 texels a side.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "gpu/context.h"
#include "gpu/resources.h"
#include "scene/scene.h"

namespace bounce::render {

// Where one texture lives (mirrors TextureAtlasEntry in texture_atlas.glsl).
struct AtlasEntry {
  std::uint32_t page = 0;
  std::uint32_t x = 0, y = 0;
  std::uint32_t log2Width = 0, log2Height = 0;
  std::uint32_t mipCount = 1;
  bool srgb = false;
};

struct AtlasLayout {
  std::uint32_t pageSize = 1;
  std::uint32_t pageCount = 1;
  std::vector<AtlasEntry> entries;
};

// Side length of a texture once resized: the power of two nearest above,
// capped at maxTextureSize.
std::uint32_t atlasSide(int side, std::uint32_t maxTextureSize);

// Shelf-packs rectangles for textures of the given power-of-two sizes
// (log2 width, log2 height) into as few square pages as it can.
AtlasLayout packAtlas(std::span<const glm::uvec2> log2Sizes, std::uint32_t maxPageSize = 4096);

// The texels of one texture's mip chain in the atlas layout: mip k of a
// (2^lw x 2^lh) texture, RGBA8, filtered in linear light (sRGB decoded
// first when the texture is sRGB).
std::vector<std::vector<std::uint8_t>> buildMipChain(const scene::Texture& texture, std::uint32_t width,
                                                     std::uint32_t height);

class TextureAtlas {
 public:
  TextureAtlas(gpu::Context& context, std::span<const scene::Texture> textures, std::uint32_t maxTextureSize = 2048);

  gpu::Image& pages() { return *pages_; }      // rgba8 array image, sampled with texelFetch
  gpu::Buffer& entries() { return *entries_; }  // one uvec4 per texture (see texture_atlas.glsl)
  const AtlasLayout& layout() const { return layout_; }

 private:
  AtlasLayout layout_;
  std::unique_ptr<gpu::Image> pages_;
  std::unique_ptr<gpu::Buffer> entries_;
};

}  // namespace bounce::render

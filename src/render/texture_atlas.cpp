#include "render/texture_atlas.h"

#include <algorithm>
#include <cstring>
#include <bit>
#include <cmath>
#include <numeric>
#include <thread>

#include "gpu/error.h"
#include "gpu/recorder.h"
#include "gpu/transfer.h"
#include "shared/color.glsl"

namespace bounce::render {
namespace {

struct Rect {
  std::uint32_t width = 0, height = 0;
};

// The rectangle a texture's whole mip chain takes: mip 0 plus a column of
// half width for the smaller levels.
Rect chainRect(const glm::uvec2& log2Size) {
  const std::uint32_t width = 1u << log2Size.x;
  const std::uint32_t height = 1u << log2Size.y;
  const bool hasMips = log2Size.x > 0 || log2Size.y > 0;
  return {width + (hasMips ? std::max(1u, width / 2) : 0u), height};
}

std::uint32_t mipCountOf(const glm::uvec2& log2Size) { return std::max(log2Size.x, log2Size.y) + 1; }

// Packs in the given order into pages of side pageSize; false if a rectangle
// does not fit even an empty page.
bool shelfPack(std::span<const glm::uvec2> log2Sizes, std::span<const std::size_t> order, std::uint32_t pageSize,
               AtlasLayout& layout) {
  layout.pageSize = pageSize;
  layout.pageCount = 1;
  layout.entries.assign(log2Sizes.size(), {});
  std::uint32_t shelfX = 0, shelfY = 0, shelfHeight = 0;
  for (std::size_t index : order) {
    const Rect rect = chainRect(log2Sizes[index]);
    if (rect.width > pageSize || rect.height > pageSize) return false;
    if (shelfX + rect.width > pageSize) {  // next shelf
      shelfY += shelfHeight;
      shelfX = 0;
      shelfHeight = 0;
    }
    if (shelfY + rect.height > pageSize) {  // next page
      ++layout.pageCount;
      shelfX = shelfY = shelfHeight = 0;
    }
    AtlasEntry& entry = layout.entries[index];
    entry.page = layout.pageCount - 1;
    entry.x = shelfX;
    entry.y = shelfY;
    entry.log2Width = log2Sizes[index].x;
    entry.log2Height = log2Sizes[index].y;
    entry.mipCount = mipCountOf(log2Sizes[index]);
    shelfX += rect.width;
    shelfHeight = std::max(shelfHeight, rect.height);
  }
  return true;
}

float decode(std::uint8_t value, bool srgb) {
  const float v = float(value) / 255.0f;
  return srgb ? shared::srgbDecode(v) : v;
}

std::uint8_t encode(float value, bool srgb) {
  const float v = std::clamp(srgb ? shared::srgbEncode(value) : value, 0.0f, 1.0f);
  return std::uint8_t(std::lround(v * 255.0f));
}

}  // namespace

std::uint32_t atlasSide(int side, std::uint32_t maxTextureSize) {
  return std::min(std::bit_ceil(std::uint32_t(std::max(side, 1))), std::bit_floor(std::max(maxTextureSize, 1u)));
}

AtlasLayout packAtlas(std::span<const glm::uvec2> log2Sizes, std::uint32_t maxPageSize) {
  AtlasLayout layout;
  if (log2Sizes.empty()) return layout;
  // Tallest first keeps shelves full.
  std::vector<std::size_t> order(log2Sizes.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return chainRect(log2Sizes[a]).height > chainRect(log2Sizes[b]).height;
  });
  std::uint64_t area = 0;
  std::uint32_t largest = 1;
  for (const glm::uvec2& size : log2Sizes) {
    const Rect rect = chainRect(size);
    area += std::uint64_t(rect.width) * rect.height;
    largest = std::max({largest, rect.width, rect.height});
  }
  if (largest > maxPageSize)
    throw gpu::GpuError("texture atlas: a texture needs " + std::to_string(largest) + " texels, pages have " +
                        std::to_string(maxPageSize));
  // The smallest power-of-two page that holds everything on one page, else
  // full-size pages.
  std::uint32_t pageSize = std::bit_ceil(std::max(largest, std::uint32_t(std::ceil(std::sqrt(double(area))))));
  for (; pageSize < maxPageSize; pageSize *= 2)
    if (shelfPack(log2Sizes, order, pageSize, layout) && layout.pageCount == 1) return layout;
  shelfPack(log2Sizes, order, maxPageSize, layout);
  return layout;
}

std::vector<std::vector<std::uint8_t>> buildMipChain(const scene::Texture& texture, std::uint32_t width,
                                                     std::uint32_t height) {
  // Resample to the power-of-two size (bilinear, clamped at the edges), in
  // linear light.
  std::vector<glm::vec4> level(std::size_t(width) * height);
  const auto texel = [&](int x, int y) {
    x = std::clamp(x, 0, texture.width - 1);
    y = std::clamp(y, 0, texture.height - 1);
    const std::uint8_t* p = &texture.rgba8[(std::size_t(y) * std::size_t(texture.width) + std::size_t(x)) * 4];
    return glm::vec4(decode(p[0], texture.srgb), decode(p[1], texture.srgb), decode(p[2], texture.srgb),
                     float(p[3]) / 255.0f);
  };
  const float scaleX = float(texture.width) / float(width);
  const float scaleY = float(texture.height) / float(height);
  for (std::uint32_t y = 0; y < height; ++y) {
    for (std::uint32_t x = 0; x < width; ++x) {
      // When shrinking, average a box of source texels so no detail aliases.
      const float x0 = float(x) * scaleX, x1 = float(x + 1) * scaleX;
      const float y0 = float(y) * scaleY, y1 = float(y + 1) * scaleY;
      glm::vec4 sum(0.0f);
      if (scaleX <= 1.0f && scaleY <= 1.0f) {
        const float sx = (float(x) + 0.5f) * scaleX - 0.5f, sy = (float(y) + 0.5f) * scaleY - 0.5f;
        const int ix = int(std::floor(sx)), iy = int(std::floor(sy));
        const float fx = sx - float(ix), fy = sy - float(iy);
        sum = glm::mix(glm::mix(texel(ix, iy), texel(ix + 1, iy), fx),
                       glm::mix(texel(ix, iy + 1), texel(ix + 1, iy + 1), fx), fy);
      } else {
        int count = 0;
        for (int sy = int(y0); sy < std::max(int(y0) + 1, int(std::ceil(y1))); ++sy)
          for (int sx = int(x0); sx < std::max(int(x0) + 1, int(std::ceil(x1))); ++sx, ++count) sum += texel(sx, sy);
        sum /= float(count);
      }
      level[std::size_t(y) * width + x] = sum;
    }
  }

  std::vector<std::vector<std::uint8_t>> chain;
  std::uint32_t w = width, h = height;
  while (true) {
    std::vector<std::uint8_t>& bytes = chain.emplace_back(std::size_t(w) * h * 4);
    for (std::size_t i = 0; i < level.size(); ++i) {
      for (int c = 0; c < 3; ++c) bytes[i * 4 + std::size_t(c)] = encode(level[i][c], texture.srgb);
      bytes[i * 4 + 3] = encode(level[i].w, false);
    }
    if (w == 1 && h == 1) break;
    const std::uint32_t nw = std::max(1u, w / 2), nh = std::max(1u, h / 2);
    std::vector<glm::vec4> next(std::size_t(nw) * nh);
    for (std::uint32_t y = 0; y < nh; ++y)
      for (std::uint32_t x = 0; x < nw; ++x) {
        const std::uint32_t x0 = std::min(2 * x, w - 1), x1 = std::min(2 * x + 1, w - 1);
        const std::uint32_t y0 = std::min(2 * y, h - 1), y1 = std::min(2 * y + 1, h - 1);
        next[std::size_t(y) * nw + x] = 0.25f * (level[std::size_t(y0) * w + x0] + level[std::size_t(y0) * w + x1] +
                                                 level[std::size_t(y1) * w + x0] + level[std::size_t(y1) * w + x1]);
      }
    level = std::move(next);
    w = nw;
    h = nh;
  }
  return chain;
}

TextureAtlas::TextureAtlas(gpu::Context& context, std::span<const scene::Texture> textures,
                           std::uint32_t maxTextureSize) {
  std::vector<glm::uvec2> log2Sizes;
  for (const scene::Texture& texture : textures)
    log2Sizes.emplace_back(std::countr_zero(atlasSide(texture.width, maxTextureSize)),
                           std::countr_zero(atlasSide(texture.height, maxTextureSize)));
  layout_ = packAtlas(log2Sizes);
  for (std::size_t i = 0; i < textures.size(); ++i) layout_.entries[i].srgb = textures[i].srgb;

  // Mip chains are independent: build them on every core.
  std::vector<std::vector<std::vector<std::uint8_t>>> chains(textures.size());
  {
    const std::size_t threads = std::max(1u, std::min(8u, std::thread::hardware_concurrency()));
    std::vector<std::jthread> workers;
    for (std::size_t t = 0; t < threads; ++t)
      workers.emplace_back([&, t] {
        for (std::size_t i = t; i < textures.size(); i += threads)
          chains[i] = buildMipChain(textures[i], 1u << log2Sizes[i].x, 1u << log2Sizes[i].y);
      });
  }

  pages_ = std::make_unique<gpu::Image>(
      context, gpu::ImageDesc{.name = "scene.texture_atlas",
                              .width = layout_.pageSize,
                              .height = layout_.pageSize,
                              .format = VK_FORMAT_R8G8B8A8_UNORM,
                              .visualize = gpu::Visualize::Color,
                              .layers = layout_.pageCount,
                              .arrayed = true});
  std::size_t totalBytes = 0;
  for (const auto& chain : chains)
    for (const auto& level : chain) totalBytes += level.size();
  if (totalBytes > 0) {
    gpu::Buffer staging(context, "scene.texture_atlas.staging", totalBytes, gpu::BufferUsage::Upload);
    std::vector<gpu::ImageRegion> regions;
    std::size_t offset = 0;
    for (std::size_t i = 0; i < chains.size(); ++i) {
      const AtlasEntry& entry = layout_.entries[i];
      const std::uint32_t width = 1u << entry.log2Width, height = 1u << entry.log2Height;
      for (std::uint32_t k = 0; k < chains[i].size(); ++k) {
        std::memcpy(static_cast<std::uint8_t*>(staging.mapped()) + offset, chains[i][k].data(), chains[i][k].size());
        const std::uint32_t x = entry.x + (k == 0 ? 0 : width);
        const std::uint32_t y = entry.y + (k == 0 ? 0 : height - (height >> (k - 1)));
        regions.push_back({0, entry.page, x, y, std::max(1u, width >> k), std::max(1u, height >> k), offset});
        offset += chains[i][k].size();
      }
    }
    context.submitAndWait([&](gpu::Recorder& recorder) {
      recorder.clearImage(*pages_, VkClearColorValue{});
      for (const gpu::ImageRegion& region : regions) recorder.copyBufferToImage(staging, *pages_, region);
    });
  } else {
    context.submitAndWait([&](gpu::Recorder& recorder) { recorder.clearImage(*pages_, VkClearColorValue{}); });
  }

  std::vector<glm::uvec4> packed(std::max<std::size_t>(1, layout_.entries.size()), glm::uvec4(0));
  for (std::size_t i = 0; i < layout_.entries.size(); ++i) {
    const AtlasEntry& e = layout_.entries[i];
    packed[i] = {e.page, e.x | (e.y << 16), e.log2Width | (e.log2Height << 8) | (e.mipCount << 16) |
                                                (e.srgb ? 1u << 24 : 0u), 0u};
  }
  entries_ = std::make_unique<gpu::Buffer>(context, "scene.texture_atlas.entries", packed.size() * sizeof(glm::uvec4),
                                           gpu::BufferUsage::DeviceLocal);
  gpu::uploadBuffer(context, *entries_, packed.data(), packed.size() * sizeof(glm::uvec4));
}

}  // namespace bounce::render

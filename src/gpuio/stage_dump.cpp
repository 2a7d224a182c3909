#include "gpuio/stage_dump.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "gpuio/gpu_images.h"
#include "gpu/error.h"
#include "io/colormap.h"

#include "shared/rng.glsl"

namespace bounce::gpuio {

using gpu::Visualize;

VisualizedImage visualize(const io::ImageF& image, Visualize how) {
  switch (how) {
    case Visualize::Radiance:
      return {io::firstChannels(image, 3), io::PngEncoding::Tonemapped};
    case Visualize::Color:
      return {io::firstChannels(image, 3), io::PngEncoding::Srgb};
    case Visualize::Signed: {
      io::ImageF out = io::firstChannels(image, 3);
      for (float& v : out.pixels) v = v * 0.5f + 0.5f;
      return {out, io::PngEncoding::Linear};
    }
    case Visualize::Range: {
      io::ImageF out = io::firstChannels(image, 1);
      float lo = std::numeric_limits<float>::max(), hi = std::numeric_limits<float>::lowest();
      for (float v : out.pixels)
        if (std::isfinite(v) && std::abs(v) < 1e30f) {
          lo = std::min(lo, v);
          hi = std::max(hi, v);
        }
      const float scale = hi > lo ? 1.0f / (hi - lo) : 0.0f;
      for (float& v : out.pixels) v = std::isfinite(v) ? (std::abs(v) < 1e30f ? (v - lo) * scale : 1.0f) : v;
      return {out, io::PngEncoding::Linear};
    }
    case Visualize::Raw:
      return {io::firstChannels(image, 3), io::PngEncoding::Linear};
    case Visualize::Motion: {
      io::ImageF out(image.width, image.height, {"R", "G", "B"});
      float largest = 0.0f;
      for (float v : image.pixels)
        if (std::isfinite(v)) largest = std::max(largest, std::abs(v));
      const float scale = largest > 0.0f ? 0.5f / largest : 0.0f;
      for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
          for (int c = 0; c < 2 && c < int(image.channelCount()); ++c)
            out.at(x, y, c) = 0.5f + image.at(x, y, c) * scale;
      return {out, io::PngEncoding::Linear};
    }
    case Visualize::Ids: {
      io::ImageF out(image.width, image.height, {"R", "G", "B"});
      for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
          // Readback gives floats: exact below 2^24, and all-ones rounds up to 2^32.
          const float value = image.at(x, y, 0);
          if (!(value >= 0.0f && value < 4294967040.0f)) continue;
          const auto id = std::uint32_t(value);
          const std::uint32_t h = shared::pcgHash(id);
          for (int c = 0; c < 3; ++c) out.at(x, y, c) = 0.2f + 0.8f * float((h >> (8 * c)) & 0xffu) / 255.0f;
        }
      return {out, io::PngEncoding::Linear};
    }
    case Visualize::Heat: {
      std::vector<float> positive;
      for (std::size_t p = 0; p < image.pixels.size(); p += image.channelCount())
        if (image.pixels[p] > 0.0f && std::isfinite(image.pixels[p])) positive.push_back(std::log(image.pixels[p]));
      io::ImageF out(image.width, image.height, {"R", "G", "B"});
      if (positive.empty()) return {out, io::PngEncoding::Linear};
      std::sort(positive.begin(), positive.end());
      const float lo = positive[positive.size() / 100], hi = positive[positive.size() - 1 - positive.size() / 100];
      const float scale = hi > lo ? 1.0f / (hi - lo) : 0.0f;
      for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
          const float v = image.at(x, y, 0);
          if (!(v > 0.0f)) continue;
          const std::array<std::uint8_t, 3> rgb = io::magma(hi > lo ? (std::log(v) - lo) * scale : 1.0f);
          for (int c = 0; c < 3; ++c) out.at(x, y, c) = float(rgb[c]) / 255.0f;
        }
      return {out, io::PngEncoding::Linear};
    }
  }
  return {image, io::PngEncoding::Linear};
}

std::vector<std::filesystem::path> writeStageDumps(const std::filesystem::path& dir,
                                                   const std::vector<gpu::CapturedStage>& captures, float exposure) {
  std::filesystem::create_directories(dir);
  std::vector<std::filesystem::path> written;
  for (const gpu::CapturedStage& capture : captures) {
    char frame[32];
    std::snprintf(frame, sizeof frame, "frame%04llu", static_cast<unsigned long long>(capture.frame));
    const std::string stem = std::string(frame) + "." + capture.pass + "." + capture.binding;
    if (capture.texels.empty()) throw gpu::GpuError("stage " + stem + " was never completed (completeCapture)");
    io::ImageF pixels = texelsToImage(capture.image, capture.texels.data());
    written.push_back(dir / (stem + ".exr"));
    io::writeExr(written.back(), pixels);
    VisualizedImage view = visualize(pixels, capture.image.visualize);
    written.push_back(dir / (stem + ".png"));
    io::writePng(written.back(), view.image, view.encoding, exposure);
  }
  return written;
}

}  // namespace bounce::gpuio

// The GI library fed poison: for one frame, NaN or +Inf is written into one
// of its input images, over the whole image or over a small block, after the
// renderer made the frame and before the library reads it. Whatever the
// input, (a) every image the library keeps (the composite, the indirect
// diffuse and all history: reservoirs, filtered light, moments, surfaces)
// stays finite at that frame and after; (b) a poisoned block does not spread:
// pixels far from it stay finite and close to an unpoisoned run's; (c) the
// history heals: eight frames later the frame differs from the unpoisoned
// run's by no more than a run that lost its history to a camera cut at the
// poisoned frame, the legitimate worst case. For a block, both differences
// are taken over the block and its surroundings, so that a poisoned patch
// that lingered (dark, or NaN, which makes the difference NaN) fails even
// though it is a small part of the frame.
//
// Every run renders the same static view of cornell at 64x48 with the same
// seed, so runs agree bit for bit until the poisoned frame. The library's
// optional emissive input is given in every run (the renderer's direct light
// already holds emission, so the lamp counts twice here; runs are compared
// with runs, so that does not matter), so that it can be poisoned too.
#include "bounce/gi.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "gpu/format.h"
#include "gpu/frame_loop.h"
#include "gpu/transfer.h"
#include "gpu_test.h"
#include "gpuio/gpu_images.h"
#include "render/frame_renderer.h"
#include "render/gi_bridge.h"
#include "scene/builtin_scenes.h"
#include "shared/color.glsl"
#include "test_meshes.h"

namespace bounce::gi {
namespace {

using namespace gpu::formats;

constexpr std::uint32_t kWidth = 64, kHeight = 48;
// Frames before the poison: every history has filled (the filter holds 12 frames by then).
constexpr std::uint32_t kPoisonedFrame = 12;
constexpr std::uint32_t kHealingFrames = 8;

// The poisoned block, in pixels, on the left wall and the floor. Pixels at
// least kFar away in x or y count as far from it: spatial reuse legitimately
// carries what changed at the block (reservoirs that are now empty) a dozen
// pixels or more at this size (4 % at 16 pixels here); at 20 the frame was
// found unchanged, bit for bit.
constexpr std::uint32_t kBlockX = 10, kBlockY = 24, kBlockSize = 6;
constexpr int kFar = 20;

enum class Input { ViewZ, Normal, Roughness, Motion, Direct, Environment, Emissive, BaseColorMetallic };
enum class Poison { NaN, Inf };

const char* name(Input input) {
  switch (input) {
    case Input::ViewZ:
      return "viewZ";
    case Input::Normal:
      return "normal";
    case Input::Roughness:
      return "roughness";
    case Input::Motion:
      return "motion";
    case Input::Direct:
      return "direct";
    case Input::Environment:
      return "environment";
    case Input::Emissive:
      return "emissive";
    case Input::BaseColorMetallic:
      return "baseColorMetallic";
  }
  return "?";
}

// One poisoning: which input, with what, and where.
struct Injection {
  Input input;
  Poison poison;
  bool block;  // false: every pixel
  std::string describe() const {
    const bool unorm = input == Input::BaseColorMetallic;  // see poisonedTexels
    const char* value = poison == Poison::NaN ? (unorm ? " all ones" : " NaN") : (unorm ? " all zeros" : " +Inf");
    return std::string(name(input)) + value + (block ? " block" : " everywhere");
  }
};

// The texel bytes of `original` with the poisoned channels of the region
// overwritten, packed tightly for a copy into that region.
std::vector<std::uint8_t> poisonedTexels(const std::vector<std::uint8_t>& original, const gpu::Image& image,
                                         const Injection& injection, const gpu::ImageRegion& region) {
  const gpu::FormatInfo& format = gpu::formatInfo(image.format());
  const std::uint32_t texelBytes = format.bytesPerPixel, channelBytes = texelBytes / format.channels;
  std::uint32_t firstChannel = 0, channelCount = format.channels;
  if (injection.input == Input::Normal) channelCount = 3;
  if (injection.input == Input::Roughness) firstChannel = 3, channelCount = 1;
  const bool nan = injection.poison == Poison::NaN;
  std::vector<std::uint8_t> texels;
  for (std::uint32_t y = region.y; y < region.y + region.height; ++y)
    for (std::uint32_t x = region.x; x < region.x + region.width; ++x) {
      std::uint8_t texel[16];
      std::memcpy(texel, &original[(std::size_t(y) * image.width() + x) * texelBytes], texelBytes);
      for (std::uint32_t c = firstChannel; c < firstChannel + channelCount; ++c) {
        std::uint8_t* channel = texel + c * channelBytes;
        if (channelBytes == 4) {
          const std::uint32_t bits = nan ? 0x7fc00000u : 0x7f800000u;
          std::memcpy(channel, &bits, 4);
        } else if (channelBytes == 2) {
          const std::uint16_t bits = nan ? 0x7e00u : 0x7c00u;
          std::memcpy(channel, &bits, 2);
        } else {
          // rgba8 unorm cannot hold NaN or infinity: the extremes it can
          // hold instead, white and fully metallic for "NaN", black for "+Inf".
          *channel = nan ? 0xffu : 0x00u;
        }
      }
      texels.insert(texels.end(), texel, texel + texelBytes);
    }
  return texels;
}

float halfToFloat(std::uint16_t bits) { return glm::unpackHalf1x16(bits); }

bool finite(float value) { return std::isfinite(value); }

// Names the first non-finite value of every image the library keeps
// (empty when all are finite). Reservoirs are checked field by field as
// shared/reservoir.glsl stores them: position, radiance, M and W.
std::string firstNonFinite(gpu::Context& context, render::GiBridge& gi) {
  const std::vector<render::GiBridge::Named> images = gi.images();
  for (const render::GiBridge::Named& named : images) {
    gpu::Image& image = *named.image;
    const std::size_t pixels = std::size_t(image.width()) * image.height();
    const auto where = [&](std::size_t i, const char* what) {
      return named.name + " pixel (" + std::to_string(i % image.width()) + ", " + std::to_string(i / image.width()) +
             ") " + what;
    };
    if (image.format() == kRgba32ui || image.format() == kRg32ui) {
      const std::vector<std::uint8_t> bytes = gpu::readbackImageBytes(context, image);
      const std::size_t words = gpu::formatInfo(image.format()).channels;
      std::vector<std::uint32_t> texels(pixels * words);
      std::memcpy(texels.data(), bytes.data(), texels.size() * 4);
      const bool firstHalf = named.name.back() == '0';  // reservoirs0: position; reservoirs1: radiance, M, W
      for (std::size_t i = 0; i < pixels; ++i) {
        const std::uint32_t* t = &texels[i * words];
        float f[3];
        std::memcpy(f, t, sizeof f);
        if (image.format() == kRg32ui) {
          if (!finite(f[0])) return where(i, "viewZ");
        } else if (firstHalf) {
          if (!finite(f[0]) || !finite(f[1]) || !finite(f[2])) return where(i, "position");
        } else {
          for (std::uint16_t half :
               {std::uint16_t(t[0]), std::uint16_t(t[0] >> 16), std::uint16_t(t[1]), std::uint16_t(t[1] >> 16)})
            if (!finite(halfToFloat(half))) return where(i, "radiance or M");
          if (!finite(f[2])) return where(i, "W");
        }
      }
      continue;
    }
    const io::ImageF values = gpuio::readbackImage(context, image);
    for (std::size_t i = 0; i < values.pixels.size(); ++i)
      if (!finite(values.pixels[i])) return where(i / values.channelCount(), "value");
  }
  return {};
}

double luminanceAt(const io::ImageF& image, int x, int y) {
  return shared::luminance(glm::vec3(image.at(x, y, 0), image.at(x, y, 1), image.at(x, y, 2)));
}

// Pixels from the block in x or y (0 inside it).
int distanceFromBlock(int x, int y) {
  const int dx = std::max({int(kBlockX) - x, x - int(kBlockX + kBlockSize - 1), 0});
  const int dy = std::max({int(kBlockY) - y, y - int(kBlockY + kBlockSize - 1), 0});
  return std::max(dx, dy);
}

// How far a frame is from another over the pixels within `reach` of the
// block (any reach beyond the image: all of it): the mean absolute luminance
// difference over the mean luminance of `reference`.
double difference(const io::ImageF& reference, const io::ImageF& test, int reach) {
  double sum = 0.0, total = 0.0;
  for (int y = 0; y < reference.height; ++y)
    for (int x = 0; x < reference.width; ++x) {
      if (distanceFromBlock(x, y) > reach) continue;
      sum += std::abs(luminanceAt(test, x, y) - luminanceAt(reference, x, y));
      total += luminanceAt(reference, x, y);
    }
  return sum / total;
}
constexpr int kEverywhere = 1 << 20;
// Around a block, what its poison may legitimately have touched by then.
constexpr int kAroundBlock = 4;

class GiNanTest : public testing::GpuTest {
 protected:
  Settings settings_;  // the library's defaults, or the denoiser's variant below
  struct Run {
    std::unique_ptr<scene::Scene> scene;
    std::unique_ptr<render::FrameRenderer> renderer;
    std::unique_ptr<render::GiBridge> gi;
    std::unique_ptr<gpu::FrameLoop> loop;
    render::FrameView previous{};
    std::uint32_t frames = 0;
  };

  Run start() {
    Run run;
    run.scene = std::make_unique<scene::Scene>(scene::makeBuiltinScene("cornell"));
    run.renderer = std::make_unique<render::FrameRenderer>(context(), *run.scene,
                                                           testing::smallRendererOptions(*run.scene, kWidth, kHeight));
    run.gi = std::make_unique<render::GiBridge>(context(), ContextDesc{.maxWidth = kWidth, .maxHeight = kHeight},
                                                settings_);
    run.loop = std::make_unique<gpu::FrameLoop>(context(), render::FrameRenderer::kFramesInFlight);
    return run;
  }

  // One frame; `afterRenderer` records what goes between the renderer's
  // passes and the library's, `beforeRenderer` what goes before both.
  void frame(Run& run, bool cut = false, const std::function<void(gpu::Recorder&)>& afterRenderer = {},
             const std::function<void(gpu::Recorder&)>& beforeRenderer = {}) {
    gpu::Recorder& recorder = run.loop->beginFrame();
    const std::uint64_t index = run.loop->frameIndex();
    const render::FrameView view{*run.scene->suggestedCamera, 0.0f, cut || run.frames == 0};
    if (beforeRenderer) beforeRenderer(recorder);
    run.renderer->record(recorder, index, view);
    if (afterRenderer) afterRenderer(recorder);
    run.gi->record(recorder, *run.renderer, index, view, run.previous, {.separateEmissive = true});
    run.loop->endFrame();
    run.previous = view;
    ++run.frames;
  }

  io::ImageF composite(Run& run) {
    run.loop->finish();
    return gpuio::readbackImage(context(), run.gi->composite());
  }

  gpu::Image& target(Run& run, Input input) {
    switch (input) {
      case Input::ViewZ:
        return run.renderer->viewZ();
      case Input::Normal:
      case Input::Roughness:
        return run.renderer->normalRoughness();
      case Input::Motion:
        return run.renderer->motion();
      case Input::Direct:
        return run.renderer->direct();
      case Input::Environment:
        return run.renderer->environment().radiance();
      case Input::Emissive:
        return run.renderer->emissive();
      case Input::BaseColorMetallic:
        return run.renderer->baseColorMetallic();
    }
    throw std::logic_error("unknown input");
  }

  // The unpoisoned run's frame at the poisoned frame and kHealingFrames
  // later, and the latter of a run with a camera cut at the poisoned frame.
  struct Baselines {
    io::ImageF atPoison, healed, cutHealed;
  };
  Baselines baselines() {
    Baselines b;
    Run run = start();
    for (std::uint32_t f = 0; f < kPoisonedFrame; ++f) frame(run);
    frame(run);
    b.atPoison = composite(run);
    for (std::uint32_t f = 0; f < kHealingFrames; ++f) frame(run);
    b.healed = composite(run);
    Run cut = start();
    for (std::uint32_t f = 0; f < kPoisonedFrame; ++f) frame(cut);
    frame(cut, true);
    for (std::uint32_t f = 0; f < kHealingFrames; ++f) frame(cut);
    b.cutHealed = composite(cut);
    return b;
  }

  // Poisons `input` four ways (NaN and +Inf, everywhere and in the block)
  // and checks (a), (b) and (c) for each.
  void checkInput(Input input) {
    const Baselines base = baselines();
    for (const Poison poison : {Poison::NaN, Poison::Inf})
      for (const bool block : {false, true}) checkInjection({input, poison, block}, base);
  }

  void checkInjection(const Injection& injection, const Baselines& base) {
    SCOPED_TRACE(injection.describe());
    Run run = start();
    for (std::uint32_t f = 0; f < kPoisonedFrame; ++f) frame(run);
    run.loop->finish();
    // The renderer makes the same images every frame of this static view,
    // so the last frame's are what it writes again before the poison.
    gpu::Image& image = target(run, injection.input);
    ASSERT_EQ(image.desc().mipLevels, 1u) << "cornell has no sky: its environment is one black level";
    const std::vector<std::uint8_t> original = gpu::readbackImageBytes(context(), image);
    const std::uint32_t blockSize = injection.input == Input::Environment ? 4 : kBlockSize;
    const gpu::ImageRegion region = injection.block
                                        ? gpu::ImageRegion{.x = injection.input == Input::Environment ? 4 : kBlockX,
                                                           .y = injection.input == Input::Environment ? 2 : kBlockY,
                                                           .width = blockSize,
                                                           .height = blockSize}
                                        : gpu::ImageRegion{.width = image.width(), .height = image.height()};
    const std::vector<std::uint8_t> poisoned = poisonedTexels(original, image, injection, region);
    gpu::Buffer poison(context(), "tests.poison", poisoned.size(), gpu::BufferUsage::Upload);
    std::memcpy(poison.mapped(), poisoned.data(), poisoned.size());
    frame(run, false, [&](gpu::Recorder& recorder) { recorder.copyBufferToImage(poison, image, region); });

    // (a) at the poisoned frame.
    const io::ImageF atPoison = composite(run);
    ASSERT_EQ(firstNonFinite(context(), *run.gi), "") << "at the poisoned frame";
    // (b) far from a poisoned block the frame is the unpoisoned one, or close.
    if (injection.block) {
      double worst = 0.0;
      for (int y = 0; y < int(kHeight); ++y)
        for (int x = 0; x < int(kWidth); ++x) {
          if (distanceFromBlock(x, y) < kFar) continue;
          const double expected = luminanceAt(base.atPoison, x, y), actual = luminanceAt(atPoison, x, y);
          worst = std::max(worst, std::abs(actual - expected) / std::max(expected, 1e-3));
        }
      std::printf("%s: far pixels at the poisoned frame differ by at most %.2e (relative)\n",
                  injection.describe().c_str(), worst);
      EXPECT_LE(worst, 0.01) << "the poison spread beyond its block";
    }

    // The environment is the renderer's once-made image: put it back, so it
    // too is poisoned for one frame only.
    gpu::Buffer restore(context(), "tests.restore", original.size(), gpu::BufferUsage::Upload);
    std::memcpy(restore.mapped(), original.data(), original.size());
    const auto unpoisonEnvironment = [&](gpu::Recorder& recorder) {
      if (injection.input == Input::Environment) recorder.copyBufferToImage(restore, image);
    };
    // (a) after it, every frame's composite and, on the next frame, all history.
    for (std::uint32_t f = 1; f <= kHealingFrames; ++f) {
      frame(run, false, {}, f == 1 ? unpoisonEnvironment : std::function<void(gpu::Recorder&)>{});
      const io::ImageF frameImage = composite(run);
      for (float value : frameImage.pixels) ASSERT_TRUE(finite(value)) << f << " frames after the poisoned one";
      if (f == 1) {
        ASSERT_EQ(firstNonFinite(context(), *run.gi), "") << "the frame after the poisoned one";
      }
    }
    ASSERT_EQ(firstNonFinite(context(), *run.gi), "") << kHealingFrames << " frames after the poisoned one";
    // (c) healed as well as a cut heals.
    const int reach = injection.block ? kAroundBlock : kEverywhere;
    const double healedDifference = difference(base.healed, composite(run), reach);
    const double cutDifference = difference(base.healed, base.cutHealed, reach);
    std::printf("%s: %u frames later the frame%s differs from the unpoisoned run's by %.4f; after a cut, by %.4f\n",
                injection.describe().c_str(), kHealingFrames, injection.block ? " around the block" : "",
                healedDifference, cutDifference);
    EXPECT_LE(healedDifference, cutDifference) << "the history has not healed";
  }
};

TEST_F(GiNanTest, ViewZ) { checkInput(Input::ViewZ); }
TEST_F(GiNanTest, Normal) { checkInput(Input::Normal); }
TEST_F(GiNanTest, Roughness) { checkInput(Input::Roughness); }
TEST_F(GiNanTest, Motion) { checkInput(Input::Motion); }
TEST_F(GiNanTest, DirectLight) { checkInput(Input::Direct); }
TEST_F(GiNanTest, Environment) { checkInput(Input::Environment); }
TEST_F(GiNanTest, Emissive) { checkInput(Input::Emissive); }
// rgba8: the extremes it can hold stand in for NaN and infinity.
TEST_F(GiNanTest, BaseColorMetallic) { checkInput(Input::BaseColorMetallic); }

// The same with the denoiser in place of the branches' filters, for the
// inputs its passes read themselves (surfaces, motion) and for the light.
class GiNanDenoisedTest : public GiNanTest {
 protected:
  GiNanDenoisedTest() { settings_.denoise.enabled = true; }
};
TEST_F(GiNanDenoisedTest, ViewZ) { checkInput(Input::ViewZ); }
TEST_F(GiNanDenoisedTest, Normal) { checkInput(Input::Normal); }
TEST_F(GiNanDenoisedTest, Motion) { checkInput(Input::Motion); }
TEST_F(GiNanDenoisedTest, DirectLight) { checkInput(Input::Direct); }

}  // namespace
}  // namespace bounce::gi

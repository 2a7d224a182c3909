// The engine's images as the GI library takes them (include/bounce/gi.h):
// every accepted format of an input's family, motion in the engine's units
// and direction, and a render size smaller than the images. Each case feeds
// one GiContext the renderer's own G-buffer and another the same G-buffer
// converted on the CPU into the other formats, frame by frame, and compares
// what the two make. Refusals of wrong inputs are in test_gi.cpp
// (BadInputsAreRefusedWithTheirNames).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>
#include <vector>

#include "bounce/gi.h"
#include "gpu/format.h"
#include "gpu/frame_loop.h"
#include "gpu_test.h"
#include "image_statistics.h"
#include "gpuio/gpu_images.h"
#include "render/frame_renderer.h"
#include "render/gi_bridge.h"
#include "scene/builtin_scenes.h"
#include "shared/color.glsl"
#include "shared/packing.glsl"
#include "test_meshes.h"

namespace bounce::gi {
namespace {

constexpr std::uint32_t kWidth = 64, kHeight = 48;

// How the second context's inputs differ from the renderer's.
struct Conversion {
  VkFormat viewZ = VK_FORMAT_R32_SFLOAT;
  VkFormat normalRoughness = VK_FORMAT_R16G16B16A16_SFLOAT;
  VkFormat baseColorMetallic = VK_FORMAT_R8G8B8A8_UNORM;
  VkFormat motion = VK_FORMAT_R16G16_SFLOAT;
  VkFormat direct = VK_FORMAT_R16G16B16A16_SFLOAT;
  // VK_FORMAT_UNDEFINED: the renderer's ids image (instance << 16 | material).
  // Else the ids' low 8 bits in this format, or what `materialIdOf` makes of them.
  VkFormat materialId = VK_FORMAT_UNDEFINED;
  std::function<std::uint32_t(std::size_t frame, int x, int y, std::uint32_t id)> materialIdOf;
  bool motionInUvYUp = false;  // motion stored as uv, y pointing up
  Settings settings;           // of the second context
  std::uint32_t imageWidth = kWidth, imageHeight = kHeight;  // the images; the render size stays kWidth x kHeight
};

io::ImageF convert(const io::ImageF& in, VkFormat format, std::uint32_t width, std::uint32_t height,
                   const std::function<void(const float* from, float* to)>& texel) {
  const int channels = int(gpu::formatInfo(format).channels);
  std::vector<std::string> names = {"R", "G", "B", "A"};
  names.resize(std::size_t(channels));
  io::ImageF out(int(width), int(height), names);
  std::vector<float> from(in.channelCount());
  std::vector<float> to(4);  // texel() may write four; the format keeps its channels
  for (int y = 0; y < in.height; ++y)
    for (int x = 0; x < in.width; ++x) {
      for (std::size_t c = 0; c < in.channelCount(); ++c) from[c] = in.at(x, y, int(c));
      std::fill(to.begin(), to.end(), 0.0f);
      texel(from.data(), to.data());
      for (int c = 0; c < channels; ++c) out.at(x, y, c) = to[std::size_t(c)];
    }
  return out;
}

class GiInputs : public testing::GpuTest {
 protected:
  struct Result {
    std::vector<io::ImageF> composites[2];  // each frame's, both contexts
    std::vector<io::ImageF> histories[2];   // each frame's indirect diffuse (alpha: history length)
  };

  // Renders `poses` (the first a cut) and gives each frame to both contexts.
  Result run(const Conversion& conversion, const std::vector<scene::CameraPose>& poses) {
    const scene::Scene cornell = scene::makeBuiltinScene("cornell");
    render::FrameRenderer renderer(context(), cornell, testing::smallRendererOptions(cornell, kWidth, kHeight));
    gpu::FrameLoop loop(context(), render::FrameRenderer::kFramesInFlight);
    render::GiBridge first(context(), {.maxWidth = kWidth, .maxHeight = kHeight});
    render::GiBridge second(context(), {.maxWidth = conversion.imageWidth, .maxHeight = conversion.imageHeight},
                            conversion.settings);
    const auto image = [&](const char* name, VkFormat format) {
      return std::make_unique<gpu::Image>(
          context(), gpu::ImageDesc{.name = name, .width = conversion.imageWidth, .height = conversion.imageHeight,
                                    .format = format, .storage = false});
    };
    auto viewZ = image("engine.viewZ", conversion.viewZ);
    auto normals = image("engine.normalRoughness", conversion.normalRoughness);
    auto albedo = image("engine.baseColorMetallic", conversion.baseColorMetallic);
    auto motion = image("engine.motion", conversion.motion);
    auto direct = image("engine.direct", conversion.direct);
    auto materialId = conversion.materialId != VK_FORMAT_UNDEFINED
                          ? image("engine.materialId", conversion.materialId)
                          : std::unique_ptr<gpu::Image>();

    Result result;
    render::FrameView previous{};
    for (std::size_t frame = 0; frame < poses.size(); ++frame) {
      const render::FrameView view{poses[frame], 0.0f, frame == 0};
      gpu::Recorder& recorder = loop.beginFrame();
      renderer.record(recorder, frame, view);
      const render::RendererInputs made = render::rendererInputs(renderer, frame, view, previous);
      first.record(recorder, made.inputs, made.images);
      loop.endFrame();
      loop.finish();
      previous = view;

      const std::uint32_t w = conversion.imageWidth, h = conversion.imageHeight;
      gpuio::uploadImage(context(), *viewZ,
                         convert(gpuio::readbackImage(context(), renderer.viewZ()), conversion.viewZ, w, h,
                                 [](const float* from, float* to) { to[0] = from[0]; }));
      const bool octahedral = conversion.normalRoughness == VK_FORMAT_A2B10G10R10_UNORM_PACK32;
      gpuio::uploadImage(context(), *normals,
                         convert(gpuio::readbackImage(context(), renderer.normalRoughness()),
                                 conversion.normalRoughness, w, h, [&](const float* from, float* to) {
                                   if (!octahedral) {
                                     std::copy_n(from, 4, to);
                                     return;
                                   }
                                   const glm::vec3 n(from[0], from[1], from[2]);
                                   const glm::vec2 e = glm::dot(n, n) > 0.0f
                                                           ? shared::encodeOctahedral(glm::normalize(n))
                                                           : glm::vec2(0.0f);
                                   to[0] = e.x * 0.5f + 0.5f;
                                   to[1] = e.y * 0.5f + 0.5f;
                                   to[2] = from[3];
                                   to[3] = 1.0f;
                                 }));
      gpuio::uploadImage(context(), *albedo,
                         convert(gpuio::readbackImage(context(), renderer.baseColorMetallic()),
                                 conversion.baseColorMetallic, w, h,
                                 [](const float* from, float* to) { std::copy_n(from, 4, to); }));
      const float uvX = conversion.motionInUvYUp ? 1.0f / kWidth : 1.0f;
      const float uvY = conversion.motionInUvYUp ? -1.0f / kHeight : 1.0f;
      gpuio::uploadImage(context(), *motion,
                         convert(gpuio::readbackImage(context(), renderer.motion()), conversion.motion, w, h,
                                 [&](const float* from, float* to) {
                                   to[0] = from[0] * uvX;
                                   to[1] = from[1] * uvY;
                                 }));
      gpuio::uploadImage(context(), *direct,
                         convert(gpuio::readbackImage(context(), renderer.direct()), conversion.direct, w, h,
                                 [](const float* from, float* to) { std::copy_n(from, 4, to); }));

      if (materialId)
        gpuio::uploadImage(context(), *materialId,
                           convert(gpuio::readbackImage(context(), renderer.ids()), conversion.materialId, w, h,
                                   [&, frame, texel = 0](const float* from, float* to) mutable {
                                     const int x = texel % int(w), y = texel / int(w);
                                     ++texel;
                                     const std::uint32_t id = std::uint32_t(from[0]) & 0xFFu;
                                     to[0] = float(conversion.materialIdOf ? conversion.materialIdOf(frame, x, y, id)
                                                                           : id);
                                   }));

      gi::FrameInputs inputs = made.inputs;
      inputs.viewZ = render::imageRef(*viewZ);
      inputs.normalRoughness = render::imageRef(*normals);
      inputs.baseColorMetallic = render::imageRef(*albedo);
      inputs.motion = render::imageRef(*motion);
      inputs.direct = render::imageRef(*direct);
      std::vector<gpu::Image*> images = {viewZ.get(),  normals.get(), albedo.get(),
                                         motion.get(), direct.get(),  &renderer.environment().radiance()};
      if (materialId) {
        inputs.materialId = render::imageRef(*materialId);
        images.push_back(materialId.get());
      } else {
        images.push_back(&renderer.ids());
      }
      second.record(loop.beginFrame(), inputs, images);
      loop.endFrame();
      loop.finish();

      render::GiBridge* bridges[] = {&first, &second};
      for (int i = 0; i < 2; ++i) {
        result.composites[i].push_back(crop(gpuio::readbackImage(context(), bridges[i]->composite())));
        result.histories[i].push_back(crop(gpuio::readbackImage(context(), bridges[i]->indirect(gi::kDiffuseSignal))));
      }
    }
    return result;
  }

  static io::ImageF crop(const io::ImageF& image) {
    io::ImageF out(int(kWidth), int(kHeight), image.channels);
    for (int y = 0; y < int(kHeight); ++y)
      for (int x = 0; x < int(kWidth); ++x)
        for (int c = 0; c < int(image.channelCount()); ++c) out.at(x, y, c) = image.at(x, y, c);
    return out;
  }
};

using bounce::testing::meanLuminance;

// The fraction of pixels whose history lengths (alpha) agree.
double sameHistory(const io::ImageF& a, const io::ImageF& b) {
  int same = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) same += a.at(x, y, 3) == b.at(x, y, 3);
  return double(same) / (double(a.width) * a.height);
}

// Ten frames still, then a fast sideways turn: history survives only where
// the motion vectors are read right.
std::vector<scene::CameraPose> stillThenTurn() {
  const scene::CameraPose front = *scene::makeBuiltinScene("cornell").suggestedCamera;
  std::vector<scene::CameraPose> poses(10, front);
  scene::CameraPose turned = front;
  turned.position.x += 0.6f;
  turned.target.x -= 0.4f;
  poses.push_back(turned);
  return poses;
}

// The frame's mean and the pixels whose history survived, against the renderer's formats.
void expectSameFrames(const char* what, const std::vector<io::ImageF> (&composites)[2],
                      const std::vector<io::ImageF> (&histories)[2]) {
  for (std::size_t frame : {std::size_t(9), std::size_t(10)}) {
    const double a = meanLuminance(composites[0][frame]), b = meanLuminance(composites[1][frame]);
    const double history = sameHistory(histories[0][frame], histories[1][frame]);
    std::printf("%s, frame %zu: mean %.4f (renderer's formats) %.4f, same history at %.1f %% of pixels\n", what,
                frame, a, b, 100.0 * history);
    EXPECT_NEAR(b / a, 1.0, 0.03) << what << ", frame " << frame;
    EXPECT_GT(history, 0.95) << what << ", frame " << frame;
  }
}

// The other format of each G-buffer family at once: R16F viewZ, octahedral
// normals in RGB10A2, sRGB base colour, RG32F motion, R8UI material ids
// (then R16UI).
TEST_F(GiInputs, EveryFormatOfEachFamilyMakesTheSameFrame) {
  Conversion other{.viewZ = VK_FORMAT_R16_SFLOAT,
                   .normalRoughness = VK_FORMAT_A2B10G10R10_UNORM_PACK32,
                   .baseColorMetallic = VK_FORMAT_R8G8B8A8_SRGB,
                   .motion = VK_FORMAT_R32G32_SFLOAT,
                   .materialId = VK_FORMAT_R8_UINT};
  const Result r = run(other, stillThenTurn());
  expectSameFrames("R16F, RGB10A2, sRGB, RG32F, R8UI", r.composites, r.histories);
  other.materialId = VK_FORMAT_R16_UINT;
  const Result r16 = run(other, stillThenTurn());
  expectSameFrames("R16F, RGB10A2, sRGB, RG32F, R16UI", r16.composites, r16.histories);
}

// REBLUR's material test: where the material id of a still surface
// changes, the denoiser keeps none of its history (the history length
// the composite reads starts over at 1), and elsewhere keeps it. With the
// ids unchanged (the first context, the renderer's own) nothing restarts.
TEST_F(GiInputs, AChangedMaterialIdRestartsTheDenoisersHistoryThere) {
  constexpr std::size_t kChange = 6;
  const scene::CameraPose front = *scene::makeBuiltinScene("cornell").suggestedCamera;
  const Conversion changed{.materialId = VK_FORMAT_R32_UINT,
                           .materialIdOf = [](std::size_t frame, int x, int, std::uint32_t id) {
                             return frame >= kChange && x < int(kWidth) / 2 ? id + 1u : id;
                           }};
  const Result r = run(changed, std::vector<scene::CameraPose>(kChange + 2, front));
  const io::ImageF& unchanged = r.histories[0][kChange];
  const io::ImageF& left = r.histories[1][kChange];
  const io::ImageF& after = r.histories[1][kChange + 1];
  int surfaces = 0;
  for (int y = 0; y < int(kHeight); ++y)
    for (int x = 0; x < int(kWidth); ++x) {
      if (unchanged.at(x, y, 3) <= 0.0f) continue;  // no surface
      ++surfaces;
      ASSERT_GT(unchanged.at(x, y, 3), 1.0f) << x << "," << y << ": the renderer's ids did not change";
      if (x < int(kWidth) / 2) {
        ASSERT_EQ(left.at(x, y, 3), 1.0f) << x << "," << y << ": the material changed here";
        ASSERT_EQ(after.at(x, y, 3), 2.0f) << x << "," << y << ": and stayed the new one";
      } else {
        ASSERT_GT(left.at(x, y, 3), 1.0f) << x << "," << y << ": the material did not change here";
      }
    }
  EXPECT_GT(surfaces, int(kWidth * kHeight) / 2);
}

// Motion as fractions of the render size with y up, told by the settings:
// the same history survives the turn. Told nothing, it does not.
TEST_F(GiInputs, MotionUnitsAndDirectionAreSettings) {
  Conversion uvYUp{.motionInUvYUp = true};
  uvYUp.settings.input.motionUnits = MotionUnits::Uv;
  uvYUp.settings.input.motionScaleY = -1.0f;
  const Result told = run(uvYUp, stillThenTurn());
  const double agreement = sameHistory(told.histories[0].back(), told.histories[1].back());
  uvYUp.settings.input = {};
  const Result untold = run(uvYUp, stillThenTurn());
  const double misread = sameHistory(untold.histories[0].back(), untold.histories[1].back());
  std::printf("after the turn: same history at %.1f %% of pixels with the settings, %.1f %% without\n",
              100.0 * agreement, 100.0 * misread);
  EXPECT_GT(agreement, 0.98);
  EXPECT_LT(misread, 0.9) << "motion read in the wrong units must change what history survives";
}

// Images larger than the render size (a viewport in the engine's larger
// targets, and a context made for the larger size): the frame is the same
// as with images of exactly the render size.
TEST_F(GiInputs, ARenderSizeSmallerThanTheImagesMakesTheSameFrame) {
  const Result r = run({.imageWidth = kWidth + 16, .imageHeight = kHeight + 12}, stillThenTurn());
  for (std::size_t frame = 0; frame < r.composites[0].size(); ++frame) {
    const io::ImageF& a = r.composites[0][frame];
    const io::ImageF& b = r.composites[1][frame];
    ASSERT_EQ(a.pixels, b.pixels) << "frame " << frame;
  }
}

}  // namespace
}  // namespace bounce::gi

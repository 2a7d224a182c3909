// The denoiser on an engine's own signals (FrameInputs::noisyDiffuse,
// noisySpecular; docs/gi.md, "Denoising an engine's own signals"). The
// signals here are made on the CPU, so their truth is known exactly and
// owes nothing to the library's reservoirs or the path tracer: over
// cornell's G-buffer (a static view, 64x48), a smooth demodulated light
// per surface (its normal as a colour), and every frame that light times
// 4 at a random quarter of the pixels and 0 elsewhere: the mean is the
// truth, the noise is a 1-spp path tracer's kind (most samples dark, a few
// bright), relMSE 3 per frame. (bounce denoise does the same with the path
// tracer's 1-spp signals: tests/test_cli.cpp.) In checkerboard mode
// (gi.denoise.checkerboard) the engine hands over half of each frame's
// samples, packed to half the width: the same noise, every other pixel.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "bounce/gi.h"
#include "gi/image_table.h"
#include "gi/unit_catalog.h"
#include "gpu/format.h"
#include "gpu/frame_loop.h"
#include "gpu_test.h"
#include "gpuio/gpu_images.h"
#include "image_statistics.h"
#include "metrics/image_metrics.h"
#include "render/frame_renderer.h"
#include "render/gi_bridge.h"
#include "scene/builtin_scenes.h"
#include "shared/checkerboard.glsl"
#include "shared/color.glsl"
#include "test_meshes.h"

namespace bounce::gi {
namespace {

constexpr std::uint32_t kWidth = 64, kHeight = 48;
constexpr int kDiffuse = 0, kSpecular = 1;
// The hit distance each signal carries: unknown for diffuse (the widest
// blur), a near wall for specular.
constexpr float kHitDistance[2] = {0.0f, 2.0f};
// A quarter of the samples bright: the mean is the truth.
constexpr float kBrightShare = 0.25f;

double relMse(const io::ImageF& reference, const io::ImageF& test) {
  return metrics::valueErrors(reference.pixels, test.pixels).relMse;
}

io::ImageF rgb(const io::ImageF& image) { return io::firstChannels(image, 3); }

using bounce::testing::meanLuminance;

shared::uint checkerboardParityOf(int signal) {
  return signal == kDiffuse ? shared::kCheckerboardDiffuseParity : shared::kCheckerboardSpecularParity;
}

bool hasSample(int x, int y, int signal, std::uint64_t frameIndex) {
  return shared::checkerboardHasData(glm::uvec2(x, y), shared::uint(frameIndex), checkerboardParityOf(signal));
}

// What an engine in checkerboard mode hands over of a full signal: the
// pixels of the signal's parity in frame `frameIndex`, packed to half width.
io::ImageF packCheckerboard(const io::ImageF& full, int signal, std::uint64_t frameIndex) {
  io::ImageF packed(int(shared::checkerboardPackedWidth(shared::uint(full.width))), full.height, full.channels);
  for (int y = 0; y < full.height; ++y)
    for (int x = 0; x < full.width; ++x)
      if (hasSample(x, y, signal, frameIndex))
        for (std::size_t c = 0; c < full.channelCount(); ++c)
          packed.at(int(shared::checkerboardPackedColumn(shared::uint(x))), y, int(c)) = full.at(x, y, int(c));
  return packed;
}

class GiEngineSignals : public testing::GpuTest {
 protected:
  struct Run {
    std::unique_ptr<scene::Scene> scene;  // the renderer keeps a reference to it
    std::unique_ptr<render::FrameRenderer> renderer;
    std::unique_ptr<render::GiBridge> gi;
    std::unique_ptr<gpu::FrameLoop> loop;
    std::unique_ptr<gpu::Image> noisy[2];  // the engine's signals: sampled rgba32f, as an engine might keep them
    // The engine's own further signals given this frame (FrameInputs::noisy[id]), uploaded by the test.
    std::vector<std::pair<SignalId, gpu::Image*>> extra;
    bool checkerboard = false;             // gi.denoise.checkerboard: they are packed to half width
    io::ImageF truth;                      // the noise-free signal (rgb), once the first frame has run
    io::ImageF lastNoisy[2];               // the last frame's signals before any packing, rgb
    render::FrameView previous{};
    std::uint64_t lastFrameIndex = 0;  // FrameInputs::frameIndex of the last frame
    std::uint32_t frames = 0;
    std::mt19937 random{7};
  };

  // `signals`: the engine's own signals beyond the library's two (ContextDesc::signals).
  Run start(const Settings& settings, std::vector<SignalDesc> signals = {}) {
    Run run;
    run.scene = std::make_unique<scene::Scene>(scene::makeBuiltinScene("cornell"));
    run.renderer = std::make_unique<render::FrameRenderer>(context(), *run.scene,
                                                           testing::smallRendererOptions(*run.scene, kWidth, kHeight));
    run.gi = std::make_unique<render::GiBridge>(
        context(), ContextDesc{.maxWidth = kWidth, .maxHeight = kHeight, .signals = std::move(signals)}, settings);
    run.loop = std::make_unique<gpu::FrameLoop>(context(), render::FrameRenderer::kFramesInFlight);
    run.checkerboard = settings.denoise.checkerboard;
    for (int s = 0; s < 2; ++s)
      run.noisy[s] = std::make_unique<gpu::Image>(
          context(), gpu::ImageDesc{.name = s == kDiffuse ? "engine.noisy_diffuse" : "engine.noisy_specular",
                                    .width = run.checkerboard ? shared::checkerboardPackedWidth(kWidth) : kWidth,
                                    .height = kHeight,
                                    .format = VK_FORMAT_R32G32B32A32_SFLOAT,
                                    .storage = false});
    return run;
  }

  // The light of each surface: its normal as a colour (constant over each
  // of cornell's planes), none on the background.
  static io::ImageF truthOf(const io::ImageF& viewZ, const io::ImageF& normals) {
    io::ImageF truth(viewZ.width, viewZ.height, {"R", "G", "B"});
    for (int y = 0; y < viewZ.height; ++y)
      for (int x = 0; x < viewZ.width; ++x)
        for (int c = 0; c < 3; ++c)
          truth.at(x, y, c) = viewZ.at(x, y, 0) > 0.0f ? 0.2f + 0.6f * std::abs(normals.at(x, y, c)) : 0.0f;
    return truth;
  }

  // This frame's noisy signals, uploaded (packed in checkerboard mode, for
  // frame `frameIndex`); `poison` may change them first. The random draws
  // are the same in either mode.
  void makeNoisy(Run& run, std::uint64_t frameIndex, const std::function<void(int signal, io::ImageF&)>& poison) {
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    for (int s = 0; s < 2; ++s) {
      io::ImageF noisy(int(kWidth), int(kHeight), {"R", "G", "B", "A"});
      for (int y = 0; y < int(kHeight); ++y)
        for (int x = 0; x < int(kWidth); ++x) {
          const float weight = uniform(run.random) < kBrightShare ? 1.0f / kBrightShare : 0.0f;
          for (int c = 0; c < 3; ++c) noisy.at(x, y, c) = run.truth.at(x, y, c) * weight;
          noisy.at(x, y, 3) = kHitDistance[s];
        }
      if (poison) poison(s, noisy);
      gpuio::uploadImage(context(), *run.noisy[s], run.checkerboard ? packCheckerboard(noisy, s, frameIndex) : noisy);
      run.lastNoisy[s] = rgb(noisy);
    }
  }

  // One frame of the static view: the renderer, then the library with the
  // signals `give` names (`poison` may change them; `edit` the inputs).
  void frame(Run& run, std::array<bool, 2> give = {true, true}, bool cut = false,
             const std::function<void(int signal, io::ImageF&)>& poison = {},
             const std::function<void(FrameInputs&)>& edit = {}) {
    if (run.frames == 0) {
      // The truth comes from the G-buffer, which the first frame makes.
      const render::FrameView view{*run.scene->suggestedCamera, 0.0f, true};
      run.renderer->record(run.loop->beginFrame(), run.loop->frameIndex(), view);
      run.loop->endFrame();
      run.loop->finish();
      run.truth = truthOf(gpuio::readbackImage(context(), run.renderer->viewZ()),
                          gpuio::readbackImage(context(), run.renderer->normalRoughness()));
    }
    run.loop->finish();  // the uploads below replace what the last frame read
    // The frame the signals are for: the next after the renderer's last.
    const std::uint64_t next = run.loop->frameIndex() + 1;
    makeNoisy(run, next, poison);
    gpu::Recorder& recorder = run.loop->beginFrame();
    const std::uint64_t index = run.loop->frameIndex();
    EXPECT_EQ(index, next) << "the checkerboard was packed for another frame";
    const render::FrameView view{*run.scene->suggestedCamera, 0.0f, cut || run.frames == 0};
    run.renderer->record(recorder, index, view);
    render::RendererInputs made = render::rendererInputs(*run.renderer, index, view, run.previous);
    if (give[kDiffuse]) {
      made.inputs.noisyDiffuse = render::imageRef(*run.noisy[kDiffuse]);
      made.images.push_back(run.noisy[kDiffuse].get());
    }
    if (give[kSpecular]) {
      made.inputs.noisySpecular = render::imageRef(*run.noisy[kSpecular]);
      made.images.push_back(run.noisy[kSpecular].get());
    }
    for (const auto& [id, image] : run.extra) {
      if (made.inputs.noisy.size() <= id) made.inputs.noisy.resize(id + 1);
      made.inputs.noisy[id] = render::imageRef(*image);
      made.images.push_back(image);
    }
    if (edit) edit(made.inputs);
    run.gi->record(recorder, made.inputs, made.images);
    run.loop->endFrame();
    run.previous = view;
    run.lastFrameIndex = index;
    ++run.frames;
  }

  // The denoised signals and the frame, once the frames recorded so far have run.
  struct Output {
    io::ImageF signal[2];  // rgba: radiance, history length
    io::ImageF composite;
  };
  Output output(Run& run) {
    run.loop->finish();
    return {{gpuio::readbackImage(context(), run.gi->indirect(gi::kDiffuseSignal)),
             gpuio::readbackImage(context(), run.gi->indirect(gi::kSpecularSignal))},
            gpuio::readbackImage(context(), run.gi->composite())};
  }

  // Refusals of bad inputs: after a frame of `run`, a frame is begun and
  // the renderer records into it; `good` holds the inputs the library
  // takes (the renderer's G-buffer and both noisy signals), and each
  // `refused(gi, inputs, words)` in `checks` records `inputs` into `gi`
  // and expects an Error containing `words`. The frame ends after them.
  using Refused = std::function<void(GiContext& gi, const FrameInputs& inputs, const std::string& words)>;
  void expectRefusals(Run& run, const std::function<void(const FrameInputs& good, const Refused& refused)>& checks) {
    frame(run);
    run.loop->finish();
    gpu::Recorder& recorder = run.loop->beginFrame();
    const render::FrameView view{*run.scene->suggestedCamera, 0.0f, false};
    run.renderer->record(recorder, run.loop->frameIndex(), view);
    FrameInputs good = render::rendererInputs(*run.renderer, run.loop->frameIndex(), view, view).inputs;
    good.noisyDiffuse = render::imageRef(*run.noisy[kDiffuse]);
    good.noisySpecular = render::imageRef(*run.noisy[kSpecular]);
    checks(good, [&](GiContext& gi, const FrameInputs& inputs, const std::string& words) {
      try {
        gi.record(recorder.commandBuffer(), inputs);
      } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
        return;
      }
      ADD_FAILURE() << "accepted: " << words;
    });
    run.loop->endFrame();
  }

  // What each pass of the frames recorded so far wrote right after it ran
  // (frames that capture their stages: FrameInputs::captureStages); the
  // denoiser's scratch images hold each signal in turn, so their copies
  // are where one signal's is seen. Takes the captures: a second call
  // returns the frames' since.
  std::vector<gpu::CapturedStage> stageOutputs(Run& run) {
    run.loop->finish();
    return run.loop->takeCaptures();
  }
  static io::ImageF stageOutput(const std::vector<gpu::CapturedStage>& captures, const std::string& pass,
                                const std::string& binding) {
    for (auto it = captures.rbegin(); it != captures.rend(); ++it)
      if (it->pass == pass && it->binding == binding) return gpuio::texelsToImage(it->image, it->texels.data());
    ADD_FAILURE() << "no capture of " << pass << " " << binding;
    return {};
  }

  // The passes of the frames recorded so far, once they have run.
  std::vector<std::string> passesRecorded(Run& run) {
    run.loop->finish();
    std::vector<std::string> passes;
    for (const gpu::PassTiming& t : run.loop->timings().summary()) passes.push_back(t.pass);
    return passes;
  }

  static Settings denoised() {
    Settings settings;
    settings.denoise.enabled = true;
    return settings;
  }

  static Settings checkerboarded() {
    Settings settings = denoised();
    settings.denoise.checkerboard = true;
    return settings;
  }
};

// With the branches enabled, the engine's signals take their place: none of
// their passes runs, and after 10 frames the library's indirect light is
// the engine's signal denoised, at a small part of the noisy input's error
// with the same mean. A denoiser that passed its input through (or blurred
// one frame only) stays near the input's error; one that lost the signal's
// scale misses the mean.
// GiContext::estimateMemoryBytes, which commands use to refuse a frame the
// device cannot hold before anything is allocated, against what contexts
// of several settings and sizes then hold: never more (the estimate counts
// texels; the pools add alignment and round up), and every image counted
// (a unit left out of the estimate, or one counted twice, breaks the bound).
TEST_F(GiEngineSignals, TheMemoryEstimateMatchesWhatAContextHolds) {
  Settings denoiseOff;
  denoiseOff.denoise.enabled = false;
  Settings bigCache;
  bigCache.cache.memoryMib = 96;
  for (const auto& [name, settings] :
       {std::pair{"defaults", Settings{}}, std::pair{"denoiser off", denoiseOff}, std::pair{"96 MiB cache", bigCache}})
    for (const auto& [width, height] : {std::pair{320u, 180u}, std::pair{640u, 360u}}) {
      const ContextDesc desc{.maxWidth = width, .maxHeight = height};
      const std::uint64_t estimate = GiContext::estimateMemoryBytes(desc, settings);
      const GiContext gi(render::giDevice(context()), desc, settings);
      const std::uint64_t held = gi.memoryBytes();
      SCOPED_TRACE(std::string(name) + " " + std::to_string(width) + "x" + std::to_string(height) + ": estimate " +
                   std::to_string(estimate >> 20) + " MiB, held " + std::to_string(held >> 20) + " MiB");
      EXPECT_LE(estimate, held);
      // The pool's blocks: the first 4 MiB, each next as large as all before
      // it up to 128 MiB, so at most about twice what is used, or 128 MiB more.
      constexpr std::uint64_t kMiB = 1 << 20;
      EXPECT_LE(held, std::max(2 * estimate, estimate + 128 * kMiB) + 4 * kMiB);
      // By unit: every allocation in one, so the units add up to what the
      // estimate counts (and what the pools' alignment adds) without the
      // pools' unused tails; the denoiser holds nothing when off.
      std::uint64_t units = 0;
      for (const UnitMemory& unit : gi.memoryByUnit()) {
        units += unit.bytes;
        if (unit.unit == "denoise")
          EXPECT_EQ(unit.bytes > 0, settings.denoise.enabled) << unit.unit;
        else
          EXPECT_GT(unit.bytes, 0u) << unit.unit;
      }
      EXPECT_LE(estimate, units);
      EXPECT_LE(units, held);
      EXPECT_LE(units, estimate + estimate / 50 + kMiB) << "alignment should add little";
      // The pool is told the estimate, so its blocks end near their last
      // allocation instead of up to half empty (192 MiB held for 104 at
      // 320x180 before).
      EXPECT_LE(held, units + units / 8 + 8 * kMiB) << "the pool's blocks left room unused";
    }
}

// The units' transient images (ImageSpec::transient: the fresh reservoirs,
// the denoiser's scratch) share one pool, as the units record one after
// another: the pool holds what the largest unit's take (the denoiser's),
// not their sum, and none of them is listed, as their memory holds another
// unit's images once their unit's record ends.
TEST_F(GiEngineSignals, TheUnitsTransientImagesShareOnePool) {
  const ContextDesc desc{.maxWidth = 320, .maxHeight = 180};
  const GiContext gi(render::giDevice(context()), desc, denoised());
  std::uint64_t largest = 0, sum = 0;
  std::vector<std::string> transient;
  for (const DeclaredUnit& unit : declaredUnits()) {
    std::uint64_t bytes = 0;
    for (const ImageSpec& spec : unit.images)
      if (spec.transient && !spec.debug) {
        transient.emplace_back(spec.name);
        if (spec.resolution != Resolution::Pyramid)
          bytes += std::uint64_t(extentOf(spec.resolution, {320, 180}).width) *
                   extentOf(spec.resolution, {320, 180}).height * gpu::formatInfo(spec.format).bytesPerPixel;
      }
    largest = std::max(largest, bytes);
    sum += bytes;
  }
  ASSERT_GE(transient.size(), 8u);
  std::uint64_t pool = 0;
  for (const UnitMemory& unit : gi.memoryByUnit())
    if (unit.unit == "transient") pool = unit.bytes;
  EXPECT_GE(pool, largest);
  EXPECT_LT(pool, largest + largest / 4) << "the pool should hold about the largest unit's, not the sum " << sum;
  EXPECT_LT(largest + largest / 4, sum);
  for (const LibraryImage& image : gi.images())
    EXPECT_EQ(std::find(transient.begin(), transient.end(), image.name), transient.end()) << image.name << " is listed";
}

// A branch whose signal the denoiser takes never runs its own temporal
// filter, so it does not make the filter's images (269 MiB at 1080p for
// the two): with the denoiser on they are neither listed nor held; a
// disabled branch keeps its filter image, which its cleared result is.
TEST_F(GiEngineSignals, BranchesWhoseSignalIsDenoisedMakeNoFilterImages) {
  const auto names = [&](const Settings& settings) {
    const GiContext gi(render::giDevice(context()), ContextDesc{.maxWidth = 64, .maxHeight = 48}, settings);
    std::set<std::string> listed;
    for (const LibraryImage& image : gi.images()) listed.insert(image.name);
    return std::pair{listed, gi.memoryByUnit()};
  };
  Settings filters = denoised();
  filters.denoise.enabled = false;
  const auto [withFilters, filterMemory] = names(filters);
  const auto [withDenoiser, denoiserMemory] = names(denoised());
  for (const char* image : {"gi.diffuse.filtered", "gi.diffuse.moments", "gi.specular.filtered", "gi.specular.moments",
                            "gi.specular.reprojection"}) {
    EXPECT_TRUE(withFilters.contains(image)) << image;
    EXPECT_FALSE(withDenoiser.contains(image)) << image << " is made, though the denoiser takes the signal";
  }
  // rgba32f filtered and moments, two of each (history): 64 bytes a pixel; specular also its rgba16f reprojection.
  constexpr std::uint64_t kPixels = 64 * 48;
  EXPECT_EQ(filterMemory[0].unit, "diffuse");
  EXPECT_EQ(filterMemory[0].bytes - denoiserMemory[0].bytes, 64 * kPixels);
  EXPECT_EQ(filterMemory[1].bytes - denoiserMemory[1].bytes, 72 * kPixels);

  Settings noDiffuse = denoised();
  noDiffuse.diffuse.enabled = false;
  const auto [withoutDiffuse, unused] = names(noDiffuse);
  EXPECT_TRUE(withoutDiffuse.contains("gi.diffuse.filtered"))
      << "a disabled branch's result is its cleared filter image";
  EXPECT_FALSE(withoutDiffuse.contains("gi.specular.filtered"));
}

TEST_F(GiEngineSignals, TheEnginesSignalsAreDenoisedInPlaceOfTheBranches) {
  Run run = start(denoised());
  for (int f = 0; f < 10; ++f) frame(run);
  const Output out = output(run);
  for (const std::string& pass : passesRecorded(run)) {
    EXPECT_NE(pass.rfind("gi.diffuse.", 0), 0u) << pass << " ran: the engine gave the diffuse signal";
    EXPECT_NE(pass.rfind("gi.specular.", 0), 0u) << pass << " ran: the engine gave the specular signal";
  }
  const std::vector<std::string> passes = passesRecorded(run);
  for (const char* pass : {"gi.engine_signal.diffuse", "gi.engine_signal.specular", "gi.denoise.temporal_accumulation"})
    EXPECT_NE(std::find(passes.begin(), passes.end(), pass), passes.end()) << pass << " did not run";
  for (int s = 0; s < 2; ++s) {
    const io::ImageF denoisedSignal = rgb(out.signal[s]);
    const double noisyError = relMse(run.truth, run.lastNoisy[s]);
    const double denoisedError = relMse(run.truth, denoisedSignal);
    const double meanRatio = meanLuminance(denoisedSignal) / meanLuminance(run.truth);
    std::printf("%s: relMSE %.4f noisy, %.4f denoised (%.4f of it); mean / truth %.3f\n",
                s == kDiffuse ? "diffuse" : "specular", noisyError, denoisedError, denoisedError / noisyError,
                meanRatio);
    EXPECT_LT(denoisedError, 0.1 * noisyError);
    EXPECT_NEAR(meanRatio, 1.0, 0.1);
  }
  // The composite adds the denoised light to the direct light.
  const io::ImageF direct = rgb(gpuio::readbackImage(context(), run.renderer->direct()));
  EXPECT_GT(meanLuminance(rgb(out.composite)), meanLuminance(direct) * 1.05);
}

// With both signals from the engine and the branches off, nothing reads the
// environment: an engine that only wants the denoiser need not make one.
// With a branch to run, its absence is refused by name.
TEST_F(GiEngineSignals, WithoutBranchesToRunTheEnvironmentMayBeLeftOut) {
  Settings settings = denoised();
  settings.diffuse.enabled = false;
  settings.specular.enabled = false;
  Run run = start(settings);
  const auto noEnvironment = [](FrameInputs& inputs) {
    inputs.environment = {};
    inputs.environmentSampler = VK_NULL_HANDLE;
  };
  for (int f = 0; f < 3; ++f) frame(run, {true, true}, false, {}, noEnvironment);
  const Output out = output(run);
  EXPECT_LT(relMse(run.truth, rgb(out.signal[kDiffuse])), relMse(run.truth, run.lastNoisy[kDiffuse]));

  Run branches = start(denoised());
  frame(branches);
  try {
    frame(branches, {true, false}, false, {}, noEnvironment);  // the specular branch runs
    ADD_FAILURE() << "a frame with a branch to run was taken without its environment";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("frame input environment is missing"), std::string::npos) << e.what();
  }
  branches.loop->endFrame();
}

TEST_F(GiEngineSignals, BadNoisySignalsAreRefusedWithTheirNames) {
  Run run = start(denoised());
  expectRefusals(run, [&](const FrameInputs& good, const Refused& refused) {
    FrameInputs wrongFormat = good;
    wrongFormat.noisySpecular = render::imageRef(run.renderer->baseColorMetallic());
    refused(run.gi->library(), wrongFormat,
            "frame input noisySpecular has the format VK_FORMAT_R8G8B8A8_UNORM; noisySpecular takes "
            "VK_FORMAT_R16G16B16A16_SFLOAT or VK_FORMAT_R32G32B32A32_SFLOAT");
    gpu::Image small(context(), {.name = "small", .width = 8, .height = 8, .format = VK_FORMAT_R16G16B16A16_SFLOAT});
    FrameInputs tooSmall = good;
    tooSmall.noisyDiffuse = render::imageRef(small);
    tooSmall.noisyDiffuse.layout = VK_IMAGE_LAYOUT_GENERAL;
    refused(run.gi->library(), tooSmall, "frame input noisyDiffuse is 8x8, smaller than the render size 64x48");
    FrameInputs noView = good;
    noView.noisyDiffuse.view = VK_NULL_HANDLE;
    refused(run.gi->library(), noView, "frame input noisyDiffuse is missing (its view is VK_NULL_HANDLE)");
    FrameInputs undefinedLayout = good;
    undefinedLayout.noisySpecular.layout = VK_IMAGE_LAYOUT_UNDEFINED;
    refused(run.gi->library(), undefinedLayout, "noisySpecular is in VK_IMAGE_LAYOUT_UNDEFINED");
    // The library takes a signal only to denoise it.
    Settings denoiserOff;
    denoiserOff.denoise.enabled = false;
    GiContext withoutDenoiser(render::giDevice(context()), {.maxWidth = kWidth, .maxHeight = kHeight}, denoiserOff);
    FrameInputs onlyDiffuse = good;
    onlyDiffuse.noisySpecular = {};
    refused(withoutDenoiser, onlyDiffuse,
            "frame input noisyDiffuse is given, but the denoiser is off (Settings::denoise.enabled, "
            "gi.denoise.enabled)");
  });
}

// Poison in the engine's signal (NaN or +Inf, everywhere or in a block)
// never reaches what the library keeps or shows, and its history heals:
// eight frames later the denoised light differs from an unpoisoned run's
// no more than that of a run whose history was cut at the poisoned frame.
// Every run draws the same noise, so runs agree until the poisoned frame.
TEST_F(GiEngineSignals, NonFiniteValuesInTheEnginesSignalsNeverReachTheOutput) {
  constexpr int kPoisonedFrame = 6, kHealingFrames = 8;
  const auto runWith = [&](const std::function<void(int, io::ImageF&)>& poison, bool cut) {
    Run run = start(denoised());
    for (int f = 0; f < kPoisonedFrame; ++f) frame(run);
    frame(run, {true, true}, cut, poison);
    return run;
  };
  const auto finite = [](const io::ImageF& image) {
    return std::all_of(image.pixels.begin(), image.pixels.end(), [](float v) { return std::isfinite(v); });
  };
  // Every image the library keeps for the denoised signals: theirs, the
  // taken-in signals and the composite.
  const auto firstNonFinite = [&](Run& run) -> std::string {
    run.loop->finish();
    for (const render::GiBridge::Named& named : run.gi->images()) {
      const bool ofTheSignals = named.name.rfind("gi.denoise.", 0) == 0 ||
                                named.name.rfind("gi.engine_signal.", 0) == 0 || named.name == "gi.composite";
      if (ofTheSignals && named.name != "gi.denoise.validation" &&
          !finite(gpuio::readbackImage(context(), *named.image)))
        return named.name;
    }
    return {};
  };
  const auto difference = [](const io::ImageF& a, const io::ImageF& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) sum += std::abs(double(a.pixels[i]) - double(b.pixels[i]));
    return sum;
  };
  // kHealingFrames more frames (the same noise in every run); `afterFirst`
  // looks at the run after the first of them.
  const auto healedSignals = [&](Run& run, const std::function<void(Run&)>& afterFirst = {}) {
    for (int f = 0; f < kHealingFrames; ++f) {
      frame(run);
      if (f == 0 && afterFirst) afterFirst(run);
    }
    const Output out = output(run);
    return std::array<io::ImageF, 2>{rgb(out.signal[kDiffuse]), rgb(out.signal[kSpecular])};
  };
  Run clean = runWith({}, false);
  const std::array<io::ImageF, 2> healedClean = healedSignals(clean);
  Run cut = runWith({}, true);
  const std::array<io::ImageF, 2> healedCut = healedSignals(cut);

  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  for (const float poison : {nan, inf})
    for (const bool block : {false, true})
      for (const int channel : {0, 3}) {  // the radiance, or the hit distance
        const std::string what = std::string(std::isnan(poison) ? "NaN" : "+Inf") + (block ? " block" : " everywhere") +
                                 (channel == 3 ? " in the hit distance" : " in the radiance");
        SCOPED_TRACE(what);
        Run run = runWith(
            [&](int, io::ImageF& noisy) {
              for (int y = 0; y < noisy.height; ++y)
                for (int x = 0; x < noisy.width; ++x)
                  if (!block || (x >= 20 && x < 30 && y >= 20 && y < 30)) noisy.at(x, y, channel) = poison;
            },
            false);
        ASSERT_EQ(firstNonFinite(run), "") << "at the poisoned frame";
        const std::array<io::ImageF, 2> healed =
            healedSignals(run, [&](Run& r) { EXPECT_EQ(firstNonFinite(r), "") << "the frame after"; });
        for (int s = 0; s < 2; ++s) {
          const double poisoned = difference(healedClean[s], healed[s]);
          const double afterCut = difference(healedClean[s], healedCut[s]);
          std::printf("%s, %s: %d frames later %.3f from the clean run; a cut's run %.3f\n", what.c_str(),
                      s == kDiffuse ? "diffuse" : "specular", kHealingFrames, poisoned, afterCut);
          EXPECT_LE(poisoned, afterCut) << (s == kDiffuse ? "diffuse" : "specular") << ": the history has not healed";
        }
      }
}

// A signal that changes hands (the engine's, then the branch's, then the
// engine's again) restarts every history for that frame, as a cut does:
// the branch never wrote its history images while the engine gave the
// signal, and the denoiser's history was of the other source. The branch's
// first frame reads nothing of them (no validation message for reading
// images never written) and everything stays finite.
TEST_F(GiEngineSignals, ASignalChangingHandsRestartsTheHistory) {
  Run run = start(denoised());
  for (int f = 0; f < 6; ++f) frame(run);
  const io::ImageF viewZ = gpuio::readbackImage(context(), run.renderer->viewZ());
  const auto historyOnSurfaces = [&](const io::ImageF& signal) {
    float longest = 0.0f;
    for (int y = 0; y < signal.height; ++y)
      for (int x = 0; x < signal.width; ++x)
        if (viewZ.at(x, y, 0) > 0.0f) longest = std::max(longest, signal.at(x, y, 3));
    return longest;
  };
  EXPECT_GT(historyOnSurfaces(output(run).signal[kDiffuse]), 1.0f) << "before the change";
  for (const std::array<bool, 2> give : {std::array<bool, 2>{false, true}, std::array<bool, 2>{true, true}}) {
    frame(run, give);
    const Output out = output(run);
    EXPECT_EQ(historyOnSurfaces(out.signal[kDiffuse]), 1.0f) << "diffuse given: " << give[kDiffuse];
    EXPECT_EQ(historyOnSurfaces(out.signal[kSpecular]), 1.0f) << "every history restarts";
    for (const io::ImageF* image : {&out.signal[kDiffuse], &out.signal[kSpecular], &out.composite})
      for (float v : image->pixels) ASSERT_TRUE(std::isfinite(v));
    frame(run, give);
    EXPECT_GT(historyOnSurfaces(output(run).signal[kDiffuse]), 1.0f) << "the frame after";
  }
  const std::vector<std::string> passes = passesRecorded(run);
  EXPECT_NE(std::find(passes.begin(), passes.end(), "gi.diffuse.resolve"), passes.end())
      << "the diffuse branch ran while the engine did not give the signal";
}

// Checkerboard mode: the engine hands over every other pixel of the same
// noisy signals (half of the samples), packed to half width. After 10
// frames the denoised light is within 2x the full signals' relMSE (half
// the samples: twice the error of a mere average; measured 1.6-1.8x), far
// below the input's error, with the same mean. A
// denoiser that left the pixels without a sample dark would miss the mean
// by a third or more; one that read the packed image as a full one would
// scramble the picture.
TEST_F(GiEngineSignals, CheckerboardedSignalsDenoiseCloseToTheFullOnes) {
  constexpr double kMaxErrorRatio = 2.0;
  Run full = start(denoised());
  Run halves = start(checkerboarded());
  for (int f = 0; f < 10; ++f) frame(full);
  for (int f = 0; f < 10; ++f) frame(halves);
  const Output fullOut = output(full);
  const Output halvesOut = output(halves);
  const std::vector<std::string> passes = passesRecorded(halves);
  for (const char* pass : {"gi.engine_signal.diffuse", "gi.denoise.pre_pass"})
    EXPECT_NE(std::find(passes.begin(), passes.end(), pass), passes.end()) << pass << " did not run";
  for (int s = 0; s < 2; ++s) {
    const double noisyError = relMse(halves.truth, halves.lastNoisy[s]);
    const double fullError = relMse(full.truth, rgb(fullOut.signal[s]));
    const io::ImageF denoisedHalves = rgb(halvesOut.signal[s]);
    const double halvesError = relMse(halves.truth, denoisedHalves);
    const double meanRatio = meanLuminance(denoisedHalves) / meanLuminance(halves.truth);
    std::printf(
        "%s: relMSE %.4f noisy (every pixel), %.4f denoised from every pixel, %.4f from the checkerboard "
        "(%.2fx); mean / truth %.3f\n",
        s == kDiffuse ? "diffuse" : "specular", noisyError, fullError, halvesError, halvesError / fullError, meanRatio);
    EXPECT_LT(halvesError, kMaxErrorRatio * fullError);
    EXPECT_LT(halvesError, 0.05 * noisyError);
    EXPECT_NEAR(meanRatio, 1.0, 0.1);
  }
}

// The checkerboard resolve, seen alone (pre-pass radius 0: the pre-pass
// runs in checkerboard mode all the same, and only fills in): over
// cornell's G-buffer, a signal whose every pixel differs (each surface's
// colour times a ramp across the frame), given in checkerboard mode. A
// pixel with a sample keeps it; one without whose left and right
// neighbours lie on its surface takes their mean; one with a neighbour on
// its surface on one side and another surface (another normal, or none)
// on the other takes that one neighbour's value, nothing across the edge.
// Both signals, of opposite parities. With the radius 0 and the mode off,
// the pre-pass hands every pixel on unchanged.
TEST_F(GiEngineSignals, TheCheckerboardResolveFillsFromNeighboursOnTheSurfaceOnly) {
  Settings settings = checkerboarded();
  settings.denoise.diffusePrePassRadius = 0.0f;
  settings.denoise.specularPrePassRadius = 0.0f;
  Run run = start(settings);
  const auto pattern = [&](int, io::ImageF& noisy) {
    for (int y = 0; y < noisy.height; ++y)
      for (int x = 0; x < noisy.width; ++x)
        for (int c = 0; c < 3; ++c) noisy.at(x, y, c) = run.truth.at(x, y, c) * (1.0f + 2.0f * float(x) / kWidth);
  };
  frame(run, {true, true}, false, pattern, [](FrameInputs& inputs) { inputs.captureStages = true; });
  const std::vector<std::string> passes = passesRecorded(run);
  ASSERT_NE(std::find(passes.begin(), passes.end(), "gi.denoise.pre_pass"), passes.end())
      << "checkerboard mode needs the pre-pass even at radius 0";
  const std::vector<gpu::CapturedStage> captures = stageOutputs(run);
  io::ImageF prePassOutputs[2];
  for (int s = 0; s < 2; ++s)
    prePassOutputs[s] = stageOutput(captures, "gi.denoise.pre_pass",
                                    std::string(s == kDiffuse ? "diffuse" : "specular") + ".gOut_PrePassed");
  const io::ImageF viewZ = gpuio::readbackImage(context(), run.renderer->viewZ());
  const io::ImageF normals = gpuio::readbackImage(context(), run.renderer->normalRoughness());
  const auto normalAt = [&](int x, int y) {
    return glm::vec3(normals.at(x, y, 0), normals.at(x, y, 1), normals.at(x, y, 2));
  };
  const auto sameSurface = [&](int x, int y, int nx) {
    const float z = viewZ.at(x, y, 0), nz = viewZ.at(nx, y, 0);
    return nz > 0.0f && glm::dot(normalAt(x, y), normalAt(nx, y)) > 0.999f && std::abs(nz - z) < 0.02f * z;
  };
  // Another normal (beyond the widest cone the weights grant) or no surface.
  const auto otherSurface = [&](int x, int y, int nx) {
    return viewZ.at(nx, y, 0) <= 0.0f || glm::dot(normalAt(x, y), normalAt(nx, y)) < 0.3f;
  };
  const auto close = [](const io::ImageF& image, int x, int y, const io::ImageF& expected, int ex, int ey,
                        const io::ImageF* other, int ox, int oy, float tolerance) {
    for (int c = 0; c < 3; ++c) {
      const float want = other ? 0.5f * (expected.at(ex, ey, c) + other->at(ox, oy, c)) : expected.at(ex, ey, c);
      if (std::abs(image.at(x, y, c) - want) > tolerance * std::max(want, 1e-3f)) return false;
    }
    return true;
  };
  for (int s = 0; s < 2; ++s) {
    SCOPED_TRACE(s == kDiffuse ? "diffuse" : "specular");
    const io::ImageF& prePassed = prePassOutputs[s];
    ASSERT_EQ(prePassed.width, int(kWidth));
    const io::ImageF& given = run.lastNoisy[s];
    int kept = 0, keptWrong = 0, between = 0, betweenWrong = 0, oneSided = 0, oneSidedWrong = 0;
    for (int y = 0; y < int(kHeight); ++y)
      for (int x = 1; x + 1 < int(kWidth); ++x) {
        if (viewZ.at(x, y, 0) <= 0.0f) continue;
        if (hasSample(x, y, s, run.lastFrameIndex)) {
          ++kept;  // rgba16f keeps 11 bits
          if (!close(prePassed, x, y, given, x, y, nullptr, 0, 0, 2e-3f)) ++keptWrong;
          continue;
        }
        const bool left = sameSurface(x, y, x - 1), right = sameSurface(x, y, x + 1);
        if (left && right) {
          ++between;
          if (!close(prePassed, x, y, given, x - 1, y, &given, x + 1, y, 3e-3f)) ++betweenWrong;
        } else if (left != right && otherSurface(x, y, left ? x + 1 : x - 1)) {
          ++oneSided;
          if (!close(prePassed, x, y, given, left ? x - 1 : x + 1, y, nullptr, 0, 0, 3e-3f)) {
            ++oneSidedWrong;
            ADD_FAILURE() << "pixel (" << x << ", " << y << ") took " << prePassed.at(x, y, 0) << ", its neighbour "
                          << "on the surface has " << given.at(left ? x - 1 : x + 1, y, 0) << ", across the edge "
                          << given.at(left ? x + 1 : x - 1, y, 0);
          }
        }
      }
    std::printf(
        "%s: %d pixels with a sample (%d changed), %d filled between two neighbours (%d wrong), %d at an "
        "edge (%d wrong)\n",
        s == kDiffuse ? "diffuse" : "specular", kept, keptWrong, between, betweenWrong, oneSided, oneSidedWrong);
    EXPECT_GT(kept, int(kWidth * kHeight) / 4);
    EXPECT_EQ(keptWrong, 0);
    EXPECT_GT(between, kept / 3) << "too few pixels between two neighbours on their surface to judge";
    EXPECT_EQ(betweenWrong, 0);
    EXPECT_GE(oneSided, 10) << "too few edges to judge";
  }

  Settings off = denoised();
  off.denoise.diffusePrePassRadius = 0.0f;
  off.denoise.specularPrePassRadius = 0.0f;
  Run full = start(off);
  frame(full, {true, true}, false, pattern, [](FrameInputs& inputs) { inputs.captureStages = true; });
  const std::vector<gpu::CapturedStage> fullCaptures = stageOutputs(full);
  for (int s = 0; s < 2; ++s) {
    SCOPED_TRACE(s == kDiffuse ? "diffuse, every pixel" : "specular, every pixel");
    const io::ImageF prePassed = stageOutput(fullCaptures, "gi.denoise.pre_pass",
                                             std::string(s == kDiffuse ? "diffuse" : "specular") + ".gOut_PrePassed");
    ASSERT_EQ(prePassed.width, int(kWidth));
    int changed = 0, surfaces = 0;
    for (int y = 0; y < int(kHeight); ++y)
      for (int x = 0; x < int(kWidth); ++x) {
        if (viewZ.at(x, y, 0) <= 0.0f) continue;
        ++surfaces;
        if (!close(prePassed, x, y, full.lastNoisy[s], x, y, nullptr, 0, 0, 2e-3f)) ++changed;
      }
    EXPECT_GT(surfaces, int(kWidth * kHeight / 2));
    EXPECT_EQ(changed, 0) << "at radius 0 a signal with every pixel passes through the pre-pass unchanged";
  }
}

// In checkerboard mode a noisy signal must cover half the render width
// (rounded up) and its height; outside it, the whole render size, as
// before. Each refusal names the input, what it must cover and its size.
TEST_F(GiEngineSignals, CheckerboardedSignalsMustCoverHalfTheWidth) {
  Run run = start(checkerboarded());
  expectRefusals(run, [&](const FrameInputs& good, const Refused& refused) {
    ASSERT_EQ(good.noisyDiffuse.width, 32u);
    gpu::Image narrow(context(),
                      {.name = "narrow", .width = 31, .height = 48, .format = VK_FORMAT_R16G16B16A16_SFLOAT});
    FrameInputs tooNarrow = good;
    tooNarrow.noisyDiffuse = render::imageRef(narrow);
    tooNarrow.noisyDiffuse.layout = VK_IMAGE_LAYOUT_GENERAL;
    refused(run.gi->library(), tooNarrow,
            "frame input noisyDiffuse is 31x48; with gi.denoise.checkerboard on it holds every other pixel of each "
            "row, packed to half width: it must cover 32x48 (ceil(width / 2) x height of the render size 64x48)");
    gpu::Image low(context(), {.name = "low", .width = 32, .height = 40, .format = VK_FORMAT_R16G16B16A16_SFLOAT});
    FrameInputs tooLow = good;
    tooLow.noisySpecular = render::imageRef(low);
    tooLow.noisySpecular.layout = VK_IMAGE_LAYOUT_GENERAL;
    refused(run.gi->library(), tooLow, "frame input noisySpecular is 32x40; with gi.denoise.checkerboard on");
    // Without the mode, the packed images are too small.
    GiContext fullMode(render::giDevice(context()), {.maxWidth = kWidth, .maxHeight = kHeight}, denoised());
    refused(fullMode, good, "frame input noisyDiffuse is 32x48, smaller than the render size 64x48");
  });
}

// NaN and +Inf in a checkerboarded signal (radiance and hit distance, in a
// block and at every third pixel, so the resolve and the pre-blur meet
// them on every side) never reach an image the library keeps.
TEST_F(GiEngineSignals, NonFiniteValuesInACheckerboardedSignalNeverReachTheOutput) {
  Run run = start(checkerboarded());
  for (int f = 0; f < 3; ++f) frame(run);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const auto poison = [&](int signal, io::ImageF& noisy) {
    for (int y = 0; y < noisy.height; ++y)
      for (int x = 0; x < noisy.width; ++x) {
        if (x >= 20 && x < 30 && y >= 20 && y < 30) noisy.at(x, y, signal == kDiffuse ? 0 : 3) = nan;
        if ((x + 2 * y) % 3 == 0) noisy.at(x, y, (x % 2) * 3) = (y % 2) ? inf : nan;
      }
  };
  // Every image the library keeps for the denoised signals (the branches' never ran).
  const auto firstNonFinite = [&]() -> std::string {
    run.loop->finish();
    for (const render::GiBridge::Named& named : run.gi->images()) {
      const bool ofTheSignals = named.name.rfind("gi.denoise.", 0) == 0 ||
                                named.name.rfind("gi.engine_signal.", 0) == 0 || named.name == "gi.composite";
      if (!ofTheSignals || named.name == "gi.denoise.validation") continue;
      const io::ImageF image = gpuio::readbackImage(context(), *named.image);
      if (!std::all_of(image.pixels.begin(), image.pixels.end(), [](float v) { return std::isfinite(v); }))
        return named.name;
    }
    return {};
  };
  frame(run, {true, true}, false, poison);
  EXPECT_EQ(firstNonFinite(), "") << "at the poisoned frame";
  frame(run, {true, true}, false, poison);
  EXPECT_EQ(firstNonFinite(), "") << "the frame after, poisoned again with the other parity";
  frame(run);
  EXPECT_EQ(firstNonFinite(), "") << "a clean frame after";
}

// The mode is the engine's: the branches' own signals are full resolution
// and denoised as they are, bit for bit, whatever gi.denoise.checkerboard
// says (nothing of theirs is taken for a pixel without a sample).
TEST_F(GiEngineSignals, CheckerboardModeLeavesTheBranchesSignalsAlone) {
  Run on = start(checkerboarded());
  Run off = start(denoised());
  for (int f = 0; f < 3; ++f) {
    frame(on, {false, false});
    frame(off, {false, false});
  }
  const Output onOut = output(on);
  const Output offOut = output(off);
  for (int s = 0; s < 2; ++s) {
    EXPECT_EQ(onOut.signal[s].pixels, offOut.signal[s].pixels) << (s == kDiffuse ? "diffuse" : "specular");
    EXPECT_GT(meanLuminance(rgb(onOut.signal[s])), 0.0) << "the branches made no light to compare";
  }
  EXPECT_EQ(onOut.composite.pixels, offOut.composite.pixels);
}

// A moving emitter's light does not stay behind: after 40 still frames,
// the light of a small emitter (4x the wall's light, 9 pixels across)
// sweeps across the diffuse signal, 4 pixels a frame, and goes out; each
// pixel it lit got 2 to 3 frames of its light. Where it passed, the
// denoised light is at most 12 % above the truth 16 frames after it went
// out, and the excess has fallen by at least 40 % since it went out. (A
// change this small hides in the 1-spp noise of the fast history, so the
// anti-lag does not see it: the light leaves at the pace of the 30-frame
// history, docs/known-issues.md. A history that never let go, or blended
// in nothing new, keeps its excess.)
TEST_F(GiEngineSignals, AMovingEmittersLightDoesNotStayBehind) {
  constexpr int kWarmUp = 40, kSweep = 12, kSpeed = 4, kStart = 8, kRadius = 4, kAfter = 16;
  constexpr float kBrightness = 4.0f;
  const int row = int(kHeight) / 2;
  Run run = start(denoised());
  for (int f = 0; f < kWarmUp; ++f) frame(run, {true, false});
  for (int t = 0; t < kSweep; ++t) {
    const int centre = kStart + kSpeed * t;
    const auto emitter = [&](int signal, io::ImageF& noisy) {
      if (signal != kDiffuse) return;
      for (int y = 0; y < noisy.height; ++y)
        for (int x = 0; x < noisy.width; ++x)
          if ((x - centre) * (x - centre) + (y - row) * (y - row) <= kRadius * kRadius)
            for (int c = 0; c < 3; ++c) noisy.at(x, y, c) += kBrightness * run.truth.at(x, y, c);
    };
    frame(run, {true, false}, false, emitter);
  }
  // The light above the truth over the surface pixels the emitter lit, as a share of the truth there.
  const auto excessWhereLit = [&]() {
    const io::ImageF denoisedSignal = rgb(output(run).signal[kDiffuse]);
    double excess = 0.0, truth = 0.0;
    for (int y = 0; y < int(kHeight); ++y)
      for (int x = 0; x < int(kWidth); ++x) {
        bool lit = false;
        for (int t = 0; t < kSweep && !lit; ++t) {
          const int centre = kStart + kSpeed * t;
          lit = (x - centre) * (x - centre) + (y - row) * (y - row) <= kRadius * kRadius;
        }
        if (!lit || run.truth.at(x, y, 0) <= 0.0f) continue;
        for (int c = 0; c < 3; ++c) {
          excess += denoisedSignal.at(x, y, c) - run.truth.at(x, y, c);
          truth += run.truth.at(x, y, c);
        }
      }
    return excess / truth;
  };
  const double wentOut = excessWhereLit();
  for (int after = 0; after < kAfter; ++after) frame(run, {true, false});
  const double later = excessWhereLit();
  std::printf("light above the truth where the emitter passed: %+.1f %% as it went out, %+.1f %% %d frames later\n",
              100.0 * wentOut, 100.0 * later, kAfter);
  EXPECT_GT(wentOut, 0.05) << "the emitter's light did not reach the denoised signal";
  EXPECT_LT(later, 0.12);
  EXPECT_LT(later, 0.6 * wentOut);
}

// Five signals take two dispatches of each denoiser stage (four slots a
// dispatch): three of the engine's own beside the library's two, each its
// own brightness (1, 2 and 3 times an occlusion-like truth), the last in
// the second dispatch. After 10 frames each is denoised to its own mean:
// a batch that bound another signal's images, or lost the fifth, would
// show another brightness or none.
TEST_F(GiEngineSignals, FiveSignalsTakeTwoDispatchesOfEachStageAndKeepTheirOwnLight) {
  Run run = start(denoised(), {{"first", SignalKind::Diffuse}, {"second", SignalKind::Specular},
                               {"third", SignalKind::Diffuse}});
  ASSERT_EQ(run.gi->library().signals().size(), 5u);
  std::vector<std::unique_ptr<gpu::Image>> images;
  for (int i = 0; i < 3; ++i)
    images.push_back(std::make_unique<gpu::Image>(context(), gpu::ImageDesc{.name = "engine.noisy_" + std::to_string(i),
                                                                          .width = kWidth,
                                                                          .height = kHeight,
                                                                          .format = VK_FORMAT_R32G32B32A32_SFLOAT,
                                                                          .storage = false}));
  frame(run);
  const io::ImageF normals = gpuio::readbackImage(context(), run.renderer->normalRoughness());
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  const auto truthOf = [&](int signal, int x, int y) {
    return run.truth.at(x, y, 0) > 0.0f ? float(signal + 1) * (0.3f + 0.7f * std::abs(normals.at(x, y, 1))) : 0.0f;
  };
  for (int f = 0; f < 10; ++f) {
    run.loop->finish();
    run.extra.clear();
    for (int i = 0; i < 3; ++i) {
      io::ImageF noisy(int(kWidth), int(kHeight), {"R", "G", "B", "A"});
      for (int y = 0; y < int(kHeight); ++y)
        for (int x = 0; x < int(kWidth); ++x) {
          const float weight = uniform(run.random) < kBrightShare ? 1.0f / kBrightShare : 0.0f;
          for (int c = 0; c < 3; ++c) noisy.at(x, y, c) = truthOf(i, x, y) * weight;
        }
      gpuio::uploadImage(context(), *images[i], noisy);
      run.extra.push_back({SignalId(2 + i), images[i].get()});
    }
    frame(run);
  }
  run.loop->finish();
  for (int i = 0; i < 3; ++i) {
    const io::ImageF denoisedSignal = rgb(gpuio::readbackImage(context(), run.gi->indirect(SignalId(2 + i))));
    double sum = 0.0, truthSum = 0.0;
    for (int y = 0; y < int(kHeight); ++y)
      for (int x = 0; x < int(kWidth); ++x) {
        sum += denoisedSignal.at(x, y, 0);
        truthSum += truthOf(i, x, y);
      }
    std::printf("engine signal %d: mean / its truth %.3f\n", i, sum / truthSum);
    EXPECT_NEAR(sum / truthSum, 1.0, 0.15) << "signal " << i;
  }
  const Output out = output(run);
  EXPECT_LT(relMse(run.truth, rgb(out.signal[kDiffuse])), 0.1 * relMse(run.truth, run.lastNoisy[kDiffuse]));
}

// A signal of the engine's own beyond the library's two (ContextDesc::
// signals: here an ambient occlusion of kind diffuse, 0.3..1 by the
// normal's height, with the fixture's noise) runs through the same
// denoiser code as the library's: after 10 frames indirect(2) is that
// signal denoised (a small part of its noise, the same mean), apart from
// the library's signals given with it, under passes named after it. A frame
// without it restarts only its own history. (A denoiser that took the
// signal for another, or shared its history, misses its truth.)
TEST_F(GiEngineSignals, AnEnginesOwnThirdSignalIsDenoisedByTheSameDenoiser) {
  Run run = start(denoised(), {{"ambient_occlusion", SignalKind::Diffuse}});
  constexpr SignalId kOcclusion = 2;
  ASSERT_EQ(run.gi->library().signals().size(), 3u);
  EXPECT_EQ(run.gi->library().signals()[kOcclusion].name, "ambient_occlusion");
  gpu::Image occlusion(context(), gpu::ImageDesc{.name = "engine.noisy_occlusion",
                                                 .width = kWidth,
                                                 .height = kHeight,
                                                 .format = VK_FORMAT_R32G32B32A32_SFLOAT,
                                                 .storage = false});
  frame(run);  // the G-buffer the truth comes from
  {
    // Not given yet: its result is zero (and in the layout every library image is in).
    run.loop->finish();
    const io::ImageF before = gpuio::readbackImage(context(), run.gi->indirect(kOcclusion));
    EXPECT_EQ(*std::max_element(before.pixels.begin(), before.pixels.end()), 0.0f);
  }
  const io::ImageF normals = gpuio::readbackImage(context(), run.renderer->normalRoughness());
  io::ImageF truth(int(kWidth), int(kHeight), {"R", "G", "B"});
  for (int y = 0; y < int(kHeight); ++y)
    for (int x = 0; x < int(kWidth); ++x)
      for (int c = 0; c < 3; ++c)
        truth.at(x, y, c) = run.truth.at(x, y, 0) > 0.0f ? 0.3f + 0.7f * std::abs(normals.at(x, y, 1)) : 0.0f;
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  io::ImageF lastNoisy;
  const auto occlusionFrame = [&](bool give) {
    run.loop->finish();  // the upload replaces what the last frame read
    io::ImageF noisy(int(kWidth), int(kHeight), {"R", "G", "B", "A"});
    for (int y = 0; y < int(kHeight); ++y)
      for (int x = 0; x < int(kWidth); ++x) {
        const float weight = uniform(run.random) < kBrightShare ? 1.0f / kBrightShare : 0.0f;
        for (int c = 0; c < 3; ++c) noisy.at(x, y, c) = truth.at(x, y, c) * weight;
      }
    gpuio::uploadImage(context(), occlusion, noisy);
    lastNoisy = rgb(noisy);
    run.extra.clear();
    if (give) run.extra.push_back({kOcclusion, &occlusion});
    frame(run);
  };
  for (int f = 0; f < 10; ++f) occlusionFrame(true);
  const std::vector<std::string> passes = passesRecorded(run);
  for (const char* pass :
       {"gi.engine_signal.ambient_occlusion", "gi.denoise.pre_pass", "gi.denoise.temporal_accumulation",
        "gi.denoise.temporal_stabilization"})
    EXPECT_NE(std::find(passes.begin(), passes.end(), pass), passes.end()) << pass << " did not run";
  const io::ImageF denoisedOcclusion = gpuio::readbackImage(context(), run.gi->indirect(kOcclusion));
  const double noisyError = relMse(truth, lastNoisy);
  const double denoisedError = relMse(truth, rgb(denoisedOcclusion));
  const double meanRatio = meanLuminance(rgb(denoisedOcclusion)) / meanLuminance(truth);
  std::printf("ambient occlusion: relMSE %.4f noisy, %.4f denoised (%.4f of it); mean / truth %.3f\n", noisyError,
              denoisedError, denoisedError / noisyError, meanRatio);
  EXPECT_LT(denoisedError, 0.1 * noisyError);
  EXPECT_NEAR(meanRatio, 1.0, 0.1);
  // The library's diffuse signal, given alongside, is still its own.
  const Output out = output(run);
  EXPECT_LT(relMse(run.truth, rgb(out.signal[kDiffuse])), 0.1 * relMse(run.truth, run.lastNoisy[kDiffuse]));
  EXPECT_GT(relMse(truth, rgb(out.signal[kDiffuse])), 10.0 * denoisedError) << "the two signals look alike";

  // A frame without the signal, then one with it: its history starts over
  // (history length 1 on every surface), the library's does not.
  occlusionFrame(false);
  occlusionFrame(true);
  run.loop->finish();
  const io::ImageF restarted = gpuio::readbackImage(context(), run.gi->indirect(kOcclusion));
  const io::ImageF diffuse = gpuio::readbackImage(context(), run.gi->indirect(kDiffuseSignal));
  double occlusionFrames = 0.0, diffuseFrames = 0.0, surfaces = 0.0;
  for (int y = 0; y < int(kHeight); ++y)
    for (int x = 0; x < int(kWidth); ++x) {
      if (run.truth.at(x, y, 0) <= 0.0f) continue;
      occlusionFrames += restarted.at(x, y, 3);
      diffuseFrames += diffuse.at(x, y, 3);
      surfaces += 1.0;
    }
  EXPECT_NEAR(occlusionFrames / surfaces, 1.0, 0.01) << "its history did not restart";
  EXPECT_GT(diffuseFrames / surfaces, 5.0) << "the library's history restarted with it";
}

// What an engine declares of its own signals is checked when the context is
// made, and the frame's signals against them, each refusal naming the fault.
TEST_F(GiEngineSignals, BadSignalDeclarationsAreRefusedWithTheirNames) {
  const auto refusedContext = [&](const Settings& settings, std::vector<SignalDesc> signals, const std::string& words) {
    try {
      GiContext gi(render::giDevice(context()), ContextDesc{.maxWidth = 16, .maxHeight = 16, .signals = signals},
                   settings);
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
      return;
    }
    ADD_FAILURE() << "accepted: " << words;
  };
  refusedContext(denoised(), {{"Ambient Occlusion", SignalKind::Diffuse}},
                 "ContextDesc::signals[0] ('Ambient Occlusion'): a signal's name is 1-32 of a-z, 0-9 and '_'");
  refusedContext(denoised(), {{"", SignalKind::Diffuse}}, "ContextDesc::signals[0] (''): a signal's name");
  refusedContext(denoised(), {{"specular", SignalKind::Specular}},
                 "ContextDesc::signals[0] ('specular'): the name is taken by the library's own signal");
  refusedContext(denoised(), {{"ao", SignalKind::Diffuse}, {"ao", SignalKind::Specular}},
                 "ContextDesc::signals[1] ('ao'): the name is taken by an earlier signal");
  refusedContext(denoised(), {{"ao", SignalKind(7)}}, "kind 7 is neither SignalKind::Diffuse nor Specular");
  refusedContext(denoised(), std::vector<SignalDesc>(31, {"ao", SignalKind::Diffuse}),
                 "declares 31 signals; at most 30 besides the library's diffuse and specular");
  Settings off = denoised();
  off.denoise.enabled = false;
  refusedContext(off, {{"ao", SignalKind::Diffuse}}, "but the denoiser is off");

  Run run = start(denoised(), {{"ao", SignalKind::Diffuse}});
  EXPECT_THROW((void)run.gi->library().indirect(3), Error);
  expectRefusals(run, [&](const FrameInputs& good, const Refused& refused) {
    FrameInputs tooMany = good;
    tooMany.noisy.resize(4);
    refused(run.gi->library(), tooMany,
            "frame input noisy has 4 entries; the context denoises 3 signals (diffuse, specular and the 1 of "
            "ContextDesc::signals)");
    FrameInputs twice = good;
    twice.noisy = {render::imageRef(*run.noisy[kSpecular])};
    refused(run.gi->library(), twice,
            "frame inputs noisy[0] (diffuse) and noisyDiffuse are both given, as different images");
    FrameInputs small = good;
    small.noisy = {{}, {}, render::imageRef(run.renderer->baseColorMetallic())};
    refused(run.gi->library(), small,
            "frame input noisy[2] (ao) has the format VK_FORMAT_R8G8B8A8_UNORM; noisy[2] (ao) takes");
  });
}

}  // namespace
}  // namespace bounce::gi

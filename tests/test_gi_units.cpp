// The library's units as a graph routed by name (gi/unit.h, gi/units.h):
// a unit registered by a test alone, without a line of the orchestrator
// changed, is made, recorded in its place, handed the products it takes
// (and they are made for it), and what it makes replaces the library's own
// product of that name for every consumer after it, down to the engine.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "bounce/gi.h"
#include "gi/image_table.h"
#include "gi/unit.h"
#include "gi/units.h"
#include "gpu/format.h"
#include "gpu_test.h"
#include "gpuio/gpu_images.h"
#include "render/frame_pipeline.h"
#include "render/gi_bridge.h"
#include "scene/builtin_scenes.h"
#include "test_meshes.h"

namespace bounce::gi {
namespace {

constexpr std::uint32_t kWidth = 40, kHeight = 24;
// The extra unit's light: what the diffuse signal must read everywhere once it replaces the branch's.
constexpr float kFlatLight[3] = {0.25f, 0.5f, 0.75f};

constexpr ImageSpec kFlatImages[] = {
    {"gi.flat_diffuse.light", Resolution::Full, gpu::formats::kRgba16f, false, gpu::Visualize::Radiance,
     "the test unit's flat indirect diffuse"},
};

// A stand-in branch (the kind an ambient-occlusion or emissive-only branch
// would be): it takes `takes`, records whether it was handed each, and
// makes `makes` (here "diffuse") as one flat light.
class FlatDiffuseUnit final : public Unit {
 public:
  FlatDiffuseUnit(gpu::Context& context, gpu::MemoryArena& arena, Extent maxSize, std::vector<std::string> takes,
                  std::string makes, std::vector<std::string>& handed)
      : images_(context, arena, kFlatImages, maxSize),
        takes_(std::move(takes)),
        makes_(std::move(makes)),
        handed_(handed) {}
  std::string_view name() const override { return "flat_diffuse"; }
  Plan plan(const FramePlan&) const override { return {.records = true, .takes = takes_}; }
  void record(const FrameState& frame) override {
    for (const std::string& taken : takes_)
      if (frame.products.has(taken)) handed_.push_back(taken);
    gpu::Image& light = images_.current(0, frame.frameIndex);
    frame.recorder.clearImage(light, {.float32 = {kFlatLight[0], kFlatLight[1], kFlatLight[2], 0.0f}});
    if (!makes_.empty()) frame.products.put(makes_, light);
  }
  std::vector<ImageSet*> imageSets() override { return {&images_}; }

 private:
  ImageSet images_;
  std::vector<std::string> takes_;
  std::string makes_;
  std::vector<std::string>& handed_;
};

UnitRegistration flatDiffuse(std::vector<std::string> takes, std::string makes, std::vector<std::string>& handed) {
  return {
      .name = "flat_diffuse",
      .produces =
          [makes](const UnitSetup&) {
            return makes.empty() ? std::vector<std::string>{} : std::vector<std::string>{makes};
          },
      .make = [takes, makes, &handed](const UnitSetup& setup, const UnitResources& resources) -> std::unique_ptr<Unit> {
        return std::make_unique<FlatDiffuseUnit>(resources.context, resources.arena, setup.maxSize, takes, makes,
                                                 handed);
      },
      .memoryBytes = [](const UnitSetup& setup) { return imageSetBytes(kFlatImages, setup.maxSize); }};
}

class GiUnits : public testing::GpuTest {
 protected:
  struct Run {
    std::unique_ptr<scene::Scene> scene;
    std::unique_ptr<render::FramePipeline> pipeline;
    render::GiBridge* gi = nullptr;  // the pipeline's
  };

  Run start(const Settings& settings) {
    Run run;
    run.scene = std::make_unique<scene::Scene>(scene::makeBuiltinScene("cornell"));
    run.pipeline = std::make_unique<render::FramePipeline>(
        context(), *run.scene,
        render::FramePipelineDesc{.renderer = testing::smallRendererOptions(*run.scene, kWidth, kHeight),
                                  .gi = std::pair(ContextDesc{.maxWidth = kWidth, .maxHeight = kHeight}, settings)});
    run.gi = run.pipeline->gi();
    return run;
  }

  void advance(Run& run, int frames) {
    for (int i = 0; i < frames; ++i) run.pipeline->frame({*run.scene->suggestedCamera, 0.0f, i == 0});
    run.pipeline->finish();
  }

  static std::vector<std::string> listed(const GiContext& gi) {
    std::vector<std::string> names;
    for (const LibraryImage& image : gi.images()) names.push_back(image.name);
    return names;
  }
  static bool contains(const std::vector<std::string>& names, const std::string& name) {
    return std::find(names.begin(), names.end(), name) != names.end();
  }
};

// Registered before the composite, the unit's "diffuse" replaces the
// denoiser's: the composite and the engine read the flat light, and the
// unit's image is listed as the library's own.
TEST_F(GiUnits, AnExtraUnitsProductReplacesTheLibrarysForEveryLaterConsumer) {
  std::vector<std::string> handed;
  io::ImageF plainComposite;
  {
    Run plain = start(Settings{});
    advance(plain, 3);
    plainComposite = gpuio::readbackImage(context(), plain.gi->composite());
  }
  const UnitRegistration::Scoped extra(flatDiffuse({"surface", "light_change"}, "diffuse", handed), "composite");
  Run run = start(Settings{});
  advance(run, 3);
  EXPECT_EQ(handed.size(), 6u) << "the unit is recorded every frame and handed both products it takes";
  const io::ImageF diffuse = gpuio::readbackImage(context(), run.gi->indirectDiffuse());
  for (int y = 0; y < diffuse.height; ++y)
    for (int x = 0; x < diffuse.width; ++x)
      for (int c = 0; c < 3; ++c) ASSERT_EQ(diffuse.at(x, y, c), kFlatLight[c]) << x << "," << y << " channel " << c;
  // The composite took it: it differs from the library's own frame where
  // there are surfaces (and the flat light is no copy of the branch's).
  const io::ImageF composite = gpuio::readbackImage(context(), run.gi->composite());
  double change = 0.0;
  for (std::size_t i = 0; i < composite.pixels.size(); ++i)
    change += std::abs(composite.pixels[i] - plainComposite.pixels[i]);
  EXPECT_GT(change / double(composite.pixels.size()), 0.01);
  EXPECT_TRUE(contains(listed(run.gi->library()), "gi.flat_diffuse.light"));
  // Registered once, in its place: just before the composite.
  const std::vector<UnitRegistration> units = registeredUnits();
  ASSERT_GE(units.size(), 2u);
  EXPECT_EQ(units[units.size() - 2].name, "flat_diffuse");
  EXPECT_EQ(units.back().name, "composite");
}

// The depth pyramid is built only on frames a unit takes it: with the
// specular branch off nobody does, until an extra unit asks for it.
TEST_F(GiUnits, AProductIsMadeOnTheFramesAUnitTakesIt) {
  Settings settings;
  settings.specular.enabled = false;
  {
    Run run = start(settings);
    advance(run, 2);
    EXPECT_FALSE(contains(listed(run.gi->library()), "gi.depth_pyramid")) << "built though no unit takes it";
  }
  std::vector<std::string> handed;
  const UnitRegistration::Scoped extra(flatDiffuse({"depth_pyramid"}, "", handed), "composite");
  Run run = start(settings);
  advance(run, 2);
  EXPECT_TRUE(contains(listed(run.gi->library()), "gi.depth_pyramid")) << "not built for the unit that takes it";
  EXPECT_EQ(handed, (std::vector<std::string>{"depth_pyramid", "depth_pyramid"}));
}

TEST_F(GiUnits, AUnitThatTakesAProductNoUnitMakesIsRefusedByName) {
  std::vector<std::string> handed;
  const UnitRegistration::Scoped extra(flatDiffuse({"ambient_occlusion"}, "", handed), "composite");
  Run run = start(Settings{});
  try {
    advance(run, 1);
    FAIL() << "a frame whose unit takes a product nobody makes was recorded";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("flat_diffuse"), std::string::npos) << what;
    EXPECT_NE(what.find("ambient_occlusion"), std::string::npos) << what;
  }
}

TEST(GiUnitRegistry, AUnitNeedsANameOfItsOwnAndAPlaceThatExists) {
  std::vector<std::string> handed;
  UnitRegistration taken = flatDiffuse({}, "", handed);
  taken.name = "diffuse";
  EXPECT_THROW(UnitRegistration::Scoped(taken, "composite"), Error);
  EXPECT_THROW(UnitRegistration::Scoped(flatDiffuse({}, "", handed), "no_such_unit"), Error);
  // The library's order: a product is made before the units that take it.
  std::vector<std::string> names;
  for (const UnitRegistration& unit : registeredUnits()) names.push_back(unit.name);
  EXPECT_EQ(names, (std::vector<std::string>{"history", "depth_pyramid", "screen_tiles", "light_change", "cache",
                                             "diffuse", "specular", "engine_signal", "denoise", "composite"}));
}

}  // namespace
}  // namespace bounce::gi

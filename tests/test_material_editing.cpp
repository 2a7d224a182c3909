// Live material editing in the renderer: FrameRenderer::materialAt (which
// material a pixel shows), setMaterial (the new values in every pass that
// reads the material table, nothing else changed; bad edits refused), the
// reference path tracer following an edit, and a glTF export of an edited
// scene rendering as the edited renderer does. On lavapipe with validation,
// the Cornell box at 64x48.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include "gpu/error.h"
#include "gpu/frame_loop.h"
#include "gpu/transfer.h"
#include "gpu_test.h"
#include "gpuio/gpu_images.h"
#include "render/frame_renderer.h"
#include "render/frame_types.glsl"
#include "render/reference_renderer.h"
#include "scene/builtin_scenes.h"
#include "scene/gltf_export.h"
#include "scene/gltf_import.h"
#include "test_meshes.h"

namespace bounce::render {
namespace {

namespace fs = std::filesystem;

constexpr std::uint32_t kWidth = 64;
constexpr std::uint32_t kHeight = 48;

std::size_t materialNamed(const scene::Scene& s, const std::string& name) {
  for (std::size_t i = 0; i < s.materials.size(); ++i)
    if (s.materials[i].name == name) return i;
  ADD_FAILURE() << "no material '" << name << "'";
  return 0;
}

// The message of what `action` throws as E, or "no exception".
template <class E, class Action>
std::string messageOf(Action&& action) {
  try {
    action();
  } catch (const E& error) {
    return error.what();
  }
  return "no exception";
}

class MaterialEditingTest : public testing::GpuTest {
 protected:
  void SetUp() override {
    GpuTest::SetUp();
    loop_ = std::make_unique<gpu::FrameLoop>(context(), FrameRenderer::kFramesInFlight);
    cornell_ = scene::makeBuiltinScene("cornell");
    view_.camera = *cornell_.suggestedCamera;
  }

  std::unique_ptr<FrameRenderer> renderer(const scene::Scene& s, std::uint32_t width = kWidth,
                                          std::uint32_t height = kHeight) {
    return std::make_unique<FrameRenderer>(context(), s, testing::smallRendererOptions(s, width, height));
  }

  // Records one frame of `view` and waits for it.
  void renderFrame(FrameRenderer& r, const FrameView& view) {
    r.record(loop_->beginFrame(), loop_->frameIndex(), view);
    loop_->endFrame();
    loop_->finish();
  }

  // The ids image as integers (exact: a float readback would round them).
  std::vector<std::uint32_t> ids(FrameRenderer& r) {
    const std::vector<std::uint8_t> bytes = gpu::readbackImageBytes(context(), r.ids());
    std::vector<std::uint32_t> values(bytes.size() / 4);
    std::memcpy(values.data(), bytes.data(), bytes.size());
    return values;
  }

  std::unique_ptr<gpu::FrameLoop> loop_;
  scene::Scene cornell_;
  FrameView view_;
};

// The floor, both side walls and the background seen from the box's
// photograph camera, and nothing from a pixel outside the image. A second
// frame from a camera 20 m to the side shows background where the red wall
// was: the answer is the last frame's.
TEST_F(MaterialEditingTest, MaterialAtNamesTheMaterialAPixelShows) {
  auto r = renderer(cornell_);
  renderFrame(*r, view_);
  EXPECT_EQ(r->materialAt(32, 44), materialNamed(cornell_, "cornell white"));  // floor
  EXPECT_EQ(r->materialAt(12, 24), materialNamed(cornell_, "cornell red"));
  EXPECT_EQ(r->materialAt(51, 24), materialNamed(cornell_, "cornell green"));
  EXPECT_EQ(r->materialAt(32, 6), materialNamed(cornell_, "cornell light"));
  EXPECT_EQ(r->materialAt(0, 0), std::nullopt);  // beside the box: the black environment
  EXPECT_EQ(r->materialAt(kWidth, 0), std::nullopt);
  EXPECT_EQ(r->materialAt(0, kHeight), std::nullopt);

  FrameView aside = view_;
  aside.camera.position.x += 20.0f;
  aside.camera.target.x += 20.0f;
  aside.cut = true;
  renderFrame(*r, aside);
  EXPECT_EQ(r->materialAt(12, 24), std::nullopt);
}

// The green wall made red: its pixels' red/green ratio rises in the direct
// light and its stored base colour changes, every other pixel's direct
// light stays the same bit for bit; only the editable values change (the
// name and the texture slots stay), and the table every scene-tracing pass
// binds holds the new values.
TEST_F(MaterialEditingTest, SetMaterialChangesOnlyThatMaterialsPixels) {
  auto r = renderer(cornell_);
  renderFrame(*r, view_);
  const io::ImageF before = gpuio::readbackImage(context(), r->direct());
  const io::ImageF albedoBefore = gpuio::readbackImage(context(), r->baseColorMetallic());
  const std::vector<std::uint32_t> idsBefore = ids(*r);

  const std::size_t green = materialNamed(cornell_, "cornell green");
  scene::Material edit;
  edit.name = "ignored";
  edit.baseColorFactor = glm::vec4(0.8f, 0.05f, 0.05f, 1.0f);
  edit.metallicFactor = 0.0f;
  edit.roughnessFactor = 0.7f;
  edit.baseColorTexture = 0;  // the scene has no textures: taking it would break the frame
  EXPECT_EQ(r->materialRevision(), 0u);
  r->setMaterial(green, edit);
  EXPECT_EQ(r->materialRevision(), 1u);
  EXPECT_EQ(r->materials()[green].name, "cornell green");
  EXPECT_EQ(r->materials()[green].baseColorTexture, -1);
  EXPECT_EQ(r->materials()[green].baseColorFactor, edit.baseColorFactor);
  EXPECT_EQ(r->materials()[green].roughnessFactor, 0.7f);
  EXPECT_EQ(cornell_.materials[green].roughnessFactor, 1.0f);  // the scene itself is not edited

  gpu::Buffer* table = nullptr;
  for (const gpu::Bind& bind : r->sceneBinds(loop_->frameIndex()))
    if (bind.name == "gIn_Materials") table = bind.buffer;
  ASSERT_NE(table, nullptr);
  const std::vector<std::uint8_t> bytes = gpu::readbackBuffer(context(), *table);
  shared::GpuMaterial stored{};
  std::memcpy(&stored, bytes.data() + green * sizeof(shared::GpuMaterial), sizeof stored);
  EXPECT_EQ(stored.baseColorFactor, edit.baseColorFactor);
  EXPECT_EQ(stored.factors.y, 0.7f);
  EXPECT_EQ(stored.textures.x, shared::kNoTexture);

  renderFrame(*r, view_);
  const io::ImageF after = gpuio::readbackImage(context(), r->direct());
  const io::ImageF albedoAfter = gpuio::readbackImage(context(), r->baseColorMetallic());
  ASSERT_EQ(ids(*r), idsBefore);
  int greenPixels = 0, otherPixels = 0;
  double ratioBefore = 0.0, ratioAfter = 0.0;
  for (int y = 0; y < int(kHeight); ++y)
    for (int x = 0; x < int(kWidth); ++x) {
      const std::uint32_t id = idsBefore[std::size_t(y) * kWidth + std::size_t(x)];
      if (id != 0xffffffffu && (id & 0xffffu) == green) {
        ++greenPixels;
        ratioBefore += before.at(x, y, 0) / std::max(before.at(x, y, 1), 1e-6f);
        ratioAfter += after.at(x, y, 0) / std::max(after.at(x, y, 1), 1e-6f);
        EXPECT_GT(albedoAfter.at(x, y, 0), albedoBefore.at(x, y, 0) + 0.5f) << x << ", " << y;
        continue;
      }
      ++otherPixels;
      for (int c = 0; c < 4; ++c)
        ASSERT_EQ(before.at(x, y, c), after.at(x, y, c)) << "pixel " << x << ", " << y << " channel " << c;
    }
  ASSERT_GT(greenPixels, 100);
  ASSERT_GT(otherPixels, 1000);
  EXPECT_LT(ratioBefore / greenPixels, 0.5);
  EXPECT_GT(ratioAfter / greenPixels, 5.0);
}

// Each bad edit is refused with the index, the material and the value,
// and leaves the material as it was.
TEST_F(MaterialEditingTest, SetMaterialRefusesBadIndicesAndValues) {
  auto r = renderer(cornell_, 16, 12);
  const std::size_t red = materialNamed(cornell_, "cornell red");
  EXPECT_EQ(messageOf<std::out_of_range>([&] { r->setMaterial(4, scene::Material{}); }),
            "setMaterial: material index 4 is out of range; the scene has 4 materials");
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const auto refusal = [&](auto change) {
    scene::Material m = cornell_.materials[red];
    change(m);
    return messageOf<std::invalid_argument>([&] { r->setMaterial(red, m); });
  };
  const std::string prefix = "setMaterial: material " + std::to_string(red) + " 'cornell red': ";
  EXPECT_EQ(refusal([](scene::Material& m) { m.roughnessFactor = 1.5f; }),
            prefix + "roughness 1.5 is not within [0, 1]");
  EXPECT_EQ(refusal([](scene::Material& m) { m.metallicFactor = -0.25f; }),
            prefix + "metallic -0.25 is not within [0, 1]");
  EXPECT_EQ(refusal([&](scene::Material& m) { m.baseColorFactor.y = nan; }),
            prefix + "base colour factor (0.63, nan, 0.05, 1) is not within [0, 1]");
  EXPECT_EQ(refusal([](scene::Material& m) { m.baseColorFactor.x = 1.25f; }),
            prefix + "base colour factor (1.25, 0.065, 0.05, 1) is not within [0, 1]");
  EXPECT_EQ(refusal([](scene::Material& m) { m.emissiveFactor.z = -1.0f; }),
            prefix + "emissive factor (0, 0, -1) is not finite and >= 0");
  EXPECT_EQ(refusal([](scene::Material& m) { m.emissiveStrength = std::numeric_limits<float>::infinity(); }),
            prefix + "emissive strength inf is not finite and >= 0");
  const std::string tooBright = refusal([](scene::Material& m) {
    m.emissiveFactor = glm::vec3(1.0f);
    m.emissiveStrength = 1e21f;
  });
  EXPECT_EQ(tooBright.rfind(prefix + "emission (strength x factor) 1e+21 is above 1e+20", 0), 0u) << tooBright;
  EXPECT_EQ(r->materials()[red].roughnessFactor, cornell_.materials[red].roughnessFactor);
  EXPECT_EQ(r->materials()[red].baseColorFactor, cornell_.materials[red].baseColorFactor);
  EXPECT_EQ(r->materialRevision(), 0u);
}

// The reference samples emitters from a list made from the materials: after
// the ceiling light is switched off, recording on from the old sums is
// refused, and restart() makes the list anew (no emitter left).
TEST_F(MaterialEditingTest, TheReferenceFollowsAnEditAfterRestart) {
  auto r = renderer(cornell_, 16, 12);
  view_.camera = *cornell_.suggestedCamera;
  renderFrame(*r, view_);
  ReferenceRenderer reference(context(), *r, cornell_, loop_->frameIndex(), 0.0f, {.maxBounces = 1});
  EXPECT_EQ(reference.emissiveTriangleCount(), 2u);

  const std::size_t light = materialNamed(cornell_, "cornell light");
  scene::Material off = r->materials()[light];
  off.emissiveStrength = 0.0f;
  r->setMaterial(light, off);
  renderFrame(*r, view_);
  gpu::Recorder& recorder = loop_->beginFrame();
  EXPECT_EQ(messageOf<gpu::GpuError>([&] { reference.record(recorder, 1); }),
            "reference: the renderer's materials changed (setMaterial) since the reference started; restart() it, so "
            "its sums and emissive triangles are the new materials'");
  reference.restart(recorder, loop_->frameIndex() - 1, 0.0f);
  EXPECT_EQ(reference.emissiveTriangleCount(), 0u);
  EXPECT_EQ(reference.record(recorder, 1), 1u);
  loop_->endFrame();
  loop_->finish();
}

// The viewer's "save": the box with an edited wall exported to glTF and
// loaded again renders as the renderer that was edited live does (the
// same ids, direct light within half-float rounding).
TEST_F(MaterialEditingTest, AnExportedEditRendersAsTheLiveEdit) {
  const std::size_t red = materialNamed(cornell_, "cornell red");
  scene::Material edit = cornell_.materials[red];
  edit.baseColorFactor = glm::vec4(0.2f, 0.3f, 0.9f, 1.0f);
  edit.roughnessFactor = 0.35f;
  edit.metallicFactor = 0.5f;

  auto live = renderer(cornell_);
  live->setMaterial(red, edit);
  renderFrame(*live, view_);
  const io::ImageF liveDirect = gpuio::readbackImage(context(), live->direct());
  const std::vector<std::uint32_t> liveIds = ids(*live);

  const fs::path folder = fs::temp_directory_path() / ("bounce_material_editing_" + std::to_string(::getpid()));
  fs::create_directories(folder);
  scene::Scene edited = cornell_;
  edited.materials = live->materials();
  scene::writeGltf(edited, folder / "cornell.gltf");
  scene::Scene loaded = scene::loadGltf(folder / "cornell.gltf", {.warn = [](const std::string&) {}});
  fs::remove_all(folder);
  ASSERT_TRUE(scene::adoptDirectionalLightAsSun(loaded));

  auto exported = renderer(loaded);
  renderFrame(*exported, view_);
  const io::ImageF exportedDirect = gpuio::readbackImage(context(), exported->direct());
  EXPECT_EQ(ids(*exported), liveIds);
  int redPixels = 0;
  for (int y = 0; y < int(kHeight); ++y)
    for (int x = 0; x < int(kWidth); ++x) {
      const std::uint32_t id = liveIds[std::size_t(y) * kWidth + std::size_t(x)];
      redPixels += id != 0xffffffffu && (id & 0xffffu) == red;
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(exportedDirect.at(x, y, c), liveDirect.at(x, y, c), 2e-3f * liveDirect.at(x, y, c) + 1e-6f)
            << "pixel " << x << ", " << y << " channel " << c;
    }
  EXPECT_GT(redPixels, 100);
}

}  // namespace
}  // namespace bounce::render

// Tests of the reference path tracer (src/render/reference_renderer) against
// closed-form answers: furnaces (a closed emitting sphere of albedo a glows
// with e / (1 - a)), a Lambert plane under a uniform sky (albedo * L), a plane
// under a sky with a bright patch (the cosine-weighted integral of the map,
// which only comes out right if environment light sampling and its MIS
// weights are), error falling as 1 / sqrt(spp), and the bookkeeping of
// halves and seeds. Plus the light distributions on the CPU. On lavapipe with
// validation; images are tiny so each test takes seconds.
#include "render/reference_renderer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "gpu/error.h"
#include "gpu/frame_loop.h"
#include "gpu_test.h"
#include "gpuio/gpu_images.h"
#include "metrics/image_metrics.h"
#include "shared/color.glsl"
#include "shared/equirect.glsl"
#include "shared/rng.glsl"
#include "shared/sampling.glsl"
#include "test_meshes.h"

namespace bounce::render {
namespace {

namespace fs = std::filesystem;

scene::Material lambert(glm::vec3 albedo) {
  scene::Material m;
  m.baseColorFactor = glm::vec4(albedo, 1.0f);
  m.metallicFactor = 0.0f;
  m.roughnessFactor = 1.0f;
  return m;
}

scene::Scene oneMeshScene(std::string name, scene::Mesh mesh, scene::Material material, float scale = 1.0f) {
  scene::Scene s;
  s.name = std::move(name);
  mesh.material = 0;
  s.materials = {material};
  s.meshes = {std::move(mesh)};
  scene::Node node;
  node.meshes = {0};
  node.local.scale = glm::vec3(scale);
  s.nodes = {node};
  s.roots = {0};
  s.hasSun = false;
  return s;
}

// A closed sphere of radius 2 that emits e and reflects with `material`.
// Its triangles face outwards, so it emits inwards only as a double-sided material.
scene::Scene furnace(scene::Material material, glm::vec3 emission) {
  material.emissiveFactor = emission;
  material.doubleSided = true;
  return oneMeshScene("furnace", testing::sphereMesh(64, 32), material, 2.0f);
}

// Per channel, the mean over the image.
glm::vec3 meanOf(const io::ImageF& image) {
  glm::dvec3 sum(0.0);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      for (int c = 0; c < 3; ++c) sum[c] += image.at(x, y, c);
  return glm::vec3(sum / double(image.width * image.height));
}

// Root mean square error of every value against one expected colour.
double rmseAgainst(const io::ImageF& image, glm::vec3 expected) {
  double sum = 0.0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      for (int c = 0; c < 3; ++c) sum += std::pow(double(image.at(x, y, c)) - expected[c], 2.0);
  return std::sqrt(sum / double(3 * image.width * image.height));
}

void expectNear(glm::vec3 actual, glm::vec3 expected, float relative, const char* what) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(actual[c], expected[c], relative * expected[c]) << what << ", channel " << c;
}

// The specular lobe's directional albedo by Monte Carlo: the mean of
// F G2 / G1 over VNDF-sampled reflections (the path tracer's estimator).
float specularAlbedo(float f0, float cosThetaV, float roughness) {
  const glm::vec3 v(std::sqrt(1.0f - cosThetaV * cosThetaV), 0.0f, cosThetaV);
  const float alpha = shared::ggxAlpha(roughness);
  std::uint32_t rng = 7u;
  double sum = 0.0;
  const int count = 200000;
  for (int i = 0; i < count; ++i) {
    const glm::vec2 u(shared::rngUniform(rng), shared::rngUniform(rng));
    const glm::vec3 m = shared::sampleGgxVisibleNormal(v, alpha, u);
    const glm::vec3 l = glm::reflect(-v, m);
    sum += shared::ggxReflectionWeight(glm::vec3(f0), glm::dot(v, m), l.z, v.z, alpha).x;
  }
  return float(sum / count);
}

class ReferenceTest : public testing::GpuTest {
 protected:
  // Renders the G-buffer of one frame, then `spp` reference samples.
  struct Run {
    std::unique_ptr<FrameRenderer> frame;
    std::unique_ptr<ReferenceRenderer> reference;
    std::unique_ptr<gpu::FrameLoop> loop;
    std::uint64_t frameIndex = 0;  // the FrameRenderer frame traced from
    ReferenceImages resolve(ReferenceHalf half = ReferenceHalf::Both) { return reference->resolve(*loop, half); }
    void addSamples(std::uint64_t spp) {
      const std::uint64_t goal = reference->samplesPerPixel() + spp;
      while (reference->samplesPerPixel() < goal) {
        reference->record(loop->beginFrame(), std::uint32_t(goal - reference->samplesPerPixel()));
        loop->endFrame();
      }
    }
  };

  Run start(const scene::Scene& s, const scene::CameraPose& camera, ReferenceOptions options,
            EnvironmentDesc environment = {}, std::uint32_t width = 16, std::uint32_t height = 16) {
    Run run;
    run.frame =
        std::make_unique<FrameRenderer>(context(), s, testing::smallRendererOptions(s, width, height, environment));
    run.loop = std::make_unique<gpu::FrameLoop>(context(), FrameRenderer::kFramesInFlight);
    run.frame->record(run.loop->beginFrame(), run.loop->frameIndex(), {camera, 0.0f, false});
    run.frameIndex = run.loop->frameIndex();
    run.loop->endFrame();
    run.loop->finish();
    run.reference = std::make_unique<ReferenceRenderer>(context(), *run.frame, s, run.frameIndex, 0.0f, options);
    return run;
  }

  // A uniform environment map of radiance `radiance` (plus an optional
  // bright patch), written as an EXR the FrameRenderer loads.
  fs::path writeEnvironment(const std::string& name, glm::vec3 radiance, glm::ivec4 patch = {},
                            glm::vec3 patchRadiance = {}) {
    io::ImageF map(64, 32, {"R", "G", "B"});
    for (int y = 0; y < map.height; ++y)
      for (int x = 0; x < map.width; ++x) {
        const bool inPatch = x >= patch.x && x < patch.x + patch.z && y >= patch.y && y < patch.y + patch.w;
        for (int c = 0; c < 3; ++c) map.at(x, y, c) = inPatch ? patchRadiance[c] : radiance[c];
      }
    const fs::path dir = fs::temp_directory_path() / ("bounce_reference_test_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path path = dir / (name + ".exr");
    io::writeExr(path, map);
    return path;
  }
};

// From the furnace's centre, so every primary ray meets the sphere head on.
scene::CameraPose furnaceCamera() { return testing::cameraAt(glm::vec3(0.0f), glm::vec3(0.3f, -0.2f, -1.0f), 60.0f); }

TEST_F(ReferenceTest, LambertFurnaceGlowsWithEmissionOverOneMinusAlbedo) {
  const glm::vec3 emission(1.0f, 0.5f, 0.25f);
  const float albedo = 0.5f;
  ReferenceOptions options;
  options.lobes = shared::kLobeDiffuse;
  options.maxBounces = 64;
  Run run = start(furnace(lambert(glm::vec3(albedo)), emission), furnaceCamera(), options);
  run.addSamples(64);
  const ReferenceImages images = run.resolve();
  EXPECT_EQ(images.droppedSamples, 0u);
  expectNear(meanOf(images.radiance), emission / (1.0f - albedo), 0.01f, "radiance");
  // Demodulated: the light arriving, e / (1 - a) from every direction.
  expectNear(meanOf(images.indirectDiffuse), emission / (1.0f - albedo), 0.01f, "indirect diffuse");
  expectNear(meanOf(images.direct), emission, 1e-3f, "direct (the emission itself)");
}

TEST_F(ReferenceTest, MirrorFurnaceGlowsWithEmissionOverOneMinusReflectance) {
  // A smooth metal sphere seen from its centre: every reflection is at normal
  // incidence, where Schlick's Fresnel is F0 = the base colour.
  const glm::vec3 emission(0.2f, 0.4f, 0.8f);
  scene::Material mirror;
  mirror.baseColorFactor = glm::vec4(glm::vec3(0.6f), 1.0f);
  mirror.metallicFactor = 1.0f;
  mirror.roughnessFactor = 0.0f;
  ReferenceOptions options;
  options.lobes = shared::kLobeSpecular;
  options.maxBounces = 64;
  Run run = start(furnace(mirror, emission), furnaceCamera(), options);
  run.addSamples(8);
  const ReferenceImages images = run.resolve();
  const float f0 = std::round(0.6f * 255.0f) / 255.0f;
  expectNear(meanOf(images.radiance), emission / (1.0f - f0), 0.01f, "radiance");
}

scene::CameraPose lookingDownAtThePlane() {
  return testing::cameraAt(glm::vec3(0.0f, 2.0f, 2.0f), glm::vec3(0.0f), 30.0f);
}

TEST_F(ReferenceTest, LambertPlaneUnderAUniformSkyReflectsAlbedoTimesSky) {
  const glm::vec3 sky(0.5f, 1.0f, 2.0f);
  const float albedo = 0.6f;
  EnvironmentDesc environment;
  environment.map = writeEnvironment("uniform", sky);
  {
    ReferenceOptions options;
    options.lobes = shared::kLobeDiffuse;
    Run run = start(oneMeshScene("plane", testing::planeMesh(50.0f), lambert(glm::vec3(albedo))),
                    lookingDownAtThePlane(), options, environment);
    run.addSamples(16);
    const ReferenceImages images = run.resolve();
    const float stored = std::round(albedo * 255.0f) / 255.0f;
    expectNear(meanOf(images.radiance), stored * sky, 0.01f, "radiance of the Lambert plane");
    expectNear(meanOf(images.indirectDiffuse), sky, 0.01f, "demodulated diffuse");
  }
  {
    // With the specular lobe too, the demodulated diffuse is still the sky,
    // and the demodulated specular is the sky to within the accuracy of
    // specularReflectance()'s fit.
    scene::Material glossy = lambert(glm::vec3(albedo));
    glossy.roughnessFactor = 0.5f;
    Run run = start(oneMeshScene("plane", testing::planeMesh(50.0f), glossy), lookingDownAtThePlane(), {}, environment);
    run.addSamples(16);
    const ReferenceImages images = run.resolve();
    expectNear(meanOf(images.indirectDiffuse), sky, 0.01f, "demodulated diffuse");
    // Under a uniform sky the specular lobe reflects its albedo times the
    // sky; demodulation divides by specularReflectance()'s fit of it.
    const glm::vec3 v = glm::normalize(lookingDownAtThePlane().position);
    const float albedoOfLobe = specularAlbedo(0.04f, v.y, glossy.roughnessFactor);
    const float fit = shared::specularReflectance(glm::vec3(0.04f), v.y, glossy.roughnessFactor).x;
    expectNear(meanOf(images.indirectSpecular), sky * (albedoOfLobe / fit), 0.03f, "demodulated specular");
  }
}

TEST_F(ReferenceTest, BrightSkyPatchGivesTheCosineWeightedIntegralOfTheMap) {
  // A dim sky with a patch 2000 times brighter: cosine sampling alone would
  // be very noisy; light sampling with MIS finds the patch. The answer is
  // the map's cosine-weighted integral over the upper hemisphere.
  const glm::vec3 base(0.02f), patchRadiance(40.0f, 30.0f, 20.0f);
  const glm::ivec4 patch(40, 6, 3, 2);  // texels x, y, width, height of the 64 x 32 map
  EnvironmentDesc environment;
  environment.map = writeEnvironment("patch", base, patch, patchRadiance);
  Run run = start(oneMeshScene("plane", testing::planeMesh(50.0f), lambert(glm::vec3(0.5f))), lookingDownAtThePlane(),
                  {}, environment);
  run.addSamples(64);
  const ReferenceImages images = run.resolve();

  // Integrate the map as it is sampled (bilinear between texel centres):
  // fine quadrature over the upper hemisphere.
  const auto texel = [&](int x, int y) {
    x = (x % 64 + 64) % 64;
    y = std::clamp(y, 0, 31);
    const bool inPatch = x >= patch.x && x < patch.x + patch.z && y >= patch.y && y < patch.y + patch.w;
    return inPatch ? patchRadiance : base;
  };
  glm::dvec3 irradianceOverPi(0.0);
  const int steps = 1024;
  for (int j = 0; j < steps / 2; ++j)
    for (int i = 0; i < steps; ++i) {
      const glm::vec2 uv((float(i) + 0.5f) / steps, (float(j) + 0.5f) / steps);
      const glm::vec3 d = shared::equirectDirection(uv);
      const float fx = uv.x * 64.0f - 0.5f, fy = uv.y * 32.0f - 0.5f;
      const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
      const float tx = fx - float(x0), ty = fy - float(y0);
      const glm::vec3 radiance = glm::mix(glm::mix(texel(x0, y0), texel(x0 + 1, y0), tx),
                                          glm::mix(texel(x0, y0 + 1), texel(x0 + 1, y0 + 1), tx), ty);
      const double solidAngle = (2.0 * M_PI / steps) * (M_PI / steps) * std::sin(M_PI * uv.y);
      irradianceOverPi += glm::dvec3(radiance) * double(std::max(d.y, 0.0f)) * solidAngle / M_PI;
    }
  expectNear(meanOf(images.indirectDiffuse), glm::vec3(irradianceOverPi), 0.02f, "demodulated diffuse");
}

TEST_F(ReferenceTest, ErrorFallsAsOneOverTheSquareRootOfTheSamples) {
  const glm::vec3 emission(1.0f);
  ReferenceOptions options;
  options.lobes = shared::kLobeDiffuse;
  options.maxBounces = 64;
  options.samplesPerDispatch = 1;
  Run run = start(furnace(lambert(glm::vec3(0.5f)), emission), furnaceCamera(), options);
  const glm::vec3 expected = emission / (1.0f - 0.5f);
  std::vector<double> errors;
  for (std::uint64_t spp : {2u, 8u, 32u, 128u}) {
    run.addSamples(spp - run.reference->samplesPerPixel());
    errors.push_back(rmseAgainst(run.resolve().indirectDiffuse, expected));
  }
  // Each quadrupling of the samples halves the error (slope -1/2 on log-log).
  const double slope = std::log(errors.back() / errors.front()) / std::log(64.0);
  EXPECT_NEAR(slope, -0.5, 0.12) << "errors " << errors[0] << ", " << errors[1] << ", " << errors[2] << ", "
                                 << errors[3];
  for (std::size_t i = 1; i < errors.size(); ++i) EXPECT_LT(errors[i], errors[i - 1]);
}

TEST_F(ReferenceTest, HalvesAreIndependentAndAverageToTheWhole) {
  scene::Scene s = furnace(lambert(glm::vec3(0.5f)), glm::vec3(1.0f));
  Run run = start(s, furnaceCamera(), {});
  run.addSamples(6);
  EXPECT_EQ(run.reference->samplesPerPixel(ReferenceHalf::A), 3u);
  EXPECT_EQ(run.reference->samplesPerPixel(ReferenceHalf::B), 3u);
  const io::ImageF whole = run.resolve().indirectDiffuse;
  const io::ImageF a = run.resolve(ReferenceHalf::A).indirectDiffuse;
  const io::ImageF b = run.resolve(ReferenceHalf::B).indirectDiffuse;
  std::size_t differing = 0;
  for (std::size_t i = 0; i < whole.pixels.size(); ++i) {
    EXPECT_NEAR(whole.pixels[i], 0.5f * (a.pixels[i] + b.pixels[i]), 1e-5f * (1.0f + whole.pixels[i]));
    differing += a.pixels[i] != b.pixels[i];
  }
  EXPECT_GT(differing, whole.pixels.size() * 9 / 10);
}

TEST_F(ReferenceTest, TheSameSeedGivesTheSameBitsAndAnotherSeedOtherNoise) {
  scene::Scene s = furnace(lambert(glm::vec3(0.5f)), glm::vec3(1.0f));
  const auto render = [&](std::uint32_t seed) {
    ReferenceOptions options;
    options.seed = seed;
    Run run = start(s, furnaceCamera(), options);
    run.addSamples(2);
    return run.resolve().radiance;
  };
  const io::ImageF first = render(1), again = render(1), other = render(2);
  EXPECT_EQ(first.pixels, again.pixels);
  EXPECT_NE(first.pixels, other.pixels);
}

// restart() traces a frame anew, as bounce denoise traces each frame of a
// sequence: from empty sums, with samples no earlier frame drew, resolved
// into the GPU images an engine's signals would be. Alpha holds the mean
// first-hit distance of the paths: inside a sphere of radius R seen from
// its centre, a cosine-sampled ray from the shell crosses a chord of 2R
// cos(theta), 4R/3 on average; a mirror sends the ray straight back
// across, 2R.
TEST_F(ReferenceTest, RestartTracesAFrameAnewWithNewSamplesAndTheFirstHitDistance) {
  constexpr float kRadius = 2.0f;  // furnace()'s
  const auto trace = [&](Run& run, std::uint32_t spp, gpu::Image& (ReferenceRenderer::*image)()) {
    gpu::Recorder& recorder = run.loop->beginFrame();
    run.reference->restart(recorder, run.frameIndex, 0.0f);
    while (run.reference->samplesPerPixel() < spp)
      run.reference->record(recorder, std::uint32_t(spp - run.reference->samplesPerPixel()));
    run.reference->recordResolve(recorder);
    run.loop->endFrame();
    run.loop->finish();
    return gpuio::readbackImage(context(), ((*run.reference).*image)());
  };
  const auto meanAlpha = [](const io::ImageF& image) {
    double sum = 0.0;
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x) sum += image.at(x, y, 3);
    return sum / double(image.width * image.height);
  };
  ReferenceOptions diffuseOnly;
  diffuseOnly.lobes = shared::kLobeDiffuse;
  Run run = start(furnace(lambert(glm::vec3(0.5f)), glm::vec3(1.0f)), furnaceCamera(), diffuseOnly);
  run.addSamples(3);
  const io::ImageF first = trace(run, 16, &ReferenceRenderer::indirectDiffuseImage);
  const io::ImageF second = trace(run, 16, &ReferenceRenderer::indirectDiffuseImage);
  EXPECT_EQ(run.reference->samplesPerPixel(), 16u) << "each restart counts its own samples";
  std::size_t differing = 0;
  for (std::size_t i = 0; i < first.pixels.size(); ++i) differing += first.pixels[i] != second.pixels[i];
  EXPECT_GT(differing, first.pixels.size() * 9 / 10) << "the second frame drew the first one's samples again";
  // Cleared sums: each is the furnace's e / (1 - a), not the sum of both.
  expectNear(meanOf(first), glm::vec3(2.0f), 0.05f, "first frame");
  expectNear(meanOf(second), glm::vec3(2.0f), 0.05f, "second frame");
  EXPECT_NEAR(meanAlpha(second), 4.0 * kRadius / 3.0, 0.03 * 4.0 * kRadius / 3.0) << "mean first-hit distance";

  scene::Material mirror;
  mirror.baseColorFactor = glm::vec4(glm::vec3(0.6f), 1.0f);
  mirror.metallicFactor = 1.0f;
  mirror.roughnessFactor = 0.0f;
  ReferenceOptions specularOnly;
  specularOnly.lobes = shared::kLobeSpecular;
  Run mirrored = start(furnace(mirror, glm::vec3(1.0f)), furnaceCamera(), specularOnly);
  EXPECT_NEAR(meanAlpha(trace(mirrored, 2, &ReferenceRenderer::indirectSpecularImage)), 2.0 * kRadius,
              0.01 * 2.0 * kRadius)
      << "a mirror's first hit";
}

TEST_F(ReferenceTest, SingleSidedEmittersLightOnlyTheirFrontSide) {
  // A furnace whose shell faces outwards and is single-sided: seen and lit
  // from inside, it emits nothing, so everything inside is black.
  scene::Material material = lambert(glm::vec3(0.5f));
  Run run = start(
      [&] {
        scene::Scene s = furnace(material, glm::vec3(1.0f));
        s.materials[0].doubleSided = false;
        return s;
      }(),
      furnaceCamera(), {});
  run.addSamples(4);
  const ReferenceImages images = run.resolve();
  EXPECT_EQ(meanOf(images.radiance), glm::vec3(0.0f));
  EXPECT_EQ(meanOf(images.direct), glm::vec3(0.0f));
}

TEST_F(ReferenceTest, BadOptionsAreRefused) {
  scene::Scene s = furnace(lambert(glm::vec3(0.5f)), glm::vec3(1.0f));
  ReferenceOptions noLobes;
  noLobes.lobes = 0;
  EXPECT_THROW(start(s, furnaceCamera(), noLobes), gpu::GpuError);
  ReferenceOptions tooDeep;
  tooDeep.maxBounces = 5000;
  EXPECT_THROW(start(s, furnaceCamera(), tooDeep), gpu::GpuError);
}

// --- the light distributions, on the CPU

TEST(LightDistributions, EnvironmentPdfIntegratesToOneAndFollowsThePower) {
  // A dim map with a bright 4 x 4 block, which the 32 x 16 distribution
  // covers with 2 x 2 cells (plus the half texel bilinear reads spread it by).
  io::ImageF map(64, 32, {"R", "G", "B"});
  for (float& v : map.pixels) v = 0.1f;
  for (int y = 8; y < 12; ++y)
    for (int x = 8; x < 12; ++x)
      for (int c = 0; c < 3; ++c) map.at(x, y, c) = 500.0f;
  const EnvironmentDistribution d = buildEnvironmentDistribution(map, 32);
  ASSERT_EQ(d.width, 32u);
  ASSERT_EQ(d.height, 16u);
  double integral = 0.0, aroundBlock = 0.0;
  for (std::uint32_t y = 0; y < d.height; ++y)
    for (std::uint32_t x = 0; x < d.width; ++x) {
      const double mass = d.pdfUv({(x + 0.5f) / d.width, (y + 0.5f) / d.height}) / double(d.width * d.height);
      integral += mass;
      if (x >= 3 && x <= 6 && y >= 3 && y <= 6) aroundBlock += mass;
    }
  EXPECT_NEAR(integral, 1.0, 1e-5);
  // The block's share of the power: luminance times sin(theta) of its rows,
  // against every texel's. The cells around it hold all of that share.
  double block = 0.0, total = 0.0;
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) {
      const double power = shared::luminance(glm::vec3(map.at(x, y, 0), map.at(x, y, 1), map.at(x, y, 2))) *
                           std::sin((y + 0.5) / map.height * M_PI);
      total += power;
      if (x >= 8 && x < 12 && y >= 8 && y < 12) block += power;
    }
  EXPECT_GT(block / total, 0.9);
  EXPECT_GE(aroundBlock, block / total - 1e-3);
  EXPECT_LE(aroundBlock, block / total + 0.02);
  EXPECT_EQ(d.marginalCdf.front(), 0.0f);
  EXPECT_EQ(d.marginalCdf.back(), 1.0f);
  for (std::size_t i = 1; i < d.marginalCdf.size(); ++i) EXPECT_GE(d.marginalCdf[i], d.marginalCdf[i - 1]);
}

TEST(LightDistributions, BlackOrNonFiniteEnvironmentsHaveNothingToSample) {
  io::ImageF black(16, 8, {"R", "G", "B"});
  EXPECT_TRUE(buildEnvironmentDistribution(black).empty());
  black.pixels[0] = std::nanf("");
  black.pixels[3] = -5.0f;
  EXPECT_TRUE(buildEnvironmentDistribution(black).empty());
  EXPECT_THROW(buildEnvironmentDistribution(io::ImageF(1, 1, {"R", "G", "B"})), std::invalid_argument);
}

TEST(LightDistributions, EmissiveTrianglesAreChosenByPowerInWorldArea) {
  scene::Scene s;
  s.name = "emitters";
  scene::Material dark = lambert(glm::vec3(0.5f));
  scene::Material bright = dark;
  bright.emissiveFactor = glm::vec3(1.0f);
  bright.emissiveStrength = 3.0f;
  s.materials = {dark, bright};
  scene::Mesh lit = testing::planeMesh(1.0f);  // two triangles of area 2
  lit.material = 1;
  scene::Mesh unlit = testing::planeMesh(1.0f);
  unlit.material = 0;
  s.meshes = {lit, unlit};
  scene::Node small, large, none;
  small.meshes = {0};
  large.meshes = {0};
  large.local.scale = glm::vec3(2.0f, 1.0f, 1.0f);  // twice the area
  none.meshes = {1};
  s.nodes = {small, large, none};
  s.roots = {0, 1, 2};
  const std::vector<scene::Instance> instances = scene::instancesAt(s, 0.0f);
  SceneBvh bvh(s);
  bvh.setInstances(instances);
  const EmissiveTriangles emissive = collectEmissiveTriangles(s, bvh, instances);
  ASSERT_EQ(emissive.count(), 4u);  // the unlit plane's two are left out
  EXPECT_NEAR(emissive.totalPower, 3.0 * (4.0 + 8.0), 1e-4);
  std::vector<float> cdf, area;
  for (const glm::uvec4& e : emissive.packed) {
    cdf.push_back(glm::uintBitsToFloat(e.z));
    area.push_back(glm::uintBitsToFloat(e.w));
    EXPECT_LT(e.x, 2u) << "instance of an emissive mesh";
  }
  EXPECT_NEAR(area[0], 2.0f, 1e-5f);
  EXPECT_NEAR(area[2], 4.0f, 1e-5f);
  EXPECT_NEAR(cdf[0], 1.0f / 6.0f, 1e-6f);
  EXPECT_NEAR(cdf[1], 2.0f / 6.0f, 1e-6f);
  EXPECT_NEAR(cdf[2], 4.0f / 6.0f, 1e-6f);
  EXPECT_EQ(cdf[3], 1.0f);
}

}  // namespace
}  // namespace bounce::render

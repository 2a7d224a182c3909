// The min-max depth pyramid (gi::DepthPyramid) and the Hi-Z trace through
// it (shaders/gi/hiz_trace.glsl) on the GPU: the pyramid against a CPU
// reduction, the trace against known answers on synthetic depth buffers
// and against a march through every pixel.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "bounce/gi.h"
#include "gi/depth_pyramid.h"
#include "gi/frame_constants.h"
#include "gpu/constants_layout.h"
#include "gpu/context.h"
#include "gpu/format.h"
#include "gpu/pass.h"
#include "gpu/recorder.h"
#include "gpu/transfer.h"
#include "gpu_test.h"
#include "test_shaders.h"

namespace bounce::testing {
namespace {

using gi::Extent;

// gi/hiz_trace.glsl's outcomes.
constexpr std::uint32_t kHizHit = 0, kHizSky = 1, kHizUndecided = 2;
constexpr float kNearest = 1e-3f;  // kHizNearest

bool background(float viewZ) { return !(std::isfinite(viewZ) && viewZ > 0.0f); }

// --- The pyramid

struct MinMax {
  float nearest = 0.0f, farthest = 0.0f;
  bool operator==(const MinMax&) const = default;
};

Extent levelSize(Extent size, std::uint32_t level) {
  return {std::max(1u, size.width >> level), std::max(1u, size.height >> level)};
}

// Level `level` straight from the pixels: texel (i, j) covers pixels
// [i 2^k, (i + 1) 2^k) x [j 2^k, (j + 1) 2^k), the last of a row or column up to the edge.
std::vector<MinMax> cpuLevel(const std::vector<float>& depth, Extent size, std::uint32_t level) {
  const Extent out = levelSize(size, level);
  std::vector<MinMax> texels(std::size_t(out.width) * out.height);
  for (std::uint32_t j = 0; j < out.height; ++j)
    for (std::uint32_t i = 0; i < out.width; ++i) {
      const std::uint32_t x1 = i + 1 == out.width ? size.width : (i + 1) << level;
      const std::uint32_t y1 = j + 1 == out.height ? size.height : (j + 1) << level;
      float nearest = std::numeric_limits<float>::max(), farthest = 0.0f;
      bool anySurface = false, anyBackground = false;
      for (std::uint32_t y = j << level; y < y1; ++y)
        for (std::uint32_t x = i << level; x < x1; ++x) {
          const float z = depth[std::size_t(y) * size.width + x];
          if (background(z)) {
            anyBackground = true;
            continue;
          }
          anySurface = true;
          nearest = std::min(nearest, z);
          farthest = std::max(farthest, z);
        }
      texels[std::size_t(j) * out.width + i] = {anySurface ? nearest : 0.0f, anyBackground ? 0.0f : farthest};
    }
  return texels;
}

std::vector<MinMax> readLevel(gpu::Context& context, gpu::Image& image, std::uint32_t level, Extent size) {
  gpu::Buffer buffer(context, "tests.pyramid_level", VkDeviceSize(size.width) * size.height * sizeof(MinMax),
                     gpu::BufferUsage::Readback);
  context.submitAndWait([&](gpu::Recorder& r) {
    r.copyImageToBuffer(image, buffer, {.mipLevel = level, .width = size.width, .height = size.height});
    r.makeHostReadable(buffer);
  });
  std::vector<MinMax> texels(std::size_t(size.width) * size.height);
  std::memcpy(texels.data(), buffer.mapped(), texels.size() * sizeof(MinMax));
  return texels;
}

// A march-depth image of `maxSize` holding `depth` (render size `size`) in
// its top-left corner and, beyond it, `beyond`.
std::unique_ptr<gpu::Image> marchDepthImage(gpu::Context& context, Extent maxSize, Extent size,
                                            const std::vector<float>& depth, float beyond) {
  auto image = std::make_unique<gpu::Image>(context, gpu::ImageDesc{.name = "tests.march_depth",
                                                                    .width = maxSize.width,
                                                                    .height = maxSize.height,
                                                                    .format = gpu::formats::kR32f,
                                                                    .visualize = gpu::Visualize::Range});
  std::vector<float> texels(std::size_t(maxSize.width) * maxSize.height, beyond);
  for (std::uint32_t y = 0; y < size.height; ++y)
    for (std::uint32_t x = 0; x < size.width; ++x)
      texels[std::size_t(y) * maxSize.width + x] = depth[std::size_t(y) * size.width + x];
  gpu::uploadImage(context, *image, texels.data(), texels.size() * sizeof(float));
  return image;
}

// Random viewZ with a fifth background, and values the pyramid must read as background.
std::vector<float> randomDepth(Extent size, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  std::vector<float> depth(std::size_t(size.width) * size.height);
  for (float& z : depth) {
    const float u = uniform(rng);
    z = u < 0.2f ? 0.0f : 0.5f + 100.0f * uniform(rng);
  }
  if (depth.size() > 8) {
    depth[1] = std::numeric_limits<float>::quiet_NaN();
    depth[3] = std::numeric_limits<float>::infinity();
    depth[5] = -4.0f;
  }
  return depth;
}

TEST(DepthPyramid, LevelsCoverTheRenderSizeDownToOneTexel) {
  EXPECT_EQ(gi::DepthPyramid::levels({1, 1}), 1u);
  EXPECT_EQ(gi::DepthPyramid::levels({2, 1}), 2u);
  EXPECT_EQ(gi::DepthPyramid::levels({37, 23}), 6u);  // 37 18 9 4 2 1
  EXPECT_EQ(gi::DepthPyramid::levels({1920, 1080}), 11u);
  EXPECT_EQ(gi::DepthPyramid::levels({1, 4096}), 13u);
}

using DepthPyramidOnGpu = GpuTest;

// Every level of every size equals the CPU's reduction, also after a larger
// frame left other values in the images (the passes read only the render size).
TEST_F(DepthPyramidOnGpu, EveryLevelIsTheNearestAndFarthestSurfaceOfItsPixels) {
  const Extent maxSize{70, 50};
  gpu::MemoryArena arena(context());
  gi::DepthPyramid pyramid(context(), arena, maxSize);
  // Level 0 is the march depth: the image holds levels 1 and up.
  ASSERT_EQ(pyramid.pyramid().desc().mipLevels, gi::DepthPyramid::levels(maxSize) - 1);
  EXPECT_EQ(pyramid.pyramid().desc().width, maxSize.width / 2);
  const std::vector<float> largeFrame = randomDepth(maxSize, 7);
  const auto largeInput = marchDepthImage(context(), maxSize, maxSize, largeFrame, 0.0f);
  context().submitAndWait([&](gpu::Recorder& r) { pyramid.record(r, *largeInput, maxSize); });

  std::uint32_t seed = 11;
  for (const Extent size : {Extent{37, 23}, Extent{1, 1}, Extent{2, 1}, Extent{1, 9}, Extent{64, 32}, Extent{33, 50},
                            Extent{70, 3}, Extent{70, 50}}) {
    SCOPED_TRACE(std::to_string(size.width) + "x" + std::to_string(size.height));
    const std::vector<float> depth = randomDepth(size, ++seed);
    // A tiny surface beyond the render size would be every tile's nearest, were it read.
    const auto input = marchDepthImage(context(), maxSize, size, depth, 0.01f);
    context().submitAndWait([&](gpu::Recorder& r) { pyramid.record(r, *input, size); });
    for (std::uint32_t level = 1; level < gi::DepthPyramid::levels(size); ++level) {
      const Extent texels = levelSize(size, level);
      const std::vector<MinMax> gpu = readLevel(context(), pyramid.pyramid(), level - 1, texels);
      const std::vector<MinMax> cpu = cpuLevel(depth, size, level);
      for (std::size_t i = 0; i < cpu.size(); ++i)
        ASSERT_EQ(gpu[i], cpu[i]) << "level " << level << " texel (" << i % texels.width << ", " << i / texels.width
                                  << "): GPU (" << gpu[i].nearest << ", " << gpu[i].farthest << "), CPU ("
                                  << cpu[i].nearest << ", " << cpu[i].farthest << ")";
    }
  }
}

// With stage capture on (copies after every pass), the build stays free of
// validation messages and leaves the image in GENERAL.
TEST_F(DepthPyramidOnGpu, CapturedBuildLeavesTheImageInGeneral) {
  const Extent size{37, 23};
  gpu::MemoryArena arena(context());
  gi::DepthPyramid pyramid(context(), arena, size);
  const auto input = marchDepthImage(context(), size, size, randomDepth(size, 3), 0.0f);
  std::vector<gpu::CapturedStage> captures;
  context().submitAndWait([&](gpu::Recorder& r) {
    r.captureStages(&captures, 0);
    pyramid.record(r, *input, size);
  });
  for (gpu::CapturedStage& capture : captures) gpu::completeCapture(capture);
  ASSERT_EQ(captures.size(), gi::DepthPyramid::levels(size) - 1);
  EXPECT_EQ(captures.front().pass, "gi.depth_pyramid");
  EXPECT_EQ(captures.back().pass, "gi.depth_pyramid_reduce");
  EXPECT_EQ(captures.back().image.width, 1u);
  EXPECT_EQ(pyramid.pyramid().sync().layout, VK_IMAGE_LAYOUT_GENERAL);
  const std::vector<gpu::PassDesc> passes = pyramid.passes();
  ASSERT_EQ(passes.size(), 2u);
  EXPECT_EQ(passes[0].name, "gi.depth_pyramid");
  EXPECT_EQ(passes[1].name, "gi.depth_pyramid_reduce");
}

// --- The trace

// A camera, a render size and a depth buffer.
struct Scene {
  shared::ScreenView view;
  Extent size;
  std::vector<float> depth;

  float at(glm::ivec2 pixel) const { return depth[std::size_t(pixel.y) * size.width + pixel.x]; }
  glm::vec2 sizeF() const { return {float(size.width), float(size.height)}; }
  // Continuous pixel position minus the jitter (pixel (i, j) covers [i, i + 1)), and viewZ.
  glm::vec3 screen(glm::vec3 world) const {
    const glm::vec3 p = shared::projectToScreen(view, world, sizeF());
    return {p.x - view.projection.z, p.y - view.projection.w, p.z};
  }
  // The world point a pixel's sample shows at viewZ.
  glm::vec3 surface(glm::ivec2 pixel, float viewZ) const {
    return shared::reconstructPosition(view, glm::vec2(pixel), viewZ, sizeF());
  }
};

Scene sceneWith(glm::vec3 position, glm::vec3 forward, Extent size, glm::vec2 jitter) {
  forward = glm::normalize(forward);
  const glm::vec3 right = glm::normalize(glm::cross(forward, glm::vec3(0, 1, 0)));
  const glm::vec3 up = glm::cross(right, forward);
  const float jitterPixels[2] = {jitter.x, jitter.y};
  const gi::Camera camera = gi::cameraFromBasis(&position.x, &right.x, &up.x, &forward.x, glm::radians(60.0f),
                                                float(size.width) / float(size.height), jitterPixels);
  Scene scene;
  scene.view = gi::screenView(camera, "camera");
  scene.size = size;
  scene.depth.assign(std::size_t(size.width) * size.height, 0.0f);
  return scene;
}

// The camera at the origin looking down -Z: world = view space.
Scene frontalScene(Extent size, glm::vec2 jitter = glm::vec2(0.0f)) {
  return sceneWith(glm::vec3(0.0f), glm::vec3(0, 0, -1), size, jitter);
}

// viewZ of the plane dot(normal, x) = offset seen through each pixel's sample (0 where it is not in front).
void fillPlane(Scene& scene, glm::vec3 normal, float offset) {
  const glm::vec3 eye = shared::viewPosition(scene.view);
  const glm::vec3 forward = -glm::vec3(scene.view.viewToWorld[2]);
  for (std::uint32_t y = 0; y < scene.size.height; ++y)
    for (std::uint32_t x = 0; x < scene.size.width; ++x) {
      const glm::vec3 d = shared::pixelRayDirection(scene.view, glm::vec2(x, y), scene.sizeF());
      const float t = (offset - glm::dot(normal, eye)) / glm::dot(normal, d);
      scene.depth[std::size_t(y) * scene.size.width + x] =
          std::isfinite(t) && t > 0.0f ? t * glm::dot(d, forward) : 0.0f;
    }
}

struct Query {
  glm::vec4 origin;     // w: thickness
  glm::vec4 direction;  // w: maxSteps
};
struct Answer {
  glm::uvec4 outcome;  // outcome, texel x, texel y
  glm::vec4 lastFreeDistance;

  std::uint32_t kind() const { return outcome.x; }
  glm::ivec2 texel() const { return {std::int32_t(outcome.y), std::int32_t(outcome.z)}; }
  glm::vec3 lastFree() const { return glm::vec3(lastFreeDistance); }
  float distance() const { return lastFreeDistance.w; }
};

Query query(glm::vec3 origin, glm::vec3 direction, float thickness, std::uint32_t maxSteps = 4096) {
  return {glm::vec4(origin, thickness), glm::vec4(direction, float(maxSteps))};
}

struct CheckParams {
  std::uint32_t count;
};

class HizTraceOnGpu : public GpuTest {
 protected:
  // Builds the scene's pyramid and traces every query through it.
  std::vector<Answer> trace(const Scene& scene, const std::vector<Query>& queries) {
    gpu::MemoryArena arena(context());
    gi::DepthPyramid pyramid(context(), arena, scene.size);
    const auto marchDepth = marchDepthImage(context(), scene.size, scene.size, scene.depth, 0.0f);
    shared::GiFrameConstants constants{};
    constants.view = scene.view;
    constants.previousView = scene.view;
    constants.renderSize = scene.sizeF();
    constants.halfSize = glm::ceil(scene.sizeF() * 0.5f);
    gpu::Buffer frame(context(), "tests.frame", sizeof constants, gpu::BufferUsage::DeviceLocal);
    gpu::uploadBuffer(context(), frame, &constants, sizeof constants);
    gpu::Buffer input(context(), "tests.queries", sizeof(Query) * queries.size(), gpu::BufferUsage::DeviceLocal);
    gpu::uploadBuffer(context(), input, queries.data(), input.size());
    gpu::Buffer output(context(), "tests.answers", sizeof(Answer) * queries.size(), gpu::BufferUsage::DeviceLocal);
    std::vector<gpu::ResourceDecl> resources = gi::frameGroupDecls(gi::GroupPart::Constants);
    resources.push_back(
        {"gIn_Queries", gpu::Access::Read, VK_FORMAT_UNDEFINED, "rays", gpu::ResourceKind::StorageBuffer});
    resources.push_back({"gOut_Answers", gpu::Access::Write, VK_FORMAT_UNDEFINED, "what hizTrace says of them",
                         gpu::ResourceKind::StorageBuffer});
    for (const gpu::ResourceDecl& decl : gi::depthPyramidDecls()) resources.push_back(decl);
    gpu::ComputePass check(
        context(), {.name = "tests.hiz_trace_check",
                    .shader = "tests/hiz_trace_check",
                    .shaders = tests::shaders(),
                    .resources = std::move(resources),
                    .constants = {gi::frameConstantsLayout(), BOUNCE_CONSTANTS_LAYOUT("", CheckParams, count)}});
    context().submitAndWait([&](gpu::Recorder& r) {
      pyramid.record(r, *marchDepth, scene.size);
      std::vector<gpu::Bind> binds = {{"gIn_Frame", frame}, {"gIn_Queries", input}, {"gOut_Answers", output}};
      for (const gpu::Bind& bind : pyramid.binds()) binds.push_back(bind);
      const CheckParams params{std::uint32_t(queries.size())};
      r.dispatch(check, std::uint32_t(queries.size()), 1, std::span<const gpu::Bind>(binds), &params, sizeof params);
    });
    const std::vector<std::uint8_t> bytes = gpu::readbackBuffer(context(), output);
    std::vector<Answer> answers(queries.size());
    std::memcpy(answers.data(), bytes.data(), sizeof(Answer) * answers.size());
    return answers;
  }
};

bool finite(const Answer& a) {
  const glm::vec3 p = a.lastFree();
  return std::isfinite(a.distance()) && std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

int chebyshev(glm::ivec2 a, glm::ivec2 b) { return std::max(std::abs(a.x - b.x), std::abs(a.y - b.y)); }

// A wall facing the camera at viewZ 10, rays from points in front of it in
// all directions that reach it on screen: each hits the pixel where the ray
// meets the plane (with the frame's jitter: pixel (i, j) shows what lies
// around its sample), at the distance it meets it.
TEST_F(HizTraceOnGpu, RaysHitAPlaneWhereTheyMeetIt) {
  Scene scene = frontalScene({96, 64}, {0.31f, -0.27f});
  std::fill(scene.depth.begin(), scene.depth.end(), 10.0f);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  std::vector<Query> queries;
  std::vector<glm::vec3> hits;
  while (queries.size() < 256) {
    const glm::ivec2 pixel(int(uniform(rng) * 96), int(uniform(rng) * 64));
    const glm::vec3 origin = scene.surface(pixel, 2.0f + 6.0f * uniform(rng));
    // Away from the camera, up to nearly parallel to the wall.
    const float phi = 6.2831853f * uniform(rng), cosTheta = 0.05f + 0.95f * uniform(rng);
    const float sinTheta = std::sqrt(1.0f - cosTheta * cosTheta);
    const glm::vec3 direction(sinTheta * std::cos(phi), sinTheta * std::sin(phi), -cosTheta);
    const glm::vec3 hit = origin + direction * ((10.0f + origin.z) / cosTheta);
    const glm::vec3 onScreen = scene.screen(hit);
    // Clear of the screen's edge and of the origin's own pixel.
    if (onScreen.x < 1.0f || onScreen.y < 1.0f || onScreen.x > 95.0f || onScreen.y > 63.0f) continue;
    if (chebyshev(glm::ivec2(glm::floor(glm::vec2(onScreen))),
                  glm::ivec2(glm::floor(glm::vec2(scene.screen(origin))))) <= 1)
      continue;
    queries.push_back(query(origin, direction * 3.0f, 0.03f));  // any length
    hits.push_back(hit);
  }
  const std::vector<Answer> answers = trace(scene, queries);
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const Answer& a = answers[i];
    const glm::vec3 origin(queries[i].origin);
    const glm::vec2 onScreen(scene.screen(hits[i]));
    const glm::ivec2 expected(glm::floor(onScreen));
    // The pixel the ray crosses the plane in (its neighbour when that is within float rounding of its edge).
    const glm::vec2 fromEdge = glm::min(onScreen - glm::floor(onScreen), glm::ceil(onScreen) - onScreen);
    const int tolerance = std::min(fromEdge.x, fromEdge.y) < 1e-3f ? 1 : 0;
    ASSERT_EQ(a.kind(), kHizHit) << "ray " << i;
    EXPECT_LE(chebyshev(a.texel(), expected), tolerance)
        << "ray " << i << ": texel (" << a.texel().x << ", " << a.texel().y << "), expected (" << expected.x << ", "
        << expected.y << ")";
    const float distance = glm::distance(origin, hits[i]);
    EXPECT_NEAR(a.distance(), distance, 1e-3f * distance) << "ray " << i;
    EXPECT_NEAR(glm::distance(a.lastFree(), hits[i]), 0.0f, 1e-3f * distance) << "ray " << i;
  }
}

// The same wall: a ray from in front of it parallel to it leaves the screen
// undecided, vouching for its path up to the screen's edge.
TEST_F(HizTraceOnGpu, ARayLeavingTheScreenIsUndecidedUpToTheEdge) {
  Scene scene = frontalScene({96, 64});
  std::fill(scene.depth.begin(), scene.depth.end(), 10.0f);
  const glm::vec3 origin = scene.surface({30, 20}, 5.0f);
  const std::vector<Answer> answers = trace(
      scene, {query(origin, {1, 0, 0}, 0.03f), query(origin, {0, -1, 0}, 0.03f), query(origin, {-1, 0, 0.5f}, 0.03f)});
  const float halfWidth = 5.0f * scene.view.projection.x;  // the screen's edge at viewZ 5
  const float halfHeight = 5.0f * scene.view.projection.y;
  for (const Answer& a : answers) {
    EXPECT_EQ(a.kind(), kHizUndecided);
    EXPECT_EQ(a.texel(), glm::ivec2(-1));
    EXPECT_TRUE(finite(a));
  }
  EXPECT_NEAR(answers[0].distance(), halfWidth - origin.x, 1e-3f);
  EXPECT_NEAR(answers[0].lastFree().x, halfWidth, 1e-3f);
  EXPECT_NEAR(answers[1].distance(), origin.y + halfHeight, 1e-3f);
  // Towards the camera and left: it leaves where x / viewZ reaches the left edge.
  const glm::vec3 edge = scene.screen(answers[2].lastFree());
  EXPECT_NEAR(edge.x, 0.0f, 1e-2f);
  EXPECT_LT(edge.z, 5.0f);
}

// A thin post in front of the wall: a ray passing behind it, farther than
// its thickness, ends undecided there, not on the wall beyond; with a
// thickness that reaches the ray, it hits the post.
TEST_F(HizTraceOnGpu, PassingBehindAThinSurfaceIsUndecidedNotAHit) {
  Scene scene = frontalScene({96, 64});
  std::fill(scene.depth.begin(), scene.depth.end(), 10.0f);
  for (std::uint32_t y = 0; y < 64; ++y)
    for (std::uint32_t x = 60; x < 63; ++x) scene.depth[y * 96 + x] = 4.0f;
  const glm::vec3 origin = scene.surface({20, 32}, 5.0f);
  const glm::vec3 towards = scene.surface({80, 32}, 7.0f);  // behind the post (viewZ 4) where it crosses it
  const glm::vec3 direction = glm::normalize(towards - origin);
  const std::vector<Answer> answers =
      trace(scene, {query(origin, direction, 0.1f), query(origin, direction, 1.0f), query(origin, direction, 0.0f)});
  EXPECT_EQ(answers[0].kind(), kHizUndecided);
  EXPECT_EQ(answers[0].texel(), glm::ivec2(60, 32));
  EXPECT_NEAR(scene.screen(answers[0].lastFree()).x, 60.0f, 1e-2f);  // free up to the post
  EXPECT_EQ(answers[1].kind(), kHizHit);                             // slab [4, 8]: the ray is in it
  EXPECT_EQ(answers[1].texel(), glm::ivec2(60, 32));
  EXPECT_EQ(answers[2].kind(), kHizUndecided);
}

// A floor under a camera looking a little down, sky above the horizon.
Scene floorScene(Extent size) {
  Scene scene = sceneWith({0.0f, 1.5f, 0.0f}, {0.0f, -0.26f, -1.0f}, size, {0.21f, 0.37f});
  fillPlane(scene, {0, 1, 0}, 0.0f);
  return scene;
}

// Rays leaving the floor upwards (off the surface by gi/world_rays.glsl's
// offset) never hit the floor they start from, whichever way they go, down
// to 2 degrees above it (grazing rays, the reflections of a glossy floor
// seen from afar); those going towards the horizon find the sky. Pixels
// flat at their sample's depth would make a staircase of the floor that
// such rays run into.
TEST_F(HizTraceOnGpu, RaysLeavingAFloorDoNotHitItAndFindTheSky) {
  const Scene scene = floorScene({96, 64});
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  std::vector<Query> queries;
  std::vector<bool> towardsHorizon;
  while (queries.size() < 512) {
    const glm::ivec2 pixel(int(uniform(rng) * 96), int(uniform(rng) * 64));
    const float viewZ = scene.at(pixel);
    if (viewZ <= 0.0f) continue;
    const glm::vec3 position = scene.surface(pixel, viewZ);
    const glm::vec3 origin =
        position + glm::vec3(0, 1, 0) * (2e-4f * std::max(1.0f, viewZ) + 1e-4f * glm::length(position));
    const float elevation = glm::radians(2.0f + 88.0f * uniform(rng) * uniform(rng)), phi = 6.2831853f * uniform(rng);
    const glm::vec3 direction(std::cos(elevation) * std::cos(phi), std::sin(elevation),
                              std::cos(elevation) * std::sin(phi));
    queries.push_back(query(origin, direction, 0.03f));
    // Away from the camera within 25 degrees and at most 40 degrees up: on
    // screen it climbs to a vanishing point above the top edge, crossing the
    // sky between the horizon and that edge.
    towardsHorizon.push_back(-direction.z > std::cos(glm::radians(25.0f)) * std::cos(elevation) &&
                             elevation < glm::radians(40.0f));
  }
  const std::vector<Answer> answers = trace(scene, queries);
  int sky = 0, horizonRays = 0;
  for (std::size_t i = 0; i < answers.size(); ++i) {
    EXPECT_NE(answers[i].kind(), kHizHit)
        << "ray " << i << " hit its own floor at (" << answers[i].texel().x << ", " << answers[i].texel().y << ")";
    EXPECT_TRUE(finite(answers[i]));
    if (answers[i].kind() == kHizSky) {
      ++sky;
      EXPECT_EQ(scene.at(answers[i].texel()), 0.0f) << "ray " << i;
    }
    if (towardsHorizon[i]) {
      ++horizonRays;
      EXPECT_EQ(answers[i].kind(), kHizSky) << "ray " << i;
    }
  }
  EXPECT_GT(horizonRays, 20);
  EXPECT_GE(sky, horizonRays);
}

// A ray towards the camera from above the floor comes down onto it: it hits
// where it meets the floor.
TEST_F(HizTraceOnGpu, ARayTowardsTheCameraHitsTheFloor) {
  const Scene scene = floorScene({128, 96});
  std::vector<Query> queries;
  std::vector<glm::vec3> hits;
  for (float x : {-1.0f, 0.0f, 0.7f})
    for (float z : {-6.0f, -9.0f}) {
      const glm::vec3 origin(x, 0.8f, z);
      const glm::vec3 direction = glm::normalize(glm::vec3(0.1f, -0.8f, 1.0f));
      queries.push_back(query(origin, direction, 0.03f));
      hits.push_back(origin + glm::vec3(0.1f, -0.8f, 1.0f));  // on the floor
    }
  const std::vector<Answer> answers = trace(scene, queries);
  for (std::size_t i = 0; i < answers.size(); ++i) {
    const glm::vec3 origin(queries[i].origin);
    ASSERT_EQ(answers[i].kind(), kHizHit) << "ray " << i;
    const glm::ivec2 expected(glm::floor(glm::vec2(scene.screen(hits[i]))));
    EXPECT_LE(chebyshev(answers[i].texel(), expected), 1) << "ray " << i;
    // The floor is known at pixel samples only, but a pixel's surface is the
    // plane through its sample and its neighbours': the floor itself.
    const float distance = glm::distance(origin, hits[i]);
    EXPECT_NEAR(answers[i].distance(), distance, 1e-3f * distance) << "ray " << i;
  }
}

// Far along a wall a ray crosses a hundred pixels in front of it, in few
// steps: stepping over what it is in front of, a level coarser each time.
TEST_F(HizTraceOnGpu, StepsOverWhatTheRayIsInFrontOf) {
  Scene scene = frontalScene({128, 64});
  std::fill(scene.depth.begin(), scene.depth.end(), 10.0f);
  const glm::vec3 origin = scene.surface({4, 30}, 4.0f);
  const glm::vec3 hit = scene.surface({118, 33}, 10.0f);
  const glm::vec3 direction = glm::normalize(hit - origin);
  const std::vector<Answer> answers =
      trace(scene, {query(origin, direction, 0.03f, 32), query(origin, direction, 0.03f)});
  ASSERT_EQ(answers[1].kind(), kHizHit);
  EXPECT_EQ(answers[0].kind(), kHizHit) << "32 steps were not enough for 114 pixels";
  EXPECT_LE(chebyshev(answers[0].texel(), {118, 33}), 1);
}

// Inputs the trace cannot follow end undecided at the origin, with finite values throughout.
TEST_F(HizTraceOnGpu, DegenerateRaysEndUndecidedAndFinite) {
  Scene scene = frontalScene({64, 48});
  std::fill(scene.depth.begin(), scene.depth.end(), 10.0f);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const glm::vec3 origin = scene.surface({20, 20}, 5.0f);
  const glm::vec3 alongPixel = glm::normalize(origin);  // the camera is at the origin
  const std::vector<Query> queries = {
      query(origin, glm::vec3(0.0f), 0.03f),                             // no direction
      query(origin, glm::vec3(nan, 0.0f, -1.0f), 0.03f),                 // NaN direction
      query(glm::vec3(inf, 0.0f, -5.0f), glm::vec3(0, 0, -1), 0.03f),    // infinite origin
      query(glm::vec3(0.0f, 0.0f, 2.0f), glm::vec3(0, 0, -1), 0.03f),    // behind the camera
      query(glm::vec3(40.0f, 0.0f, -5.0f), glm::vec3(-1, 0, 0), 0.03f),  // off screen
      query(origin, alongPixel, 0.03f),                                  // along its own pixel, away
      query(origin, -alongPixel, 0.03f),                                 // along its own pixel, towards the camera
      query(origin, glm::vec3(0, 0, -1), nan),                           // NaN thickness
      query(origin, glm::vec3(0, 0, -1), 0.03f, 0),                      // no steps
      query(origin, glm::vec3(1e-30f, 0.0f, 0.0f), 0.03f),               // a denormal-sized direction
  };
  const std::vector<Answer> answers = trace(scene, queries);
  for (std::size_t i = 0; i < answers.size(); ++i) {
    EXPECT_TRUE(finite(answers[i])) << "ray " << i;
    if (i == 7) continue;
    EXPECT_EQ(answers[i].kind(), kHizUndecided) << "ray " << i;
    // Towards the camera in its own pixel the ray is free as far as it goes.
    if (i != 6) {
      EXPECT_EQ(answers[i].distance(), 0.0f) << "ray " << i;
    }
  }
  // A NaN thickness is none: the ray still hits the wall in the pixel where it crosses it.
  EXPECT_EQ(answers[7].kind(), kHizHit);
  EXPECT_NEAR(answers[7].distance(), 5.0f, 1e-3f);
  // Towards the camera, slightly off its own pixel's ray: it comes close to
  // the camera plane without leaving the screen, and stops there.
  const glm::vec3 almost = glm::normalize(-alongPixel + glm::vec3(1e-4f, 0.0f, 0.0f));
  const Answer near = trace(scene, {query(origin, almost, 0.03f)})[0];
  EXPECT_EQ(near.kind(), kHizUndecided);
  EXPECT_TRUE(finite(near));
}

// --- Against a march through every pixel

struct Reference {
  std::uint32_t outcome;
  glm::ivec2 texel;
};

// What hizTrace should say, found by marching the ray in steps of at most a
// twentieth of a pixel and 0.2 % of its viewZ and deciding each pixel it
// crosses from the steps in it. A pixel's surface is the plane (in 1 / viewZ
// over the screen) through its sample with, in x and in y, the mean slope to
// its two neighbours where they agree, else the slope to the smoother one
// (when within a quarter of its 1 / viewZ).
// In order:
//   - a background pixel: sky;
//   - every step nearer than the sample, or in front of the surface: in front
//     (the ray has left its own surface);
//   - every step behind the surface by more than its thickness: undecided;
//   - else, once the ray has left its own surface, a hit.
// The origin's pixel is no hit; a ray leaving it behind its slab is undecided there.
Reference marchEveryPixel(const Scene& scene, glm::vec3 origin, glm::vec3 direction, float thickness) {
  const Reference undecided{kHizUndecided, {-1, -1}};
  const glm::vec3 o(scene.view.worldToView * glm::vec4(origin, 1.0f));
  const glm::vec3 v = glm::normalize(glm::vec3(scene.view.worldToView * glm::vec4(direction, 0.0f)));
  const glm::vec2 size = scene.sizeF();
  const float tx = scene.view.projection.x, ty = scene.view.projection.y;
  const auto screen = [&](float t) { return scene.screen(origin + t * glm::normalize(direction)); };
  const auto inside = [&](glm::vec2 p) { return p.x >= 0.0f && p.y >= 0.0f && p.x < size.x && p.y < size.y; };
  const glm::vec3 start = screen(0.0f);
  if (start.z <= 0.0f || !inside(glm::vec2(start))) return undecided;
  const glm::ivec2 originPixel(glm::floor(glm::vec2(start)));
  const float slab = 1.0f + thickness;
  const auto inverseDepth = [&](glm::ivec2 p) {
    if (!inside(glm::vec2(p))) return 0.0f;
    const float d = scene.at(p);
    return background(d) ? 0.0f : 1.0f / d;
  };
  // The steps in the pixel the march is in, against its surface.
  struct Steps {
    glm::ivec2 pixel;
    float w = 0.0f;  // 1 / viewZ at the sample, 0: background
    glm::vec2 slope{0.0f};
    float farthest = 0.0f;  // viewZ of the farthest step
    float minGap = std::numeric_limits<float>::max(), maxSlabGap = std::numeric_limits<float>::lowest();
    // The step's 1 / viewZ times `scale` minus the surface's.
    float gap(glm::vec3 step, float scale) const {
      return scale / step.z - w - glm::dot(slope, glm::vec2(step) - (glm::vec2(pixel) + 0.5f));
    }
    void add(glm::vec3 step, float slabScale) {
      farthest = std::max(farthest, step.z);
      minGap = std::min(minGap, gap(step, 1.0f));
      maxSlabGap = std::max(maxSlabGap, gap(step, slabScale));
    }
  };
  const auto stepsIn = [&](glm::ivec2 pixel) {
    Steps steps;
    steps.pixel = pixel;
    steps.w = inverseDepth(pixel);
    if (steps.w <= 0.0f) return steps;
    for (int axis = 0; axis < 2; ++axis) {
      const glm::ivec2 step = axis == 0 ? glm::ivec2(1, 0) : glm::ivec2(0, 1);
      const float before = inverseDepth(pixel - step), after = inverseDepth(pixel + step);
      const float fromBefore = steps.w - before, fromAfter = after - steps.w;
      if (before > 0.0f && after > 0.0f &&
          std::abs(fromBefore - fromAfter) <= 0.25f * std::max(std::abs(fromBefore), std::abs(fromAfter))) {
        steps.slope[axis] = 0.5f * (fromBefore + fromAfter);
        continue;
      }
      std::optional<float> slope;
      if (before > 0.0f) slope = fromBefore;
      if (after > 0.0f && (!slope || std::abs(fromAfter) <= std::abs(*slope))) slope = fromAfter;
      if (slope && std::abs(*slope) < 0.25f * steps.w) steps.slope[axis] = *slope;
    }
    return steps;
  };
  bool emerged = false;
  // The decision on a pixel the ray has crossed (or stops in), if it ends the ray.
  const auto decide = [&](const Steps& in) -> std::optional<Reference> {
    if (in.pixel == originPixel) return std::nullopt;
    if (in.farthest * in.w < 1.0f || in.minGap > 0.0f) {
      emerged = true;
      return std::nullopt;
    }
    if (in.maxSlabGap < 0.0f) return Reference{kHizUndecided, in.pixel};
    if (!emerged) return std::nullopt;
    return Reference{kHizHit, in.pixel};
  };
  Steps steps = stepsIn(originPixel);
  float ownSlabGap = std::numeric_limits<float>::max();  // the least, over the steps in the origin's pixel
  const auto addStep = [&](glm::vec3 p) {
    steps.add(p, slab);
    if (steps.pixel == originPixel && steps.w > 0.0f) ownSlabGap = std::min(ownSlabGap, steps.gap(p, slab));
  };
  addStep(start);
  const auto pixelAt = [&](glm::vec3 p) {
    return p.z >= kNearest * start.z && inside(glm::vec2(p)) ? glm::ivec2(glm::floor(glm::vec2(p))) : glm::ivec2(-1);
  };
  float t = 0.0f;
  for (int step = 0; step < 4000000; ++step) {
    const glm::vec3 q = o + t * v;
    const float z = -q.z, dz = -v.z;
    const float dx = 0.5f * size.x / tx * (v.x * z - q.x * dz) / (z * z);
    const float dy = 0.5f * size.y / ty * (v.y * z - q.y * dz) / (z * z);
    const float speed = std::max(std::abs(dx), std::abs(dy));
    const float previous = t;
    t += std::min(0.05f / std::max(speed, 1e-12f), 0.002f * z / std::max(std::abs(dz), 1e-12f));
    const glm::vec3 p = screen(t);
    const glm::ivec2 now = pixelAt(p);
    if (now == steps.pixel) {
      addStep(p);
      continue;
    }
    // Where the ray leaves the pixel, closely: the pixel's extremes lie there.
    float inPixel = previous, outside = t;
    for (int i = 0; i < 24; ++i) {
      const float middle = 0.5f * (inPixel + outside);
      (pixelAt(screen(middle)) == steps.pixel ? inPixel : outside) = middle;
    }
    addStep(screen(inPixel));
    // Left the origin's pixel behind its own surface's slab: through it.
    if (steps.pixel == originPixel && ownSlabGap < 0.0f) return undecided;
    if (auto decided = decide(steps)) return *decided;
    if (now.x < 0) return {kHizUndecided, p.z < kNearest * start.z ? steps.pixel : now};
    steps = stepsIn(now);
    if (pixelAt(screen(outside)) == now) addStep(screen(outside));
    addStep(p);
    if (steps.w <= 0.0f) return {kHizSky, now};
  }
  return undecided;
}

// A rolling height field with holes of sky and thin posts, rays from its
// surface (and from points in front of it) in every direction, towards the
// camera too: the pyramid's traversal decides as the march through every
// pixel does.
TEST_F(HizTraceOnGpu, AgreesWithAMarchThroughEveryPixel) {
  Scene scene = sceneWith({0.0f, 0.0f, 0.0f}, {0.1f, -0.05f, -1.0f}, {80, 56}, {-0.17f, 0.29f});
  for (std::uint32_t y = 0; y < scene.size.height; ++y)
    for (std::uint32_t x = 0; x < scene.size.width; ++x) {
      float z = 8.0f + 2.5f * std::sin(0.21f * float(x)) * std::cos(0.17f * float(y)) +
                1.5f * std::sin(0.05f * float(x + 2 * y));
      if (std::sin(0.11f * float(x)) * std::sin(0.13f * float(y)) > 0.8f) z = 0.0f;  // sky
      if (x % 23 == 5) z = 3.0f + 0.01f * float(y);                                  // posts
      scene.depth[std::size_t(y) * scene.size.width + x] = z;
    }
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  std::vector<Query> queries;
  std::vector<float> thicknesses = {0.03f, 0.3f};
  while (queries.size() < 1024) {
    const glm::ivec2 pixel(int(uniform(rng) * 80), int(uniform(rng) * 56));
    const float viewZ = scene.at(pixel);
    if (viewZ <= 0.0f) continue;
    // On the surface or in front of it.
    const glm::vec3 origin = scene.surface(pixel, viewZ * (uniform(rng) < 0.5f ? 0.999f : 0.3f + 0.6f * uniform(rng)));
    const float cosTheta = 2.0f * uniform(rng) - 1.0f, phi = 6.2831853f * uniform(rng);
    const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
    queries.push_back(
        query(origin, {sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta}, thicknesses[queries.size() % 2]));
  }
  const std::vector<Answer> answers = trace(scene, queries);
  int agree = 0, hits = 0, sky = 0, towardsCamera = 0;
  int differing = 0;
  std::string differences;
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const Reference expected =
        marchEveryPixel(scene, glm::vec3(queries[i].origin), glm::vec3(queries[i].direction), queries[i].origin.w);
    const Answer& a = answers[i];
    EXPECT_TRUE(finite(a)) << "ray " << i;
    const bool same = a.kind() == expected.outcome &&
                      (expected.texel.x < 0 ? a.texel().x < 0 : chebyshev(a.texel(), expected.texel) <= 1);
    if (same) {
      ++agree;
    } else if (++differing <= 20) {
      differences += "\n  ray " + std::to_string(i) + ": Hi-Z " + std::to_string(a.kind()) + " at (" +
                     std::to_string(a.texel().x) + ", " + std::to_string(a.texel().y) + "), march " +
                     std::to_string(expected.outcome) + " at (" + std::to_string(expected.texel.x) + ", " +
                     std::to_string(expected.texel.y) + ")";
    }
    hits += expected.outcome == kHizHit;
    sky += expected.outcome == kHizSky;
    towardsCamera += queries[i].direction.z > 0.0f && expected.outcome == kHizHit;
  }
  // Every outcome must be represented for the comparison to mean something.
  EXPECT_GT(hits, 100);
  EXPECT_GT(sky, 50);
  EXPECT_GT(towardsCamera, 20);
  EXPECT_GE(agree, int(std::ceil(0.99 * double(queries.size())))) << "first differences:" << differences;
  std::printf("Hi-Z and the march agree on %d of %zu rays (%d hits, %d sky)\n", agree, queries.size(), hits, sky);
}

}  // namespace
}  // namespace bounce::testing

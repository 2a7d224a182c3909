// Tests of shaders/shared/reservoir.glsl and screen_view.glsl on the CPU:
// packing, streaming, and that the ReSTIR chain the GI passes run (RIS of
// candidates, temporal merges with capped M, spatial merges with the
// reconnection Jacobian and Z normalisation) stays unbiased, on a
// flatland-like scene whose answer is known; and that the GI library's view
// reconstruction agrees with the renderer's camera rays.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/type_ptr.hpp>
#include <limits>
#include <vector>

#include "render/frame_renderer.h"
#include "render/gi_bridge.h"
#include "shared/reservoir.glsl"
#include "shared/rng.glsl"
#include "shared/screen_view.glsl"
#include "test_meshes.h"

namespace bounce::shared {
namespace {

TEST(Reservoir, PackingKeepsEverythingTheShadersRead) {
  Reservoir r = emptyReservoir();
  r.position = vec3(1.5f, -2.25f, 1e4f);
  r.normal = normalize(vec3(0.3f, -0.8f, 0.52f));
  r.radiance = vec3(0.125f, 7.5f, 70000.0f);  // the last beyond half floats
  r.M = 37.0f;
  r.W = 3.25e-3f;
  r.flags = kReservoirHasSample | kReservoirEnvironment;
  uvec4 a, b;
  packReservoir(r, a, b);
  const Reservoir u = unpackReservoir(a, b);
  EXPECT_EQ(u.position, r.position);
  EXPECT_LT(length(u.normal - r.normal), 1e-4f);
  EXPECT_EQ(u.radiance.x, 0.125f);
  EXPECT_EQ(u.radiance.y, 7.5f);
  EXPECT_EQ(u.radiance.z, 65504.0f) << "clamped to the largest half float";
  EXPECT_EQ(u.M, 37.0f);
  EXPECT_EQ(u.W, r.W);
  EXPECT_EQ(u.flags, r.flags);
  EXPECT_EQ(sizeof(a) + sizeof(b), 32u) << "at most 32 bytes a reservoir";
}

// The reservoirs are history: whatever went into one, what is stored is
// finite, and a sample that is not is dropped whole.
TEST(Reservoir, PackingStoresOnlyFiniteValues) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const auto stored = [](const Reservoir& r) {
    uvec4 a, b;
    packReservoir(r, a, b);
    return unpackReservoir(a, b);
  };
  const auto finite = [](const Reservoir& r) {
    return isFinite(r.position) && isFinite(r.normal) && isFinite(r.radiance) && isFinite(r.M) && isFinite(r.W);
  };
  Reservoir good = emptyReservoir();
  good.position = vec3(1.0f, 2.0f, 3.0f);
  good.normal = vec3(0.0f, 1.0f, 0.0f);
  good.radiance = vec3(1.0f);
  good.M = 4.0f;
  good.W = 0.5f;
  good.flags = kReservoirHasSample;
  for (int which = 0; which < 4; ++which)
    for (float bad : {nan, inf, -inf}) {
      Reservoir r = good;
      if (which == 0) r.position.y = bad;
      if (which == 1) r.normal.x = bad;
      if (which == 2) r.W = bad;
      if (which == 3) r.M = bad;
      const Reservoir u = stored(r);
      EXPECT_TRUE(finite(u)) << "field " << which << ", value " << bad;
      if (which < 3) {
        EXPECT_FALSE(reservoirHasSample(u)) << "a sample with a non-finite field is dropped: " << which;
        EXPECT_EQ(u.W, 0.0f);
        EXPECT_EQ(u.M, good.M) << "the candidates were still seen";
      } else {
        EXPECT_TRUE(reservoirHasSample(u));
        EXPECT_EQ(u.M, 0.0f) << "a non-finite confidence counts as none";
      }
    }
  Reservoir r = good;
  r.radiance = vec3(1.0f, nan, 1.0f);
  EXPECT_EQ(stored(r).radiance, vec3(0.0f)) << "non-finite radiance is no light";
  r.radiance = vec3(inf);
  EXPECT_EQ(stored(r).radiance, vec3(0.0f));
}

TEST(Reservoir, NonFiniteWeightsAreRefused) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  Reservoir r = emptyReservoir();
  EXPECT_TRUE(reservoirStream(r, vec3(1.0f), vec3(0, 0, 1), vec3(1.0f), 0u, 2.0f, 1.0f, 0.5f));
  for (float bad : {nan, inf, -inf, 0.0f, -1.0f})
    EXPECT_FALSE(reservoirStream(r, vec3(2.0f), vec3(0, 0, 1), vec3(1.0f), 0u, bad, 1.0f, 0.0f)) << bad;
  EXPECT_EQ(r.weightSum, 2.0f) << "refused weights do not count";
  EXPECT_EQ(r.M, 6.0f) << "but their candidates were seen";
  EXPECT_EQ(r.position, vec3(1.0f));
  reservoirFinalize(r, 1.0f, 1e-45f);  // W = 2 / 1.4e-45 overflows
  EXPECT_FALSE(reservoirHasSample(r));
  EXPECT_EQ(r.W, 0.0f);
}

TEST(Reservoir, StreamingKeepsEachCandidateInProportionToItsWeight) {
  const float weights[3] = {1.0f, 3.0f, 6.0f};
  int kept[3] = {0, 0, 0};
  uint rng = 11u;
  const int trials = 200000;
  for (int t = 0; t < trials; ++t) {
    Reservoir r = emptyReservoir();
    int chosen = -1;
    for (int i = 0; i < 3; ++i)
      if (reservoirStream(r, vec3(float(i)), vec3(0, 0, 1), vec3(1.0f), 0u, weights[i], 1.0f, rngUniform(rng)))
        chosen = i;
    ASSERT_GE(chosen, 0);
    ++kept[chosen];
    EXPECT_EQ(r.M, 3.0f);
  }
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(kept[i] / double(trials), weights[i] / 10.0, 0.005);
}

TEST(Reservoir, ZeroAndNanWeightsAreNeverChosenButCount) {
  Reservoir r = emptyReservoir();
  EXPECT_FALSE(reservoirStream(r, vec3(0), vec3(0, 0, 1), vec3(1), 0u, 0.0f, 2.0f, 0.0f));
  EXPECT_FALSE(reservoirStream(r, vec3(0), vec3(0, 0, 1), vec3(1), 0u, std::nanf(""), 3.0f, 0.0f));
  EXPECT_FALSE(reservoirHasSample(r));
  EXPECT_EQ(r.M, 5.0f);
  reservoirFinalize(r, 1.0f, r.M);
  EXPECT_EQ(r.W, 0.0f);
}

TEST(Reservoir, TargetNeedsTheSenderToFaceTheReceiver) {
  Reservoir r = emptyReservoir();
  r.position = vec3(0.0f, 1.0f, 0.0f);
  r.normal = vec3(0.0f, -1.0f, 0.0f);  // facing down, towards the origin
  r.radiance = vec3(2.0f);
  r.flags = kReservoirHasSample;
  EXPECT_NEAR(targetPdf(r, vec3(0.0f), vec3(0, 1, 0), 0u), 2.0f, 1e-6f);
  r.normal = vec3(0.0f, 1.0f, 0.0f);
  EXPECT_EQ(targetPdf(r, vec3(0.0f), vec3(0, 1, 0), 0u), 0.0f) << "sender faces away";
  r.normal = vec3(0.0f, -1.0f, 0.0f);
  EXPECT_EQ(targetPdf(r, vec3(0.0f), vec3(0, -1, 0), 0u), 0.0f) << "below the receiver's horizon";
  EXPECT_NEAR(targetBrightness(vec3(3.0f, 4.0f, 0.0f), 1u), 5.0f, 1e-6f) << "colour-vector length";
}

TEST(Reservoir, JacobianIsTheRatioOfSolidAngles) {
  // A sender patch at the origin facing +Y; receivers straight above at
  // heights 1 and 2: from twice as far it covers a quarter of the solid angle.
  const vec3 y(0.0f), n(0, 1, 0);
  EXPECT_NEAR(reconnectionJacobian(y, n, vec3(0, 2, 0), vec3(0, 1, 0)), 4.0f, 1e-5f);
  EXPECT_NEAR(reconnectionJacobian(y, n, vec3(0, 1, 0), vec3(0, 2, 0)), 0.25f, 1e-6f);
  // At 60 degrees off the normal the sender's projected area halves.
  const vec3 slanted = vec3(std::sin(1.0471976f), std::cos(1.0471976f), 0.0f);
  EXPECT_NEAR(reconnectionJacobian(y, n, vec3(0, 1, 0), slanted), 0.5f, 1e-5f);
  EXPECT_EQ(reconnectionJacobian(y, n, vec3(0, 1, 0), vec3(0, -1, 0)), 0.0f) << "behind the sender";
}

// The whole chain the GI passes run, on the CPU with the shared functions:
// receivers on a grid on the floor y = 0 (x in [0, 4.9], up to the foot of
// the wall where the Jacobian varies most; z in [-1, 1]) lit only by an
// emitting wall x = 5 (y in [0, 2], z in [-0.5, 0.5], radiance 1, facing -X).
// Each frame every receiver gathers candidates (most land on unlit surfaces,
// as on a screen), merges with its history (M capped at 20), then with
// random neighbours twice (Jacobian, Z normalisation); the history kept is
// the temporal result (gi::DiffuseSettings::spatialFeedback's default). The
// mean over frames of f * W must be the wall's form factor.
float wallFormFactor(vec3 x) {
  const int steps = 200;
  double sum = 0.0;
  for (int j = 0; j < steps; ++j)
    for (int i = 0; i < steps; ++i) {
      const vec3 y(5.0f, 2.0f * (float(j) + 0.5f) / steps, -0.5f + (float(i) + 0.5f) / steps);
      const vec3 d = y - x;
      const float d2 = dot(d, d);
      const float cosX = d.y / std::sqrt(d2), cosY = d.x / std::sqrt(d2);
      if (cosX > 0.0f && cosY > 0.0f) sum += double(cosX * cosY / d2) * (2.0 / steps) * (1.0 / steps);
    }
  return float(sum / M_PI);
}

TEST(Reservoir, TemporalAndSpatialReuseStayUnbiased) {
  constexpr int side = 12, n = side * side, frames = 3000, candidates = 6, neighbours = 5;
  constexpr float wallShare = 0.3f, wallArea = 2.0f, radius = 3.0f;
  const vec3 up(0, 1, 0), wallNormal(-1, 0, 0);
  std::vector<vec3> receivers(n);
  for (int i = 0; i < n; ++i)
    receivers[i] = vec3(4.9f * (float(i % side) + 0.5f) / side, 0.0f, -1.0f + 2.0f * (float(i / side) + 0.5f) / side);
  std::vector<Reservoir> history(n, emptyReservoir());
  std::vector<double> sums(n, 0.0);
  uint rng = 1234u;
  const auto merge = [&](Reservoir& merged, const Reservoir& r, int at, float scale) {
    const float u = rngUniform(rng);
    reservoirStream(merged, r.position, r.normal, r.radiance, r.flags,
                    targetPdf(r, receivers[at], up, 0u) * r.W * r.M * scale, r.M, u);
  };
  for (int frame = 0; frame < frames; ++frame) {
    std::vector<Reservoir> temporal(n);
    for (int i = 0; i < n; ++i) {
      // Fresh candidates by uniform area sampling of the wall (which a
      // candidate hits with probability wallShare), to solid angle.
      Reservoir fresh = emptyReservoir();
      for (int c = 0; c < candidates; ++c) {
        const float u0 = rngUniform(rng), u1 = rngUniform(rng), u2 = rngUniform(rng), hit = rngUniform(rng);
        if (hit >= wallShare) continue;
        Reservoir candidate = emptyReservoir();
        candidate.position = vec3(5.0f, 2.0f * u0, u1 - 0.5f);
        candidate.normal = wallNormal;
        candidate.radiance = vec3(1.0f);
        const vec3 d = receivers[i] - candidate.position;
        const float d2 = dot(d, d);
        const float pdf = (wallShare / wallArea) * d2 / (dot(wallNormal, d) / std::sqrt(d2));
        const float pHat = targetPdf(candidate, receivers[i], up, 0u);
        reservoirStream(fresh, candidate.position, candidate.normal, candidate.radiance, 0u, pHat / (candidates * pdf),
                        0.0f, u2);
      }
      reservoirFinalize(fresh, targetPdf(fresh, receivers[i], up, 0u), 1.0f);
      fresh.M = 1.0f;
      Reservoir old = history[i];
      old.M = std::min(old.M, 20.0f);
      Reservoir merged = emptyReservoir();
      merge(merged, fresh, i, 1.0f);
      merge(merged, old, i, 1.0f);
      reservoirFinalize(merged, targetPdf(merged, receivers[i], up, 0u), merged.M);
      temporal[i] = merged;
    }
    const auto spatialPass = [&](const std::vector<Reservoir>& input) {
      std::vector<Reservoir> output(n);
      for (int i = 0; i < n; ++i) {
        Reservoir merged = emptyReservoir();
        merge(merged, input[i], i, 1.0f);
        std::vector<int> picked;
        for (int k = 0; k < neighbours; ++k) {
          const int dx = int(std::floor((rngUniform(rng) * 2.0f - 1.0f) * radius));
          const int dz = int(std::floor((rngUniform(rng) * 2.0f - 1.0f) * radius));
          const int j = std::clamp(i % side + dx, 0, side - 1) + side * std::clamp(i / side + dz, 0, side - 1);
          if (j == i) continue;
          merge(merged, input[j], i, reuseJacobian(input[j], receivers[j], receivers[i], kMaxSpatialJacobian, true));
          picked.push_back(j);
        }
        float confidence = input[i].M;
        for (int j : picked)
          if (canHandOver(merged, receivers[j], up, receivers[i], kMaxSpatialJacobian, true, 0u))
            confidence += input[j].M;
        reservoirFinalize(merged, targetPdf(merged, receivers[i], up, 0u), confidence);
        output[i] = merged;
      }
      return output;
    };
    const std::vector<Reservoir> spatial = spatialPass(spatialPass(temporal));
    for (int i = 0; i < n; ++i)
      if (reservoirHasSample(spatial[i])) {
        const vec3 d = sampleDirection(spatial[i], receivers[i]);
        sums[i] += spatial[i].radiance.x * std::max(d.y, 0.0f) * kInvPi * spatial[i].W;
      }
    history = temporal;
  }
  double expected = 0.0, estimated = 0.0;
  for (int i = 0; i < n; ++i) {
    expected += wallFormFactor(receivers[i]);
    estimated += sums[i] / frames;
  }
  std::printf("reuse chain: form factor %.5f, estimated %.5f\n", expected / n, estimated / n);
  EXPECT_NEAR(estimated / n, expected / n, 0.04 * expected / n);
}

// The GI library's view of the renderer's camera: a pixel's surface
// reconstructed from its viewZ lies on the renderer's ray through that pixel
// (jitter included), and projects back to the pixel's centre.
TEST(ScreenView, AgreesWithTheRenderersCamera) {
  const scene::CameraPose pose = testing::cameraAt(vec3(1.0f, 2.0f, 5.0f), vec3(-0.5f, 0.7f, -1.0f), 55.0f);
  const std::uint32_t width = 320, height = 180;
  const vec2 size(width, height), jitter(0.31f, -0.27f);
  const gi::Camera camera = render::giCamera(pose, width, height, jitter);
  const mat4 worldToView = glm::make_mat4(camera.worldToView);
  const mat4 viewToClip = glm::make_mat4(camera.viewToClip);
  const ScreenView view{worldToView, glm::inverse(worldToView),
                        vec4(1.0f / viewToClip[0][0], 1.0f / viewToClip[1][1], jitter.x, jitter.y)};
  const GpuCamera rays = render::gpuCamera(pose, width, height);
  const vec3 forward = normalize(pose.target - pose.position);
  for (const vec2 pixel : {vec2(0, 0), vec2(319, 179), vec2(160, 90), vec2(17, 150)}) {
    const vec3 direction = cameraRayDirection(rays, pixel + vec2(0.5f) + jitter, size);
    const float viewZ = 3.7f;
    const vec3 expected = pose.position + direction * (viewZ / dot(direction, forward));
    const vec3 reconstructed = reconstructPosition(view, pixel, viewZ, size);
    EXPECT_LT(length(reconstructed - expected), 1e-4f) << pixel.x << "," << pixel.y;
    EXPECT_LT(length(pixelRayDirection(view, pixel, size) - direction), 1e-5f);
    const vec3 back = projectToScreen(view, reconstructed, size);
    EXPECT_NEAR(back.x, pixel.x + 0.5f + jitter.x, 1e-3f);
    EXPECT_NEAR(back.y, pixel.y + 0.5f + jitter.y, 1e-3f);
    EXPECT_NEAR(back.z, viewZ, 1e-4f);
  }
  EXPECT_LE(projectToScreen(view, pose.position - forward, size).z, 0.0f) << "behind the camera";
}

// A pixel's footprint: at viewZ 2 head-on, a pixel of a 90 degree, 100 x 100
// view covers (2 * 2 / 100)^2 m^2; tilting the surface by 60 degrees doubles it.
TEST(ScreenView, PixelFootprintGrowsWithDepthSquaredAndTilt) {
  ScreenView view{mat4(1.0f), mat4(1.0f), vec4(1.0f, 1.0f, 0.0f, 0.0f)};
  EXPECT_NEAR(pixelFootprintArea(view, 2.0f, 1.0f, 1.0f, vec2(100.0f)), 0.0016f, 1e-7f);
  EXPECT_NEAR(pixelFootprintArea(view, 2.0f, 1.0f, 0.5f, vec2(100.0f)), 0.0032f, 1e-7f);
  EXPECT_NEAR(pixelFootprintArea(view, 4.0f, 1.0f, 1.0f, vec2(100.0f)), 0.0064f, 1e-7f);
}

}  // namespace
}  // namespace bounce::shared

// The smallest engine that uses the Bounce GI library: its own Vulkan device,
// a G-buffer it writes with its own commands (a grey floor and an emitting
// panel, computed analytically and copied into the images), the library
// recorded into its command buffer for a few frames, and the result read
// back and checked: the floor, which no direct light reaches, must be lit by
// the panel, more near it than far from it. Validation and synchronization
// validation are on when the layer is installed; any message fails the run.
#include <bounce/gi.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "vulkan_setup.h"

namespace gi = bounce::gi;
constexpr std::uint32_t kWidth = 160, kHeight = 120, kFrames = 12;

// What the engine's G-buffer holds at one pixel.
struct Texel {
  float viewZ = 0.0f;                  // 0: background
  float normal[3] = {0, 0, 0};
  float albedo = 0.0f;
  float emission = 0.0f;
};

// Camera at (0, 1, 3) looking down -Z with a 60 degree field of view; the
// floor is y = 0, the panel x in [-1, 1], y in [0, 1.5] at z = -1, facing +Z.
constexpr float kTanHalfFov = 0.57735f;
Texel shade(std::uint32_t x, std::uint32_t y) {
  const float aspect = float(kWidth) / float(kHeight);
  const float dx = (2.0f * (x + 0.5f) / kWidth - 1.0f) * kTanHalfFov * aspect;
  const float dy = (1.0f - 2.0f * (y + 0.5f) / kHeight) * kTanHalfFov;  // row 0 is the top
  Texel t;
  const float tPanel = 4.0f;  // along -Z: viewZ = t for a direction (dx, dy, -1)
  const float px = dx * tPanel, py = 1.0f + dy * tPanel;
  if (px >= -1.0f && px <= 1.0f && py >= 0.0f && py <= 1.5f) {
    t = {tPanel, {0, 0, 1}, 0.0f, 4.0f};
  } else if (dy < 0.0f) {
    const float tFloor = 1.0f / -dy;
    if (3.0f - tFloor > -1.0f) t = {tFloor, {0, 1, 0}, 0.8f, 0.0f};  // in front of the panel only
  }
  return t;
}

std::uint16_t half(float value) {  // finite, normal or zero values only
  if (value == 0.0f) return 0;
  std::uint32_t bits;
  std::memcpy(&bits, &value, 4);
  return std::uint16_t(((bits >> 16) & 0x8000u) | ((((bits >> 23) & 0xFFu) - 112u) << 10) | ((bits >> 13) & 0x3FFu));
}

float fromHalf(std::uint16_t h) {
  const std::uint32_t exponent = (h >> 10) & 0x1Fu;
  const float mantissa = float(h & 0x3FFu) / 1024.0f;
  return exponent == 0 ? 0.0f : std::ldexp(1.0f + mantissa, int(exponent) - 15);
}

int main() {
  Vulkan vk;
  // The G-buffer in the formats of each input's family the engine prefers.
  GpuImage viewZ = vk.image(VK_FORMAT_R32_SFLOAT, kWidth, kHeight);
  GpuImage normals = vk.image(VK_FORMAT_R16G16B16A16_SFLOAT, kWidth, kHeight);
  GpuImage albedo = vk.image(VK_FORMAT_R8G8B8A8_SRGB, kWidth, kHeight);
  GpuImage motion = vk.image(VK_FORMAT_R16G16_SFLOAT, kWidth, kHeight);
  GpuImage direct = vk.image(VK_FORMAT_R16G16B16A16_SFLOAT, kWidth, kHeight);
  GpuImage sky = vk.image(VK_FORMAT_R16G16B16A16_SFLOAT, 64, 32);
  {
    std::vector<float> z;
    std::vector<std::uint16_t> n, d, m(kWidth * kHeight * 2, 0);
    std::vector<std::uint8_t> a;
    for (std::uint32_t y = 0; y < kHeight; ++y)
      for (std::uint32_t x = 0; x < kWidth; ++x) {
        const Texel t = shade(x, y);
        const std::uint8_t srgb = std::uint8_t(std::lround(255.0 * std::pow(t.albedo, 1.0 / 2.2)));
        z.push_back(t.viewZ);
        n.insert(n.end(), {half(t.normal[0]), half(t.normal[1]), half(t.normal[2]), half(1.0f)});
        a.insert(a.end(), {srgb, srgb, srgb, 0});
        d.insert(d.end(), {half(t.emission), half(t.emission), half(t.emission), half(1.0f)});
      }
    vk.upload(viewZ, z.data(), z.size() * 4);
    vk.upload(normals, n.data(), n.size() * 2);
    vk.upload(albedo, a.data(), a.size());
    vk.upload(motion, m.data(), m.size() * 2);
    vk.upload(direct, d.data(), d.size() * 2);
    vk.upload(sky, nullptr, 0);  // black: all the light comes from the panel
  }

  int failures = 0;
  try {
    const gi::Device device{vk.instance, vk.physicalDevice, vk.device, vk.queueFamily, vk.debugUtils};
    gi::GiContext context(device, {.maxWidth = kWidth, .maxHeight = kHeight});
    gi::EnvironmentPrefilter environment(device, {.width = 64, .height = 32, .samplesPerTexel = 16});
    std::printf("GI library %s: %.1f MiB of device memory\n", BOUNCE_VERSION_STRING,
                double(context.memoryBytes() + environment.memoryBytes()) / (1 << 20));
    const float position[3] = {0, 1, 3}, right[3] = {1, 0, 0}, up[3] = {0, 1, 0}, forward[3] = {0, 0, -1};
    const gi::Camera camera =
        gi::cameraFromBasis(position, right, up, forward, 2.0f * std::atan(kTanHalfFov), float(kWidth) / kHeight);
    for (std::uint64_t frame = 0; frame < kFrames; ++frame) {
      VkCommandBuffer cmd = vk.begin();
      // The engine's G-buffer pass of this frame: it writes every input anew.
      for (GpuImage* image : {&viewZ, &normals, &albedo, &motion, &direct}) vk.recordUpload(cmd, *image);
      if (frame == 0) {
        vk.recordUpload(cmd, sky);
        environment.record(cmd, sky.ref());
      }
      gi::FrameInputs inputs{.viewZ = viewZ.ref(), .normalRoughness = normals.ref(),
                             .baseColorMetallic = albedo.ref(), .motion = motion.ref(), .direct = direct.ref(),
                             .environment = environment.output(), .environmentSampler = environment.sampler(),
                             .width = kWidth, .height = kHeight, .camera = camera, .previousCamera = camera,
                             .frameIndex = frame, .cameraCut = frame == 0};
      context.record(cmd, inputs);
      vk.submitAndWait(cmd);
      for (const gi::PassTiming& t : context.collect(frame).timings)
        if (frame + 1 == kFrames) std::printf("  %-32s %8.3f ms\n", t.pass.c_str(), t.milliseconds);
    }

    // The composite is in GENERAL, last written by a compute shader.
    const std::vector<std::uint16_t> frame = vk.readback(context.composite(), kWidth * kHeight * 4);
    double nearSum = 0, farSum = 0;
    int nearCount = 0, farCount = 0;
    for (std::uint32_t y = 0; y < kHeight; ++y)
      for (std::uint32_t x = 0; x < kWidth; ++x) {
        const Texel t = shade(x, y);
        if (t.albedo == 0.0f) continue;  // floor pixels only
        const float r = fromHalf(frame[(y * kWidth + x) * 4]);
        if (!std::isfinite(r)) ++failures;
        const float floorZ = 3.0f - t.viewZ;  // z of the floor point (the camera looks straight down -Z)
        (floorZ < 0.0f ? nearSum : farSum) += r;
        ++(floorZ < 0.0f ? nearCount : farCount);
      }
    const double nearMean = nearSum / nearCount, farMean = farSum / farCount;
    std::printf("floor radiance: %.4f within 1 m of the panel, %.4f beyond\n", nearMean, farMean);
    if (!(nearMean > 0.05 && nearMean > 2.0 * farMean && farMean > 0.0)) {
      std::printf("FAILED: the floor is not lit by the panel as expected\n");
      ++failures;
    }
  } catch (const gi::Error& e) {
    std::printf("FAILED: %s\n", e.what());
    return 1;
  }
  vk.close();
  std::printf("validation messages: %d%s\n", vk.messages(), vk.validated() ? "" : " (layer not installed)");
  return failures == 0 && vk.messages() == 0 ? 0 : 1;
}

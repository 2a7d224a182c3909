// The environment: what a ray that leaves the scene sees, as one
// equirectangular rgba16f image with a prefiltered mip chain that later
// passes sample by roughness (shaders/render/environment.glsl).
//
// It is one of
//   - the procedural sky (default): Preetham et al. 1999, built from the same
//     scene::Sun as the directional light and scaled so that its brightness
//     relative to the sun's illuminance E is the model's (docs/environment.md);
//   - an equirectangular HDR/EXR map from a file, times an intensity and
//     turned about +Y;
//   - black, when the scene has no sun and no map (closed rooms).
// Mip 0 is the sharp environment; mip k the GGX-prefiltered radiance for
// perceptual roughness k / (mipCount - 1). Neither holds the sun's disk: the
// renderer lights with the sun as a directional light, and shared/sky.glsl's
// sunDiskRadiance() draws the disk for background pixels.
//
// The prefiltered chain is made by the GI library's gi::EnvironmentPrefilter,
// through its public interface, as an engine would make its own.
// Passes (recorded once, by the first record()):
//   render.sky_bake            the sky into the source image (maps are uploaded there)
//   gi.environment.downsample  the library: the source's box-filtered chain
//   gi.environment.prefilter   the library: the GGX-prefiltered chain
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>
#include <glm/glm.hpp>

#include "bounce/gi.h"
#include "gpu/context.h"
#include "gpu/pass.h"
#include "gpu/recorder.h"
#include "gpu/resources.h"
#include "io/image_io.h"
#include "scene/scene.h"

namespace bounce::render {

struct EnvironmentDesc {
  std::filesystem::path map;     // equirect .exr/.hdr (2:1); empty: the procedural sky (or black without a sun)
  float intensity = 1.0f;        // multiplies the map or the sky (>= 0)
  float rotationDegrees = 0.0f;  // turns the map about +Y: a feature's azimuth grows by this (the sky follows the sun)
  scene::Sun sun;                // the sky is built for this sun
  bool hasSun = true;            // false and no map: a black environment
  float turbidity = 3.0f;        // Preetham haze, clamped to [1.7, 10]: 2 very clear, 3 clear, 6 hazy
  float groundAlbedo = 0.2f;     // the sky's ground below the horizon: Lambert, lit by sun and sky (0 = black)
  std::uint32_t skyWidth = 512;  // equirect width of the baked sky (height = width / 2), at least 8
  std::uint32_t maxMapWidth = 2048;      // wider maps are area-filtered down to this width on load
  std::uint32_t maxMipCount = 6;         // levels of the prefiltered chain, fewer for small images
  std::uint32_t prefilterSamples = 256;  // GGX samples per texel of each prefiltered level
};

// "" when the environment's intensity is within scene::kMaxLightStrength and,
// for the sky (built from the sun), so is intensity x the sun's illuminance x
// its colour's largest channel; else why not, to follow the intensity's value
// in a message: "times the sun's illuminance 1e+15 (1e+25) is above ...".
// The constructor refuses such a desc; the CLI names --env-intensity.
std::string environmentIntensityProblem(const EnvironmentDesc& desc);

// Levels of the prefiltered chain for an environment `height` texels tall:
// down to a level 8 texels tall (so even roughness 1 keeps some shape), at
// most maxMipCount, at least 1.
std::uint32_t prefilteredMipCount(std::uint32_t height, std::uint32_t maxMipCount);

// Illuminance (lux) of the Preetham sun at normal incidence after the
// atmosphere: the paper's extraterrestrial solar radiance times its
// Rayleigh, aerosol (from the turbidity), ozone and water-vapour
// transmittances at the Kasten air mass, integrated against the CIE
// photopic curve over the sun's disk: 128 klux outside the atmosphere, 83
// klux for T = 3 at 50 degrees, 2 lux for T = 3 at the horizon. The sky's
// scale uses it (at least 10 % of the 128 klux; docs/environment.md).
float preethamSunIlluminance(float elevationDegrees, float turbidity);

// How much the sky dims below the horizon (1 at and above it): ten times per
// 2 degrees of depression, as measured twilight skies do, and 0 from -12
// degrees (nautical dusk) on. Preetham has no twilight.
float twilightFactor(float elevationDegrees);

// The sky's parameters: the members of shared::SkyParams (shared/sky.glsl),
// which the bake gets as push constants. A type of its own because the
// shared types live in a per-translation-unit namespace; convert with
// shared::SkyParams{p.toSunTurbidity, p.scale, p.groundRadiance}.
struct SkyParameters {
  glm::vec4 toSunTurbidity{0.0f};  // xyz unit direction towards the sun, w turbidity
  glm::vec4 scale{0.0f};           // x: renderer radiance per cd/m^2 of sky (0 = black sky)
  glm::vec4 groundRadiance{0.0f};  // rgb: radiance below the horizon
};

// The sky for a desc, for the bake and for anyone evaluating the same sky
// analytically (shared/sky.glsl skyRadiance()). All zero when !hasSun.
SkyParameters skyParams(const EnvironmentDesc& desc);

// Irradiance on a horizontal surface from the sky above the horizon, in
// renderer units (the sky of `params` with no ground, integrated numerically).
glm::vec3 skyHorizontalIrradiance(const SkyParameters& params);

// An equirect map as the environment stores it: RGBA, each texel through
// sanitizeRadiance (clamped to [0, 65504], float16's range, since lossy EXR
// codecs leave small negatives; black where a channel is NaN or infinite, as
// everywhere in the renderer: docs/conventions.md), area-filtered
// down to maxWidth if wider, turned by rotationDegrees about +Y, times
// intensity. Throws io::ImageIoError naming `name` if it is not 2:1 (within
// 1 %) or narrower than 8 texels, or if a texel's radiance (times the
// intensity, when above 1) is beyond scene::kMaxLightStrength or negative
// beyond a lossy codec's ringing (below -10 % of the brightest texel), naming
// the first such texel and their count.
io::ImageF prepareEnvironmentMap(const io::ImageF& map, const std::string& name, float intensity, float rotationDegrees,
                                 std::uint32_t maxWidth);

// prepareEnvironmentMap's refusals of a map's shape and channels (a lone
// alpha channel is no light), for a size known from a header: throws
// io::ImageIoError naming `name`.
void checkEnvironmentMapShape(int width, int height, const std::vector<std::string>& channels, const std::string& name);

// The most prepareEnvironmentMap holds beside the map it is given, in bytes:
// a wide map is shrunk as it is read (no full-size copy), a narrow one copied
// once. The Environment refuses a map whose reading or preparing would hold
// more than io::kImageMemoryLimit.
std::uint64_t environmentMapWorkingBytes(int width, int height, std::uint32_t maxWidth);

class Environment {
 public:
  // Loads and checks the map now (errors name the file); creates the images
  // and passes. Throws gpu::GpuError for a desc out of range.
  Environment(gpu::Context& context, const EnvironmentDesc& desc);
  ~Environment();
  Environment(const Environment&) = delete;
  Environment& operator=(const Environment&) = delete;

  // The first call records the bake (or the map's upload was done) and the
  // library's prefilter; later calls record nothing until setSun changes
  // the sky.
  void record(gpu::Recorder& recorder);

  // Moves the sun (the sky is built for it): a procedural sky is baked and
  // prefiltered again by the next record(); a map stays as it is. Throws
  // gpu::GpuError, changing nothing, for a sun out of range (as the
  // constructor). Precondition: no recorded frame that reads the
  // environment is still running (the bake overwrites its images).
  void setSun(const scene::Sun& sun);

  // rgba16f equirect, mipCount() levels of prefiltered radiance (the
  // library's image, wrapped); valid once the command buffer of the first
  // record() has run.
  gpu::Image& radiance() { return *radiance_; }
  std::uint32_t mipCount() const { return radiance_->desc().mipLevels; }
  // Bilinear + linear-mip sampler that repeats across the equirect seam
  // (u = 0 = 1) and clamps at the poles; bind radiance() with it. The
  // context's linear sampler clamps u too, which shows a seam at +Z.
  VkSampler sampler() const;

  enum class Kind { Sky, Map, Black };
  Kind kind() const { return kind_; }
  const EnvironmentDesc& desc() const { return desc_; }
  // The sky's parameters (meaningful for Kind::Sky).
  const SkyParameters& sky() const { return sky_; }

 private:
  gpu::Context& context_;
  EnvironmentDesc desc_;
  Kind kind_ = Kind::Sky;
  SkyParameters sky_;
  bool recorded_ = false;
  std::unique_ptr<gpu::Image> source_;  // the sharp environment at its full size, one level
  std::unique_ptr<gi::EnvironmentPrefilter> prefilter_;
  std::unique_ptr<gpu::Image> radiance_;  // prefilter_'s output
  std::unique_ptr<gpu::ComputePass> skyBakePass_;
};

}  // namespace bounce::render

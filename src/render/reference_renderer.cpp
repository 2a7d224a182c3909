#include "render/reference_renderer.h"

#include <algorithm>
#include <cmath>

#include "gpu/constants_layout.h"
#include "gpu/error.h"
#include "gpu/format.h"
#include "gpu/transfer.h"
#include "gpuio/gpu_images.h"
#include "render/render_shaders.h"

namespace bounce::render {
namespace {

using namespace gpu::formats;

// Paths per dispatch the automatic samplesPerDispatch aims for on a GPU.
constexpr double kPathsPerDispatch = 1 << 20;

std::vector<gpu::ConstantsDecl> join(std::vector<gpu::ConstantsDecl> a, const std::vector<gpu::ConstantsDecl>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

gpu::PassDesc pathDesc() {
  using gpu::Access;
  using gpu::ResourceKind;
  std::vector<gpu::ResourceDecl> decls = FrameRenderer::sceneResources();
  decls.insert(decls.end(),
               {
                   {"gIn_ViewZ", Access::Read, kR32f, "primary hit depth; 0 = background"},
                   {"gIn_NormalRoughness", Access::Read, kRgba16f, "primary hit shading normal, roughness"},
                   {"gIn_GeometricNormal", Access::Read, kRgba16f, "primary hit ray offset and horizon"},
                   {"gIn_BaseColorMetallic", Access::Read, kRgba8, "primary hit material"},
                   {"gIn_Lights", Access::Read, VK_FORMAT_UNDEFINED, "punctual lights", ResourceKind::StorageBuffer},
                   {"gIn_Environment", Access::Read, VK_FORMAT_UNDEFINED, "radiance of escaping rays",
                    ResourceKind::SampledImage},
                   {"gIn_EnvironmentCdf", Access::Read, VK_FORMAT_UNDEFINED, "environment light distribution",
                    ResourceKind::StorageBuffer},
                   {"gIn_EmissiveTriangles", Access::Read, VK_FORMAT_UNDEFINED, "emissive triangles by power",
                    ResourceKind::StorageBuffer},
                   {"gHistory_DiffuseSumA", Access::ReadWrite, kRgba32f, "half A: summed demodulated diffuse"},
                   {"gHistory_SpecularSumA", Access::ReadWrite, kRgba32f, "half A: summed specular"},
                   {"gHistory_DiffuseSumB", Access::ReadWrite, kRgba32f, "half B: summed demodulated diffuse"},
                   {"gHistory_SpecularSumB", Access::ReadWrite, kRgba32f, "half B: summed specular"},
                   {"gHistory_HitDistanceSum", Access::ReadWrite, kRgba32f,
                    "summed first-hit distances and their paths: diffuse, specular"},
               });
  return {
      .name = "render.reference_path",
      .shader = "render/reference_path",
      .shaders = shaders(),
      .resources = decls,
      .constants = join(FrameRenderer::sceneConstants(),
                        {BOUNCE_CONSTANTS_LAYOUT("", shared::ReferencePathParams, sampleBase, firstSample, sampleCount,
                                                 seed, maxBounces, rouletteBounces, lobes, environmentWidth,
                                                 environmentHeight, emissiveCount, emissivePower)})};
}

gpu::PassDesc resolveDesc() {
  using gpu::Access;
  return {.name = "render.reference_resolve",
          .shader = "render/reference_resolve",
          .shaders = shaders(),
          .resources =
              {
                  {"gIn_Frame", Access::Read, VK_FORMAT_UNDEFINED, "camera", gpu::ResourceKind::UniformBuffer},
                  {"gIn_ViewZ", Access::Read, kR32f, "background mask"},
                  {"gIn_NormalRoughness", Access::Read, kRgba16f, "for specularReflectance"},
                  {"gIn_BaseColorMetallic", Access::Read, kRgba8, "remodulation"},
                  {"gIn_Direct", Access::Read, kRgba16f, "render.direct_light's image"},
                  {"gIn_DiffuseSumA", Access::Read, kRgba32f, "half A's diffuse sum"},
                  {"gIn_SpecularSumA", Access::Read, kRgba32f, "half A's specular sum"},
                  {"gIn_DiffuseSumB", Access::Read, kRgba32f, "half B's diffuse sum"},
                  {"gIn_SpecularSumB", Access::Read, kRgba32f, "half B's specular sum"},
                  {"gIn_HitDistanceSum", Access::Read, kRgba32f, "summed first-hit distances"},
                  {"gOut_Radiance", Access::Write, kRgba32f, "the whole frame, linear HDR"},
                  {"gOut_Diffuse", Access::Write, kRgba32f, "indirect diffuse, demodulated; mean first-hit distance"},
                  {"gOut_Specular", Access::Write, kRgba32f, "indirect specular, demodulated; mean first-hit distance"},
              },
          .constants = join(FrameRenderer::sceneConstants(),
                            {BOUNCE_CONSTANTS_LAYOUT("", shared::ReferenceResolveParams, weightA, weightB)})};
}

}  // namespace

ReferenceRenderer::ReferenceRenderer(gpu::Context& context, FrameRenderer& frame, const scene::Scene& scene,
                                     std::uint64_t frameIndex, float time, const ReferenceOptions& options)
    : context_(context), frame_(frame), scene_(scene), frameIndex_(frameIndex), time_(time), options_(options) {
  if (options.lobes == 0 || (options.lobes & ~shared::kLobesAll) != 0)
    throw gpu::GpuError("reference: lobes must be diffuse, specular or both");
  if (options.maxBounces > 1000) throw gpu::GpuError("reference: at most 1000 bounces");
  // lavapipe (llvmpipe) ends any shader invocation's loops after 65535
  // iterations in all, silently (gallivm's loop limiter), so on a CPU device
  // each dispatch takes one sample: a few paths of BVH walks stay within it.
  const double pixels = double(frame.width()) * double(frame.height());
  const bool cpuDevice = context.deviceInfo().type == "CPU";
  samplesPerDispatch_ = options.samplesPerDispatch > 0 ? options.samplesPerDispatch
                        : cpuDevice                    ? 1u
                                    : std::uint32_t(std::clamp(std::floor(kPathsPerDispatch / pixels), 1.0, 64.0));

  // Lights: the environment as the FrameRenderer built it, and every emissive
  // triangle where the scene is at `time`.
  const EnvironmentDistribution environment =
      frame.environment().kind() == Environment::Kind::Black
          ? EnvironmentDistribution{}
          : buildEnvironmentDistribution(gpuio::readbackImage(context, frame.environment().radiance()));
  if (!environment.empty()) {
    environmentWidth_ = environment.width;
    environmentHeight_ = environment.height;
  }
  const std::vector<float> cdf = environment.packed();
  environmentCdf_ = std::make_unique<gpu::Buffer>(context, "reference.environment_cdf", cdf.size() * sizeof(float),
                                                  gpu::BufferUsage::DeviceLocal);
  gpu::uploadBuffer(context, *environmentCdf_, cdf.data(), cdf.size() * sizeof(float));

  uploadEmissiveTriangles(time);

  const auto image = [&](const std::string& name, gpu::Visualize visualize) {
    return std::make_unique<gpu::Image>(context,
                                        gpu::ImageDesc{name, frame.width(), frame.height(), kRgba32f, visualize});
  };
  for (int half = 0; half < 2; ++half) {
    const std::string suffix = half == 0 ? ".a" : ".b";
    diffuseSum_[half] = image("reference.diffuse_sum" + suffix, gpu::Visualize::Radiance);
    specularSum_[half] = image("reference.specular_sum" + suffix, gpu::Visualize::Radiance);
  }
  hitDistanceSum_ = image("reference.hit_distance_sum", gpu::Visualize::Raw);
  radiance_ = image("reference.radiance", gpu::Visualize::Radiance);
  diffuse_ = image("reference.indirect_diffuse", gpu::Visualize::Radiance);
  specular_ = image("reference.indirect_specular", gpu::Visualize::Radiance);
  context.submitAndWait([&](gpu::Recorder& r) { clearSums(r); });
  pathPass_ = std::make_unique<gpu::ComputePass>(context, pathDesc());
  resolvePass_ = std::make_unique<gpu::ComputePass>(context, resolveDesc());
}

ReferenceRenderer::~ReferenceRenderer() = default;

std::uint64_t ReferenceRenderer::frameImageBytes(std::uint32_t width, std::uint32_t height) {
  // Two halves of diffuse and specular sums, the hit distances, the radiance and its two parts: all rgba32f.
  constexpr std::uint64_t kImages = 2 * 2 + 1 + 3;
  return kImages * gpu::formatInfo(kRgba32f).bytesPerPixel * width * height;
}

// Every emissive triangle where the scene is at `time`, in a new buffer.
void ReferenceRenderer::uploadEmissiveTriangles(float time) {
  const std::vector<scene::Instance> instances = scene::instancesAt(scene_, time);
  EmissiveTriangles emissive = collectEmissiveTriangles(frame_.materials(), frame_.bvh(), instances);
  emissiveCount_ = emissive.count();
  emissivePower_ = float(emissive.totalPower);
  if (emissive.packed.empty()) emissive.packed.emplace_back(0u);
  emissiveTriangles_ =
      std::make_unique<gpu::Buffer>(context_, "reference.emissive_triangles",
                                    emissive.packed.size() * sizeof(glm::uvec4), gpu::BufferUsage::DeviceLocal);
  gpu::uploadBuffer(context_, *emissiveTriangles_, emissive.packed.data(), emissive.packed.size() * sizeof(glm::uvec4));
  time_ = time;
  materialRevision_ = frame_.materialRevision();
}

void ReferenceRenderer::clearSums(gpu::Recorder& recorder) {
  for (int half = 0; half < 2; ++half) {
    recorder.clearImage(*diffuseSum_[half], {});
    recorder.clearImage(*specularSum_[half], {});
  }
  recorder.clearImage(*hitDistanceSum_, {});
}

void ReferenceRenderer::restart(gpu::Recorder& recorder, std::uint64_t frameIndex, float time) {
  // Lights move only in an animated scene and change only with the
  // materials; elsewhere the list made for the first frame holds for every
  // frame, and nothing needs waiting for.
  if ((scene::isAnimated(scene_) && time != time_) || materialsChanged()) uploadEmissiveTriangles(time);
  clearSums(recorder);
  sampleBase_ += samples_;
  samples_ = 0;
  frameIndex_ = frameIndex;
}

std::uint64_t ReferenceRenderer::samplesPerPixel(ReferenceHalf half) const {
  // Even-numbered samples go to half A, odd ones to half B.
  switch (half) {
    case ReferenceHalf::A:
      return (samples_ + 1) / 2;
    case ReferenceHalf::B:
      return samples_ / 2;
    case ReferenceHalf::Both:
      break;
  }
  return samples_;
}

std::uint32_t ReferenceRenderer::record(gpu::Recorder& recorder, std::uint32_t samples) {
  if (materialsChanged())
    throw gpu::GpuError(
        "reference: the renderer's materials changed (setMaterial) since the reference started; restart() it, so its "
        "sums and emissive triangles are the new materials'");
  if (samples == 0) return 0;
  const std::uint32_t count = std::min(samples, samplesPerDispatch_);
  const shared::ReferencePathParams params{
      .sampleBase = std::uint32_t(sampleBase_),
      .firstSample = std::uint32_t(samplesPerPixel()),
      .sampleCount = count,
      .seed = options_.seed,
      .maxBounces = options_.maxBounces,
      .rouletteBounces = options_.rouletteBounces,
      .lobes = options_.lobes,
      .environmentWidth = environmentWidth_,
      .environmentHeight = environmentHeight_,
      .emissiveCount = std::uint32_t(emissiveCount_),
      .emissivePower = emissivePower_,
  };
  std::vector<gpu::Bind> binds = frame_.sceneBinds(frameIndex_);
  Environment& environment = frame_.environment();
  binds.insert(binds.end(), {{"gIn_ViewZ", frame_.viewZ()},
                             {"gIn_NormalRoughness", frame_.normalRoughness()},
                             {"gIn_GeometricNormal", frame_.geometricNormal()},
                             {"gIn_BaseColorMetallic", frame_.baseColorMetallic()},
                             {"gIn_Lights", frame_.lights()},
                             {"gIn_Environment", environment.radiance(), environment.sampler()},
                             {"gIn_EnvironmentCdf", *environmentCdf_},
                             {"gIn_EmissiveTriangles", *emissiveTriangles_},
                             {"gHistory_DiffuseSumA", *diffuseSum_[0]},
                             {"gHistory_SpecularSumA", *specularSum_[0]},
                             {"gHistory_DiffuseSumB", *diffuseSum_[1]},
                             {"gHistory_SpecularSumB", *specularSum_[1]},
                             {"gHistory_HitDistanceSum", *hitDistanceSum_}});
  recorder.dispatch(*pathPass_, frame_.width(), frame_.height(), binds, params);
  samples_ += count;
  return count;
}

void ReferenceRenderer::recordResolve(gpu::Recorder& recorder, ReferenceHalf half) {
  const auto weight = [&](ReferenceHalf h) {
    if (half != ReferenceHalf::Both && half != h) return 0.0f;
    const std::uint64_t samples = samplesPerPixel(half);
    return samples > 0 ? 1.0f / float(samples) : 0.0f;
  };
  const shared::ReferenceResolveParams params{weight(ReferenceHalf::A), weight(ReferenceHalf::B)};
  recorder.dispatch(*resolvePass_, frame_.width(), frame_.height(),
                    {{"gIn_Frame", frame_.frameConstants(frameIndex_)},
                     {"gIn_ViewZ", frame_.viewZ()},
                     {"gIn_NormalRoughness", frame_.normalRoughness()},
                     {"gIn_BaseColorMetallic", frame_.baseColorMetallic()},
                     {"gIn_Direct", frame_.direct()},
                     {"gIn_DiffuseSumA", *diffuseSum_[0]},
                     {"gIn_SpecularSumA", *specularSum_[0]},
                     {"gIn_DiffuseSumB", *diffuseSum_[1]},
                     {"gIn_SpecularSumB", *specularSum_[1]},
                     {"gIn_HitDistanceSum", *hitDistanceSum_},
                     {"gOut_Radiance", *radiance_},
                     {"gOut_Diffuse", *diffuse_},
                     {"gOut_Specular", *specular_}},
                    params);
}

ReferenceImages ReferenceRenderer::resolve(gpu::FrameLoop& loop, ReferenceHalf half) {
  recordResolve(loop.beginFrame(), half);
  loop.endFrame();
  loop.finish();

  ReferenceImages images;
  images.radiance = io::firstChannels(gpuio::readbackImage(context_, *radiance_), 3);
  images.direct = io::firstChannels(gpuio::readbackImage(context_, frame_.direct()), 3);
  images.indirectDiffuse = io::firstChannels(gpuio::readbackImage(context_, *diffuse_), 3);
  images.indirectSpecular = io::firstChannels(gpuio::readbackImage(context_, *specular_), 3);
  for (int h = 0; h < 2; ++h)
    for (gpu::Image* sum : {diffuseSum_[h].get(), specularSum_[h].get()}) {
      const io::ImageF values = gpuio::readbackImage(context_, *sum);
      for (std::size_t p = 3; p < values.pixels.size(); p += 4)
        images.droppedSamples += std::uint64_t(values.pixels[p]);
    }
  return images;
}

}  // namespace bounce::render

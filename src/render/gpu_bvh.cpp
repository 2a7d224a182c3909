#include "render/gpu_bvh.h"

#include <algorithm>
#include <cstring>

#include "gpu/constants_layout.h"
#include "gpu/error.h"
#include "gpu/transfer.h"
#include "render/render_shaders.h"

namespace bounce::render {
namespace {

template <class T>
std::unique_ptr<gpu::Buffer> makeBuffer(gpu::Context& context, const std::string& name, std::size_t capacity,
                                        gpu::BufferUsage usage) {
  // Vulkan buffers cannot be empty; an empty array gets one unused element.
  return std::make_unique<gpu::Buffer>(context, name, std::max<std::size_t>(1, capacity) * sizeof(T), usage);
}

template <class T>
std::unique_ptr<gpu::Buffer> uploadArray(gpu::Context& context, const std::string& name, const std::vector<T>& data) {
  auto buffer = makeBuffer<T>(context, name, data.size(), gpu::BufferUsage::DeviceLocal);
  if (!data.empty()) gpu::uploadBuffer(context, *buffer, data.data(), data.size() * sizeof(T));
  return buffer;
}

gpu::ResourceDecl bufferDecl(const char* name, const char* purpose) {
  return {name, gpu::Access::Read, VK_FORMAT_UNDEFINED, purpose, gpu::ResourceKind::StorageBuffer};
}

}  // namespace

GpuBvh::GpuBvh(gpu::Context& context, const SceneBvh& bvh, std::uint32_t framesInFlight)
    : context_(context), bvh_(bvh) {
  if (framesInFlight == 0) throw gpu::GpuError("GpuBvh needs at least one frame slot");
  instanceCapacity_ = std::max<std::size_t>(1, bvh.instanceCount());
  // A binary tree with one instance per leaf has n - 1 interior nodes, and
  // the wide layout keeps at most one node per interior node (one for n <= 1).
  tlasNodeCapacity_ = instanceCapacity_;
  checkCapacity();

  blasNodes_ = uploadArray(context, "bvh.blas_nodes", bvh.blasNodes());
  triangles_ = uploadArray(context, "bvh.triangles", bvh.triangles());
  positions_ = uploadArray(context, "bvh.positions", bvh.positions());
  instances_ = makeBuffer<BvhInstance>(context, "bvh.instances", instanceCapacity_, gpu::BufferUsage::DeviceLocal);
  tlasNodes_ = makeBuffer<BvhWideNode>(context, "bvh.tlas_nodes", tlasNodeCapacity_, gpu::BufferUsage::DeviceLocal);
  if (!bvh.instances().empty())
    gpu::uploadBuffer(context, *instances_, bvh.instances().data(), bvh.instances().size() * sizeof(BvhInstance));
  gpu::uploadBuffer(context, *tlasNodes_, bvh.tlasNodes().data(), bvh.tlasNodes().size() * sizeof(BvhWideNode));

  for (std::uint32_t i = 0; i < framesInFlight; ++i) {
    const std::string suffix = ".staging.slot" + std::to_string(i);
    slots_.push_back(
        {makeBuffer<BvhInstance>(context, "bvh.instances" + suffix, instanceCapacity_, gpu::BufferUsage::Upload),
         makeBuffer<BvhWideNode>(context, "bvh.tlas_nodes" + suffix, tlasNodeCapacity_, gpu::BufferUsage::Upload)});
  }
}

GpuBvh::~GpuBvh() = default;

void GpuBvh::checkCapacity() const {
  if (bvh_.instances().size() > instanceCapacity_ || bvh_.tlasNodes().size() > tlasNodeCapacity_)
    throw gpu::GpuError("GpuBvh: the scene now has " + std::to_string(bvh_.instances().size()) +
                        " traceable instances; its buffers were sized for " + std::to_string(instanceCapacity_));
}

void GpuBvh::updateInstances(gpu::Recorder& recorder, std::uint32_t frameSlot) {
  if (frameSlot >= slots_.size())
    throw gpu::GpuError("GpuBvh: frame slot " + std::to_string(frameSlot) + " of " + std::to_string(slots_.size()));
  checkCapacity();
  Slot& slot = slots_[frameSlot];
  const std::size_t instanceBytes = bvh_.instances().size() * sizeof(BvhInstance);
  const std::size_t tlasBytes = bvh_.tlasNodes().size() * sizeof(BvhWideNode);
  // With nothing to trace the vectors are empty and their data() may be
  // null, which memcpy must not be given even for zero bytes.
  if (instanceBytes) {
    std::memcpy(slot.instances->mapped(), bvh_.instances().data(), instanceBytes);
    recorder.copyBuffer(*slot.instances, *instances_, instanceBytes);
  }
  if (tlasBytes) {
    std::memcpy(slot.tlasNodes->mapped(), bvh_.tlasNodes().data(), tlasBytes);
    recorder.copyBuffer(*slot.tlasNodes, *tlasNodes_, tlasBytes);
  }
}

std::vector<gpu::ResourceDecl> GpuBvh::traceResources() {
  return {bufferDecl("gIn_BvhNodes", "BVH: every mesh's BLAS nodes"),
          bufferDecl("gIn_BvhTriangles", "BVH: triangle vertex indices, material | alpha-mask bit"),
          bufferDecl("gIn_BvhPositions", "BVH: object-space vertex positions, then each triangle's corners"),
          bufferDecl("gIn_BvhInstances", "BVH: instance transforms and BLAS roots, this frame"),
          bufferDecl("gIn_BvhTlasNodes", "BVH: the TLAS over the instances, this frame")};
}

void GpuBvh::appendBinds(std::vector<gpu::Bind>& binds) {
  binds.insert(binds.end(), {{"gIn_BvhNodes", *blasNodes_},
                             {"gIn_BvhTriangles", *triangles_},
                             {"gIn_BvhPositions", *positions_},
                             {"gIn_BvhInstances", *instances_},
                             {"gIn_BvhTlasNodes", *tlasNodes_}});
}

gpu::PassDesc bvhTraceRaysPassDesc(std::string name, std::string shader,
                                   std::span<const gpu::EmbeddedShader> library) {
  std::vector<gpu::ResourceDecl> resources = {
      bufferDecl("gIn_Rays", "origin, tMin, direction, tMax per ray"),
      {"gOut_Results", gpu::Access::Write, VK_FORMAT_UNDEFINED,
       "t, barycentrics, blocked flag, instance, triangle, material per ray", gpu::ResourceKind::StorageBuffer}};
  for (const gpu::ResourceDecl& decl : GpuBvh::traceResources()) resources.push_back(decl);
  return {.name = std::move(name),
          .shader = std::move(shader),
          .shaders = library.empty() ? shaders() : library,
          .resources = std::move(resources),
          .constants = {BOUNCE_CONSTANTS_LAYOUT("", shared::BvhTraceRaysParams, rayCountMode)}};
}

BvhRayTracer::BvhRayTracer(gpu::Context& context, gpu::PassDesc desc) : context_(context), pass_(context, desc) {}

void BvhRayTracer::record(gpu::Recorder& recorder, GpuBvh& bvh, gpu::Buffer& rays, gpu::Buffer& results,
                          std::uint32_t rayCount, BvhTraceMode mode) {
  const auto fail = [&](const std::string& why) { return gpu::GpuError("pass '" + pass_.name() + "': " + why); };
  if (rayCount == 0) return;
  if (rays.size() < std::size_t(rayCount) * sizeof(BvhRay) ||
      results.size() < std::size_t(rayCount) * sizeof(BvhTraceResult))
    throw fail(std::to_string(rayCount) + " rays do not fit buffers '" + rays.name() + "' and '" + results.name() +
               "'");
  const std::uint64_t maxRays =
      std::uint64_t(context_.properties().limits.maxComputeWorkGroupCount[0]) * pass_.localSize()[0];
  if (rayCount > maxRays)
    throw fail(std::to_string(rayCount) + " rays in one dispatch; at most " + std::to_string(maxRays));
  std::vector<gpu::Bind> binds = {{"gIn_Rays", rays}, {"gOut_Results", results}};
  bvh.appendBinds(binds);
  const shared::BvhTraceRaysParams params{glm::uvec4(rayCount, std::uint32_t(mode), 0u, 0u)};
  recorder.dispatch(pass_, rayCount, 1, binds, params);
}

}  // namespace bounce::render

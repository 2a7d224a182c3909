// The scene BVH on the GPU: the buffers render/bvh_trace.glsl reads, the
// per-frame TLAS upload, and the render.bvh_trace_rays pass.
//
// A pass that traces rays includes render/bvh_trace.glsl, adds
// GpuBvh::traceResources() to its declaration and GpuBvh::appendBinds() to
// its binds:
//
//   std::vector<gpu::ResourceDecl> decls = {... the pass's own ...};
//   for (const gpu::ResourceDecl& d : GpuBvh::traceResources()) decls.push_back(d);
//   ...
//   sceneBvh.setInstances(instancesNow);                  // CPU: rebuilds the TLAS
//   gpuBvh.updateInstances(recorder, frameIndex % framesInFlight);
//   std::vector<gpu::Bind> binds = {... the pass's own ...};
//   gpuBvh.appendBinds(binds);
//   recorder.dispatch(pass, width, height, binds, params);
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "gpu/context.h"
#include "gpu/pass.h"
#include "gpu/recorder.h"
#include "gpu/resources.h"
#include "render/bvh.h"

namespace bounce::render {

using shared::BvhRay;
using shared::BvhTraceResult;

class GpuBvh {
 public:
  // Uploads every BLAS, the triangles and the positions once (blocking), and
  // the TLAS and instances as `bvh` holds them now, so tracing works before
  // the first updateInstances. The TLAS buffers are sized for
  // bvh.instanceCount() instances, which must not grow later.
  GpuBvh(gpu::Context& context, const SceneBvh& bvh, std::uint32_t framesInFlight);
  ~GpuBvh();
  GpuBvh(const GpuBvh&) = delete;
  GpuBvh& operator=(const GpuBvh&) = delete;

  // Records the upload of the SceneBvh's current TLAS and instance records:
  // the CPU writes them into this frame slot's host-visible staging buffers,
  // then the recorder copies them into the device-local buffers the shaders
  // read. Call it inside the FrameLoop frame whose slot is `frameSlot`
  // (frameIndex % framesInFlight): that slot's previous frame has finished,
  // so its staging buffers are free, and the copies wait (recorder barriers)
  // for every earlier frame's reads, so no frame sees a half-written TLAS.
  void updateInstances(gpu::Recorder& recorder, std::uint32_t frameSlot);

  // The declarations of bvh_trace.glsl's BVH_BINDING_COUNT bindings, for a pass that includes it.
  static std::vector<gpu::ResourceDecl> traceResources();
  // The matching binds.
  void appendBinds(std::vector<gpu::Bind>& binds);

  gpu::Buffer& blasNodes() { return *blasNodes_; }
  gpu::Buffer& triangles() { return *triangles_; }
  gpu::Buffer& positions() { return *positions_; }
  gpu::Buffer& instances() { return *instances_; }
  gpu::Buffer& tlasNodes() { return *tlasNodes_; }
  std::size_t instanceCapacity() const { return instanceCapacity_; }

 private:
  struct Slot {
    std::unique_ptr<gpu::Buffer> instances;
    std::unique_ptr<gpu::Buffer> tlasNodes;
  };
  // Throws when the SceneBvh holds more instances than the buffers were sized for.
  void checkCapacity() const;

  gpu::Context& context_;
  const SceneBvh& bvh_;
  std::size_t instanceCapacity_ = 0;
  std::size_t tlasNodeCapacity_ = 0;
  std::unique_ptr<gpu::Buffer> blasNodes_, triangles_, positions_, instances_, tlasNodes_;
  std::vector<Slot> slots_;
};

enum class BvhTraceMode : std::uint32_t { Closest = shared::kBvhTraceClosest, Any = shared::kBvhTraceAny };

// The declaration of render.bvh_trace_rays. Shaders with the same interface
// (a test's variant with an alpha-test hook) reuse it under their own name,
// from their own shader library (empty: the renderer's).
gpu::PassDesc bvhTraceRaysPassDesc(std::string name = "render.bvh_trace_rays",
                                   std::string shader = "render/bvh_trace_rays",
                                   std::span<const gpu::EmbeddedShader> library = {});

// render.bvh_trace_rays: traces `rays` (BvhRay each) and writes one
// BvhTraceResult per ray into `results`, one thread per ray.
class BvhRayTracer {
 public:
  explicit BvhRayTracer(gpu::Context& context, gpu::PassDesc desc = bvhTraceRaysPassDesc());
  void record(gpu::Recorder& recorder, GpuBvh& bvh, gpu::Buffer& rays, gpu::Buffer& results, std::uint32_t rayCount,
              BvhTraceMode mode);
  const gpu::ComputePass& pass() const { return pass_; }

 private:
  gpu::Context& context_;
  gpu::ComputePass pass_;
};

}  // namespace bounce::render

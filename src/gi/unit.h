// A GI unit: a stage of the library's frame (the frame's history, the depth
// pyramid, a branch, the radiance cache, the denoiser, the composite, ...).
// Each declares by name what it makes and takes (its products); GiContext
// records the units in the order they are registered (gi/units.h) and routes
// products by name, knowing nothing of what a unit does inside. A product
// made again by a later unit replaces the earlier one for the units after
// it: the denoiser's "diffuse" replaces the diffuse branch's own filtered one.
// docs/architecture.md ("Units and products") lists every unit and product.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "bounce/gi.h"
#include "gi/engine_images.h"
#include "gi/frame_constants.h"
#include "gi/image_table.h"
#include "gpu/pass.h"
#include "gpu/recorder.h"

namespace bounce::gi {

// The names of the products the library's own units make and take. A
// signal's products are named after it: SIGNAL (what the composite or the
// engine reads: "diffuse", "specular", an engine's signal) and SIGNAL.noisy
// (what the denoiser takes).
namespace product {
inline constexpr std::string_view kSurface = "surface";                       // this frame's viewZ, normal, material id
inline constexpr std::string_view kPreviousSurface = "surface.previous";      // last frame's (history)
inline constexpr std::string_view kMarchDepth = "march_depth";                // the viewZ visibility marches read
inline constexpr std::string_view kPreviousComposite = "composite.previous";  // last frame's frame (history)
inline constexpr std::string_view kComposite = "composite";
inline constexpr std::string_view kDepthPyramid = "depth_pyramid";  // binds: gIn_DepthPyramid
inline constexpr std::string_view kScreenTiles = "screen_tiles";    // binds: the tiles and border
inline constexpr std::string_view kLightChange = "light_change";
inline constexpr std::string_view kCache = "cache";  // binds: the radiance cache's buffers
// binds: gIn_Diffuse_Reservoir0/1, the diffuse branch's final reservoirs of
// this frame (half resolution; rough specular pixels take their samples).
inline constexpr std::string_view kDiffuseReservoirs = "diffuse.reservoirs";
// The engine's environment (FrameInputs::environment), which the context
// makes: a frame no unit takes it of may leave it out.
inline constexpr std::string_view kEnvironment = "engine.environment";
// SIGNAL.noisy for a signal's name.
std::string noisy(std::string_view signal);
}  // namespace product

// A frame's products by name, as the units recorded so far made them.
class Products {
 public:
  // Makes (or makes again, replacing the earlier) an image product.
  void put(std::string_view name, gpu::Image& image);
  // A product that is resources a consumer binds under the names its
  // producer's shader include declares (the cache's buffers, the tiles).
  void put(std::string_view name, std::vector<gpu::Bind> binds);
  bool has(std::string_view name) const { return entries_.find(name) != entries_.end(); }
  // The image product `name`, or null where none was made.
  gpu::Image* find(std::string_view name) const;
  // The image product `name`; throws Error naming it and what was made
  // (a unit that takes a product it did not declare, or a routing fault).
  gpu::Image& image(std::string_view name) const;
  // The binds of product `name`; none where it was not made (a pass that
  // declares them then refuses the dispatch, naming the binding).
  std::span<const gpu::Bind> binds(std::string_view name) const;
  std::vector<std::string> names() const;
  void clear() { entries_.clear(); }

 private:
  struct Entry {
    gpu::Image* image = nullptr;
    std::vector<gpu::Bind> binds;
  };
  std::map<std::string, Entry, std::less<>> entries_;
};

// What a unit gets to record one frame.
struct FrameState {
  gpu::Recorder& recorder;
  const FrameGroup& group;  // gIn_Frame, gIn_ViewZ, gIn_NormalRoughness
  EngineImages& engine;
  VkSampler environmentSampler;
  VkSampler nearestSampler;  // for the engine's images, read with texelFetch
  std::uint64_t frameIndex;  // the history images' index (frames recorded before this one)
  Extent renderSize;
  bool hasHistory;                      // last frame's images hold a frame (perhaps of another camera: a cut)
  bool usableHistory;                   // ... and it may be reused (no cut, same render size, same sources of signals)
  bool capturing;                       // this frame's stages are captured: debug passes run too
  std::array<float, 3> cameraPosition;  // world space
  // The context's signals by SignalId, and which of them the engine gives
  // this frame and gave last frame.
  std::span<const SignalDesc> signals;
  const std::vector<bool>& given;
  const std::vector<bool>& givenLastFrame;
  Products& products;        // this frame's, made by the units recorded before
  const Products& previous;  // last frame's (none on the first frame)
};

// What a unit is told before a frame, to say whether it records and what it takes.
struct FramePlan {
  std::span<const SignalDesc> signals;
  const std::vector<bool>& given;  // the engine gives the signal this frame (FrameInputs::noisy)
  // Products that units recorded after this one take this frame.
  const std::set<std::string, std::less<>>& wanted;
  // Whether the engine gives the signal called `signal` this frame.
  bool engineGives(std::string_view signal) const;
};

class Unit {
 public:
  virtual ~Unit() = default;
  // "diffuse": its passes and images are gi.diffuse.*.
  virtual std::string_view name() const = 0;
  // This frame's part: whether it records, and the products it takes then
  // (each one made by a unit before it: UnitRegistration::produces; the
  // context refuses a frame whose plan takes one that none makes).
  struct Plan {
    bool records = false;
    std::vector<std::string> takes;
  };
  virtual Plan plan(const FramePlan& frame) const = 0;
  // At the start of every frame, before any unit records: the products its
  // history holds from last frame (the composite's "composite.previous").
  virtual void putHistory(Products& products, std::uint64_t frameIndex) {
    (void)products;
    (void)frameIndex;
  }
  virtual void record(const FrameState& frame) = 0;
  // Once every unit that took one of its products this frame has recorded
  // (the radiance cache's update, after the branches' queries).
  virtual void recordAfterConsumers(const FrameState& frame) { (void)frame; }
  // Its images as GiContext::images() lists them, this frame's for history entries.
  virtual std::vector<ImageSet::Listed> listImages(std::uint64_t frameIndex) {
    std::vector<ImageSet::Listed> listed;
    for (ImageSet* set : imageSets()) {
      std::vector<ImageSet::Listed> ofSet = set->list(frameIndex);
      listed.insert(listed.end(), ofSet.begin(), ofSet.end());
    }
    return listed;
  }
  // The image tables it made (their images are handed back to GENERAL
  // after a captured frame).
  virtual std::vector<ImageSet*> imageSets() { return {}; }
  // Its buffers in the transient pool (buffers written and read only while
  // it records), taken as ImageSet::takeTransients takes images.
  virtual std::vector<gpu::Buffer*> transientBuffers() { return {}; }
};

// What the branches share (a unit that makes one of the library's signals:
// SIGNAL and SIGNAL.noisy): it rests on frames the engine gives the signal
// in its place, and disabled it records only the clearing of its result.
class BranchUnit : public Unit {
 public:
  // `signal`: a name of static storage (the branch's kSignal).
  BranchUnit(std::string_view signal, bool enabled) : signal_(signal), enabled_(enabled) {}
  std::string_view name() const final { return signal_; }
  Plan plan(const FramePlan& frame) const final {
    if (frame.engineGives(signal_)) return {};
    if (!enabled_) return {.records = true};
    return {.records = true, .takes = takes()};
  }

 protected:
  // What it takes on the frames it runs.
  virtual std::vector<std::string> takes() const = 0;

 private:
  std::string_view signal_;
  bool enabled_;
};

// A unit that records only on the frames a unit after it takes its product
// (the depth pyramid, the screen tiles, the light change), and lists its
// images only when the last frame built them (else they show an older
// frame, or nothing).
class OnDemandUnit : public Unit {
 public:
  explicit OnDemandUnit(std::string_view product) : product_(product) {}
  Plan plan(const FramePlan& frame) const final {
    return {.records = frame.wanted.contains(product_), .takes = takes()};
  }
  void putHistory(Products& products, std::uint64_t frameIndex) final {
    built_ = false;
    putLastBuilt(products, frameIndex);
  }
  void record(const FrameState& frame) final {
    build(frame);
    built_ = true;
  }
  std::vector<ImageSet::Listed> listImages(std::uint64_t frameIndex) final {
    return built_ ? listBuilt(frameIndex) : std::vector<ImageSet::Listed>{};
  }

 protected:
  // What it takes when it records.
  virtual std::vector<std::string> takes() const { return {}; }
  // Its product as last built, for a pass that declares it but does not
  // read it this frame (bound only to fill the slot); none by default.
  virtual void putLastBuilt(Products& products, std::uint64_t frameIndex) {
    (void)products;
    (void)frameIndex;
  }
  // Records the unit and puts its product.
  virtual void build(const FrameState& frame) = 0;
  virtual std::vector<ImageSet::Listed> listBuilt(std::uint64_t frameIndex) { return Unit::listImages(frameIndex); }

 private:
  std::string product_;
  bool built_ = false;
};

}  // namespace bounce::gi

#include "gi/engine_images.h"

#include <algorithm>
#include <string>

#include "gpu/format.h"

namespace bounce::gi {
namespace {

struct InputFamily {
  Input input;
  const char* name;  // as in FrameInputs: "viewZ"
  std::span<const VkFormat> formats;
  bool optional;     // may be absent (image VK_NULL_HANDLE)
  bool renderSized;  // must cover the render size (the environment need not)
};

constexpr VkFormat kViewZ[] = {VK_FORMAT_R32_SFLOAT, VK_FORMAT_R16_SFLOAT};
constexpr VkFormat kNormalRoughness[] = {VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_A2B10G10R10_UNORM_PACK32};
constexpr VkFormat kBaseColorMetallic[] = {VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_R8G8B8A8_SRGB};
constexpr VkFormat kMotion[] = {VK_FORMAT_R16G16_SFLOAT, VK_FORMAT_R32G32_SFLOAT};
// B10G11R11_UFLOAT is not taken yet: given it, the composite's colours came
// out wrong on lavapipe and on an H100 alike (docs/known-issues.md).
constexpr VkFormat kRadiance[] = {VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_R32G32B32A32_SFLOAT};
constexpr VkFormat kMaterialId[] = {VK_FORMAT_R8_UINT, VK_FORMAT_R16_UINT, VK_FORMAT_R32_UINT};
constexpr VkFormat kEnvironment[] = {VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_R32G32B32A32_SFLOAT};

constexpr InputFamily kFamilies[] = {
    {Input::ViewZ, "viewZ", kViewZ, false, true},
    {Input::NormalRoughness, "normalRoughness", kNormalRoughness, false, true},
    {Input::BaseColorMetallic, "baseColorMetallic", kBaseColorMetallic, false, true},
    {Input::Motion, "motion", kMotion, false, true},
    {Input::Direct, "direct", kRadiance, false, true},
    {Input::Emissive, "emissive", kRadiance, true, true},
    {Input::Environment, "environment", kEnvironment, false, false},
    {Input::MaterialId, "materialId", kMaterialId, true, true},
};

const ImageRef& refOf(const FrameInputs& frame, Input input) {
  switch (input) {
    case Input::ViewZ:
      return frame.viewZ;
    case Input::NormalRoughness:
      return frame.normalRoughness;
    case Input::BaseColorMetallic:
      return frame.baseColorMetallic;
    case Input::Motion:
      return frame.motion;
    case Input::Direct:
      return frame.direct;
    case Input::Emissive:
      return frame.emissive;
    case Input::MaterialId:
      return frame.materialId;
    case Input::Environment:
    case Input::Count:
      break;
  }
  return frame.environment;
}

// Layouts a compute shader may sample a colour image in without a transition.
bool sampleableInPlace(VkImageLayout layout) {
  return layout == VK_IMAGE_LAYOUT_GENERAL || layout == VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL ||
         layout == VK_IMAGE_LAYOUT_READ_ONLY_OPTIMAL;
}

std::string size(std::uint32_t width, std::uint32_t height) {
  return std::to_string(width) + "x" + std::to_string(height);
}

}  // namespace

ImageRef libraryRef(const gpu::Image& image) {
  return {.image = image.handle(),
          .view = image.view(),
          .format = image.format(),
          .width = image.width(),
          .height = image.height(),
          .mipLevels = image.desc().mipLevels,
          .layout = VK_IMAGE_LAYOUT_GENERAL,
          .stage = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
          .access = VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT};
}

gpu::ExternalImage engineImage(const ImageRef& ref, std::string name) {
  gpu::ExternalImage external{.image = ref.image,
                              .view = ref.view,
                              .desc = {.name = std::move(name),
                                       .width = ref.width,
                                       .height = ref.height,
                                       .format = ref.format,
                                       .mipLevels = ref.mipLevels,
                                       .storage = false}};
  // As if the engine's last use were a write at its stage: the first
  // barrier then waits for it and makes it visible.
  external.state.writeStage = ref.stage;
  external.state.writeAccess = ref.access & gpu::kWriteAccessFlags;
  external.state.layout = ref.layout;
  return external;
}

std::string formatList(std::span<const VkFormat> formats) {
  std::string list;
  for (std::size_t i = 0; i < formats.size(); ++i)
    list += (i == 0 ? "" : i + 1 == formats.size() ? " or " : ", ") + gpu::formatName(formats[i]);
  return list;
}

void EngineImages::take(const FrameInputs& frame, std::span<const Noisy> noisy, InputState state,
                        bool needsEnvironment) {
  // Every input as one list of slots: the Inputs, then the noisy signals
  // (GiContext checks their size, which checkerboard mode halves).
  struct Slot {
    std::string_view name;
    const ImageRef* ref;
    std::span<const VkFormat> formats;
    bool optional, renderSized, environment;
  };
  std::vector<Slot> slots;
  for (const InputFamily& family : kFamilies)
    slots.push_back({family.name, &refOf(frame, family.input), family.formats, family.optional, family.renderSized,
                     family.input == Input::Environment});
  for (const Noisy& signal : noisy) slots.push_back({signal.name, &signal.ref, kRadiance, true, false, false});

  // Every check first: a throw leaves nothing half-taken.
  for (const Slot& slot : slots) {
    const ImageRef& ref = *slot.ref;
    const std::string input = "gi: frame input " + std::string(slot.name);
    if (ref.image == VK_NULL_HANDLE && (slot.optional || (slot.environment && !needsEnvironment))) continue;
    if (ref.image == VK_NULL_HANDLE || ref.view == VK_NULL_HANDLE)
      throw Error(input + " is missing (its " + (ref.image == VK_NULL_HANDLE ? "image" : "view") +
                  " is VK_NULL_HANDLE)" +
                  (slot.environment ? "; the branches read it (only a frame whose every enabled signal comes from "
                                      "the engine, FrameInputs::noisy, may leave it out)"
                                    : ""));
    if (std::find(slot.formats.begin(), slot.formats.end(), ref.format) == slot.formats.end())
      throw Error(input + " has the format " + gpu::formatName(ref.format) + "; " + std::string(slot.name) + " takes " +
                  formatList(slot.formats));
    if (ref.width == 0 || ref.height == 0 || ref.mipLevels == 0)
      throw Error(input + " is " + size(ref.width, ref.height) + " with " + std::to_string(ref.mipLevels) +
                  " mip levels; give its real size");
    if (slot.renderSized && (ref.width < frame.width || ref.height < frame.height))
      throw Error(input + " is " + size(ref.width, ref.height) + ", smaller than the render size " +
                  size(frame.width, frame.height));
    if (ref.layout == VK_IMAGE_LAYOUT_UNDEFINED || ref.layout == VK_IMAGE_LAYOUT_PREINITIALIZED)
      throw Error(input + " is in " + gpu::layoutName(ref.layout) +
                  ", whose contents are undefined to a reader; give the layout the engine's last use left it in");
  }
  if (frame.environmentSampler == VK_NULL_HANDLE && (needsEnvironment || frame.environment.image != VK_NULL_HANDLE))
    throw Error("gi: frame input environmentSampler is missing (EnvironmentPrefilter::sampler() is one)");
  for (std::size_t a = 0; a < slots.size(); ++a)
    for (std::size_t b = 0; b < a; ++b) {
      const ImageRef& ra = *slots[a].ref;
      const ImageRef& rb = *slots[b].ref;
      if (ra.image == VK_NULL_HANDLE || ra.image != rb.image) continue;
      if (ra.view != rb.view || ra.layout != rb.layout || ra.stage != rb.stage || ra.access != rb.access)
        throw Error("gi: frame inputs " + std::string(slots[b].name) + " and " + std::string(slots[a].name) +
                    " are the same VkImage but differ in view, layout, stage or access; one image is in one state");
    }

  state_ = state;
  given_.assign(slots.size(), ImageRef{});
  owned_.clear();
  owned_.resize(slots.size());
  wrapped_.assign(slots.size(), nullptr);
  for (std::size_t i = 0; i < slots.size(); ++i) {
    const ImageRef& ref = *slots[i].ref;
    given_[i] = ref;
    if (ref.image == VK_NULL_HANDLE) continue;
    const auto same = std::find_if(slots.begin(), slots.begin() + std::ptrdiff_t(i),
                                   [&](const Slot& earlier) { return earlier.ref->image == ref.image; });
    if (same != slots.begin() + std::ptrdiff_t(i)) {
      wrapped_[i] = wrapped_[std::size_t(same - slots.begin())];
      continue;
    }
    owned_[i] = std::make_unique<gpu::Image>(context_, engineImage(ref, "engine." + std::string(slots[i].name)));
    owned_[i]->setSampledLayout(state == InputState::LeaveGeneral ? VK_IMAGE_LAYOUT_GENERAL
                                : sampleableInPlace(ref.layout)   ? ref.layout
                                                                  : VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    wrapped_[i] = owned_[i].get();
  }
}

void EngineImages::handBack(gpu::Recorder& recorder) {
  for (std::size_t slot = 0; slot < owned_.size(); ++slot) {
    if (!owned_[slot]) continue;
    gpu::Image& image = *owned_[slot];
    const ImageRef& ref = given_[slot];
    if (state_ == InputState::Restore) {
      // The engine's next barrier starts from ref.stage: one from the
      // library's reads to that stage chains the two. Reads in that very
      // stage (compute) in an unchanged layout need none.
      const VkPipelineStageFlags2 stage = ref.stage == VK_PIPELINE_STAGE_2_NONE ? VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT
                                                                                : ref.stage;
      const bool covered = image.sync().layout == ref.layout &&
                           (stage & (VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT));
      if (!covered) recorder.handOver(image, ref.layout, stage, ref.access);
    }
    owned_[slot].reset();
    wrapped_[slot] = nullptr;
  }
  recorder.flush();
}

}  // namespace bounce::gi

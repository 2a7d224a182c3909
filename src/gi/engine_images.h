// The engine's images as the library takes them each frame. Each input has
// a family of formats it accepts; record() checks every input against its
// family and the render size before recording anything (gi::Error naming
// the input, what it takes and what it was given, formats and layouts by
// their Vulkan names), wraps each as a gpu::Image that starts from the state
// the engine says it is in (so the first barrier waits for the engine's
// last use and keeps its contents), and after the library's passes hands
// each back as ContextDesc::inputState asks.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "bounce/gi.h"
#include "gpu/context.h"
#include "gpu/recorder.h"
#include "gpu/resources.h"

namespace bounce::gi {

enum class Input : std::size_t {
  ViewZ,
  NormalRoughness,
  BaseColorMetallic,
  Motion,
  Direct,
  Emissive,
  Environment,
  MaterialId,  // optional
  Count
};

// "VK_FORMAT_R32_SFLOAT or VK_FORMAT_R16_SFLOAT"
std::string formatList(std::span<const VkFormat> formats);

// One of the engine's images, read by the library (not written), starting
// from the state `ref` gives.
gpu::ExternalImage engineImage(const ImageRef& ref, std::string name);

// An image of the library as the engine may use it (LibraryImage's
// contract): layout GENERAL, last written by a compute shader.
ImageRef libraryRef(const gpu::Image& image);

class EngineImages {
 public:
  explicit EngineImages(gpu::Context& context) : context_(context), wrapped_(std::size_t(Input::Count), nullptr) {}

  // An engine's noisy signal for the denoiser (FrameInputs::noisy), by the
  // name errors give it ("noisy[2] (ao)", or "noisyDiffuse" where the
  // engine used the older field). Its size GiContext checks (checkerboard
  // mode halves its width).
  struct Noisy {
    std::string_view name;  // outlives the frame (the context keeps its signals' names)
    ImageRef ref;           // image VK_NULL_HANDLE: not given
  };

  // Checks every input of `frame` and the noisy signals, one per signal
  // (throws Error naming the first bad one), and wraps them, reading in
  // place when the layout allows (LeaveGeneral: in GENERAL).
  // `needsEnvironment`: a branch runs this frame, so the environment and
  // its sampler must be given (else they are optional).
  void take(const FrameInputs& frame, std::span<const Noisy> noisy, InputState state, bool needsEnvironment);
  bool has(Input input) const { return wrapped_[std::size_t(input)] != nullptr; }
  gpu::Image& operator[](Input input) { return *wrapped_[std::size_t(input)]; }
  // Signal `signal`'s noisy image this frame; null when not given.
  gpu::Image* noisy(std::size_t signal) const {
    const std::size_t slot = std::size_t(Input::Count) + signal;
    return slot < wrapped_.size() ? wrapped_[slot] : nullptr;
  }

  // Records what hands the inputs back after the library's last read of
  // them (Restore: their layouts and the stage and access the engine gave;
  // LeaveGeneral: GENERAL, as the library left them), then forgets them.
  void handBack(gpu::Recorder& recorder);

 private:
  gpu::Context& context_;
  InputState state_ = InputState::Restore;
  // By slot: the Inputs, then the noisy signals.
  std::vector<ImageRef> given_;
  std::vector<std::unique_ptr<gpu::Image>> owned_;
  std::vector<gpu::Image*> wrapped_;  // shared when two inputs are one image
};

}  // namespace bounce::gi

// The library's units, registered in the order GiContext records them
// (src/gi/units.cpp: one entry each). Adding a branch is a folder with its
// unit and one entry there; the orchestrator names no unit. A test (or a
// tool) may register a unit of its own for the contexts it makes while it
// holds a UnitRegistration::Scoped.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "bounce/gi.h"
#include "bounce/gi_settings.h"
#include "gi/scene_bridge.h"
#include "gi/unit.h"
#include "gpu/context.h"
#include "gpu/resources.h"

namespace bounce::gi {

// What a unit is made for: known before anything is made, so that the
// context's memory can be estimated from it alone.
struct UnitSetup {
  Extent maxSize;
  const Settings& settings;             // a unit's maker hands its unit only its own section
  std::span<const SignalDesc> signals;  // by SignalId: the library's two, then ContextDesc::signals
  bool bridgeTraces;                    // a scene bridge that traces world rays is bound
  // Whether a unit registered after this one makes `product` (with these
  // settings): then this unit's own version of it is replaced for every
  // consumer, and need not be kept (the diffuse branch's filter when the
  // denoiser takes its signal).
  std::function<bool(std::string_view product)> madeLater;
};

// What a unit is made with on the device.
struct UnitResources {
  gpu::Context& context;
  gpu::MemoryArena& arena;
  const SceneBridgeBinding& scene;
  // Where the unit's transient images live (ImageSpec::transient): memory
  // every unit's transients share, as the units record one at a time.
  gpu::MemoryArena* transientPool = nullptr;
};

struct UnitRegistration {
  std::string name;
  // The products a unit made for `setup` would make (what madeLater
  // answers for the units before it); none when it is not made.
  std::function<std::vector<std::string>(const UnitSetup& setup)> produces;
  // The unit; null when these settings make none (the denoiser, off).
  std::function<std::unique_ptr<Unit>(const UnitSetup& setup, const UnitResources& resources)> make;
  // The bytes of device memory the unit made for `setup` holds of its own,
  // and of the transient pool (its transient images; none when null).
  std::function<std::uint64_t(const UnitSetup& setup)> memoryBytes;
  std::function<std::uint64_t(const UnitSetup& setup)> transientBytes;

  // Registers `unit` before the library's unit called `before` (at the end
  // where empty) for every context made while it lives.
  class Scoped {
   public:
    Scoped(UnitRegistration unit, std::string before);
    ~Scoped();
    Scoped(const Scoped&) = delete;
    Scoped& operator=(const Scoped&) = delete;

   private:
    std::string name_;
  };
};

// Whether a branch that makes `signal` keeps its own temporal filter: it is
// disabled (its result is the cleared filter image), or no unit after it
// makes the signal from the resolved one (the denoiser). Without, the
// filter's images are not made.
inline bool branchKeepsOwnFilter(const UnitSetup& setup, std::string_view signal, bool enabled) {
  return !enabled || !setup.madeLater(signal);
}

// The registration of a unit made from the device alone (its constructor
// takes the context, the arena and the maximum size), which always makes
// `products` and holds `memoryBytes(maxSize)`: the frame-level units.
template <typename U>
UnitRegistration sizedUnit(std::string name, std::vector<std::string> products,
                           std::uint64_t (*memoryBytes)(Extent maxSize)) {
  return {.name = std::move(name),
          .produces = [products = std::move(products)](const UnitSetup&) { return products; },
          .make = [](const UnitSetup& setup, const UnitResources& resources) -> std::unique_ptr<Unit> {
            return std::make_unique<U>(resources.context, resources.arena, setup.maxSize);
          },
          .memoryBytes = [memoryBytes](const UnitSetup& setup) { return memoryBytes(setup.maxSize); }};
}

// The units a context is made of, in recording order: the library's
// (src/gi/units.cpp), with any scoped ones in their places.
std::vector<UnitRegistration> registeredUnits();

}  // namespace bounce::gi

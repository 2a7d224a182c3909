// The library's units in recording order, and the products they route by
// name (gi/unit.h, gi/units.h). A new unit is one entry in libraryUnits().
#include "gi/units.h"

#include <algorithm>
#include <mutex>

#include "gi/cache/radiance_cache.h"
#include "gi/denoise/denoiser.h"
#include "gi/depth_pyramid.h"
#include "gi/diffuse/diffuse_branch.h"
#include "gi/frame_passes.h"
#include "gi/light_change.h"
#include "gi/screen_tiles.h"
#include "gi/specular/specular_branch.h"

namespace bounce::gi {

std::string product::noisy(std::string_view signal) { return std::string(signal) + ".noisy"; }

void Products::put(std::string_view name, gpu::Image& image) {
  Entry& entry = entries_[std::string(name)];
  entry = {&image, {}};
}

void Products::put(std::string_view name, std::vector<gpu::Bind> binds) {
  Entry& entry = entries_[std::string(name)];
  entry = {nullptr, std::move(binds)};
}

gpu::Image* Products::find(std::string_view name) const {
  const auto found = entries_.find(name);
  return found == entries_.end() ? nullptr : found->second.image;
}

gpu::Image& Products::image(std::string_view name) const {
  if (gpu::Image* image = find(name)) return *image;
  std::string made;
  for (const std::string& entry : names()) made += (made.empty() ? "" : ", ") + entry;
  throw Error("gi: no unit made the image product '" + std::string(name) +
              "' this frame (made: " + (made.empty() ? "none" : made) + ")");
}

std::span<const gpu::Bind> Products::binds(std::string_view name) const {
  const auto found = entries_.find(name);
  return found == entries_.end() ? std::span<const gpu::Bind>() : std::span<const gpu::Bind>(found->second.binds);
}

std::vector<std::string> Products::names() const {
  std::vector<std::string> list;
  for (const auto& [name, entry] : entries_) list.push_back(name);
  return list;
}

bool FramePlan::engineGives(std::string_view signal) const {
  for (std::size_t id = 0; id < signals.size(); ++id)
    if (signals[id].name == signal) return given[id];
  return false;
}

namespace {

// The library's units in the order they record; each one's products are
// made before the units after it take them.
std::vector<UnitRegistration> libraryUnits() {
  return {historyUnit(), depthPyramidUnit(), screenTilesUnit(),  lightChangeUnit(), cacheUnit(),
          diffuseUnit(), specularUnit(),     engineSignalUnit(), denoiseUnit(),     compositeUnit()};
}

struct ScopedEntry {
  UnitRegistration unit;
  std::string before;
};

std::mutex& scopedMutex() {
  static std::mutex mutex;
  return mutex;
}

std::vector<ScopedEntry>& scopedUnits() {
  static std::vector<ScopedEntry> units;
  return units;
}

}  // namespace

UnitRegistration::Scoped::Scoped(UnitRegistration unit, std::string before) : name_(unit.name) {
  const std::vector<UnitRegistration> library = libraryUnits();
  const auto named = [&](const UnitRegistration& entry) { return entry.name == unit.name; };
  if (unit.name.empty() || std::any_of(library.begin(), library.end(), named))
    throw Error("gi: a unit registered for a test or tool needs a name of its own; '" + unit.name + "' is taken");
  if (!before.empty() &&
      std::none_of(library.begin(), library.end(), [&](const UnitRegistration& entry) { return entry.name == before; }))
    throw Error("gi: unit '" + unit.name + "' is registered before '" + before + "', which is no unit of the library");
  const std::lock_guard lock(scopedMutex());
  scopedUnits().push_back({std::move(unit), std::move(before)});
}

UnitRegistration::Scoped::~Scoped() {
  const std::lock_guard lock(scopedMutex());
  std::vector<ScopedEntry>& units = scopedUnits();
  units.erase(
      std::remove_if(units.begin(), units.end(), [&](const ScopedEntry& entry) { return entry.unit.name == name_; }),
      units.end());
}

std::vector<UnitRegistration> registeredUnits() {
  std::vector<UnitRegistration> units = libraryUnits();
  const std::lock_guard lock(scopedMutex());
  for (const ScopedEntry& scoped : scopedUnits()) {
    const auto place = std::find_if(units.begin(), units.end(),
                                    [&](const UnitRegistration& entry) { return entry.name == scoped.before; });
    units.insert(place, scoped.unit);
  }
  return units;
}

}  // namespace bounce::gi

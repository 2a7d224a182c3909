// The library's units as they declare themselves (gi/unit_catalog.h).
#include "gi/unit_catalog.h"

#include <iterator>

#include "bounce/gi.h"
#include "gi/cache/radiance_cache.h"
#include "gi/denoise/denoiser.h"
#include "gi/depth_pyramid.h"
#include "gi/diffuse/diffuse_branch.h"
#include "gi/environment_prefilter.h"
#include "gi/frame_passes.h"
#include "gi/light_change.h"
#include "gi/screen_tiles.h"
#include "gi/specular/specular_branch.h"

namespace bounce::gi {
namespace {

std::vector<ImageSpec> listOf(std::span<const ImageSpec> table) { return {table.begin(), table.end()}; }

std::vector<DeclaredUnit> makeUnits() {
  // The run-time tables own the names their specs point to: kept for the
  // life of the catalog.
  static ImageTableBuilder denoiseTable, engineSignalTable;
  addDenoiseImages(denoiseTable, kLibrarySignals);
  std::vector<gpu::PassDesc> engineSignalPasses;
  for (const SignalDesc& signal : kLibrarySignals) {
    addEngineSignalImage(engineSignalTable, signal.name);
    engineSignalPasses.push_back(engineSignalPass(signal.name));
  }
  return {
      {"environment", environmentPrefilterPasses(), {}},
      {"history", {storeHistoryPass()}, listOf(historyImageTable())},
      {"depth_pyramid", DepthPyramid::passes(), {DepthPyramid::spec()}},
      {"screen_tiles", ScreenTiles::passes(), listOf(screenTilesImageTable())},
      {"light_change", LightChange::passes(), listOf(lightChangeImageTable())},
      {"cache", RadianceCache::passes(), listOf(cacheImageTable())},
      {"diffuse", DiffuseBranch::passes(), listOf(diffuseImageTable())},
      {"specular", SpecularBranch::passes(), listOf(specularImageTable())},
      {"engine_signal", std::move(engineSignalPasses), listOf(engineSignalTable.specs())},
      {"denoise", Denoiser::passes(kLibrarySignals), listOf(denoiseTable.specs())},
      {"composite", {compositePass()}, listOf(compositeImageTable())},
  };
}

}  // namespace

const std::vector<DeclaredUnit>& declaredUnits() {
  static const std::vector<DeclaredUnit> units = makeUnits();
  return units;
}

}  // namespace bounce::gi

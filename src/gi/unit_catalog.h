// Every unit of the library as it declares itself: the passes it may record
// (debug views included) and the images its tables make, in frame order:
// the environment's prefilter, then every registered unit (gi/units.h).
// What docs/passes.md lists is checked against it (tests/test_gi_settings.cpp,
// GiDocs.*), so the docs follow the code, not a reader's memory of it.
#pragma once

#include <string>
#include <vector>

#include "gi/image_table.h"
#include "gpu/pass.h"

namespace bounce::gi {

struct DeclaredUnit {
  std::string name;  // a registered unit's (gi/units.h), or "environment" (recorded by the engine, not by record())
  std::vector<gpu::PassDesc> passes;
  std::vector<ImageSpec> images;  // a pyramid's entry stands for its levels
};

// The units of a context without ContextDesc::signals (the denoiser and the
// engine-signal passes for the library's diffuse and specular signals).
const std::vector<DeclaredUnit>& declaredUnits();

}  // namespace bounce::gi

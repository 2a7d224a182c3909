// bounce brdf-viz: animated plots of the material model (seed 002's
// pictures): how reflectance, the sampling pdf and the samples themselves
// spread over the hemisphere as roughness sweeps 0..1 at a fixed view, and
// as the view sweeps to grazing at fixed roughness. Each frame is labelled
// with its parameters; the animations are written as APNG. The plots
// evaluate the same shared functions the shaders run
// (shaders/shared/brdf.glsl, sampling.glsl), on the CPU.
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/option_checks.h"
#include "app/plot.h"
#include "app/progress.h"
#include "io/colormap.h"
#include "io/image_io.h"
#include "shared/brdf.glsl"
#include "shared/color.glsl"
#include "shared/sampling.glsl"

namespace bounce::app {
namespace {

namespace fs = std::filesystem;

// The upper hemisphere (z up) in a unit disk, area-preserving (Lambert
// azimuthal): equal areas on the disk are equal solid angles, so a lobe's
// visual size is its real share of directions.
glm::vec3 diskToDirection(glm::vec2 p) {
  const float r2 = glm::dot(p, p);  // in [0, 1] inside the disk
  const float cosTheta = 1.0f - r2;
  const float scale = std::sqrt(std::max(0.0f, 2.0f - r2));
  return {p.x * scale, p.y * scale, cosTheta};
}

glm::vec2 directionToDisk(glm::vec3 d) {
  const float r = std::sqrt(std::max(0.0f, 1.0f - d.z));
  const float horizontal = std::sqrt(d.x * d.x + d.y * d.y);
  return horizontal > 0.0f ? glm::vec2(d.x, d.y) * (r / horizontal) : glm::vec2(0.0f);
}

struct Parameters {
  float roughness;
  float viewDegrees;
};

// Samples drawn in the third panel of each frame.
constexpr std::uint32_t kSampleCount = 384;

// One frame, three hemisphere plots side by side: f * cos for light
// directions, the pdf of sampleMaterial, and where its samples land
// (specular-lobe samples orange, diffuse ones green); the view direction and
// its mirror are marked, and the parameters written below.
io::ImageF drawFrame(const BrdfVizOptions& options, const Parameters& p) {
  const int size = int(options.size);
  const int margin = 12, titleHeight = 24, labelHeight = 60;
  Canvas canvas(3 * size + 4 * margin, size + 2 * margin + titleHeight + labelHeight, glm::vec3(0.08f));
  const float viewRadians = glm::radians(p.viewDegrees);
  const glm::vec3 n(0.0f, 0.0f, 1.0f);
  const glm::vec3 v(std::sin(viewRadians), 0.0f, std::cos(viewRadians));
  const glm::vec3 baseColor(options.baseColor[0], options.baseColor[1], options.baseColor[2]);
  const float radius = 0.5f * float(size);
  const int top = margin + titleHeight;
  const auto panelLeft = [&](int panel) { return margin + panel * (size + margin); };
  const auto centre = [&](int panel) { return glm::vec2(float(panelLeft(panel)) + radius, float(top) + radius); };
  // A fixed, saturating tone curve keeps frames comparable with each other.
  const auto plot = [&](int panel, const std::function<float(glm::vec3)>& value) {
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        const glm::vec2 disk((float(x) + 0.5f - radius) / radius, (radius - float(y) - 0.5f) / radius);
        if (glm::dot(disk, disk) > 1.0f) continue;
        const std::array<std::uint8_t, 3> colour = io::magma(1.0f - std::exp(-value(diskToDirection(disk))));
        canvas.set(panelLeft(panel) + x, top + y, glm::vec3(colour[0], colour[1], colour[2]) / 255.0f);
      }
  };
  plot(0, [&](glm::vec3 l) {
    return shared::luminance(shared::materialBrdfCosine(n, v, l, baseColor, options.metallic, p.roughness));
  });
  plot(1, [&](glm::vec3 l) { return shared::pdfMaterial(n, v, l, baseColor, options.metallic, p.roughness); });
  plot(2, [](glm::vec3) { return 0.0f; });
  const auto mark = [&](int panel, glm::vec3 d, float size, glm::vec3 colour) {
    const glm::vec2 q = directionToDisk(d);
    canvas.dot(centre(panel).x + q.x * radius, centre(panel).y - q.y * radius, size, colour);
  };
  const float specularProbability = shared::specularSelectionProbability(baseColor, options.metallic, v.z);
  for (std::uint32_t i = 0; i < kSampleCount; ++i) {
    const glm::vec2 u2 = shared::r2Point(i);
    const glm::vec3 u(u2.x, u2.y, shared::radicalInverseBase2(i));
    glm::vec3 l;
    float pdf;
    if (!shared::sampleMaterial(n, v, baseColor, options.metallic, p.roughness, u, l, pdf)) continue;
    mark(2, l, 1.5f, u.z < specularProbability ? glm::vec3(1.0f, 0.6f, 0.2f) : glm::vec3(0.4f, 0.9f, 0.4f));
  }
  for (int panel = 0; panel < 3; ++panel) {
    mark(panel, v, 4.0f, glm::vec3(0.3f, 0.8f, 1.0f));
    mark(panel, glm::reflect(-v, n), 4.0f, glm::vec3(1.0f));
  }
  canvas.text(panelLeft(0), margin, "f cos", glm::vec3(0.9f));
  canvas.text(panelLeft(1), margin, "pdf", glm::vec3(0.9f));
  canvas.text(panelLeft(2), margin, "samples", glm::vec3(0.9f));
  char line[64];
  const int labels = top + size + margin;
  std::snprintf(line, sizeof line, "roughness %.2f", double(p.roughness));
  canvas.text(margin, labels, line, glm::vec3(1.0f));
  std::snprintf(line, sizeof line, "view %.0f deg", double(p.viewDegrees));
  canvas.text(margin, labels + 20, line, glm::vec3(1.0f));
  std::snprintf(line, sizeof line, "metallic %.2f", double(options.metallic));
  canvas.text(margin, labels + 40, line, glm::vec3(0.6f));
  std::snprintf(line, sizeof line, "p spec %.2f", double(specularProbability));
  canvas.text(panelLeft(2), labels, line, glm::vec3(0.6f));
  return canvas.image();
}

void writeSweep(const BrdfVizOptions& options, const fs::path& path, const char* what,
                const std::function<Parameters(float)>& parametersAt) {
  std::vector<io::ImageF> frames;
  ProgressBar progress(what, options.frames);
  for (std::uint32_t f = 0; f < options.frames; ++f) {
    const float t = options.frames > 1 ? float(f) / float(options.frames - 1) : 0.0f;
    frames.push_back(drawFrame(options, parametersAt(t)));
    progress.update(f + 1);
  }
  progress.finish();
  io::writeApng(path, frames, options.fps);
  std::printf("wrote %s (%u frames)\n", path.c_str(), options.frames);
}

}  // namespace

CLI::App* addBrdfVizCommand(CLI::App& app, BrdfVizOptions& options) {
  CLI::App* command = app.add_subcommand(
      "brdf-viz",
      "Animated hemisphere plots of the material model (reflectance, pdf, samples; roughness and view sweeps) as APNG");
  command->add_option("--out", options.out, "Output directory (created if missing)");
  command->add_option("--size", options.size, "Plot diameter in pixels")->check(CLI::Range(32u, 2048u));
  command->add_option("--frames", options.frames, "Frames per sweep")->check(CLI::Range(1u, 1000u));
  command->add_option("--fps", options.fps, "Playback frames per second")->check(finiteRange(0.1, 100.0));
  command->add_option("--base-color", options.baseColor, "Linear base colour r,g,b")
      ->delimiter(',')
      ->expected(3)
      ->check(finiteRange(0.0, 1.0));
  command->add_option("--metallic", options.metallic, "Metallic in [0,1]")->check(finiteRange(0.0, 1.0));
  command->add_option("--roughness", options.roughness, "Roughness of the view sweep")->check(finiteRange(0.0, 1.0));
  command->add_option("--view", options.viewDegrees, "View angle from the normal of the roughness sweep, degrees")
      ->check(finiteRange(0.0, 89.0));
  return command;
}

int runBrdfViz(const BrdfVizOptions& options) {
  const fs::path dir = options.out;
  fs::create_directories(dir);
  writeSweep(options, dir / "roughness_sweep.png", "roughness sweep", [&](float t) {
    return Parameters{t, options.viewDegrees};
  });
  writeSweep(options, dir / "view_sweep.png", "view sweep", [&](float t) {
    return Parameters{options.roughness, 85.0f * t};
  });
  return 0;
}

}  // namespace bounce::app

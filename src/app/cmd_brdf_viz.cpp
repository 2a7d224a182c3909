// bounce brdf-viz: animated plots of the material model (the pictures of the
// microfacet write-up "A new shiny specular BRDF"): how reflectance, the sampling pdf and the samples themselves
// spread over the hemisphere as roughness sweeps 0..1 at a fixed view, and
// as the view sweeps to grazing at fixed roughness. Each frame is labelled
// with its parameters; the animations are written as APNG. The plots
// (plot/hemisphere_plot.h) evaluate the same shared functions the shaders
// run (shaders/shared/brdf.glsl, sampling.glsl), on the CPU.
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/option_checks.h"
#include "app/output_files.h"
#include "app/progress.h"
#include "io/image_io.h"
#include "plot/hemisphere_plot.h"

namespace bounce::app {
namespace {

namespace fs = std::filesystem;

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
  plot::Canvas canvas(3 * size + 4 * margin, size + 2 * margin + titleHeight + labelHeight, glm::vec3(0.08f));
  const plot::MaterialView material{glm::vec3(options.baseColor[0], options.baseColor[1], options.baseColor[2]),
                                    options.metallic, p.roughness, p.viewDegrees};
  const int top = margin + titleHeight;
  const auto panelLeft = [&](int panel) { return margin + panel * (size + margin); };
  const auto panel = [&](int index) { return plot::HemispherePanel{panelLeft(index), top, size}; };
  panel(0).fill(canvas, [&](glm::vec3 l) { return material.brdfCosine(l); });
  panel(1).fill(canvas, [&](glm::vec3 l) { return material.pdf(l); });
  panel(2).fill(canvas, [](glm::vec3) { return 0.0f; });
  for (std::uint32_t i = 0; i < kSampleCount; ++i) {
    glm::vec3 l;
    bool specular;
    if (material.sample(i, l, specular))
      panel(2).mark(canvas, l, 1.5f, specular ? plot::kSpecularSampleColour : plot::kDiffuseSampleColour);
  }
  for (int index = 0; index < 3; ++index) panel(index).markViewAndMirror(canvas, material);
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
  std::snprintf(line, sizeof line, "p spec %.2f", double(material.specularProbability()));
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
  addOverwriteFlag(*command, options.overwrite);
  return command;
}

int runBrdfViz(const BrdfVizOptions& options) {
  const fs::path dir = options.out;
  checkWritableDirectory(dir, "--out");
  OutputFolder(dir, "--out", options.overwrite).prepare({"roughness_sweep.png", "view_sweep.png"}, {}, {});
  writeSweep(options, dir / "roughness_sweep.png", "roughness sweep", [&](float t) {
    return Parameters{t, options.viewDegrees};
  });
  writeSweep(options, dir / "view_sweep.png", "view sweep", [&](float t) {
    return Parameters{options.roughness, 85.0f * t};
  });
  return 0;
}

}  // namespace bounce::app

// bounce ghosting --event light, --event sun and --event cut: how many
// frames the GI takes to settle after the light changes or its histories
// are dropped, seen from a still camera.
//
// light: at the event frame the --light-change material edits are made
// (FrameRenderer::setMaterial, the edit the viewer's material editor
// makes), e.g. a lamp's emission switched on or off. Every frame from the
// one before the event is compared with one path-traced reference of the
// new lighting (the camera and scene stand still, so one reference serves
// every frame): the indirect diffuse and specular means against the
// reference's, and their relMSE.
// sun: the same when the sun's azimuth turns by --sun-jump degrees at the
// event frame (FrameRenderer::setSun: its direct light, and a procedural
// sky baked again).
// cut: at the event frame the camera cuts to where it stands (every
// history is dropped; the radiance cache keeps what it knows); the means
// are compared with the frame before the cut, the value the GI had
// converged to, and with the reference.
// Both also measure a settled frame, --settle frames after the last
// measured one, so that how fast the GI gets there (to within 10 % and 5 %
// of its own settled mean) is told apart from where it gets (its bias
// against the reference).
#include "app/ghosting_convergence.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/option_checks.h"
#include "app/output_files.h"
#include "app/progress.h"
#include "app/reference_sampling.h"
#include "gpu/frame_loop.h"
#include "gpuio/gpu_images.h"
#include "io/image_io.h"
#include "metrics/image_metrics.h"
#include "plot/canvas.h"
#include "render/frame_memory.h"
#include "render/frame_renderer.h"
#include "render/gi_bridge.h"
#include "render/reference_renderer.h"
#include "scene/camera_path.h"

namespace bounce::app {
namespace {

namespace fs = std::filesystem;

enum Signal { kDiffuse = 0, kSpecular = 1, kSignalCount = 2 };
constexpr const char* kSignalNames[kSignalCount] = {"indirect_diffuse", "indirect_specular"};
constexpr const char* kSignalLabels[kSignalCount] = {"indirect diffuse", "indirect specular"};
// The tolerances the issue asks about: within 10 % and within 5 %.
constexpr std::array<double, 2> kTolerances = {0.10, 0.05};

struct Measured {
  std::uint32_t frame = 0;
  int after = 0;  // frames after the event (-1: the frame before it)
  std::array<double, kSignalCount> mean{};
  std::array<double, kSignalCount> relMse{};
  // The library's verdict that frame (gi.light_change): the share of the
  // direct light that changed, and the share of its history every temporal
  // history kept.
  double lightChanged = 0.0;
  double historyKept = 1.0;
};

// The first measured frame from which on every later one (the settled frame
// included) lies within `tolerance` of `target`: frames after the event, or
// nullopt where the last one still does not.
std::optional<int> settledWithin(const std::vector<Measured>& frames, const Measured& settled, int signal,
                                 double target, double tolerance) {
  if (!(target > 0.0)) return std::nullopt;
  const auto inside = [&](const Measured& m) { return std::abs(m.mean[signal] / target - 1.0) <= tolerance; };
  if (!inside(settled)) return std::nullopt;
  std::optional<int> from;
  for (const Measured& m : frames) {
    if (m.after < 0) continue;
    if (!inside(m))
      from.reset();
    else if (!from)
      from = m.after;
  }
  return from;
}

// "+k on", or "not by +last" (the last frame measured after the event);
// "undefined" where the value aimed at is not above 0 (a black reference):
// no share of it can be within a tolerance.
std::string afterText(std::optional<int> after, int last, double target) {
  if (!(target > 0.0)) return "undefined, it is 0";
  return after ? "+" + std::to_string(*after) + " on" : "not by +" + std::to_string(last);
}

// Each signal's mean over frames after the event, as a share of the
// reference (solid) and of the GI's own settled mean (dashed), with the
// 10 % and 5 % bands around 1.
io::ImageF convergencePlot(const std::string& title, const std::vector<Measured>& frames, const Measured& settled,
                           const std::array<double, kSignalCount>& reference,
                           const std::array<double, kSignalCount>& converged, const std::string& convergedName) {
  constexpr int kWidth = 760, kHeader = 56, kPanelHeight = 250, kLeft = 64, kRight = 24, kTop = 30, kBottom = 44;
  const glm::vec3 kReferenceColour(0.95f, 0.55f, 0.2f), kConvergedColour(0.35f, 0.7f, 0.95f);
  plot::Canvas canvas(kWidth, kHeader + kPanelHeight * kSignalCount, glm::vec3(0.08f));
  canvas.text(12, 10, title, glm::vec3(0.95f), 2);
  canvas.fillRect(12, 39, 18, 4, kReferenceColour);
  canvas.text(36, 36, "mean / reference", glm::vec3(0.9f), 1);
  plot::drawLine(canvas, {200.0f, 41.0f}, {218.0f, 41.0f}, kConvergedColour, 1.0f, 3.0f);
  const std::string convergedLegend = "mean / " + convergedName;
  canvas.text(224, 36, convergedLegend, glm::vec3(0.9f), 1);
  canvas.text(236 + plot::Canvas::textWidth(convergedLegend, 1), 36, "bands: 10 % and 5 %", glm::vec3(0.6f), 1);
  for (int s = 0; s < kSignalCount; ++s) {
    const int top = kHeader + s * kPanelHeight + kTop, bottom = kHeader + (s + 1) * kPanelHeight - kBottom;
    const int left = kLeft, right = kWidth - kRight;
    canvas.text(left, top - 20, kSignalLabels[s], glm::vec3(0.95f), 1);
    std::vector<double> toReference, toConverged;
    for (const Measured& m : frames) {
      toReference.push_back(reference[s] > 0.0 ? m.mean[s] / reference[s] : std::nan(""));
      toConverged.push_back(converged[s] > 0.0 ? m.mean[s] / converged[s] : std::nan(""));
    }
    double hi = 1.2;
    for (const std::vector<double>* line : {&toReference, &toConverged})
      for (double v : *line)
        if (std::isfinite(v)) hi = std::max(hi, v * 1.05);
    hi = std::min(hi, 10.0);
    const auto yOf = [&](double v) {
      return std::clamp(float(bottom) - float(v / hi) * float(bottom - top), float(top), float(bottom));
    };
    const std::size_t count = frames.size();
    const auto xOf = [&](std::size_t k) {
      return float(left) + (count > 1 ? float(k) / float(count - 1) : 0.5f) * float(right - left);
    };
    for (double tolerance : kTolerances)
      canvas.fillRect(left, int(yOf(1.0 + tolerance)), right - left, int(yOf(1.0 - tolerance) - yOf(1.0 + tolerance)),
                      glm::vec3(0.12f + float(0.1 - tolerance)));
    for (double v = 0.0; v <= hi + 1e-9; v += hi > 3.0 ? 1.0 : 0.2) {
      canvas.fillRect(left, int(yOf(v)), right - left, 1, glm::vec3(0.3f));
      char label[16];
      std::snprintf(label, sizeof label, "%.1f", v);
      canvas.text(left - 8 - plot::Canvas::textWidth(label, 1), int(yOf(v)) - 3, label, glm::vec3(0.8f), 1);
    }
    canvas.fillRect(left, top, 1, bottom - top + 1, glm::vec3(0.6f));
    canvas.fillRect(left, bottom, right - left + 1, 1, glm::vec3(0.6f));
    const std::size_t labelEvery = std::max<std::size_t>(1, count / 12);
    for (std::size_t k = 0; k < count; k += labelEvery) {
      const std::string label = frames[k].after < 0 ? "-1" : "+" + std::to_string(frames[k].after);
      canvas.fillRect(int(xOf(k)), bottom, 1, 5, glm::vec3(0.6f));
      canvas.text(int(xOf(k)) - plot::Canvas::textWidth(label, 1) / 2, bottom + 8, label, glm::vec3(0.8f), 1);
    }
    const std::string axis = "frames after the event (settled at frame " + std::to_string(settled.frame) + ")";
    canvas.text((left + right - plot::Canvas::textWidth(axis, 1)) / 2, bottom + 24, axis, glm::vec3(0.7f), 1);
    const auto series = [&](const std::vector<double>& values, glm::vec3 colour, bool dashed) {
      std::optional<glm::vec2> last;
      for (std::size_t k = 0; k < values.size(); ++k) {
        if (!std::isfinite(values[k])) {
          last.reset();
          continue;
        }
        const glm::vec2 p(xOf(k), yOf(values[k]));
        if (last) plot::drawLine(canvas, *last, p, colour, dashed ? 1.0f : 1.4f, dashed ? 3.0f : 0.0f);
        if (!dashed) canvas.dot(p.x, p.y, 3.0f, colour);
        last = p;
      }
    };
    series(toConverged, kConvergedColour, true);
    series(toReference, kReferenceColour, false);
  }
  return canvas.image();
}

// A mean over another (the reference's, the settled one): none where that
// is not above 0 (a black reference), where the ratio is undefined; a 0
// there would read as "the GI found none of the light".
std::optional<double> shareOf(double mean, double of) {
  if (!(of > 0.0)) return std::nullopt;
  return mean / of;
}

// As denoise writes a ratio over a black reference: null in the JSON,
// "undefined" in the table.
nlohmann::json shareJson(std::optional<double> share) {
  return share ? nlohmann::json(*share) : nlohmann::json(nullptr);
}

std::string shareCell(std::optional<double> share) {
  if (!share) return "undefined";
  char text[32];
  std::snprintf(text, sizeof text, "%.3f", *share);
  return text;
}

nlohmann::json measuredJson(const Measured& m, const std::array<double, kSignalCount>& reference,
                            const std::array<double, kSignalCount>& converged) {
  nlohmann::json json = {
      {"frame", m.frame}, {"after_event", m.after}, {"light_changed", m.lightChanged}, {"history_kept", m.historyKept}};
  for (int s = 0; s < kSignalCount; ++s)
    json[kSignalNames[s]] = {{"mean", m.mean[s]},
                             {"mean_over_reference", shareJson(shareOf(m.mean[s], reference[s]))},
                             {"mean_over_converged", shareJson(shareOf(m.mean[s], converged[s]))},
                             {"relmse", m.relMse[s]}};
  return json;
}

// The name of material NAME in a change NAME:KEY=VALUE (as applyMaterialChange reads it), "" if none.
std::string changedName(const std::string& change) {
  const std::size_t colon = change.rfind(':');
  return colon == std::string::npos ? std::string() : change.substr(0, colon);
}

// A --light-change naming no material of the scene is refused with the
// scene's lamps as the hint (its materials that emit, or that a --material
// edit gives an emission: cornell's lamp is 'cornell light', not 'light'),
// before applyMaterialChange's list of every material, which names them
// all without saying which of them is a light.
void checkLightChangeNames(const scene::Scene& scene, const SceneOptions& shot, const std::string& change) {
  const std::string name = changedName(change);
  if (name.empty()) return;  // malformed: applyMaterialChange says how
  for (const scene::Material& m : scene.materials)
    if (m.name == name) return;
  std::vector<std::string> lamps;
  for (const scene::Material& m : scene.materials) {
    bool emits = m.emissiveTexture >= 0 ||
                 (m.emissiveStrength > 0.0f && glm::any(glm::greaterThan(m.emissiveFactor, glm::vec3(0.0f))));
    for (const std::string& edit : shot.materials)
      emits = emits || (changedName(edit) == m.name && edit.find(":emission=") != std::string::npos);
    if (emits && std::find(lamps.begin(), lamps.end(), m.name) == lamps.end()) lamps.push_back(m.name);
  }
  if (lamps.empty()) return;  // no lamp to suggest: applyMaterialChange lists every material
  std::string names;
  for (const std::string& lamp : lamps) names += (names.empty() ? "'" : ", '") + lamp + "'";
  throw UsageError("--light-change " + change + ": the scene has no material '" + name + "'; its lamps " +
                   "(materials that emit light) are " + names + ", e.g. --light-change '" + lamps.front() +
                   ":emission=0,0,0' switches " + (lamps.size() == 1 ? "it" : "'" + lamps.front() + "'") + " off");
}

// The least angle the sun must move for --event sun to have something to
// measure: a hundredth of a degree (the sun's disc is half a degree
// across; a shadow 10 m long moves by under 2 mm).
constexpr double kLeastSunMoveDegrees = 0.01;

// --event sun measures the light following the sun as it turns: refused,
// as the command-line mistake it is, when the sun is below the horizon
// (no daylight to follow: the sky is dark from 12 degrees below) or when
// the turn does not move it (at the zenith the azimuth moves nothing, and
// a jump lost to float precision, 105 + 1e-30, is no turn), consistent
// with --sun-jump 0.
void checkSunMoves(const scene::Sun& before, const scene::Sun& after, const SceneOptions& shot,
                   const std::string& sceneName, float sunJump) {
  char elevation[32], jump[32], azimuths[64];
  std::snprintf(elevation, sizeof elevation, "%g", double(before.elevationDegrees));
  std::snprintf(jump, sizeof jump, "%g", double(sunJump));
  std::snprintf(azimuths, sizeof azimuths, "azimuth %g -> %g", double(before.azimuthDegrees),
                double(after.azimuthDegrees));
  const std::string whose = shot.sunElevation ? std::string("the sun (--sun-elevation ") + elevation + ")"
                                              : sceneName + "'s sun (elevation " + elevation + " degrees)";
  if (before.elevationDegrees < 0.0f)
    throw UsageError("--event sun: " + whose +
                     " is below the horizon: there is no daylight whose change to follow; give --sun-elevation "
                     "between 0 and 90");
  // The angle between the sun's directions before and after, in double:
  // a chord of 2 cos(elevation) sin(turn / 2) on the unit sphere.
  const double radians = std::numbers::pi / 180.0;
  const double turn = (double(after.azimuthDegrees) - double(before.azimuthDegrees)) * radians;
  const double chord = 2.0 * std::cos(double(before.elevationDegrees) * radians) * std::abs(std::sin(turn / 2.0));
  const double moved = 2.0 * std::asin(std::min(chord / 2.0, 1.0)) / radians;
  if (moved >= kLeastSunMoveDegrees) return;
  char movedText[32], least[32];
  std::snprintf(movedText, sizeof movedText, "%.3g", moved);
  std::snprintf(least, sizeof least, "%g", kLeastSunMoveDegrees);
  if (before.elevationDegrees > 89.0f)
    throw UsageError("--event sun: --sun-jump " + std::string(jump) + " moves the sun by only " + movedText +
                     " degrees (" + azimuths + "): " + whose +
                     " stands at the zenith, where turning its azimuth moves nothing; give --sun-elevation below "
                     "89");
  throw UsageError("--event sun: --sun-jump " + std::string(jump) + " moves the sun by " + movedText + " degrees (" +
                   azimuths + "): nothing changes; the sun must move by at least " + least +
                   " degrees: give a larger --sun-jump");
}

}  // namespace

int runConvergence(const GhostingOptions& options) {
  const bool light = options.event == "light", sun = options.event == "sun";
  if (options.events) throw UsageError("--events is for --event object, not --event " + options.event);
  if (options.turnDegrees) throw UsageError("--turn-degrees is for --event turn, not --event " + options.event);
  if (options.sunJump && !sun) throw UsageError("--sun-jump is for --event sun, not --event " + options.event);
  const float sunJump = options.sunJump.value_or(kDefaultSunJumpDegrees);
  if (sun && sunJump == 0.0f) throw UsageError("--sun-jump 0 does not move the sun: nothing changes");
  if (light && options.lightChanges.empty())
    throw UsageError(
        "--event light needs what changes at the event: --light-change NAME:emission=R,G,B (e.g. "
        "'cornell light:emission=0,0,0' switches cornell's lamp off)");
  if (!light && !options.lightChanges.empty())
    throw UsageError("--light-change is for --event light, not --event " + options.event);
  if (options.settle == 0)
    throw UsageError("--settle 0: --event " + options.event +
                     " measures how fast the GI reaches its settled value, "
                     "which needs the settled frame");

  const fs::path outDir = options.out;
  checkWritableDirectory(outDir, "--out");  // before the minutes of rendering, not after

  const SceneOptions& shot = options.view;
  const gi::Settings settings = giSettings(options.gi);
  const scene::Scene scene = loadScene(shot);
  // The lighting after the event: the scene's materials with the changes made.
  scene::Scene changed = scene;
  for (const std::string& change : options.lightChanges) {
    checkLightChangeNames(scene, shot, change);
    applyMaterialChange(changed, change, "--light-change");
  }
  std::vector<std::size_t> changedMaterials;
  for (std::size_t m = 0; m < scene.materials.size(); ++m)
    if (changed.materials[m].emissiveFactor != scene.materials[m].emissiveFactor ||
        changed.materials[m].baseColorFactor != scene.materials[m].baseColorFactor ||
        changed.materials[m].roughnessFactor != scene.materials[m].roughnessFactor ||
        changed.materials[m].metallicFactor != scene.materials[m].metallicFactor)
      changedMaterials.push_back(m);
  if (light && changedMaterials.empty())
    throw UsageError("--light-change: the changes leave every material as it was: nothing happens at the event");
  // The sun after the event: the renderer's (the scene's, or as the flags
  // set it) with its azimuth turned.
  const render::FrameRendererOptions rendererOptions = frameRendererOptions(scene, shot);
  scene::Sun movedSun = rendererOptions.environment.sun;
  if (sun) {
    if (!rendererOptions.environment.hasSun)
      throw UsageError("--event sun needs a sun, and " + scene.name +
                       " has none here (a scene without one, or "
                       "--no-sun): give it one with --sun-elevation");
    movedSun.azimuthDegrees += sunJump;
    checkSunMoves(rendererOptions.environment.sun, movedSun, shot, scene.name, sunJump);
  }

  OutputFolder(outDir, "--out", options.overwrite)
      .prepare({"ghosting.json", "ghosting.png"}, {}, inputFiles(scene, shot, &options.gi));

  // A still camera: the path's first pose, the scene at time 0, every frame.
  const std::unique_ptr<scene::CameraPath> path = cameraPathOf(scene, shot);
  const scene::CameraPose pose = checkedCameraFrames(*path, 0, 1, shot).front().pose;
  const std::uint32_t eventFrame = options.eventFrame;
  const std::uint32_t lastMeasured = eventFrame + options.after;
  const std::uint32_t settledFrame = lastMeasured + options.settle;

  GhostingRig rig(options, scene, rendererOptions, settings);
  const std::unique_ptr<gpu::Context>& context = rig.context;
  render::FrameRenderer& renderer = *rig.renderer;
  gpu::FrameLoop& loop = *rig.loop;
  render::GiBridge& gi = *rig.gi;
  char sunText[96];
  std::snprintf(sunText, sizeof sunText, "sun turned by %g degrees (azimuth %g -> %g)", double(sunJump),
                double(rendererOptions.environment.sun.azimuthDegrees), double(movedSun.azimuthDegrees));
  std::string what = light ? "light change (" : sun ? sunText : "camera cut in place";
  if (light)
    for (std::size_t i = 0; i < options.lightChanges.size(); ++i)
      what += (i ? ", " : "") + options.lightChanges[i] + (i + 1 == options.lightChanges.size() ? ")" : "");
  std::printf(
      "scene: %s; %s at frame %u, measured to frame %u and at frame %u, %ux%u, after %u warm-up frames; "
      "reference %u spp\n",
      scene.name.c_str(), what.c_str(), eventFrame, lastMeasured, settledFrame, shot.width, shot.height,
      options.gi.warmup, options.referenceSpp);

  const auto start = std::chrono::steady_clock::now();
  const auto record = [&](bool cut) { return rig.record({pose, 0.0f, cut}); };

  const auto measure = [&](std::uint32_t frame) {
    loop.finish();
    Measured m;
    m.frame = frame;
    m.after = int(frame) - int(eventFrame);
    const io::ImageF diffuse = gpuio::readbackImage(*context, gi.indirect(gi::kDiffuseSignal));
    const io::ImageF specular = gpuio::readbackImage(*context, gi.indirect(gi::kSpecularSignal));
    m.mean = {metrics::meanLuminance(diffuse), metrics::meanLuminance(specular)};
    for (const render::GiBridge::Named& image : gi.images())
      if (image.name == "gi.light_change") {
        const io::ImageF verdict = gpuio::readbackImage(*context, *image.image);
        m.lightChanged = verdict.pixels.at(0);
        m.historyKept = verdict.pixels.at(2);
      }
    return std::pair(m, std::array<io::ImageF, kSignalCount>{diffuse, specular});
  };

  {
    ProgressBar warming("gi warm-up", std::max(options.gi.warmup, 1u));
    for (std::uint32_t i = 0; i < options.gi.warmup; ++i) {
      record(i == 0);
      warming.update(i + 1);
    }
    warming.finish();
  }
  std::vector<Measured> frames;
  std::vector<std::array<io::ImageF, kSignalCount>> images;
  std::optional<Measured> settled;
  std::array<io::ImageF, kSignalCount> settledImages;
  std::uint64_t lastIndex = 0;
  ProgressBar progress("frames", settledFrame + 1);
  for (std::uint32_t frame = 0; frame <= settledFrame; ++frame) {
    if (frame == eventFrame && (light || sun)) {
      loop.finish();  // the upload and the sky's bake overwrite what frames in flight read
      for (std::size_t m : changedMaterials) renderer.setMaterial(m, changed.materials[m]);
      if (sun) renderer.setSun(movedSun);
    }
    const bool cut = (frame == 0 && options.gi.warmup == 0) || (frame == eventFrame && !light && !sun);
    lastIndex = record(cut);
    if (frame + 1 >= eventFrame && frame <= lastMeasured) {
      auto [m, made] = measure(frame);
      frames.push_back(m);
      images.push_back(std::move(made));
    } else if (frame == settledFrame) {
      auto [m, made] = measure(frame);
      settled = m;
      settledImages = std::move(made);
    }
    progress.update(frame + 1);
  }
  progress.finish();

  // One reference of the lighting after the event, traced from the
  // G-buffer of the last frame (the camera and scene stand still).
  render::ReferenceOptions tracing;
  tracing.seed = options.seed;
  tracing.maxBounces = options.maxBounces;
  gpu::FrameLoop sampling(*context, render::FrameRenderer::kFramesInFlight);
  render::ReferenceRenderer pathTracer(*context, renderer, scene, lastIndex, 0.0f, tracing);
  render::ReferenceImages traced = sampleReference(pathTracer, sampling, options.referenceSpp, "reference spp");
  const std::array<io::ImageF, kSignalCount> referenceImages = {std::move(traced.indirectDiffuse),
                                                                std::move(traced.indirectSpecular)};
  const std::array<double, kSignalCount> reference = {metrics::meanLuminance(referenceImages[kDiffuse]),
                                                      metrics::meanLuminance(referenceImages[kSpecular])};
  for (std::size_t i = 0; i < frames.size(); ++i)
    for (int s = 0; s < kSignalCount; ++s)
      frames[i].relMse[s] = metrics::valueErrors(referenceImages[s], images[i][s]).relMse;
  for (int s = 0; s < kSignalCount; ++s)
    settled->relMse[s] = metrics::valueErrors(referenceImages[s], settledImages[s]).relMse;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  // What the GI converges to: its own settled frame; for a cut also the
  // frame before it (the value it had converged to and lost).
  const std::array<double, kSignalCount> convergedMean = settled->mean;
  const std::string convergedName = "settled";
  std::printf("\n%s in %s at frame %u; reference of the lighting after it: %u spp; settled: frame %u\n", what.c_str(),
              scene.name.c_str(), eventFrame, options.referenceSpp, settledFrame);
  std::printf("%4s %6s %7s %5s", "+k", "frame", "changed", "kept");
  for (int s = 0; s < kSignalCount; ++s)
    std::printf(" | %-17s %9s %9s %9s", kSignalLabels[s], "/ ref", "/ settled", "relMSE");
  std::printf("\n");
  const auto row = [&](const Measured& m, const char* label) {
    std::printf("%4s %6u %7.3f %5.2f", label, m.frame, m.lightChanged, m.historyKept);
    for (int s = 0; s < kSignalCount; ++s)
      std::printf(" | %17.5g %9s %9s %9.4g", m.mean[s], shareCell(shareOf(m.mean[s], reference[s])).c_str(),
                  shareCell(shareOf(m.mean[s], convergedMean[s])).c_str(), m.relMse[s]);
    std::printf("\n");
  };
  for (const Measured& m : frames) row(m, m.after < 0 ? "-1" : ("+" + std::to_string(m.after)).c_str());
  row(*settled, "set.");
  std::printf("%4s %6s %7s %5s", "ref.", "", "", "");
  for (int s = 0; s < kSignalCount; ++s) std::printf(" | %17.5g %9s %9s %9s", reference[s], "", "", "");
  std::printf("\n");
  for (int s = 0; s < kSignalCount; ++s)
    if (!(reference[s] > 0.0))
      std::printf("(%s / ref is undefined: the reference's %s is black; null in ghosting.json)\n", kSignalLabels[s],
                  kSignalLabels[s]);

  nlohmann::json within = nlohmann::json::object();
  const int last = frames.back().after;
  for (int s = 0; s < kSignalCount; ++s) {
    nlohmann::json signal = nlohmann::json::object();
    std::printf("%s: the mean within", kSignalLabels[s]);
    for (double tolerance : kTolerances) {
      const std::optional<int> ofReference = settledWithin(frames, *settled, s, reference[s], tolerance);
      const std::optional<int> ofSettled = settledWithin(frames, *settled, s, convergedMean[s], tolerance);
      std::optional<int> ofBefore;
      if (!light && !sun) ofBefore = settledWithin(frames, *settled, s, frames.front().mean[s], tolerance);
      const std::string key = std::to_string(int(std::lround(tolerance * 100.0))) + "_percent";
      const auto value = [](std::optional<int> v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); };
      signal[key] = {{"of_reference", value(ofReference)}, {"of_settled", value(ofSettled)}};
      std::printf(" %.0f %% of its settled value: %s (of the reference: %s", tolerance * 100.0,
                  afterText(ofSettled, last, convergedMean[s]).c_str(),
                  afterText(ofReference, last, reference[s]).c_str());
      if (!light && !sun) {
        signal[key]["of_before_cut"] = value(ofBefore);
        std::printf("; of the value before the cut: %s", afterText(ofBefore, last, frames.front().mean[s]).c_str());
      }
      std::printf(")%s", tolerance == kTolerances.back() ? "\n" : ";");
    }
    within[kSignalNames[s]] = signal;
  }

  const std::string title = scene.name + ": " +
                            (light ? "light change"
                             : sun ? "sun turned"
                                   : "camera cut in place") +
                            (settings.denoise.enabled ? "" : ", denoiser off");
  io::writePng(outDir / "ghosting.png",
               convergencePlot(title, frames, *settled, reference, convergedMean, convergedName),
               io::PngEncoding::Linear);
  nlohmann::json framesJson = nlohmann::json::array();
  for (const Measured& m : frames) framesJson.push_back(measuredJson(m, reference, convergedMean));
  nlohmann::json referenceJson = nlohmann::json::object();
  for (int s = 0; s < kSignalCount; ++s) referenceJson[kSignalNames[s]] = reference[s];
  nlohmann::json meta = ghostingRunJson(options, settings, context->deviceInfo().name, seconds);
  meta.update({{"scene", scene.name},
               {"event", options.event},
               {"light_changes", options.lightChanges},
               {"sun_jump_degrees", sun ? nlohmann::json(sunJump) : nlohmann::json(nullptr)},
               {"event_frame", eventFrame},
               {"reference_mean", referenceJson},
               {"frames", framesJson},
               {"settled", measuredJson(*settled, reference, convergedMean)},
               {"within", within}});
  writeTextFile(outDir / "ghosting.json", meta.dump(2) + "\n");
  std::printf("\nwrote %s and %s (the means against frames after the event) in %.1f s\n",
              (outDir / "ghosting.json").c_str(), (outDir / "ghosting.png").filename().c_str(), seconds);
  return validationExitCode(*context);
}

}  // namespace bounce::app

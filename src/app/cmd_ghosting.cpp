// bounce ghosting: does the GI leave ghosts? Renders a sequence with the GI
// library through an event — a fast turn of the camera (in one frame), or a
// moving object uncovering what was behind it — and path-traces a reference
// of every frame measured. The pixels that show surfaces the frame before
// did not (worked out on the CPU from the G-buffers, metrics/uncovered.h)
// are followed through the frames after, and so are two regions to compare
// them with: the rest (every pixel whose surface has been on screen all
// along) and the nearby rest (those of the rest within a few pixels of the
// uncovered ones at the event, on surfaces that did not move: the same
// place in the same frames, only with history). Each frame's relMSE over each region, of the frame and of
// each indirect signal, against the frames since the event gives the curve
// issue 14 asks for: the uncovered pixels' error must come back to the
// level of the rest within a few frames. A moving object uncovers a thin
// strip a frame, so its event spans several frames, pooled by the frames
// since. --settle frames later every region is measured once more: the
// level the uncovered pixels' own error settles to.
//
// Writes a table per part, ghosting.json, the plot ghosting.png and the
// regions at the last event frame (regions.exr, a label image `bounce
// compare --regions` takes, and regions.png). docs/metrics.md describes it.
// The events that change the whole frame's light instead (--event light,
// --event cut) are ghosting_convergence.cpp's.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/ghosting_convergence.h"
#include "app/option_checks.h"
#include "app/output_files.h"
#include "app/progress.h"
#include "app/reference_sampling.h"
#include "gpu/frame_loop.h"
#include "gpu/transfer.h"
#include "gpuio/gpu_images.h"
#include "io/image_io.h"
#include "metrics/image_metrics.h"
#include "metrics/uncovered.h"
#include "plot/canvas.h"
#include "render/frame_memory.h"
#include "render/frame_renderer.h"
#include "render/gi_bridge.h"
#include "render/reference_renderer.h"
#include "scene/camera_path.h"

namespace bounce::app {
namespace {

namespace fs = std::filesystem;

// The images measured: the frame, and each indirect signal (demodulated) on its own.
enum Part { kFrame, kDiffuse, kSpecular, kPartCount };
constexpr const char* kPartKeys[kPartCount] = {"frame", "indirect_diffuse", "indirect_specular"};
constexpr const char* kPartLabels[kPartCount] = {"frame", "indirect diffuse", "indirect specular"};

// The regions compared.
enum Region { kUncovered, kNearby, kRest, kRegionCount };
constexpr const char* kRegionKeys[kRegionCount] = {"uncovered", "nearby", "rest"};

// Labels of regions.exr.
enum Label : std::uint8_t {
  kLabelBackground = 0,
  kLabelRest = 1,       // the rest, not near the uncovered pixels
  kLabelUncovered = 2,  // newly uncovered at one of the event frames
  kLabelNeither = 3,    // on screen for too short a time, or unclear
  kLabelNearby = 4,     // the rest near the uncovered pixels
};

// The built-in fast turn: the starting camera until the event, then, from
// the event frame on, the same camera turned about its up vector.
class TurnPath final : public scene::CameraPath {
 public:
  TurnPath(const scene::CameraPose& before, float degrees, float eventTime)
      : before_(before), after_(turned(before, degrees)), eventTime_(eventTime) {}
  scene::CameraPose pose(float time) const override { return time < eventTime_ ? before_ : after_; }
  float duration() const override { return eventTime_; }

  static scene::CameraPose turned(const scene::CameraPose& pose, float degrees) {
    const glm::mat4 turn = glm::rotate(glm::mat4(1.0f), glm::radians(degrees), glm::normalize(pose.up));
    scene::CameraPose result = pose;
    result.target = pose.position + glm::vec3(turn * glm::vec4(pose.target - pose.position, 0.0f));
    return result;
  }

 private:
  scene::CameraPose before_, after_;
  float eventTime_;
};

// What the numbers of a region are made of, summed over its pixels and
// over the frames pooled: relMSE is the mean of (t - r)^2 / (r^2 + eps)
// over every RGB value, the history the mean of the library's history
// length (alpha of its indirect diffuse, or of its indirect specular when
// the diffuse branch is off) over the pixels.
struct Pool {
  std::size_t pixels = 0;
  std::array<double, kPartCount> error{};
  double history = 0.0;
};

struct RegionNumbers {
  std::size_t pixels = 0;
  std::array<double, kPartCount> relMse{};
  double history = 0.0;
};

RegionNumbers numbersOf(const Pool& pool, const std::array<bool, kPartCount>& measured) {
  RegionNumbers numbers;
  numbers.pixels = pool.pixels;
  const double pixels = double(pool.pixels);
  for (int part = 0; part < kPartCount; ++part)
    numbers.relMse[part] = measured[part] && pool.pixels > 0 ? pool.error[part] / (3.0 * pixels) : std::nan("");
  numbers.history = pool.pixels > 0 ? pool.history / pixels : std::nan("");
  return numbers;
}

// One measured frame, pixel by pixel: each part's relative squared error
// summed over RGB, and the history length.
struct FrameErrors {
  std::array<std::vector<double>, kPartCount> error;
  std::vector<float> history;

  void addTo(Pool& pool, const std::vector<std::uint8_t>& mask) const {
    for (std::size_t p = 0; p < mask.size(); ++p) {
      if (!mask[p]) continue;
      ++pool.pixels;
      pool.history += history[p];
      for (int part = 0; part < kPartCount; ++part)
        if (!error[part].empty()) pool.error[part] += error[part][p];
    }
  }
};

FrameErrors frameErrors(const std::array<io::ImageF, kPartCount>& reference,
                        const std::array<io::ImageF, kPartCount>& gi, const std::array<bool, kPartCount>& measured) {
  FrameErrors errors;
  const std::size_t pixels = std::size_t(gi[kFrame].width) * std::size_t(gi[kFrame].height);
  for (int part = 0; part < kPartCount; ++part) {
    if (!measured[part]) continue;
    const io::ImageF &r = reference[part], &t = gi[part];
    std::vector<double>& error = errors.error[part];
    error.assign(pixels, 0.0);
    for (std::size_t p = 0; p < pixels; ++p)
      for (std::size_t c = 0; c < 3; ++c) {
        const double want = r.pixels[p * r.channelCount() + c], got = t.pixels[p * t.channelCount() + c];
        error[p] += (got - want) * (got - want) / (want * want + metrics::kRelMseEpsilon);
      }
  }
  const io::ImageF& history = measured[kDiffuse] ? gi[kDiffuse] : gi[kSpecular];
  errors.history.resize(pixels);
  for (std::size_t p = 0; p < pixels; ++p) errors.history[p] = history.pixels[p * history.channelCount() + 3];
  return errors;
}

// The numbers of one age: k frames after the pixels were uncovered, pooled
// over the event frames (one frame each), and the other regions in the
// same frames.
struct AgeNumbers {
  std::uint32_t age = 0;
  std::vector<std::uint32_t> frames;
  std::array<RegionNumbers, kRegionCount> regions;
};

// The pixels of `within` no farther than `radius` pixels (in x and in y)
// from a pixel of `seeds`.
std::vector<std::uint8_t> near(const std::vector<std::uint8_t>& seeds, const std::vector<std::uint8_t>& within,
                               int width, int height, int radius) {
  std::vector<std::uint8_t> rows(seeds.size(), 0), result(seeds.size(), 0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int dx = -radius; dx <= radius && !rows[std::size_t(y) * width + x]; ++dx) {
        const int sx = x + dx;
        if (sx >= 0 && sx < width && seeds[std::size_t(y) * width + sx]) rows[std::size_t(y) * width + x] = 1;
      }
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const std::size_t p = std::size_t(y) * width + x;
      if (!within[p]) continue;
      for (int dy = -radius; dy <= radius && !result[p]; ++dy) {
        const int sy = y + dy;
        if (sy >= 0 && sy < height && rows[std::size_t(sy) * width + x]) result[p] = 1;
      }
    }
  return result;
}

// The frame's surfaces as the G-buffer shows them (metrics::FrameSurfaces).
metrics::FrameSurfaces readSurfaces(gpu::Context& context, render::FrameRenderer& renderer, const scene::Scene& scene,
                                    const scene::CameraPose& pose, float time) {
  metrics::FrameSurfaces surfaces;
  surfaces.width = int(renderer.width());
  surfaces.height = int(renderer.height());
  surfaces.view =
      metrics::screenViewOf(pose.position, pose.target, pose.up, pose.fovYDegrees, surfaces.width, surfaces.height);
  const io::ImageF viewZ = gpuio::readbackImage(context, renderer.viewZ());
  const io::ImageF normal = gpuio::readbackImage(context, renderer.geometricNormal());
  const std::vector<std::uint8_t> idBytes = gpu::readbackImageBytes(context, renderer.ids());
  const std::size_t pixels = std::size_t(surfaces.width) * std::size_t(surfaces.height);
  if (idBytes.size() != pixels * sizeof(std::uint32_t))
    throw std::runtime_error("ghosting: the ids image read back has an unexpected size");
  surfaces.viewZ.resize(pixels);
  surfaces.normal.resize(pixels);
  surfaces.instance.resize(pixels);
  for (std::size_t p = 0; p < pixels; ++p) {
    surfaces.viewZ[p] = viewZ.pixels[p * viewZ.channelCount()];
    const float* n = &normal.pixels[p * normal.channelCount()];
    surfaces.normal[p] = glm::vec3(n[0], n[1], n[2]);
    std::uint32_t id = 0;
    std::memcpy(&id, &idBytes[p * sizeof id], sizeof id);
    // ids: instance << 16 | material (docs/conventions.md); all ones = background.
    surfaces.instance[p] = id == metrics::kNoInstance ? metrics::kNoInstance : id >> 16;
  }
  for (const scene::Instance& instance : scene::instancesAt(scene, time))
    surfaces.objectToWorld.push_back(instance.objectToWorld);
  return surfaces;
}

// The first age (frames since uncovered, 0 = the event frame) from which on
// the uncovered pixels' error stays within `within` times the level given
// per age (another region's, or their own once settled); none when the
// last age measured is still above.
std::optional<std::uint32_t> recoveredAfter(const std::vector<AgeNumbers>& ages, int part, double within,
                                            const std::function<double(const AgeNumbers&)>& level) {
  std::optional<std::uint32_t> from;
  for (std::size_t k = ages.size(); k-- > 0;) {
    const double u = ages[k].regions[kUncovered].relMse[part], l = level(ages[k]);
    if (!(std::isfinite(u) && std::isfinite(l) && u <= within * l)) break;
    from = std::uint32_t(k);
  }
  return from;
}

// When the uncovered pixels came within `within` times each level, per part.
struct Recovery {
  std::array<std::optional<std::uint32_t>, kPartCount> rest, nearby, ownSettled;
};

// --- the plot

const glm::vec3 kUncoveredColour(1.0f, 0.55f, 0.1f), kNearbyColour(0.35f, 0.85f, 0.75f), kRestColour(0.35f, 0.6f, 1.0f),
    kMarkColour(0.45f, 0.95f, 0.35f);

// "+3": frames after the event.
std::string afterLabel(std::size_t frames) {
  char text[24];
  std::snprintf(text, sizeof text, "+%zu", frames);
  return text;
}

std::string decadeLabel(int exponent) {
  switch (exponent) {
    case 0:
      return "1";
    case 1:
      return "10";
    case 2:
      return "100";
    case -1:
      return "0.1";
    case -2:
      return "0.01";
    case -3:
      return "0.001";
    default:
      return "1e" + std::to_string(exponent);
  }
}

struct Panel {
  std::string title;
  std::array<std::vector<double>, kRegionCount> lines;  // per age
  std::optional<std::uint32_t> recovered;               // within `within` x the rest from here on
  double settled = std::nan("");                        // the uncovered pixels' error once settled (NaN: not measured)
};

// Error against frames since uncovered, one panel per part, log scale: the
// uncovered pixels, the nearby rest, the rest, `within` times the rest
// (dotted), where the uncovered pixels come within that for good (green),
// and, when measured, the uncovered pixels' settled error (dashed).
io::ImageF errorPlot(const std::string& title, const std::vector<Panel>& panels, double within, const std::string& axis,
                     std::uint32_t settledFrame) {
  constexpr int kWidth = 760, kHeader = 72, kPanelHeight = 250, kLeft = 78, kRight = 24, kTop = 30, kBottom = 44;
  plot::Canvas canvas(kWidth, kHeader + kPanelHeight * int(panels.size()), glm::vec3(0.08f));
  canvas.text(12, 10, title, glm::vec3(0.95f), 2);
  // The legend, two rows.
  int x = 12, y = 36;
  const auto entry = [&](const std::string& text, const std::function<void(int, int)>& swatch) {
    swatch(x, y);
    canvas.text(x + 24, y, text, glm::vec3(0.9f), 1);
    x += 24 + plot::Canvas::textWidth(text, 1) + 20;
  };
  const auto solid = [&](glm::vec3 colour) {
    return [&canvas, colour](int sx, int sy) { canvas.fillRect(sx, sy + 3, 18, 4, colour); };
  };
  entry("newly uncovered", solid(kUncoveredColour));
  entry("nearby rest", solid(kNearbyColour));
  entry("rest", solid(kRestColour));
  char withinText[48];
  std::snprintf(withinText, sizeof withinText, "%.3g x the rest", within);
  entry(withinText, [&](int sx, int sy) {
    plot::drawLine(canvas, {float(sx), float(sy + 5)}, {float(sx + 18), float(sy + 5)}, kRestColour, 1.0f, 4.0f);
  });
  x = 12, y += 16;
  entry("uncovered within it from here on",
        [&](int sx, int sy) { canvas.fillRect(sx + 7, sy - 1, 3, 11, kMarkColour); });
  if (settledFrame > 0)
    entry("uncovered, settled (frame " + std::to_string(settledFrame) + ")", [&](int sx, int sy) {
      plot::drawLine(canvas, {float(sx), float(sy + 5)}, {float(sx + 18), float(sy + 5)}, kUncoveredColour, 1.0f, 3.0f);
    });

  for (std::size_t i = 0; i < panels.size(); ++i) {
    const Panel& panel = panels[i];
    const int top = kHeader + int(i) * kPanelHeight + kTop, bottom = kHeader + int(i + 1) * kPanelHeight - kBottom;
    const int left = kLeft, right = kWidth - kRight;
    canvas.text(left, top - 20, panel.title, glm::vec3(0.95f), 1);
    double lo = INFINITY, hi = 0.0;
    const auto include = [&](double v) {
      if (std::isfinite(v) && v > 0.0) lo = std::min(lo, v), hi = std::max(hi, v);
    };
    for (const std::vector<double>& line : panel.lines)
      for (double v : line) include(v);
    for (double v : panel.lines[kRest]) include(within * v);
    include(panel.settled);
    if (!(hi > 0.0)) {
      canvas.text(left + 10, (top + bottom) / 2, "no finite error to plot", glm::vec3(0.9f), 1);
      continue;
    }
    const int d0 = int(std::floor(std::log10(lo))), d1 = std::max(d0 + 1, int(std::ceil(std::log10(hi))));
    const auto yOf = [&](double v) {
      const double t = (std::log10(v) - d0) / double(d1 - d0);
      return std::clamp(float(bottom) - float(t) * float(bottom - top), float(top), float(bottom));
    };
    const std::size_t count = panel.lines[kUncovered].size();
    const auto xOf = [&](std::size_t k) {
      return float(left) + (count > 1 ? float(k) / float(count - 1) : 0.5f) * float(right - left);
    };
    // Grid: every decade labelled, 2x and 5x faint.
    for (int d = d0; d <= d1; ++d) {
      const float gy = yOf(std::pow(10.0, d));
      canvas.fillRect(left, int(gy), right - left, 1, glm::vec3(0.3f));
      const std::string label = decadeLabel(d);
      canvas.text(left - 8 - plot::Canvas::textWidth(label, 1), int(gy) - 3, label, glm::vec3(0.8f), 1);
      if (d < d1)
        for (double m : {2.0, 5.0})
          canvas.fillRect(left, int(yOf(m * std::pow(10.0, d))), right - left, 1, glm::vec3(0.17f));
    }
    canvas.fillRect(left, top, 1, bottom - top + 1, glm::vec3(0.6f));
    canvas.fillRect(left, bottom, right - left + 1, 1, glm::vec3(0.6f));
    for (std::size_t k = 0; k < count; ++k) {
      const std::string label = afterLabel(k);
      canvas.fillRect(int(xOf(k)), bottom, 1, 5, glm::vec3(0.6f));
      canvas.text(int(xOf(k)) - plot::Canvas::textWidth(label, 1) / 2, bottom + 8, label, glm::vec3(0.8f), 1);
    }
    canvas.text((left + right - plot::Canvas::textWidth(axis, 1)) / 2, bottom + 24, axis, glm::vec3(0.7f), 1);
    if (panel.recovered) {
      const int mx = int(xOf(*panel.recovered));
      canvas.fillRect(mx - 1, top, 3, bottom - top, kMarkColour);
      const std::string mark = afterLabel(*panel.recovered);
      canvas.text(std::min(mx + 6, right - plot::Canvas::textWidth(mark, 1)), top + 4, mark, kMarkColour, 1);
    }
    if (std::isfinite(panel.settled) && panel.settled > 0.0)
      plot::drawLine(canvas, {float(left), yOf(panel.settled)}, {float(right), yOf(panel.settled)}, kUncoveredColour,
                     1.0f, 3.0f);
    const auto series = [&](const std::vector<double>& values, double scale, glm::vec3 colour, bool dotted) {
      std::optional<glm::vec2> last;
      for (std::size_t k = 0; k < values.size(); ++k) {
        const double v = values[k] * scale;
        if (!(std::isfinite(v) && v > 0.0)) {
          last.reset();
          continue;
        }
        const glm::vec2 p(xOf(k), yOf(v));
        if (last) plot::drawLine(canvas, *last, p, colour, dotted ? 1.0f : 1.4f, dotted ? 5.0f : 0.0f);
        if (!dotted) canvas.dot(p.x, p.y, 3.5f, colour);
        last = p;
      }
    };
    series(panel.lines[kRest], within, kRestColour, true);
    series(panel.lines[kRest], 1.0, kRestColour, false);
    series(panel.lines[kNearby], 1.0, kNearbyColour, false);
    series(panel.lines[kUncovered], 1.0, kUncoveredColour, false);
  }
  return canvas.image();
}

// A frame with the regions over it: the uncovered pixels orange, the nearby
// rest tinted, pixels in no region darkened, the rest as they are.
io::ImageF regionsPicture(const io::ImageF& frame, const std::vector<std::uint8_t>& labels, float exposure) {
  io::ImageF picture = io::toDisplay(frame, io::PngEncoding::Tonemapped, exposure);
  for (std::size_t p = 0; p < labels.size(); ++p) {
    float* rgb = &picture.pixels[p * picture.channelCount()];
    if (labels[p] == kLabelUncovered)
      for (int c = 0; c < 3; ++c) rgb[c] = 0.3f * rgb[c] + 0.7f * kUncoveredColour[c];
    else if (labels[p] == kLabelNearby)
      for (int c = 0; c < 3; ++c) rgb[c] = 0.6f * rgb[c] + 0.4f * kNearbyColour[c];
    else if (labels[p] == kLabelNeither)
      for (int c = 0; c < 3; ++c) rgb[c] *= 0.3f;
  }
  return picture;
}

// --- the JSON and the table

nlohmann::json number(double value) { return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr); }

nlohmann::json poseJson(const scene::CameraPose& pose) {
  return {{"position", {pose.position.x, pose.position.y, pose.position.z}},
          {"target", {pose.target.x, pose.target.y, pose.target.z}},
          {"up", {pose.up.x, pose.up.y, pose.up.z}},
          {"fovY", pose.fovYDegrees}};
}

nlohmann::json regionJson(const RegionNumbers& region) {
  nlohmann::json relMse;
  for (int part = 0; part < kPartCount; ++part) relMse[kPartKeys[part]] = number(region.relMse[part]);
  return {{"pixels", region.pixels}, {"relmse", relMse}, {"history", number(region.history)}};
}

nlohmann::json ageJson(const AgeNumbers& a) {
  nlohmann::json json = {{"after_event", a.age}, {"frames", a.frames}};
  for (int r = 0; r < kRegionCount; ++r) json[kRegionKeys[r]] = regionJson(a.regions[r]);
  for (int r : {kRest, kNearby}) {
    nlohmann::json ratio;
    for (int part = 0; part < kPartCount; ++part)
      ratio[kPartKeys[part]] = number(a.regions[kUncovered].relMse[part] / a.regions[r].relMse[part]);
    json[std::string("ratio_to_") + kRegionKeys[r]] = ratio;
  }
  return json;
}

nlohmann::json partsJson(const std::array<std::optional<std::uint32_t>, kPartCount>& values) {
  nlohmann::json json;
  for (int part = 0; part < kPartCount; ++part)
    json[kPartKeys[part]] = values[part] ? nlohmann::json(*values[part]) : nlohmann::json(nullptr);
  return json;
}

std::string cell(double value) {
  if (!std::isfinite(value)) return "-";
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", value);
  return text;
}

// The uncovered pixels' relMSE over another region's: "-" where either was
// not measured, "undefined" where the other's is 0 (a black reference),
// which "-" used to hide.
std::string ratioCell(double uncovered, double other) {
  if (std::isfinite(uncovered) && std::isfinite(other) && other == 0.0) return "undefined";
  return cell(uncovered / other);
}

std::string framesCell(const std::vector<std::uint32_t>& frames) {
  if (frames.empty()) return "-";
  if (frames.size() == 1) return std::to_string(frames.front());
  return std::to_string(frames.front()) + "-" + std::to_string(frames.back());
}

// One table per part: the regions' relMSE per age and the uncovered
// pixels' ratios to the others; the first also the history lengths and sizes.
void printTables(const std::vector<AgeNumbers>& ages, const std::optional<AgeNumbers>& settled,
                 const std::array<bool, kPartCount>& measured, const Recovery& recovery, double within) {
  bool first = true;
  for (int part = 0; part < kPartCount; ++part) {
    if (!measured[part]) continue;
    std::printf("\n%s relMSE%s\n", kPartLabels[part],
                first ? "; history: the library's history length (frames), mean over the region" : "");
    std::printf("%4s %-9s %10s %10s %10s %10s %10s", "+k", "frames", "uncovered", "nearby", "rest", "u/nearby",
                "u/rest");
    if (first) std::printf(" | %-26s | %s", "history: uncovered nearby rest", "pixels: uncovered, nearby, rest");
    std::printf("\n");
    const auto row = [&](const AgeNumbers& a) {
      const auto& r = a.regions;
      std::printf("%4s %-9s %10s %10s %10s %10s %10s", afterLabel(a.age).c_str(), framesCell(a.frames).c_str(),
                  cell(r[kUncovered].relMse[part]).c_str(), cell(r[kNearby].relMse[part]).c_str(),
                  cell(r[kRest].relMse[part]).c_str(),
                  ratioCell(r[kUncovered].relMse[part], r[kNearby].relMse[part]).c_str(),
                  ratioCell(r[kUncovered].relMse[part], r[kRest].relMse[part]).c_str());
      if (first)
        std::printf(" | %8s %8s %8s | %zu, %zu, %zu", cell(r[kUncovered].history).c_str(),
                    cell(r[kNearby].history).c_str(), cell(r[kRest].history).c_str(), r[kUncovered].pixels,
                    r[kNearby].pixels, r[kRest].pixels);
      std::printf("\n");
    };
    for (const AgeNumbers& a : ages) row(a);
    if (settled) {
      std::printf("settled:\n");
      row(*settled);
    }
    const auto from = [&](const std::optional<std::uint32_t>& k) {
      return k ? "from " + afterLabel(*k) + " on" : "not by " + afterLabel(ages.size() - 1);
    };
    std::printf("the uncovered pixels within %.3g x the rest: %s; x the nearby rest: %s", within,
                from(recovery.rest[part]).c_str(), from(recovery.nearby[part]).c_str());
    if (settled) std::printf("; x their own settled error: %s", from(recovery.ownSettled[part]).c_str());
    std::printf("\n");
    first = false;
  }
}

}  // namespace

nlohmann::json ghostingRunJson(const GhostingOptions& options, const gi::Settings& settings, const std::string& device,
                               double seconds) {
  // The settings that differ from the library's defaults.
  nlohmann::json changed = nlohmann::json::object();
  const gi::Settings defaults;
  for (const gi::SettingInfo& info : gi::settingKeys()) {
    const std::string value = gi::settingValue(settings, info.key);
    if (value != gi::settingValue(defaults, info.key)) changed[info.key] = value;
  }
  return {{"warmup", options.gi.warmup},
          {"after", options.after},
          {"settle", options.settle},
          {"width", options.view.width},
          {"height", options.view.height},
          {"reference_spp", options.referenceSpp},
          {"seed", options.seed},
          {"max_bounces", options.maxBounces},
          {"gi", options.gi.mode},
          {"scene_bridge", options.gi.sceneBridge},
          {"settings", changed},
          {"device", device},
          {"seconds", seconds}};
}

GhostingRig::GhostingRig(const GhostingOptions& options, const scene::Scene& scene,
                         const render::FrameRendererOptions& rendererOptions, const gi::Settings& settings) {
  const SceneOptions& shot = options.view;
  context = openContext(options.gpu);
  std::printf("device: %s (%s)\n", context->deviceInfo().name.c_str(), context->deviceInfo().type.c_str());
  render::requireFrameMemory(*context, shot.width, shot.height,
                             std::pair(giContextDesc(shot.width, shot.height, options.gi), settings), true);
  pipeline = std::make_unique<render::FramePipeline>(
      *context, scene,
      render::FramePipelineDesc{.renderer = rendererOptions,
                                .gi = std::pair(giContextDesc(shot.width, shot.height, options.gi), settings)});
  renderer = &pipeline->renderer();
  loop = &pipeline->loop();
  gi = pipeline->gi();
  checkDeviceMemoryFits(*context, shot.width, shot.height);
}

std::uint64_t GhostingRig::record(const render::FrameView& view) { return pipeline->frame(view); }

CLI::App* addGhostingCommand(CLI::App& app, GhostingOptions& options) {
  CLI::App* command = app.add_subcommand(
      "ghosting",
      "Measure ghosting: the GI's error on the pixels a fast camera turn or a moving object newly uncovers, against "
      "the rest of the frame, frame by frame after the event (each frame against a path-traced reference): tables, "
      "ghosting.json, the plot ghosting.png and the regions (regions.exr, regions.png); with --event light or cut, "
      "how fast a still camera's indirect light settles after a light change or a cut");
  addGpuOptions(*command, options.gpu);
  addSceneOptions(*command, options.view);
  addGiOptions(*command, options.gi);
  command
      ->add_option("--event", options.event,
                   "turn: the camera holds, turns by --turn-degrees in one frame, and holds (default scene "
                   "sun-room; with --camera, that path's own motion at the event frame); object: a moving object "
                   "uncovers what was behind it (an animated scene; default sun-room-animated, the scene's camera); "
                   "light: a still camera, and at the event frame the --light-change edits are made (a lamp switched "
                   "on or off): the indirect means frame by frame against a reference of the new lighting, and the "
                   "frames until they are within 10 % and 5 % of it and of their settled value; sun: the same when "
                   "the sun's azimuth turns by --sun-jump degrees at the event frame; cut: a still camera "
                   "cuts in place at the event frame (every history dropped): the same, and against the value before "
                   "the cut")
      ->check(CLI::IsMember({"turn", "object", "light", "sun", "cut"}))
      ->capture_default_str();
  command->add_option("--light-change", options.lightChanges,
                      "With --event light: a material edit made at the event frame, NAME:KEY=VALUE as --material "
                      "(repeatable), e.g. 'cornell light:emission=0,0,0' switches cornell's lamp off");
  command
      ->add_option("--sun-jump", options.sunJump,
                   "With --event sun: degrees the sun's azimuth turns at the event frame (default 30)")
      ->check(finiteRange(-180.0, 180.0));
  command
      ->add_option("--event-frame", options.eventFrame,
                   "The (first) event frame; the frames before it, after --gi-warmup, lead up to it (at least "
                   "--after + 1 of them)")
      ->check(CLI::Range(1u, kMaxFrames / 2))
      ->capture_default_str();
  command
      ->add_option("--events", options.events,
                   "Event frames from --event-frame on, whose newly uncovered pixels are pooled by the frames since "
                   "(default: 1 for turn, 8 for object: a moving object uncovers a thin strip a frame)")
      ->check(CLI::Range(1u, 1000u));
  command
      ->add_option("--after", options.after,
                   "Frames measured after each event frame; the rest is what has been on screen since this many "
                   "frames before the event and stays")
      ->check(CLI::Range(1u, 1000u))
      ->capture_default_str();
  command
      ->add_option("--settle", options.settle,
                   "Then render this many frames more and measure every region once more: the level the uncovered "
                   "pixels' error settles to (0: do not)")
      ->check(CLI::Range(0u, 10000u))
      ->capture_default_str();
  command
      ->add_option("--nearby", options.nearby,
                   "The nearby rest: the rest within this many pixels of the uncovered ones at the event, on "
                   "surfaces that did not move (default: the height / 40, at least 2)")
      ->check(CLI::Range(1u, 4096u));
  command
      ->add_option("--turn-degrees", options.turnDegrees,
                   "The built-in turn's angle about the camera's up vector, degrees (positive: to the left; "
                   "default 20)")
      ->check(finiteRange(-180.0, 180.0));
  command->add_option("--reference-spp", options.referenceSpp, "Samples per pixel of each measured frame's reference")
      ->check(CLI::Range(1u, 1u << 24))
      ->capture_default_str();
  command->add_option("--seed", options.seed, "Random seed of the references")->capture_default_str();
  command->add_option("--max-bounces", options.maxBounces, "Surfaces a reference path may bounce off")
      ->check(CLI::Range(1u, 1000u))
      ->capture_default_str();
  command
      ->add_option("--within", options.within,
                   "The uncovered pixels have recovered once their relMSE stays at most this times the rest's")
      ->check(finiteRange(1.0, 1e6))
      ->capture_default_str();
  command->add_option("--out", options.out, "Output directory (created if missing)")->capture_default_str();
  addOverwriteFlag(*command, options.overwrite);
  command->add_option("--exposure", options.exposure, "Exposure multiplier of regions.png")->check(finitePositive());
  return command;
}

int runGhosting(const GhostingOptions& options) {
  // Every event measures the GI: without it a light change or a cut has no history to follow.
  if (!giEnabled(options.gi))
    throw UsageError("--gi off: bounce ghosting --event " + options.event +
                     " measures the GI, and there is none to measure: leave --gi out or name a branch (--gi diffuse)");
  if (options.event == "light" || options.event == "sun" || options.event == "cut") return runConvergence(options);
  const bool turn = options.event == "turn";
  if (options.eventFrame < options.after + 1)
    throw UsageError("--event-frame " + std::to_string(options.eventFrame) + " is too early for --after " +
                     std::to_string(options.after) + ": the rest is followed from frame event - after - 1, " +
                     "so the event frame must be at least " + std::to_string(options.after + 1));
  if (!options.lightChanges.empty())
    throw UsageError("--light-change is for --event light, not --event " + options.event);
  if (options.sunJump) throw UsageError("--sun-jump is for --event sun, not --event " + options.event);
  if (options.turnDegrees && !turn)
    throw UsageError("--turn-degrees is for --event turn, not --event " + options.event);
  if (options.turnDegrees && !options.view.camera.empty())
    throw UsageError("--turn-degrees turns the scene's camera; with --camera " + options.view.camera +
                     " the path itself must turn at --event-frame (leave one of them out)");
  const float turnDegrees = options.turnDegrees.value_or(kDefaultTurnDegrees);
  if (turn && options.view.camera.empty() && turnDegrees == 0.0f)
    throw UsageError("--turn-degrees 0 does not turn: nothing is uncovered");

  const fs::path outDir = options.out;
  checkWritableDirectory(outDir, "--out");  // before the minutes of rendering, not after

  SceneOptions shot = options.view;
  if (shot.scene.empty() && !turn) shot.scene = "sun-room-animated";
  const gi::Settings settings = giSettings(options.gi);
  const scene::Scene scene = loadScene(shot);
  if (!turn && !scene::isAnimated(scene))
    throw UsageError("--event object needs a moving object, and scene " + scene.name +
                     " has no animation (try sun-room-animated)");
  // No output may replace an input or a file no Bounce run wrote.
  OutputFolder(outDir, "--out", options.overwrite)
      .prepare({"ghosting.json", "ghosting.png", "regions.exr", "regions.png"}, {},
               inputFiles(scene, shot, &options.gi));

  // Frames: --gi-warmup at the first frame's camera and time, unseen; the
  // frames up to the event; the event frames, whose newly uncovered pixels
  // are each followed for `after` frames; then `settle` more, of which the
  // last is measured once more.
  const std::uint32_t firstEvent = options.eventFrame;
  const std::uint32_t events = options.events.value_or(turn ? 1u : 8u);
  const std::uint32_t lastEvent = firstEvent + events - 1;
  const std::uint32_t lastMeasured = lastEvent + options.after;
  const bool settles = options.settle > 0;
  const std::uint32_t settledFrame = lastMeasured + options.settle;
  const std::uint32_t frameCount = settledFrame + 1;
  const std::uint32_t firstFollowed = firstEvent - options.after - 1;  // the rest: on screen since this frame
  const int nearbyRadius = int(options.nearby.value_or(std::max(2u, (shot.height + 20) / 40)));
  const std::unique_ptr<scene::CameraPath> path =
      turn && shot.camera.empty()
          ? std::unique_ptr<scene::CameraPath>(std::make_unique<TurnPath>(
                scene::defaultCameraPath(scene)->pose(0.0f), turnDegrees, (float(firstEvent) - 0.5f) / shot.fps))
          : cameraPathOf(scene, shot);
  const std::vector<scene::CameraFrame> cameraFrames = checkedCameraFrames(*path, 0, frameCount, shot);
  for (std::uint32_t f = firstFollowed + 1; f < frameCount; ++f)
    if (cameraFrames[f].cut)
      throw std::runtime_error("--camera " + shot.camera + " cuts at frame " + std::to_string(f) +
                               ", inside the frames followed (" + std::to_string(firstFollowed) + " to " +
                               std::to_string(frameCount - 1) + "): a cut restarts every history, nothing is followed");
  const render::FrameRendererOptions rendererOptions = frameRendererOptions(scene, shot);

  GhostingRig rig(options, scene, rendererOptions, settings);
  const std::unique_ptr<gpu::Context>& context = rig.context;
  render::FrameRenderer& renderer = *rig.renderer;
  gpu::FrameLoop& loop = *rig.loop;
  render::GiBridge& gi = *rig.gi;
  const std::string eventName = turn ? (shot.camera.empty() ? "fast turn" : "camera path") : "moving object";
  const std::string eventFrames = events == 1
                                      ? "frame " + std::to_string(firstEvent)
                                      : "frames " + std::to_string(firstEvent) + "-" + std::to_string(lastEvent);
  std::printf(
      "scene: %s; %s, events at %s, measured to frame %u%s, %ux%u, after %u warm-up frames; references %u "
      "spp\n",
      scene.name.c_str(), eventName.c_str(), eventFrames.c_str(), lastMeasured,
      settles ? (" and at frame " + std::to_string(settledFrame)).c_str() : "", shot.width, shot.height,
      options.gi.warmup, options.referenceSpp);

  const std::array<bool, kPartCount> measuredParts = {true, settings.diffuse.enabled, settings.specular.enabled};
  render::ReferenceOptions tracing;
  tracing.seed = options.seed;
  tracing.maxBounces = options.maxBounces;
  std::unique_ptr<render::ReferenceRenderer> pathTracer;
  gpu::FrameLoop sampling(*context, render::FrameRenderer::kFramesInFlight);

  const auto start = std::chrono::steady_clock::now();
  if (options.gi.warmup > 0) {
    // As bounce render does: light needs frames to bounce and histories to fill.
    ProgressBar warming("gi warm-up", options.gi.warmup);
    for (std::uint32_t i = 0; i < options.gi.warmup; ++i) {
      rig.record({cameraFrames[0].pose, 0.0f, i == 0});
      warming.update(i + 1);
    }
    warming.finish();
  }

  std::optional<metrics::FrameSurfaces> previousSurfaces;
  std::vector<std::uint8_t> rest, labels;
  // [i]: the pixels uncovered at frame firstEvent + i, and the rest near them, followed.
  std::vector<std::vector<std::uint8_t>> uncovered(events), nearby(events);
  std::vector<std::size_t> uncoveredAtEvent(events, 0);
  std::vector<std::array<Pool, kRegionCount>> pools(options.after + 1);
  std::vector<std::vector<std::uint32_t>> poolFrames(options.after + 1);
  std::array<Pool, kRegionCount> settledPools;
  io::ImageF lastEventImage;
  ProgressBar progress("ghosting", frameCount);
  for (std::uint32_t frame = 0; frame < frameCount; ++frame) {
    const scene::CameraFrame& camera = cameraFrames[frame];
    const float time = float(frame) / shot.fps;
    // The path's first frame is a cut, unless the warm-up already stood there.
    const std::uint64_t index = rig.record({camera.pose, time, camera.cut && !(frame == 0 && options.gi.warmup > 0)});
    if (frame < firstFollowed) {
      progress.update(frame + 1);
      continue;
    }

    // Which surfaces this frame shows that the last one did not, and the
    // regions followed into this frame.
    loop.finish();
    metrics::FrameSurfaces surfaces = readSurfaces(*context, renderer, scene, camera.pose, time);
    if (!previousSurfaces) {
      rest.assign(surfaces.viewZ.size(), 0);
      for (std::size_t p = 0; p < rest.size(); ++p) rest[p] = surfaces.viewZ[p] > 0.0f ? 1 : 0;
    } else {
      const metrics::Reprojection step = metrics::reproject(*previousSurfaces, surfaces);
      rest = metrics::followRegion(rest, step);
      for (std::uint32_t i = 0; i < events && firstEvent + i < frame; ++i) {
        uncovered[i] = metrics::followRegion(uncovered[i], step);
        nearby[i] = metrics::followRegion(nearby[i], step);
      }
      if (frame >= firstEvent && frame <= lastEvent) {
        // The nearby rest lies on surfaces that stood still: a moving
        // object beside the strip it uncovers is no background to it.
        std::vector<std::uint8_t> still = rest;
        for (std::size_t p = 0; p < still.size(); ++p) {
          const std::uint32_t instance = surfaces.instance[p];
          if (still[p] && instance < surfaces.objectToWorld.size() &&
              instance < previousSurfaces->objectToWorld.size() &&
              surfaces.objectToWorld[instance] != previousSurfaces->objectToWorld[instance])
            still[p] = 0;
        }
        const std::uint32_t i = frame - firstEvent;
        uncovered[i].assign(step.history.size(), 0);
        for (std::size_t p = 0; p < step.history.size(); ++p)
          uncovered[i][p] = step.history[p] == metrics::PixelHistory::Uncovered ? 1 : 0;
        uncoveredAtEvent[i] = step.count(metrics::PixelHistory::Uncovered);
        nearby[i] = near(uncovered[i], still, surfaces.width, surfaces.height, nearbyRadius);
      }
      if (frame == lastEvent) {
        // The regions as they stand at the last event frame.
        labels.assign(step.history.size(), kLabelNeither);
        for (std::size_t p = 0; p < labels.size(); ++p) {
          bool isUncovered = false, isNearby = false;
          for (std::uint32_t i = 0; i < events; ++i) {
            isUncovered = isUncovered || uncovered[i][p];
            isNearby = isNearby || nearby[i][p];
          }
          labels[p] = step.history[p] == metrics::PixelHistory::Background ? kLabelBackground
                      : isUncovered                                        ? kLabelUncovered
                      : isNearby                                           ? kLabelNearby
                      : rest[p]                                            ? kLabelRest
                                                                           : kLabelNeither;
        }
        std::size_t total = 0;
        for (std::size_t n : uncoveredAtEvent) total += n;
        if (total == 0)
          throw std::runtime_error("nothing is newly uncovered at " + eventFrames + " (" + eventName + " in " +
                                   scene.name + "): choose another --event-frame" +
                                   (turn ? " or --turn-degrees" : " or more --events"));
      }
    }
    previousSurfaces = std::move(surfaces);

    const bool settledNow = settles && frame == settledFrame;
    if ((frame >= firstEvent && frame <= lastMeasured) || settledNow) {
      const std::array<io::ImageF, kPartCount> made = {
          gpuio::readbackImage(*context, gi.composite()),
          gpuio::readbackImage(*context, gi.indirect(gi::kDiffuseSignal)),
          gpuio::readbackImage(*context, gi.indirect(gi::kSpecularSignal))};
      // This frame's reference, traced from the same G-buffer.
      if (!pathTracer) {
        pathTracer = std::make_unique<render::ReferenceRenderer>(*context, renderer, scene, index, time, tracing);
      } else {
        pathTracer->restart(sampling.beginFrame(), index, time);
        sampling.endFrame();
      }
      render::ReferenceImages traced =
          sampleReference(*pathTracer, sampling, options.referenceSpp, "", "frame " + std::to_string(frame) + ": ");
      const std::array<io::ImageF, kPartCount> reference = {
          std::move(traced.radiance), std::move(traced.indirectDiffuse), std::move(traced.indirectSpecular)};
      const FrameErrors errors = frameErrors(reference, made, measuredParts);
      // Each event's pixels at their age this frame, beside the others in the same frame.
      for (std::uint32_t i = 0; i < events; ++i) {
        const std::uint32_t eventFrame = firstEvent + i;
        if (frame < eventFrame || frame - eventFrame > options.after) continue;
        std::array<Pool, kRegionCount>& pool = pools[frame - eventFrame];
        errors.addTo(pool[kUncovered], uncovered[i]);
        errors.addTo(pool[kNearby], nearby[i]);
        errors.addTo(pool[kRest], rest);
        poolFrames[frame - eventFrame].push_back(frame);
      }
      if (settledNow)
        for (std::uint32_t i = 0; i < events; ++i) {
          errors.addTo(settledPools[kUncovered], uncovered[i]);
          errors.addTo(settledPools[kNearby], nearby[i]);
          errors.addTo(settledPools[kRest], rest);
        }
      if (frame == lastEvent) lastEventImage = io::firstChannels(made[kFrame], 3);
    }
    progress.update(frame + 1);
  }
  loop.finish();
  progress.finish();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  const auto numbers = [&](const std::array<Pool, kRegionCount>& pool) {
    std::array<RegionNumbers, kRegionCount> regions;
    for (int r = 0; r < kRegionCount; ++r) regions[r] = numbersOf(pool[r], measuredParts);
    return regions;
  };
  std::vector<AgeNumbers> ages;
  for (std::uint32_t age = 0; age <= options.after; ++age) ages.push_back({age, poolFrames[age], numbers(pools[age])});
  std::optional<AgeNumbers> settled;
  if (settles) settled = AgeNumbers{settledFrame - lastEvent, {settledFrame}, numbers(settledPools)};
  Recovery recovery;
  for (int part = 0; part < kPartCount; ++part) {
    if (!measuredParts[part]) continue;
    const auto of = [&](int region) {
      return [region, part](const AgeNumbers& a) { return a.regions[region].relMse[part]; };
    };
    recovery.rest[part] = recoveredAfter(ages, part, options.within, of(kRest));
    recovery.nearby[part] = recoveredAfter(ages, part, options.within, of(kNearby));
    if (settled)
      recovery.ownSettled[part] = recoveredAfter(
          ages, part, options.within, [&](const AgeNumbers&) { return settled->regions[kUncovered].relMse[part]; });
  }

  std::size_t uncoveredTotal = 0;
  for (std::size_t n : uncoveredAtEvent) uncoveredTotal += n;
  const std::size_t restPixels = ages.front().regions[kRest].pixels / std::max<std::size_t>(1, events);
  std::printf(
      "\n%s in %s, %s: %zu pixels newly uncovered%s; the nearby rest: the rest within %d pixels of them; "
      "the rest: %zu pixels on screen since frame %u; references %u spp\n",
      eventName.c_str(), scene.name.c_str(), eventFrames.c_str(), uncoveredTotal, events > 1 ? " in all" : "",
      nearbyRadius, restPixels, firstFollowed, options.referenceSpp);
  printTables(ages, settled, measuredParts, recovery, options.within);

  // The plot, the regions, the JSON.
  std::vector<Panel> panels;
  for (int part = 0; part < kPartCount; ++part) {
    if (!measuredParts[part]) continue;
    Panel panel{std::string(kPartLabels[part]) + " relmse",
                {},
                recovery.rest[part],
                settled ? settled->regions[kUncovered].relMse[part] : std::nan("")};
    for (const AgeNumbers& a : ages)
      for (int r = 0; r < kRegionCount; ++r) panel.lines[r].push_back(a.regions[r].relMse[part]);
    panels.push_back(std::move(panel));
  }
  const std::string title = scene.name + ": " + eventName + (settings.denoise.enabled ? "" : ", denoiser off");
  const std::string axis = events == 1
                               ? "frames after the event (frame " + std::to_string(firstEvent) + "), relmse, log scale"
                               : "frames since uncovered (events at " + eventFrames + "), relmse, log scale";
  io::writePng(outDir / "ghosting.png", errorPlot(title, panels, options.within, axis, settles ? settledFrame : 0),
               io::PngEncoding::Linear);
  io::ImageF labelImage(int(shot.width), int(shot.height), {"Y"});
  for (std::size_t p = 0; p < labels.size(); ++p) labelImage.pixels[p] = float(labels[p]);
  io::writeExr(outDir / "regions.exr", labelImage);
  io::writePng(outDir / "regions.png", regionsPicture(lastEventImage, labels, options.exposure),
               io::PngEncoding::Linear);

  nlohmann::json agesJson = nlohmann::json::array();
  for (const AgeNumbers& a : ages) agesJson.push_back(ageJson(a));
  nlohmann::json eventsJson = nlohmann::json::array();
  for (std::uint32_t i = 0; i < events; ++i)
    eventsJson.push_back({{"frame", firstEvent + i}, {"uncovered_pixels", uncoveredAtEvent[i]}});
  nlohmann::json meta = ghostingRunJson(options, settings, context->deviceInfo().name, seconds);
  meta.update({{"scene", scene.name},
               {"event", options.event},
               {"camera", shot.camera.empty() ? (turn ? "built-in turn" : "default") : shot.camera},
               {"event_frame", firstEvent},
               {"events", eventsJson},
               {"nearby_radius", nearbyRadius},
               {"rest_since_frame", firstFollowed},
               {"fps", shot.fps},
               {"camera_before_event", poseJson(cameraFrames[firstEvent - 1].pose)},
               {"camera_at_event", poseJson(cameraFrames[firstEvent].pose)},
               {"within", options.within},
               {"recovered_after",
                {{"rest", partsJson(recovery.rest)},
                 {"nearby", partsJson(recovery.nearby)},
                 {"own_settled", settled ? partsJson(recovery.ownSettled) : nlohmann::json(nullptr)}}},
               {"ages", agesJson},
               {"settled", settled ? ageJson(*settled) : nlohmann::json(nullptr)}});
  if (turn && shot.camera.empty()) meta["turn_degrees"] = turnDegrees;
  writeTextFile(outDir / "ghosting.json", meta.dump(2) + "\n");
  std::printf("\nwrote %s, %s (error against frames since uncovered), %s and %s (the regions at frame %u) in %.1f s\n",
              (outDir / "ghosting.json").c_str(), (outDir / "ghosting.png").filename().c_str(),
              (outDir / "regions.exr").filename().c_str(), (outDir / "regions.png").filename().c_str(), lastEvent,
              seconds);
  return validationExitCode(*context);
}

}  // namespace bounce::app

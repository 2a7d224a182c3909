#include "app/images.h"

#include <algorithm>
#include <cstdio>
#include <map>

#include "gpu/transfer.h"
#include "gpuio/gpu_images.h"
#include "gpuio/stage_dump.h"
#include "io/colormap.h"
#include "plot/canvas.h"

namespace bounce::app {

namespace fs = std::filesystem;

const std::set<std::string>& knownAovs() {
  static const std::set<std::string> names = {"viewZ",           "normal", "geometric-normal", "albedo",    "emissive",
                                              "motion",          "ids",    "direct",           "roughness", "metallic",
                                              "indirect-diffuse", "indirect-specular"};
  return names;
}

std::string knownAovList() {
  std::string list;
  for (const std::string& name : knownAovs()) list += (list.empty() ? "" : ", ") + name;
  return list;
}

io::ImageF shrinkImage(const io::ImageF& image, int shrink) {
  const int width = image.width / shrink, height = image.height / shrink;
  io::ImageF small(width, height, {"R", "G", "B"});
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c) {
        float sum = 0.0f;
        for (int sy = 0; sy < shrink; ++sy)
          for (int sx = 0; sx < shrink; ++sx) sum += image.at(x * shrink + sx, y * shrink + sy, c);
        small.at(x, y, c) = sum / float(shrink * shrink);
      }
  return small;
}

io::ImageF contactSheet(const std::vector<io::ImageF>& cells, int columns, int shrink) {
  const int cellWidth = cells.front().width / shrink, cellHeight = cells.front().height / shrink;
  const int rows = (int(cells.size()) + columns - 1) / columns;
  io::ImageF sheet(cellWidth * columns, cellHeight * rows, {"R", "G", "B"});
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const io::ImageF small = shrinkImage(cells[i], shrink);
    const int ox = int(i) % columns * cellWidth, oy = int(i) / columns * cellHeight;
    for (int y = 0; y < cellHeight; ++y)
      for (int x = 0; x < cellWidth; ++x)
        for (int c = 0; c < 3; ++c) sheet.at(ox + x, oy + y, c) = small.at(x, y, c);
  }
  return sheet;
}

SheetLayout sheetLayout(int cellWidth, int cellHeight, std::size_t cellCount, int columns,
                        const std::vector<std::string>& labels) {
  SheetLayout layout;
  layout.cellWidth = cellWidth;
  layout.cellHeight = cellHeight;
  layout.columns = columns;
  layout.rows = int((cellCount + std::size_t(columns) - 1) / std::size_t(columns));
  if (labels.empty()) return layout;
  // Large text where the longest label fits its cell, else small.
  std::size_t longest = 0;
  for (const std::string& label : labels) longest = std::max(longest, label.size());
  layout.textScale = plot::Canvas::textWidth(std::string(longest, 'x'), 2) + 12 <= cellWidth ? 2 : 1;
  layout.strip = 7 * layout.textScale + 8;
  return layout;
}

void drawLabels(plot::Canvas& canvas, const SheetLayout& layout, const std::vector<std::string>& labels, int row,
                int top) {
  const std::size_t fits = std::size_t(std::max(0, layout.cellWidth - 8) / (6 * layout.textScale));
  for (int column = 0; column < layout.columns; ++column) {
    const std::size_t i = std::size_t(row) * std::size_t(layout.columns) + std::size_t(column);
    if (i < labels.size())
      canvas.text(layout.cellX(i) + 6, top + 4, labels[i].substr(0, fits), glm::vec3(0.95f), layout.textScale);
  }
}

io::ImageF labelledSheet(const std::vector<io::ImageF>& cells, const std::vector<std::string>& labels, int columns) {
  // Strips above the cells even when no cell has a label.
  const SheetLayout layout = sheetLayout(cells.front().width, cells.front().height, cells.size(), columns,
                                         labels.empty() ? std::vector<std::string>{""} : labels);
  plot::Canvas canvas(layout.width(), layout.height(), glm::vec3(kSheetBackground));
  for (int row = 0; row < layout.rows; ++row)
    drawLabels(canvas, layout, labels, row, row * (layout.cellHeight + layout.strip));
  for (std::size_t i = 0; i < cells.size(); ++i)
    for (int y = 0; y < layout.cellHeight; ++y)
      for (int x = 0; x < layout.cellWidth; ++x)
        canvas.set(layout.cellX(i) + x, layout.cellY(i) + y,
                   glm::vec3(cells[i].at(x, y, 0), cells[i].at(x, y, 1), cells[i].at(x, y, 2)));
  return canvas.image();
}

namespace {

// The alpha channel of an image, alone: where the G-buffer and the filter
// keep a scalar beside a colour (roughness, metallic, history length).
io::ImageF alphaChannel(const io::ImageF& image, const std::string& name) {
  io::ImageF channel(image.width, image.height, {name});
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) channel.at(x, y, 0) = image.at(x, y, 3);
  return channel;
}

}  // namespace

std::vector<fs::path> writeAovs(gpu::Context& context, render::FrameRenderer& renderer,
                                const std::vector<std::string>& wanted, const fs::path& dir, float exposure,
                                const std::vector<render::Aov>& extra) {
  fs::create_directories(dir);
  std::vector<fs::path> written;
  const bool all = std::find(wanted.begin(), wanted.end(), "all") != wanted.end();
  const auto wants = [&](const std::string& name) {
    return all || std::find(wanted.begin(), wanted.end(), name) != wanted.end();
  };
  std::vector<io::ImageF> cells;
  std::string order;
  std::map<std::string, std::size_t> cellOf;
  const auto write = [&](const std::string& name, const io::ImageF& pixels, gpu::Visualize how) {
    io::writeExr(written.emplace_back(dir / (name + ".exr")), pixels);
    const gpuio::VisualizedImage view = gpuio::visualize(pixels, how);
    io::writePng(written.emplace_back(dir / (name + ".png")), view.image, view.encoding, exposure);
    cellOf[name] = cells.size();
    cells.push_back(io::toDisplay(view.image, view.encoding, exposure));
    order += (order.empty() ? "" : ", ") + name;
  };
  std::vector<render::Aov> aovs = renderer.aovs();
  aovs.insert(aovs.end(), extra.begin(), extra.end());
  for (const render::Aov& aov : aovs) {
    // roughness and metallic live in the alpha channels of normal and albedo.
    const bool roughness = aov.name == "normal" && wants("roughness");
    const bool metallic = aov.name == "albedo" && wants("metallic");
    if (!wants(aov.name) && !roughness && !metallic) continue;
    const io::ImageF image = gpuio::readbackImage(context, *aov.image);
    if (wants(aov.name)) write(aov.name, image, aov.image->desc().visualize);
    if (roughness || metallic) {
      const std::string name = roughness ? "roughness" : "metallic";
      write(name, alphaChannel(image, name), gpu::Visualize::Raw);
    }
  }
  const int shrink = cells.front().width > 480 ? 2 : 1;
  io::writePng(written.emplace_back(dir / "sheet.png"), contactSheet(cells, 4, shrink), io::PngEncoding::Linear);
  std::printf("wrote AOVs to %s; sheet.png shows, left to right, top to bottom: %s\n", dir.c_str(), order.c_str());
  if (cellOf.count("normal") && cellOf.count("geometric-normal")) {
    io::writePng(written.emplace_back(dir / "normals.png"),
                 contactSheet({cells[cellOf["normal"]], cells[cellOf["geometric-normal"]]}, 2, 1),
                 io::PngEncoding::Linear);
    std::printf("wrote %s: shading normals (left) beside geometric normals (right)\n", (dir / "normals.png").c_str());
  }
  return written;
}

namespace {

// The captured image of `pass`'s `binding` in `frame`, or null.
const gpu::CapturedStage* findCapture(const std::vector<gpu::CapturedStage>& captures, std::uint64_t frame,
                                      const std::string& pass, const std::string& binding) {
  for (const gpu::CapturedStage& c : captures)
    if (c.frame == frame && c.pass == pass && c.binding == binding) return &c;
  return nullptr;
}

io::ImageF capturedPixels(const gpu::CapturedStage& capture) {
  return gpuio::texelsToImage(capture.image, capture.texels.data());
}

io::ImageF displayOf(const io::ImageF& pixels, gpu::Visualize how, float exposure) {
  const gpuio::VisualizedImage view = gpuio::visualize(pixels, how);
  return io::toDisplay(view.image, view.encoding, exposure);
}

// History length in magma on 0..cap: fixed, so sheets of different frames
// compare and a frame whose history was all reset shows black.
io::ImageF historyHeat(const io::ImageF& history, float cap) {
  io::ImageF out(history.width, history.height, {"R", "G", "B"});
  for (int y = 0; y < history.height; ++y)
    for (int x = 0; x < history.width; ++x) {
      const std::array<std::uint8_t, 3> rgb = io::magma(std::clamp(history.at(x, y, 0) / cap, 0.0f, 1.0f));
      for (int c = 0; c < 3; ++c) out.at(x, y, c) = float(rgb[c]) / 255.0f;
    }
  return io::toDisplay(out, io::PngEncoding::Linear, 1.0f);
}

}  // namespace

std::vector<fs::path> writeValidationSheets(const fs::path& dir, const std::vector<gpu::CapturedStage>& captures,
                                            float exposure, float historyCap) {
  std::vector<fs::path> written;
  for (const gpu::CapturedStage& filter : captures) {
    // The diffuse history: the branch's temporal filter, or the denoiser's
    // temporal accumulation of the diffuse signal when it runs in the
    // filter's place.
    const bool branchFilter = filter.pass == "gi.diffuse.temporal_filter" && filter.binding == "gOut_Filtered";
    const bool denoiser =
        filter.pass == "gi.denoise.temporal_accumulation" && filter.binding == "diffuse.gOut_Accumulated";
    if (!branchFilter && !denoiser) continue;
    const std::uint64_t frame = filter.frame;
    const gpu::CapturedStage* viewZ = findCapture(captures, frame, "render.gbuffer", "gOut_ViewZ");
    const gpu::CapturedStage* normal = findCapture(captures, frame, "render.gbuffer", "gOut_NormalRoughness");
    const gpu::CapturedStage* motion = findCapture(captures, frame, "render.gbuffer", "gOut_Motion");
    const gpu::CapturedStage* composite = findCapture(captures, frame, "gi.composite", "gOut_Composite");
    if (!viewZ || !normal || !motion || !composite) continue;
    const io::ImageF depth = capturedPixels(*viewZ);
    const io::ImageF filtered = capturedPixels(filter);
    const io::ImageF history = alphaChannel(filtered, "frames");
    io::ImageF failures = displayOf(capturedPixels(*composite), gpu::Visualize::Radiance, exposure);
    for (int y = 0; y < failures.height; ++y)
      for (int x = 0; x < failures.width; ++x)
        if (depth.at(x, y, 0) > 0.0f && history.at(x, y, 0) <= 1.0f) {
          failures.at(x, y, 0) = 1.0f;
          failures.at(x, y, 1) = 0.0f;
          failures.at(x, y, 2) = 0.0f;
        }
    const std::vector<io::ImageF> cells = {displayOf(depth, gpu::Visualize::Range, exposure),
                                           displayOf(capturedPixels(*normal), gpu::Visualize::Signed, exposure),
                                           displayOf(capturedPixels(*motion), gpu::Visualize::Motion, exposure),
                                           historyHeat(history, historyCap), failures};
    char name[48];
    std::snprintf(name, sizeof name, "frame%04llu.validation.png", static_cast<unsigned long long>(frame));
    written.push_back(dir / name);
    io::writePng(
        written.back(),
        labelledSheet(
            cells, {"viewZ", "normals", "motion vectors", "history length (frames)", "reprojection failures (red)"}, 3),
        io::PngEncoding::Linear);
  }
  return written;
}

}  // namespace bounce::app

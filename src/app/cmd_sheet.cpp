// bounce sheet: images side by side on one PNG, with labels: reference |
// test | test, scene after scene, as the docs show them. EXR/HDR inputs are
// tonemapped as render's PNGs are; PNG/JPEG inputs are shown as they are.
#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "app/commands.h"
#include "app/images.h"
#include "app/option_checks.h"
#include "app/output_files.h"
#include "io/image_io.h"
#include "plot/canvas.h"

namespace bounce::app {
namespace {

namespace fs = std::filesystem;

// The most images on one sheet and the largest shrink: enough for every
// scene of a comparison, and a sheet that still fits in a PNG.
constexpr std::size_t kMaxSheetImages = 256;
constexpr int kMaxShrink = 16;
// The widest and tallest sheet: what a PNG reader takes (io::readImage's limit).
constexpr int kMaxSheetSide = 65536;

// Besides ASCII letters and digits, what the sheet's 5x7 font
// (plot::Canvas::text) draws. Any other character would come out as a box,
// so a label holding one is refused rather than shown garbled.
constexpr std::string_view kLabelPunctuation = " .,:=()-/+%";

CLI::Validator drawableLabel() {
  return CLI::Validator(
      [](std::string& label) -> std::string {
        std::size_t position = 0;  // in characters: a UTF-8 sequence counts once
        for (std::size_t i = 0; i < label.size(); ++position) {
          std::size_t length = 1;  // the character's bytes: a lead byte and its continuation bytes
          while (i + length < label.size() && (static_cast<unsigned char>(label[i + length]) & 0xC0) == 0x80) ++length;
          const auto c = static_cast<unsigned char>(label[i]);
          if (length == 1 &&
              ((c < 0x80 && std::isalnum(c)) || kLabelPunctuation.find(char(c)) != std::string_view::npos)) {
            ++i;
            continue;
          }
          return "'" + label + "' has a character the sheet's font cannot draw ('" + label.substr(i, length) +
                 "' at position " + std::to_string(position + 1) +
                 "); a label holds letters, digits, space and . , : = ( ) - / + %";
        }
        return {};
      },
      "TEXT");
}

}  // namespace

CLI::App* addSheetCommand(CLI::App& app, SheetOptions& options) {
  CLI::App* command = app.add_subcommand(
      "sheet", "Lay images side by side on one PNG, left to right and top to bottom, with a label above each "
               "of the first row (e.g. reference | screen-only | hybrid, one scene per row)");
  command->add_option("images", options.images, "Images (EXR, HDR, PNG or JPEG), all the same size")->required();
  command->add_option("--out", options.out, "The PNG to write; never over an input")
      ->required()
      ->check(outputExtension(".png", "PNG"));
  command->add_option("--columns", options.columns, "Images per row (default: all on one row, at most 8)")
      ->check(CLI::Range(1, 64));
  command
      ->add_option("--label", options.labels,
                   "A label for the next cell of the first row (repeat it; letters, shown lower-case, digits, "
                   "space and . , : = ( ) - / + %)")
      // One value each: `--label a img1 img2` must not take the images for labels.
      ->allow_extra_args(false)
      ->check(drawableLabel());
  command->add_option("--shrink", options.shrink, "Shrink every image this many times (box filter; default 1)")
      ->check(CLI::Range(1, kMaxShrink));
  command->add_option("--exposure", options.exposure, "Exposure of EXR/HDR inputs before the tonemap (default 1)")
      ->check(finiteRange(1e-6, 1e6));
  return command;
}

int runSheet(const SheetOptions& options) {
  if (options.images.size() > kMaxSheetImages)
    throw UsageError("sheet: " + std::to_string(options.images.size()) + " images; at most " +
                             std::to_string(kMaxSheetImages) + " fit on one sheet");
  const int columns = options.columns ? *options.columns : int(std::min<std::size_t>(options.images.size(), 8));
  if (options.labels.size() > std::size_t(columns))
    throw UsageError("sheet: " + std::to_string(options.labels.size()) + " labels for " +
                             std::to_string(columns) + " columns (labels name the first row's cells)");
  const fs::path out = options.out;
  std::vector<fs::path> inputs(options.images.begin(), options.images.end());
  refuseToOverwriteInputs(out, "--out", inputs);
  checkWritableFile(out, "--out");

  // Every header first: a size that differs, or a sheet too large to make,
  // is refused before a pixel is decoded.
  const auto sizeText = [](int w, int h) { return std::to_string(w) + "x" + std::to_string(h); };
  std::vector<io::ImageInfo> infos;
  for (const fs::path& path : inputs) {
    const io::ImageInfo info = io::readImageInfo(path);
    if (!infos.empty() && (info.width != infos.front().width || info.height != infos.front().height))
      throw std::runtime_error(path.string() + ": " + sizeText(info.width, info.height) +
                               " differs from the size of the first image, " + inputs.front().string() + " (" +
                               sizeText(infos.front().width, infos.front().height) + ")");
    if (info.width < options.shrink || info.height < options.shrink)
      throw std::runtime_error(path.string() + ": " + sizeText(info.width, info.height) + " is smaller than --shrink " +
                               std::to_string(options.shrink));
    infos.push_back(info);
  }
  std::vector<std::string> labels;
  for (std::string label : options.labels) {
    std::transform(label.begin(), label.end(), label.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    labels.push_back(label);
  }
  // Cells of the later rows get no label: a blank one keeps the layout.
  while (!labels.empty() && labels.size() < inputs.size()) labels.push_back("");
  const int shrink = options.shrink;
  const SheetLayout layout =
      sheetLayout(infos.front().width / shrink, infos.front().height / shrink, inputs.size(), columns, labels);
  const std::string what = "a sheet of " + (inputs.size() == 1 ? std::string("one") : std::to_string(inputs.size())) +
                           " " + sizeText(infos.front().width, infos.front().height) +
                           (inputs.size() == 1 ? " image" : " images");
  if (layout.width() > kMaxSheetSide || layout.height() > kMaxSheetSide)
    throw std::runtime_error(inputs.front().string() + ": " + what + " would be " +
                             sizeText(layout.width(), layout.height()) + ", more than " +
                             std::to_string(kMaxSheetSide) + " pixels a side (try --shrink or --columns)");

  // The sheet is made as the bytes it is written as: beside them, one input
  // at a time and a label strip, then the PNG encoder's buffers.
  const std::uint64_t sheetPixels = std::uint64_t(layout.width()) * std::uint64_t(layout.height());
  std::uint64_t largestRead = 0;
  for (const io::ImageInfo& info : infos) largestRead = std::max(largestRead, info.readBytes());
  const std::uint64_t strip = std::uint64_t(layout.width()) * std::uint64_t(layout.strip) * 3 * sizeof(float);
  io::refuseOverMemoryLimit(inputs.front(),
                            3 * sheetPixels + std::max(largestRead + strip, io::pngWriteBytes(sheetPixels, 3)), what);

  const int width = layout.width();
  std::vector<std::uint8_t> sheet(3 * sheetPixels, labels.empty() ? 0 : io::displayByte(kSheetBackground));
  const auto put = [&](int x, int y, glm::vec3 colour) {
    std::uint8_t* pixel = sheet.data() + 3 * (std::size_t(y) * std::size_t(width) + std::size_t(x));
    for (int c = 0; c < 3; ++c) pixel[c] = io::displayByte(colour[c]);
  };
  if (!labels.empty()) {
    for (int row = 0; row < layout.rows; ++row) {
      plot::Canvas canvas(width, layout.strip, glm::vec3(kSheetBackground));
      drawLabels(canvas, layout, labels, row, 0);
      const int top = row * (layout.cellHeight + layout.strip);
      for (int y = 0; y < layout.strip; ++y)
        for (int x = 0; x < width; ++x)
          put(x, top + y,
              glm::vec3(canvas.image().at(x, y, 0), canvas.image().at(x, y, 1), canvas.image().at(x, y, 2)));
    }
  }
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const io::ImageF image = io::readImage(inputs[i]);
    const io::PngEncoding encoding = io::holdsRadiance(inputs[i]) ? io::PngEncoding::Tonemapped : io::PngEncoding::Srgb;
    const std::size_t channelCount = image.channelCount();
    const auto display = [&](int x, int y) {
      return io::displayColour(
          &image.pixels[(std::size_t(y) * std::size_t(image.width) + std::size_t(x)) * channelCount], channelCount,
          encoding, options.exposure);
    };
    // A shrunk cell averages each block of display colours, channel by
    // channel in the block's row order, as shrinkImage does.
    std::vector<glm::vec3> block(std::size_t(shrink) * std::size_t(shrink));
    for (int y = 0; y < layout.cellHeight; ++y)
      for (int x = 0; x < layout.cellWidth; ++x) {
        for (int sy = 0; sy < shrink; ++sy)
          for (int sx = 0; sx < shrink; ++sx)
            block[std::size_t(sy * shrink + sx)] = display(x * shrink + sx, y * shrink + sy);
        glm::vec3 colour = block[0];
        if (shrink > 1) {
          for (int c = 0; c < 3; ++c) {
            float sum = 0.0f;
            for (const glm::vec3& value : block) sum += value[c];
            colour[c] = sum / float(shrink * shrink);
          }
        }
        put(layout.cellX(i) + x, layout.cellY(i) + y, colour);
      }
  }
  io::writePngBytes(out, layout.width(), layout.height(), 3, sheet);
  std::printf("wrote %s (%dx%d: %zu images, %d to a row)\n", out.c_str(), layout.width(), layout.height(),
              inputs.size(), columns);
  return 0;
}

}  // namespace bounce::app

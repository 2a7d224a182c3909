// bounce sheet: images side by side on one PNG, with labels: reference |
// test | test, scene after scene, as the docs show them. EXR/HDR inputs are
// tonemapped as render's PNGs are; PNG/JPEG inputs are shown as they are.
#include <algorithm>
#include <cctype>
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

namespace bounce::app {
namespace {

namespace fs = std::filesystem;

// The most images on one sheet and the largest shrink: enough for every
// scene of a comparison, and a sheet that still fits in a PNG.
constexpr std::size_t kMaxSheetImages = 256;
constexpr int kMaxShrink = 16;

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
  command->add_option("--out", options.out, "The PNG to write; never over an input")->required();
  command->add_option("--columns", options.columns, "Images per row (default: all on one row, at most 8)")
      ->check(CLI::Range(1, 64));
  command
      ->add_option("--label", options.labels,
                   "A label for the next cell of the first row (repeat it; letters, shown lower-case, digits, "
                   "space and . , : = ( ) - / + %)")
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

  std::vector<io::ImageF> cells;
  int width = 0, height = 0;  // the first image's
  const auto sizeText = [](int w, int h) { return std::to_string(w) + "x" + std::to_string(h); };
  for (const fs::path& path : inputs) {
    const io::ImageF image = io::readImage(path);
    if (cells.empty()) {
      width = image.width;
      height = image.height;
    } else if (image.width != width || image.height != height) {
      throw std::runtime_error(path.string() + ": " + sizeText(image.width, image.height) +
                               " differs from the size of the first image, " + inputs.front().string() + " (" +
                               sizeText(width, height) + ")");
    }
    if (image.width < options.shrink || image.height < options.shrink)
      throw std::runtime_error(path.string() + ": " + sizeText(image.width, image.height) +
                               " is smaller than --shrink " + std::to_string(options.shrink));
    const io::ImageF shown = io::toDisplay(
        image, io::holdsRadiance(path) ? io::PngEncoding::Tonemapped : io::PngEncoding::Srgb, options.exposure);
    cells.push_back(options.shrink > 1 ? shrinkImage(shown, options.shrink) : shown);
  }
  std::vector<std::string> labels;
  for (std::string label : options.labels) {
    std::transform(label.begin(), label.end(), label.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    labels.push_back(label);
  }
  // Cells of the later rows get no label: a blank one keeps the layout.
  while (!labels.empty() && labels.size() < cells.size()) labels.push_back("");
  const io::ImageF sheet = labels.empty() ? contactSheet(cells, columns, 1) : labelledSheet(cells, labels, columns);
  io::writePng(out, sheet, io::PngEncoding::Linear);
  std::printf("wrote %s (%dx%d: %zu images, %d to a row)\n", out.c_str(), sheet.width, sheet.height, cells.size(),
              columns);
  return 0;
}

}  // namespace bounce::app

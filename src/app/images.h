// Images the commands write for people: AOVs of a frame as EXR + false-colour
// PNG, and contact sheets that put several of them side by side.
#pragma once

#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "gpu/context.h"
#include "gpu/recorder.h"
#include "io/image_io.h"
#include "plot/canvas.h"
#include "render/frame_renderer.h"

namespace bounce::app {

// The AOV names --aov accepts (besides "all"), and them as one line.
const std::set<std::string>& knownAovs();
std::string knownAovList();

// An image shrunk `shrink` times in each direction (box filter; a partial
// last row or column is dropped), its first three channels.
io::ImageF shrinkImage(const io::ImageF& image, int shrink);

// Lays display images (all the size of the first) out left to right, top to
// bottom, `columns` to a row, each shrunk by `shrink` (box filter), on black.
io::ImageF contactSheet(const std::vector<io::ImageF>& cells, int columns, int shrink);

// Display images (all the size of the first) side by side, `columns` to a
// row, each with its label in a strip above it (lower-case text).
io::ImageF labelledSheet(const std::vector<io::ImageF>& cells, const std::vector<std::string>& labels, int columns);

// Where labelledSheet puts things: `columns` cells to a row, each row of
// cells under a strip for their labels (strip 0: no labels, as
// contactSheet's layout).
struct SheetLayout {
  int cellWidth = 0;
  int cellHeight = 0;
  int columns = 1;
  int rows = 0;
  int strip = 0;      // pixels of label strip above each row of cells
  int textScale = 1;  // of the label font (plot::Canvas::text)

  int width() const { return cellWidth * columns; }
  int height() const { return (cellHeight + strip) * rows; }
  // The top-left pixel of cell i (its label's strip is above it).
  int cellX(std::size_t i) const { return int(i % std::size_t(columns)) * cellWidth; }
  int cellY(std::size_t i) const { return int(i / std::size_t(columns)) * (cellHeight + strip) + strip; }
};

// The layout of `cellCount` cells, labelled when `labels` is not empty.
SheetLayout sheetLayout(int cellWidth, int cellHeight, std::size_t cellCount, int columns,
                        const std::vector<std::string>& labels);

// Draws the labels of the cells of row `row` (labels[i] above cell i; fewer
// labels than cells leave the rest blank) into `canvas`, whose row `top` is
// the top of that row's strip.
void drawLabels(plot::Canvas& canvas, const SheetLayout& layout, const std::vector<std::string>& labels, int row,
                int top);

// The background of a labelled sheet (its strips, and cells no image fills).
inline constexpr float kSheetBackground = 0.08f;

// Writes each wanted AOV of the renderer's last frame ("all" for every one)
// as EXR + false-colour PNG into `dir`, all of them side by side on
// sheet.png, and, when both normals are written, normals.png: shading
// normals (normal-mapped) beside geometric ones, where normal maps show.
// `extra` are AOVs from elsewhere (the GI library's), written after the
// renderer's. Returns every file written.
std::vector<std::filesystem::path> writeAovs(gpu::Context& context, render::FrameRenderer& renderer,
                                             const std::vector<std::string>& wanted, const std::filesystem::path& dir,
                                             float exposure, const std::vector<render::Aov>& extra = {});

// NRD-style validation sheets, one per captured frame that ran the GI
// library: viewZ, normals, motion vectors, the diffuse history's length
// (the temporal filter's, or the denoiser's temporal accumulation's) (magma on a fixed 0..historyCap scale, so a reset
// frame reads as black rather than as a uniform image stretched to full range), and the frame with pixels whose history
// was lost this frame (disocclusion, cut) in red. Returns the files written (DIR/frameNNNN.validation.png).
std::vector<std::filesystem::path> writeValidationSheets(const std::filesystem::path& dir,
                                                         const std::vector<gpu::CapturedStage>& captures,
                                                         float exposure, float historyCap);

}  // namespace bounce::app

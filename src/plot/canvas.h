// A small raster canvas for the pictures the tools draw (BRDF plots, the
// ghosting plot, contact sheets' labels): filled rectangles, dots, and text in
// a built-in 5x7 pixel font, so labels need no font files or libraries.
// Colours are display values in [0,1].
#pragma once

#include <string_view>

#include <glm/glm.hpp>

#include "io/image_io.h"

namespace bounce::plot {

class Canvas {
 public:
  Canvas(int width, int height, glm::vec3 background = glm::vec3(0.0f));

  void fillRect(int x, int y, int width, int height, glm::vec3 colour);
  void dot(float x, float y, float radius, glm::vec3 colour);
  // Lower-case letters, digits, space and . , : = ( ) - / + %; other
  // characters draw as a box. `scale` multiplies the 5x7 glyphs.
  void text(int x, int y, std::string_view text, glm::vec3 colour, int scale = 2);
  static int textWidth(std::string_view text, int scale = 2) { return int(text.size()) * 6 * scale; }

  void set(int x, int y, glm::vec3 colour);
  const io::ImageF& image() const { return image_; }
  int width() const { return image_.width; }
  int height() const { return image_.height; }

 private:
  io::ImageF image_;
};

// A line of dots `radius` wide from a to b; with `gap` > 0, dotted: a dot
// every `gap` pixels.
void drawLine(Canvas& canvas, glm::vec2 a, glm::vec2 b, glm::vec3 colour, float radius, float gap = 0.0f);

}  // namespace bounce::plot

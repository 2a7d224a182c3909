#include "plot/canvas.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>

namespace bounce::plot {
namespace {

// 5x7 glyphs, one string of 7 rows of 5 columns each ('#' = ink).
struct Glyph {
  char character;
  const char* rows;
};

constexpr std::array kGlyphs = {
    Glyph{'a', "...........###.....#.#####...#.####"}, Glyph{'b', "#....#....####.#...##...##...#####."},
    Glyph{'c', "...........#####....#....#.....####"}, Glyph{'d', "....#....#.#####...##...##...#.####"},
    Glyph{'e', "...........###.#...#######.....###."}, Glyph{'f', "..##..#...####..#....#....#....#..."},
    Glyph{'g', "..........####.#...#.####....#.###."}, Glyph{'h', "#....#....####.#...##...##...##...#"},
    Glyph{'i', "..#........##....#....#....#...###."}, Glyph{'j', "...#........##....#....#.#..#..##.."},
    Glyph{'k', "#....#....#..#.#.#..##...#.#..#..#."}, Glyph{'l', ".##....#....#....#....#....#...###."},
    Glyph{'m', "..........##.#.#.#.##.#.##.#.##...#"}, Glyph{'n', "..........####.#...##...##...##...#"},
    Glyph{'o', "...........###.#...##...##...#.###."}, Glyph{'p', ".....####.#...##...#####.#....#...."},
    Glyph{'q', "......#####...##...#.####....#....#"}, Glyph{'r', "..........#.##.##..##....#....#...."},
    Glyph{'s', "...........#####.....###.....#####."}, Glyph{'t', ".#....#...####..#....#....#..#..##."},
    Glyph{'u', "..........#...##...##...##..##.##.#"}, Glyph{'v', "..........#...##...##...#.#.#...#.."},
    Glyph{'w', "..........#...##...##.#.##.#.#.#.#."}, Glyph{'x', "..........#...#.#.#...#...#.#.#...#"},
    Glyph{'y', ".....#...##...##...#.####....#.###."}, Glyph{'z', "..........#####...#...#...#...#####"},
    Glyph{'0', ".###.#...##..###.#.###..##...#.###."}, Glyph{'1', "..#...##....#....#....#....#...###."},
    Glyph{'2', ".###.#...#....#...#...#...#...#####"}, Glyph{'3', "#####...#...#.....#.....##...#.###."},
    Glyph{'4', "...#...##..#.#.#..#.#####...#....#."}, Glyph{'5', "######....####.....#....##...#.###."},
    Glyph{'6', "..##..#...#....####.#...##...#.###."}, Glyph{'7', "#####....#...#...#...#....#....#..."},
    Glyph{'8', ".###.#...##...#.###.#...##...#.###."}, Glyph{'9', ".###.#...##...#.####....#...#..##.."},
    Glyph{'.', "..........................##...##.."}, Glyph{',', ".....................##....#...#..."},
    Glyph{':', "......##...##........##...##......."}, Glyph{'=', "..........#####.....#####.........."},
    Glyph{'(', "...#...#...#....#....#.....#.....#."}, Glyph{')', ".#.....#.....#....#....#...#...#..."},
    Glyph{'-', "...............#####..............."}, Glyph{'+', ".......#....#..#####..#....#......."},
    Glyph{'/', ".........#...#...#...#...#........."}, Glyph{'%', "##...##..#...#...#...#...#..##...##"},
    Glyph{' ', "..................................."},
};

const char* glyphRows(char c) {
  for (const Glyph& g : kGlyphs)
    if (g.character == c) return g.rows;
  return "######...##...##...##...##...######";
}

}  // namespace

Canvas::Canvas(int width, int height, glm::vec3 background) : image_(width, height, {"R", "G", "B"}) {
  fillRect(0, 0, width, height, background);
}

void Canvas::set(int x, int y, glm::vec3 colour) {
  if (x < 0 || y < 0 || x >= image_.width || y >= image_.height) return;
  for (int c = 0; c < 3; ++c) image_.at(x, y, c) = colour[c];
}

void Canvas::fillRect(int x, int y, int width, int height, glm::vec3 colour) {
  for (int j = std::max(0, y); j < std::min(image_.height, y + height); ++j)
    for (int i = std::max(0, x); i < std::min(image_.width, x + width); ++i) set(i, j, colour);
}

void Canvas::dot(float x, float y, float radius, glm::vec3 colour) {
  for (int j = int(std::floor(y - radius)); j <= int(std::ceil(y + radius)); ++j)
    for (int i = int(std::floor(x - radius)); i <= int(std::ceil(x + radius)); ++i) {
      const float dx = float(i) + 0.5f - x, dy = float(j) + 0.5f - y;
      if (dx * dx + dy * dy <= radius * radius) set(i, j, colour);
    }
}

void Canvas::text(int x, int y, std::string_view text, glm::vec3 colour, int scale) {
  for (std::size_t k = 0; k < text.size(); ++k) {
    const char* rows = glyphRows(char(std::tolower(static_cast<unsigned char>(text[k]))));
    for (int row = 0; row < 7; ++row)
      for (int column = 0; column < 5; ++column)
        if (rows[row * 5 + column] == '#')
          fillRect(x + (int(k) * 6 + column) * scale, y + row * scale, scale, scale, colour);
  }
}

void drawLine(Canvas& canvas, glm::vec2 a, glm::vec2 b, glm::vec3 colour, float radius, float gap) {
  const float length = glm::length(b - a);
  const int steps = std::max(1, int(std::ceil(length / 0.5f)));
  float sinceDot = gap;
  for (int i = 0; i <= steps; ++i) {
    const glm::vec2 p = a + (b - a) * (float(i) / float(steps));
    if (gap > 0.0f) {
      sinceDot += length / float(steps);
      if (sinceDot < gap) continue;
      sinceDot = 0.0f;
    }
    canvas.dot(p.x, p.y, radius, colour);
  }
}

}  // namespace bounce::plot

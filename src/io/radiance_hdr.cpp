// Radiance RGBE decoder; see radiance_hdr.h for why it is ours.
//
// File layout: text header lines ("#?RADIANCE", "FORMAT=...", ...) ending in an
// empty line, a resolution line ("-Y 512 +X 1024"), then one scanline per row.
// A scanline is either flat (4 bytes R,G,B,E per pixel) or, for widths 8..32767,
// run-length encoded per component after a 4-byte marker (2, 2, width hi, lo).
#include "io/radiance_hdr.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

namespace bounce::io {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const fs::path& path, const std::string& reason) {
  throw ImageIoError(path.string() + ": " + reason);
}

// A cursor over the file bytes that fails with the file name instead of ever
// reading past the end.
class ByteCursor {
 public:
  ByteCursor(const fs::path& path, const std::vector<unsigned char>& bytes) : path_(path), bytes_(bytes) {}

  bool atEnd() const { return position_ >= bytes_.size(); }
  std::size_t remaining() const { return bytes_.size() - position_; }
  const unsigned char* here() const { return bytes_.data() + position_; }

  unsigned char next() {
    if (atEnd()) truncated();
    return bytes_[position_++];
  }

  void advance(std::size_t count) {
    if (count > remaining()) truncated();
    position_ += count;
  }

  // One header line without its '\n'. Header lines are short; a long one means
  // this is not a Radiance file (or the header never ends).
  std::string_view line() {
    constexpr std::size_t kMaxHeaderLine = 4096;
    const std::size_t start = position_;
    while (true) {
      if (atEnd()) fail(path_, "truncated or corrupt (header does not end)");
      if (bytes_[position_] == '\n') break;
      if (position_ - start > kMaxHeaderLine) fail(path_, "corrupt header (line longer than 4096 bytes)");
      ++position_;
    }
    const std::string_view text(reinterpret_cast<const char*>(bytes_.data() + start), position_ - start);
    ++position_;
    return text;
  }

  [[noreturn]] void truncated() const { fail(path_, "truncated or corrupt (pixel data ends early)"); }

 private:
  const fs::path& path_;
  const std::vector<unsigned char>& bytes_;
  std::size_t position_ = 0;
};

// Radiance's own conversion: the mantissa names the centre of its bucket.
void rgbeToFloat(const unsigned char rgbe[4], float* rgb) {
  if (rgbe[3] == 0) {
    rgb[0] = rgb[1] = rgb[2] = 0.0f;
    return;
  }
  const float scale = std::ldexp(1.0f, int(rgbe[3]) - (128 + 8));
  for (int c = 0; c < 3; ++c) rgb[c] = (float(rgbe[c]) + 0.5f) * scale;
}

void readHeader(const fs::path& path, ByteCursor& cursor) {
  const std::string_view magic = cursor.line();
  if (magic != "#?RADIANCE" && magic != "#?RGBE") fail(path, "not a Radiance HDR file (bad signature)");
  while (true) {
    const std::string_view line = cursor.line();
    if (line.empty()) return;
    if (line.starts_with("FORMAT=") && line != "FORMAT=32-bit_rle_rgbe") {
      fail(path, "unsupported Radiance pixel format '" + std::string(line.substr(7)) + "' (only 32-bit_rle_rgbe)");
    }
  }
}

// New-style run-length encoding exists for these widths only.
bool isRunLengthWidth(long width) { return width >= 8 && width <= 32767; }

// Reads the scanline into rgbe (width * 4 bytes, pixel-interleaved).
void readScanline(ByteCursor& cursor, int width, std::vector<unsigned char>& rgbe, const fs::path& path) {
  const bool runLengthEncoded = isRunLengthWidth(width) && cursor.remaining() >= 4 && cursor.here()[0] == 2 &&
                                cursor.here()[1] == 2 && (cursor.here()[2] & 0x80) == 0;
  if (!runLengthEncoded) {
    if (std::size_t(width) * 4 > cursor.remaining()) cursor.truncated();
    std::copy_n(cursor.here(), std::size_t(width) * 4, rgbe.begin());
    cursor.advance(std::size_t(width) * 4);
    return;
  }
  const int encodedWidth = (int(cursor.here()[2]) << 8) | int(cursor.here()[3]);
  if (encodedWidth != width) {
    fail(path, "corrupt scanline (encoded width " + std::to_string(encodedWidth) + ", image width " +
                   std::to_string(width) + ")");
  }
  cursor.advance(4);
  for (int component = 0; component < 4; ++component) {
    int x = 0;
    while (x < width) {
      int count = cursor.next();
      const bool run = count > 128;
      if (run) count -= 128;
      if (count == 0 || x + count > width) fail(path, "corrupt run-length scanline");
      if (run) {
        const unsigned char value = cursor.next();
        for (int i = 0; i < count; ++i) rgbe[std::size_t(x++) * 4 + component] = value;
      } else {
        for (int i = 0; i < count; ++i) rgbe[std::size_t(x++) * 4 + component] = cursor.next();
      }
    }
  }
}

// The fewest bytes a scanline of `width` pixels can take: new-style run
// length encoding stores each of the 4 components in runs of at most 127
// equal values (2 bytes each) after a 4-byte marker; other widths are flat.
std::uint64_t smallestScanlineBytes(long width) {
  if (isRunLengthWidth(width)) return 4 + 4 * 2 * ((std::uint64_t(width) + 126) / 127);
  return 4 * std::uint64_t(width);
}

}  // namespace

RadianceHeader readRadianceHeader(const fs::path& path, const std::vector<unsigned char>& bytes, std::uint64_t fileSize,
                                  int maxSide, std::int64_t maxPixels) {
  ByteCursor cursor(path, bytes);
  readHeader(path, cursor);

  const std::string resolution(cursor.line());
  char yAxis[3] = {};
  char xAxis[3] = {};
  long height = 0;
  long width = 0;
  int consumed = 0;
  if (std::sscanf(resolution.c_str(), "%2s %ld %2s %ld%n", yAxis, &height, xAxis, &width, &consumed) != 4 ||
      std::size_t(consumed) != resolution.size()) {
    fail(path, "corrupt resolution line '" + resolution + "'");
  }
  const std::string_view y(yAxis);
  if ((y != "-Y" && y != "+Y") || std::string_view(xAxis) != "+X") {
    fail(path, "unsupported Radiance orientation '" + resolution + "' (only -Y H +X W and +Y H +X W)");
  }
  if (width <= 0 || height <= 0) {
    fail(path, "image has no pixels (" + std::to_string(width) + "x" + std::to_string(height) + ")");
  }
  const std::string size = std::to_string(width) + "x" + std::to_string(height);
  if (width > maxSide || height > maxSide)
    fail(path,
         "image size " + size + " is larger than " + std::to_string(maxSide) + " pixels a side (corrupt header?)");
  if (std::int64_t(width) * std::int64_t(height) > maxPixels)
    fail(path, "image size " + size + " is more than " + std::to_string(maxPixels) + " pixels");
  const std::size_t headerBytes = bytes.size() - cursor.remaining();
  const std::uint64_t pixelBytes = fileSize > headerBytes ? fileSize - headerBytes : 0;
  const std::uint64_t needed = std::uint64_t(height) * smallestScanlineBytes(width);
  if (needed > pixelBytes)
    fail(path, "truncated: the header declares " + size + " pixels, which take at least " + std::to_string(needed) +
                   " bytes; the file has " + std::to_string(pixelBytes) + " after its header");
  return {int(width), int(height), y == "+Y", headerBytes};
}

ImageF decodeRadianceHdr(const fs::path& path, const std::vector<unsigned char>& bytes, int maxSide,
                         std::int64_t maxPixels) {
  const RadianceHeader header = readRadianceHeader(path, bytes, bytes.size(), maxSide, maxPixels);
  const int width = header.width, height = header.height;
  ByteCursor cursor(path, bytes);
  cursor.advance(header.pixelOffset);

  ImageF image(width, height, {"R", "G", "B"});
  std::vector<unsigned char> rgbe(std::size_t(width) * 4);
  for (int row = 0; row < height; ++row) {
    readScanline(cursor, width, rgbe, path);
    const int imageRow = header.bottomUp ? height - 1 - row : row;
    for (int x = 0; x < width; ++x) rgbeToFloat(&rgbe[std::size_t(x) * 4], &image.at(x, imageRow, 0));
  }
  return image;
}

}  // namespace bounce::io

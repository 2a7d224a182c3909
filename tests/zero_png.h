// A black PNG of any size written in a few bytes per thousand pixels, as
// a file that is small on disk and huge in memory: its pixel data is one
// deflate block of runs of zeros (literal 0, then copies of 258 bytes at
// distance 1), so a 16384 x 16384 image takes under 2 MB. With `rows` less
// than the height the stream ends early: a header that declares the size
// and data that cannot be decoded, to show that a size is refused before
// any decoding starts.
#pragma once

#include <cstdint>
#include <vector>

namespace bounce::testing {

namespace zero_png_detail {

inline std::uint32_t crc32(const std::vector<std::uint8_t>& data, std::size_t begin) {
  std::uint32_t crc = 0xffffffffu;
  for (std::size_t i = begin; i < data.size(); ++i) {
    crc ^= data[i];
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

inline void bigEndian32(std::vector<std::uint8_t>& out, std::uint32_t value) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(std::uint8_t(value >> shift));
}

inline void chunk(std::vector<std::uint8_t>& png, const char* type, const std::vector<std::uint8_t>& data) {
  bigEndian32(png, std::uint32_t(data.size()));
  const std::size_t typeStart = png.size();
  png.insert(png.end(), type, type + 4);
  png.insert(png.end(), data.begin(), data.end());
  bigEndian32(png, crc32(png, typeStart));
}

// Deflate's bit order: values least significant bit first; Huffman codes
// most significant bit first.
class BitWriter {
 public:
  std::vector<std::uint8_t> bytes;
  void bits(std::uint32_t value, int count) {
    for (int i = 0; i < count; ++i) put((value >> i) & 1u);
  }
  void code(std::uint32_t value, int count) {
    for (int i = count - 1; i >= 0; --i) put((value >> i) & 1u);
  }

 private:
  void put(std::uint32_t bit) {
    if (used_ == 0) bytes.push_back(0);
    bytes.back() |= std::uint8_t(bit << used_);
    used_ = (used_ + 1) % 8;
  }
  int used_ = 0;
};

}  // namespace zero_png_detail

// components: 1 grey, 2 grey and alpha, 3 RGB, 4 RGBA; bitDepth 8 or 16.
inline std::vector<std::uint8_t> zeroPng(std::uint32_t width, std::uint32_t height, std::uint32_t rows,
                                         int components = 1, int bitDepth = 8) {
  using namespace zero_png_detail;
  // Each row: its filter byte (0, none) and its zero samples.
  const std::uint64_t rowBytes = std::uint64_t(width) * std::uint64_t(components) * std::uint64_t(bitDepth / 8);
  const std::uint64_t zeros = std::uint64_t(rows) * (rowBytes + 1);
  BitWriter deflate;
  deflate.bits(1, 1);  // the final block
  deflate.bits(1, 2);  // fixed Huffman codes
  std::uint64_t written = 0;
  const auto literalZero = [&] {
    deflate.code(0x30, 8);  // literal 0
    ++written;
  };
  if (zeros > 0) literalZero();
  while (zeros - written >= 258) {
    deflate.code(0xc5, 8);  // length 258 (code 285)
    deflate.code(0, 5);     // distance 1 (code 0)
    written += 258;
  }
  while (written < zeros) literalZero();
  deflate.code(0, 7);  // end of block (code 256)

  std::vector<std::uint8_t> zlib = {0x78, 0x01};
  zlib.insert(zlib.end(), deflate.bytes.begin(), deflate.bytes.end());
  bigEndian32(zlib, std::uint32_t((zeros % 65521) << 16 | 1));  // Adler-32 of zeros: a = 1, b = count

  std::vector<std::uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  std::vector<std::uint8_t> header;
  bigEndian32(header, width);
  bigEndian32(header, height);
  const std::uint8_t colourType[] = {0, 0, 4, 2, 6};
  // Deflate, adaptive filters, not interlaced.
  header.insert(header.end(), {std::uint8_t(bitDepth), colourType[components], 0, 0, 0});
  chunk(png, "IHDR", header);
  chunk(png, "IDAT", zlib);
  chunk(png, "IEND", {});
  return png;
}

}  // namespace bounce::testing

// Radiance RGBE (.hdr) decoding. Our own decoder rather than stb's: the stb
// in Debian 12 loops forever on a run-length scanline whose count byte is zero,
// which is exactly what a truncated file looks like, and it fills missing bytes
// with zeros instead of failing. Internal to bounce_io.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "io/image_io.h"

namespace bounce::io {

// What a Radiance file's header says: its size, its row order and where its
// pixels start.
struct RadianceHeader {
  int width = 0;
  int height = 0;
  bool bottomUp = false;        // "+Y H": the first scanline is the bottom row
  std::size_t pixelOffset = 0;  // of the first scanline, in bytes
};

// Reads the header from `bytes`, the start of a file of fileSize bytes (all
// of it, or enough to hold the header), with the checks below: the size
// against maxSide and maxPixels, and against the bytes the file has.
RadianceHeader readRadianceHeader(const std::filesystem::path& path, const std::vector<unsigned char>& bytes,
                                  std::uint64_t fileSize, int maxSide, std::int64_t maxPixels);

// Decodes a whole Radiance file (32-bit_rle_rgbe, flat or new-style run-length
// scanlines, "-Y H +X W" or "+Y H +X W" orientation) into an RGB float image.
// Every inconsistency (truncation, run past the scanline, zero count, size over
// maxSide or maxPixels) throws ImageIoError naming the file. The declared size
// is checked against the bytes the file has before any pixel memory is
// allocated, so a tiny file cannot make it allocate gigabytes.
ImageF decodeRadianceHdr(const std::filesystem::path& path, const std::vector<unsigned char>& bytes, int maxSide,
                         std::int64_t maxPixels);

}  // namespace bounce::io

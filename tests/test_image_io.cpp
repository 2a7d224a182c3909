// Tests of src/io/image_io: every format read and written, and every way a file
// can be bad. Files are generated inside each test (in a private temp folder),
// including hand-built EXR and 16-bit PNG files for cases our writers never
// produce (offset data windows, half and luminance channels, 16-bit samples).
#include "io/image_io.h"

#include <gtest/gtest.h>
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <zlib.h>

#include "shared/color.glsl"
#include "zero_png.h"

namespace bounce::io {
namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<std::uint8_t>;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// --- files and errors

Bytes readBytes(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
}

void writeBytes(const fs::path& path, const Bytes& bytes) {
  std::ofstream file(path, std::ios::binary);
  file.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  ASSERT_TRUE(file.good()) << path;
}

// The message of the ImageIoError that f throws, or a test failure if it throws none.
std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const ImageIoError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected an ImageIoError";
  return {};
}

void expectContains(const std::string& text, const std::string& part) {
  EXPECT_NE(text.find(part), std::string::npos) << "\"" << text << "\" does not contain \"" << part << "\"";
}

// Every test gets its own empty folder, removed afterwards.
class ImageIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("bounce-test-image-io-" + std::to_string(::getpid()) + "-" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  fs::path file(const std::string& name) const { return dir_ / name; }

  std::vector<std::string> folderEntries() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir_)) names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }

  // Cuts a copy of source to each of the given sizes and expects readImage to
  // reject every one with a message that names the file.
  void expectTruncationsThrow(const fs::path& source, const std::vector<std::size_t>& sizes) {
    const Bytes whole = readBytes(source);
    ASSERT_NO_THROW(readImage(source)) << "the uncut file must read";
    for (std::size_t size : sizes) {
      ASSERT_LT(size, whole.size());
      const fs::path cut = file("cut-" + std::to_string(size) + source.extension().string());
      writeBytes(cut, Bytes(whole.begin(), whole.begin() + std::ptrdiff_t(size)));
      SCOPED_TRACE("cut to " + std::to_string(size) + " of " + std::to_string(whole.size()) + " bytes");
      expectContains(errorOf([&] { readImage(cut); }), cut.string());
    }
  }

  fs::path dir_;
};

std::vector<float> randomValues(std::size_t count, float lo, float hi, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> dist(lo, hi);
  std::vector<float> values(count);
  for (float& v : values) v = dist(rng);
  return values;
}

ImageF randomImage(int width, int height, std::vector<std::string> channels, float lo, float hi, unsigned seed) {
  ImageF image(width, height, std::move(channels));
  image.pixels = randomValues(image.pixels.size(), lo, hi, seed);
  return image;
}

// Raw 8-bit samples of a PNG/JPEG as stored, without any decoding of ours.
struct RawImage {
  int width = 0;
  int height = 0;
  int components = 0;
  Bytes samples;
};

RawImage readRaw(const fs::path& path) {
  RawImage raw;
  stbi_uc* pixels = stbi_load(path.c_str(), &raw.width, &raw.height, &raw.components, 0);
  if (!pixels) {
    ADD_FAILURE() << "stb cannot read " << path;
    return raw;
  }
  raw.samples.assign(pixels, pixels + std::size_t(raw.width) * raw.height * raw.components);
  stbi_image_free(pixels);
  return raw;
}

std::uint8_t expectedByte(float v) { return std::uint8_t(std::floor(v * 255.0f + 0.5f)); }

// --- a minimal EXR writer: single part, scanline, uncompressed. It can write
// what writeExr never does (half and uint channels, a data window away from the
// origin, subsampled channels), and values given as raw bits (NaN halves).

enum class ExrType : std::int32_t { Uint = 0, Half = 1, Float = 2 };

struct ExrChannel {
  std::string name;  // channels must be given in alphabetical order, as in a file
  ExrType type = ExrType::Half;
  int sampling = 1;                      // x and y subsampling
  std::function<float(int, int)> value;  // sample value at data-window pixel (x, y)
};

struct ExrBuilder {
  Bytes bytes;
  void u8(std::uint8_t v) { bytes.push_back(v); }
  void u16(std::uint16_t v) { u8(std::uint8_t(v)), u8(std::uint8_t(v >> 8)); }
  void u32(std::uint32_t v) { u16(std::uint16_t(v)), u16(std::uint16_t(v >> 16)); }
  void u64(std::uint64_t v) { u32(std::uint32_t(v)), u32(std::uint32_t(v >> 32)); }
  void i32(std::int32_t v) { u32(std::uint32_t(v)); }
  void f32(float v) {
    std::uint32_t bits;
    std::memcpy(&bits, &v, 4);
    u32(bits);
  }
  void text(const std::string& s) {
    bytes.insert(bytes.end(), s.begin(), s.end());
    u8(0);
  }
  void attribute(const std::string& name, const std::string& type, std::size_t size) {
    text(name);
    text(type);
    i32(std::int32_t(size));
  }
  void box(int x0, int y0, int x1, int y1) { i32(x0), i32(y0), i32(x1), i32(y1); }
};

Bytes buildExr(int x0, int y0, int width, int height, const std::vector<ExrChannel>& channels) {
  ExrBuilder b;
  b.u32(20000630);  // magic, 76 2f 31 01
  b.u32(2);         // version 2, single-part scanline, short names
  std::size_t channelListSize = 1;
  for (const ExrChannel& c : channels) channelListSize += c.name.size() + 1 + 16;
  b.attribute("channels", "chlist", channelListSize);
  for (const ExrChannel& c : channels) {
    b.text(c.name);
    b.i32(std::int32_t(c.type));
    b.u32(0);  // pLinear and reserved bytes
    b.i32(c.sampling);
    b.i32(c.sampling);
  }
  b.u8(0);
  b.attribute("compression", "compression", 1);
  b.u8(0);  // NO_COMPRESSION: one scanline per chunk
  b.attribute("dataWindow", "box2i", 16);
  b.box(x0, y0, x0 + width - 1, y0 + height - 1);
  b.attribute("displayWindow", "box2i", 16);
  b.box(x0, y0, x0 + width - 1, y0 + height - 1);
  b.attribute("lineOrder", "lineOrder", 1);
  b.u8(0);
  b.attribute("pixelAspectRatio", "float", 4);
  b.f32(1.0f);
  b.attribute("screenWindowCenter", "v2f", 8);
  b.f32(0.0f);
  b.f32(0.0f);
  b.attribute("screenWindowWidth", "float", 4);
  b.f32(1.0f);
  b.u8(0);

  std::vector<Bytes> chunks;
  for (int y = y0; y < y0 + height; ++y) {
    ExrBuilder chunk;
    for (const ExrChannel& c : channels) {
      if (y % c.sampling != 0) continue;
      for (int x = x0; x < x0 + width; x += c.sampling) {
        const float v = c.value(x - x0, y - y0);
        if (c.type == ExrType::Half) chunk.u16(glm::packHalf1x16(v));
        if (c.type == ExrType::Float) chunk.f32(v);
        if (c.type == ExrType::Uint) chunk.u32(std::uint32_t(v));
      }
    }
    chunks.push_back(chunk.bytes);
  }
  std::uint64_t offset = b.bytes.size() + 8 * chunks.size();
  for (const Bytes& chunk : chunks) {
    b.u64(offset);
    offset += 8 + chunk.size();
  }
  for (int y = y0; y < y0 + height; ++y) {
    const Bytes& chunk = chunks[std::size_t(y - y0)];
    b.i32(y);
    b.i32(std::int32_t(chunk.size()));
    b.bytes.insert(b.bytes.end(), chunk.begin(), chunk.end());
  }
  return b.bytes;
}

// --- a minimal 16-bit PNG writer (stb writes only 8-bit): stored (uncompressed)
// deflate blocks, which every inflater must accept.

std::uint32_t crc32(const std::uint8_t* data, std::size_t size, std::uint32_t crc = 0) {
  crc = ~crc;
  for (std::size_t i = 0; i < size; ++i) {
    crc ^= data[i];
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

void putBigEndian32(Bytes& out, std::uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(std::uint8_t(v >> shift));
}

void pngChunk(Bytes& png, const char type[5], const Bytes& data) {
  putBigEndian32(png, std::uint32_t(data.size()));
  Bytes typed(type, type + 4);
  typed.insert(typed.end(), data.begin(), data.end());
  png.insert(png.end(), typed.begin(), typed.end());
  putBigEndian32(png, crc32(typed.data(), typed.size()));
}

// colorType 0 = grey, 2 = RGB, 4 = grey + alpha, 6 = RGBA; samples row-major.
Bytes buildPng16(int width, int height, int colorType, const std::vector<std::uint16_t>& samples) {
  const int components = colorType == 0 ? 1 : colorType == 2 ? 3 : colorType == 4 ? 2 : 4;
  Bytes raw;
  for (int y = 0; y < height; ++y) {
    raw.push_back(0);  // filter: none
    for (int i = 0; i < width * components; ++i) {
      const std::uint16_t v = samples[std::size_t(y) * width * components + i];
      raw.push_back(std::uint8_t(v >> 8));
      raw.push_back(std::uint8_t(v));
    }
  }
  Bytes zlib = {0x78, 0x01};
  for (std::size_t start = 0; start < raw.size(); start += 65535) {
    const std::size_t length = std::min<std::size_t>(65535, raw.size() - start);
    zlib.push_back(start + length == raw.size() ? 1 : 0);
    zlib.push_back(std::uint8_t(length)), zlib.push_back(std::uint8_t(length >> 8));
    zlib.push_back(std::uint8_t(~length)), zlib.push_back(std::uint8_t(~length >> 8));
    zlib.insert(zlib.end(), raw.begin() + std::ptrdiff_t(start), raw.begin() + std::ptrdiff_t(start + length));
  }
  std::uint32_t a = 1, b = 0;  // Adler-32
  for (std::uint8_t byte : raw) a = (a + byte) % 65521, b = (b + a) % 65521;
  putBigEndian32(zlib, (b << 16) | a);

  Bytes png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  Bytes header;
  putBigEndian32(header, std::uint32_t(width));
  putBigEndian32(header, std::uint32_t(height));
  header.insert(header.end(), {16, std::uint8_t(colorType), 0, 0, 0});
  pngChunk(png, "IHDR", header);
  pngChunk(png, "IDAT", zlib);
  pngChunk(png, "IEND", {});
  return png;
}

// ============================================================== ImageF

TEST(ImageF, ConstructorAllocatesZeroedInterleavedPixels) {
  ImageF image(3, 2, {"R", "G"});
  EXPECT_EQ(image.channelCount(), 2u);
  ASSERT_EQ(image.pixels.size(), 12u);
  EXPECT_TRUE(std::all_of(image.pixels.begin(), image.pixels.end(), [](float v) { return v == 0.0f; }));
  image.at(2, 1, 1) = 5.0f;
  EXPECT_EQ(image.pixels[(1 * 3 + 2) * 2 + 1], 5.0f);
}

// ============================================================== EXR

TEST_F(ImageIoTest, ExrRoundTripIsExactForFloat32Rgba) {
  ImageF image = randomImage(37, 19, {"R", "G", "B", "A"}, -1000.0f, 1000.0f, 1);
  image.at(0, 0, 0) = 1.0e-30f;  // values half or 8-bit would lose
  image.at(1, 0, 1) = 3.0e38f;
  image.at(2, 0, 2) = -0.0f;
  const fs::path path = file("rgba.exr");
  writeExr(path, image);
  const ImageF back = readImage(path);
  EXPECT_EQ(back.width, 37);
  EXPECT_EQ(back.height, 19);
  EXPECT_EQ(back.channels, (std::vector<std::string>{"R", "G", "B", "A"}));
  ASSERT_EQ(back.pixels.size(), image.pixels.size());
  EXPECT_EQ(std::memcmp(back.pixels.data(), image.pixels.data(), image.pixels.size() * sizeof(float)), 0);
}

TEST_F(ImageIoTest, ExrRoundTripKeepsSingleViewZChannel) {
  const ImageF image = randomImage(16, 9, {"viewZ"}, 0.1f, 500.0f, 2);
  const fs::path path = file("viewz.exr");
  writeExr(path, image);
  const ImageF back = readImage(path);
  EXPECT_EQ(back.channels, std::vector<std::string>{"viewZ"});
  EXPECT_EQ(back.pixels, image.pixels);
}

TEST_F(ImageIoTest, ExrRoundTripKeepsNamedLayersInFileOrder) {
  const ImageF image = randomImage(8, 5, {"viewZ", "diffuse.R", "normal.X", "diffuse.G"}, -2.0f, 2.0f, 3);
  const fs::path path = file("layers.exr");
  writeExr(path, image);
  const ImageF back = readImage(path);
  // OpenEXR keeps channels sorted by name.
  ASSERT_EQ(back.channels, (std::vector<std::string>{"diffuse.G", "diffuse.R", "normal.X", "viewZ"}));
  for (std::size_t c = 0; c < image.channels.size(); ++c) {
    const std::size_t cb =
        std::size_t(std::find(back.channels.begin(), back.channels.end(), image.channels[c]) - back.channels.begin());
    for (int y = 0; y < image.height; ++y) {
      for (int x = 0; x < image.width; ++x) ASSERT_EQ(back.at(x, y, int(cb)), image.at(x, y, int(c)));
    }
  }
}

TEST_F(ImageIoTest, ExrExtraChannelsFollowRgba) {
  const ImageF image = randomImage(4, 3, {"viewZ", "B", "A", "R", "G"}, 0.0f, 1.0f, 4);
  const fs::path path = file("rgba-viewz.exr");
  writeExr(path, image);
  const ImageF back = readImage(path);
  ASSERT_EQ(back.channels, (std::vector<std::string>{"R", "G", "B", "A", "viewZ"}));
  EXPECT_EQ(back.at(3, 2, 0), image.at(3, 2, 3));  // R
  EXPECT_EQ(back.at(3, 2, 3), image.at(3, 2, 2));  // A
  EXPECT_EQ(back.at(3, 2, 4), image.at(3, 2, 0));  // viewZ
}

TEST_F(ImageIoTest, ExrReadsHalfAndUintChannelsInAnOffsetDataWindow) {
  // A data window from (-3, 5) to (2, 8): the image is its 6x4 pixels.
  const auto red = [](int x, int y) { return float(x) + 0.25f * float(y); };
  const auto green = [](int x, int y) { return float(x * y) * 0.5f; };
  const auto blue = [](int x, int y) { return float(100 * y + x); };
  const fs::path path = file("window.exr");
  writeBytes(path,
             buildExr(-3, 5, 6, 4,
                      {{"B", ExrType::Uint, 1, blue}, {"G", ExrType::Float, 1, green}, {"R", ExrType::Half, 1, red}}));
  const ImageF image = readImage(path);
  ASSERT_EQ(image.width, 6);
  ASSERT_EQ(image.height, 4);
  ASSERT_EQ(image.channels, (std::vector<std::string>{"R", "G", "B"}));
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 6; ++x) {
      EXPECT_EQ(image.at(x, y, 0), red(x, y)) << x << "," << y;
      EXPECT_EQ(image.at(x, y, 1), green(x, y)) << x << "," << y;
      EXPECT_EQ(image.at(x, y, 2), blue(x, y)) << x << "," << y;
    }
  }
}

TEST_F(ImageIoTest, ExrLuminanceOnlyBecomesGreyRgb) {
  const auto luminance = [](int x, int y) { return 0.5f * float(x + 4 * y); };
  const fs::path grey = file("y.exr");
  writeBytes(grey, buildExr(0, 0, 4, 3, {{"Y", ExrType::Half, 1, luminance}}));
  const ImageF image = readImage(grey);
  ASSERT_EQ(image.channels, (std::vector<std::string>{"R", "G", "B"}));
  for (int c = 0; c < 3; ++c) EXPECT_EQ(image.at(3, 2, c), luminance(3, 2));

  const fs::path greyAlpha = file("ya.exr");
  writeBytes(greyAlpha,
             buildExr(0, 0, 4, 3,
                      {{"A", ExrType::Half, 1, [](int, int) { return 0.25f; }}, {"Y", ExrType::Half, 1, luminance}}));
  const ImageF withAlpha = readImage(greyAlpha);
  ASSERT_EQ(withAlpha.channels, (std::vector<std::string>{"R", "G", "B", "A"}));
  EXPECT_EQ(withAlpha.at(1, 1, 0), luminance(1, 1));
  EXPECT_EQ(withAlpha.at(1, 1, 2), luminance(1, 1));
  EXPECT_EQ(withAlpha.at(1, 1, 3), 0.25f);
}

TEST_F(ImageIoTest, ExrLuminanceChromaWithSubsampledChromaBecomesRgb) {
  // A flat colour as OpenEXR stores it in YC form: Y, and RY = (R - Y) / Y and
  // BY = (B - Y) / Y on a 2x2-subsampled grid (Rec.709 luminance weights).
  const float r = 0.8f, g = 0.4f, b = 0.2f;
  const float y = 0.2126f * r + 0.7152f * g + 0.0722f * b;
  const fs::path path = file("yc.exr");
  writeBytes(path, buildExr(0, 0, 8, 6,
                            {{"BY", ExrType::Half, 2, [&](int, int) { return (b - y) / y; }},
                             {"RY", ExrType::Half, 2, [&](int, int) { return (r - y) / y; }},
                             {"Y", ExrType::Half, 1, [&](int, int) { return y; }}}));
  const ImageF image = readImage(path);
  ASSERT_EQ(image.channels, (std::vector<std::string>{"R", "G", "B"}));
  ASSERT_EQ(image.width, 8);
  ASSERT_EQ(image.height, 6);
  for (int py = 0; py < 6; ++py) {
    for (int px = 0; px < 8; ++px) {
      EXPECT_NEAR(image.at(px, py, 0), r, 0.01f);
      EXPECT_NEAR(image.at(px, py, 1), g, 0.01f);
      EXPECT_NEAR(image.at(px, py, 2), b, 0.01f);
    }
  }
}

TEST_F(ImageIoTest, ExrOtherSubsampledChannelsAreRejected) {
  const fs::path path = file("subsampled.exr");
  writeBytes(path, buildExr(0, 0, 4, 4, {{"mask", ExrType::Half, 2, [](int, int) { return 1.0f; }}}));
  const std::string message = errorOf([&] { readImage(path); });
  expectContains(message, path.string());
  expectContains(message, "subsampling");
}

TEST_F(ImageIoTest, ExrTruncatedFileThrows) {
  // Noise, so that the ZIP chunks stay large and a cut lands inside pixel data.
  const fs::path path = file("whole.exr");
  writeExr(path, randomImage(64, 64, {"R", "G", "B", "A"}, 0.0f, 1.0f, 5));
  const std::size_t size = fs::file_size(path);
  expectTruncationsThrow(path, {8, 100, size / 4, size / 2, 3 * size / 4, size - 1});
}

TEST_F(ImageIoTest, ExrNonFiniteValuesThrowUnlessAllowed) {
  ImageF image(5, 4, {"R", "G", "B"});
  image.at(2, 1, 1) = kNaN;
  image.at(0, 3, 2) = kInf;
  image.at(4, 3, 0) = -kInf;
  const fs::path path = file("nan.exr");
  writeExr(path, image);

  const std::string message = errorOf([&] { readImage(path); });
  expectContains(message, path.string());
  expectContains(message, "3 non-finite values (NaN or Inf), first at pixel (2, 1) channel G");

  const ImageF allowed = readImage(path, true);
  EXPECT_TRUE(std::isnan(allowed.at(2, 1, 1)));
  EXPECT_EQ(allowed.at(0, 3, 2), kInf);
  EXPECT_EQ(allowed.at(4, 3, 0), -kInf);
}

TEST_F(ImageIoTest, ExrHalfNanThrows) {
  const fs::path path = file("half-nan.exr");
  writeBytes(
      path,
      buildExr(0, 0, 3, 2, {{"viewZ", ExrType::Half, 1, [](int x, int y) { return x == 1 && y == 1 ? kNaN : 1.0f; }}}));
  expectContains(errorOf([&] { readImage(path); }), "first at pixel (1, 1) channel viewZ");
}

TEST_F(ImageIoTest, ExrOversizeImageThrows) {
  const fs::path path = file("wide.exr");
  writeBytes(path, buildExr(0, 0, 70000, 1, {{"Y", ExrType::Half, 1, [](int, int) { return 1.0f; }}}));
  const std::string message = errorOf([&] { readImage(path); });
  expectContains(message, path.string());
  expectContains(message, "70000x1");
}

TEST_F(ImageIoTest, ExrRealDwabHdriLoads) {
  const fs::path path = fs::path(BOUNCE_SOURCE_DIR) / ".." / "shared" / "scenes" / "hdri" / "courtyard.exr";
  if (!fs::exists(path)) GTEST_SKIP() << path << " is absent (the shared scenes are optional)";
  const ImageF image = readImage(path);
  EXPECT_EQ(image.width, 1024);
  EXPECT_EQ(image.height, 512);
  ASSERT_EQ(image.channels, (std::vector<std::string>{"R", "G", "B"}));
  double sum = 0.0;
  for (float v : image.pixels) sum += v;
  const double mean = sum / double(image.pixels.size());
  EXPECT_TRUE(std::isfinite(mean));
  EXPECT_GT(mean, 0.0);
}

// ============================================================== PNG

TEST_F(ImageIoTest, PngLinearEncodingStoresValuesWithinHalfStep) {
  ImageF image = randomImage(23, 11, {"R", "G", "B"}, 0.0f, 1.0f, 6);
  image.at(0, 0, 0) = -3.0f;  // clamped
  image.at(0, 0, 1) = 7.0f;
  const fs::path path = file("linear.png");
  writePng(path, image, PngEncoding::Linear);

  const RawImage raw = readRaw(path);
  ASSERT_EQ(raw.components, 3);
  ASSERT_EQ(raw.samples.size(), image.pixels.size());
  for (std::size_t i = 0; i < raw.samples.size(); ++i) {
    const float clamped = std::clamp(image.pixels[i], 0.0f, 1.0f);
    EXPECT_LE(std::abs(raw.samples[i] / 255.0f - clamped), 0.5f / 255.0f + 1e-6f) << i;
    EXPECT_EQ(raw.samples[i], expectedByte(clamped)) << i;
  }

  // readImage treats every PNG as sRGB: it returns the decoded stored bytes.
  const ImageF back = readImage(path);
  ASSERT_EQ(back.channels, (std::vector<std::string>{"R", "G", "B"}));
  for (std::size_t i = 0; i < raw.samples.size(); ++i) {
    EXPECT_FLOAT_EQ(back.pixels[i], shared::srgbDecode(raw.samples[i] / 255.0f)) << i;
  }
}

TEST_F(ImageIoTest, PngSrgbEncodingOfHalfIs188) {
  ImageF image(2, 1, {"R", "G", "B"});
  std::fill(image.pixels.begin(), image.pixels.end(), 0.5f);
  const fs::path path = file("half.png");
  writePng(path, image, PngEncoding::Srgb);
  const RawImage raw = readRaw(path);
  ASSERT_EQ(raw.samples.size(), 6u);
  for (std::uint8_t v : raw.samples) EXPECT_EQ(v, 188);
}

TEST_F(ImageIoTest, PngSrgbRoundTripIsWithinHalfStepOfEncodedValue) {
  const ImageF image = randomImage(16, 16, {"R", "G", "B"}, 0.0f, 1.0f, 7);
  const fs::path path = file("srgb.png");
  writePng(path, image, PngEncoding::Srgb);
  const ImageF back = readImage(path);
  ASSERT_EQ(back.pixels.size(), image.pixels.size());
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    EXPECT_LE(std::abs(shared::srgbEncode(back.pixels[i]) - shared::srgbEncode(image.pixels[i])), 0.5f / 255.0f + 1e-5f)
        << i;
  }
}

TEST_F(ImageIoTest, PngTonemappedWritesDisplayEncode) {
  ImageF image = randomImage(16, 8, {"R", "G", "B"}, 0.0f, 20.0f, 8);
  image.at(0, 0, 0) = 1.0e30f;  // huge but finite radiance is white, not an overflow NaN
  image.at(0, 0, 1) = 1.0e30f;
  image.at(0, 0, 2) = 1.0e30f;
  const float exposure = 0.7f;
  const fs::path path = file("tonemapped.png");
  writePng(path, image, PngEncoding::Tonemapped, exposure);
  const RawImage raw = readRaw(path);
  ASSERT_EQ(raw.components, 3);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const glm::vec3 radiance(image.at(x, y, 0), image.at(x, y, 1), image.at(x, y, 2));
      const glm::vec3 display = x == 0 && y == 0 ? glm::vec3(1.0f) : shared::displayEncode(radiance, exposure);
      const std::size_t i = (std::size_t(y) * image.width + x) * 3;
      EXPECT_EQ(raw.samples[i + 0], expectedByte(display.x)) << x << "," << y;
      EXPECT_EQ(raw.samples[i + 1], expectedByte(display.y)) << x << "," << y;
      EXPECT_EQ(raw.samples[i + 2], expectedByte(display.z)) << x << "," << y;
    }
  }
}

TEST_F(ImageIoTest, PngAlphaIsStoredAndReadLinearly) {
  ImageF image(2, 1, {"R", "G", "B", "A"});
  image.pixels = {4.0f, 4.0f, 4.0f, 0.5f, 0.0f, 0.0f, 0.0f, 2.0f};
  const fs::path path = file("alpha.png");
  writePng(path, image, PngEncoding::Tonemapped);
  const RawImage raw = readRaw(path);
  ASSERT_EQ(raw.components, 4);
  EXPECT_EQ(raw.samples[3], 128);  // 0.5, neither tonemapped nor sRGB-encoded
  EXPECT_EQ(raw.samples[7], 255);  // clamped
  const ImageF back = readImage(path);
  ASSERT_EQ(back.channels, (std::vector<std::string>{"R", "G", "B", "A"}));
  EXPECT_FLOAT_EQ(back.at(0, 0, 3), 128.0f / 255.0f);
  EXPECT_FLOAT_EQ(back.at(0, 0, 0), shared::srgbDecode(raw.samples[0] / 255.0f));
}

TEST_F(ImageIoTest, PngChannelCountsMapToGreyRgbAndRgba) {
  ImageF grey(3, 2, {"viewZ"});
  grey.pixels = {0.0f, 0.2f, 0.4f, 0.6f, 0.8f, 1.0f};
  writePng(file("grey.png"), grey, PngEncoding::Linear);
  const RawImage rawGrey = readRaw(file("grey.png"));
  EXPECT_EQ(rawGrey.components, 1);
  EXPECT_EQ(rawGrey.samples, (Bytes{0, 51, 102, 153, 204, 255}));

  ImageF motion(1, 1, {"X", "Y"});  // two channels: red and green, blue zero
  motion.pixels = {0.25f, 0.75f};
  writePng(file("motion.png"), motion, PngEncoding::Linear);
  EXPECT_EQ(readRaw(file("motion.png")).samples, (Bytes{64, 191, 0}));

  ImageF many(1, 1, {"a", "b", "c", "d", "e"});  // more than four: the first three
  many.pixels = {0.0f, 0.5f, 1.0f, 0.1f, 0.1f};
  writePng(file("many.png"), many, PngEncoding::Linear);
  const RawImage rawMany = readRaw(file("many.png"));
  EXPECT_EQ(rawMany.components, 3);
  EXPECT_EQ(rawMany.samples, (Bytes{0, 128, 255}));
}

TEST_F(ImageIoTest, PngNonFiniteInputBecomesMagenta) {
  ImageF image(3, 1, {"R", "G", "B", "A"});
  image.pixels = {0.5f, kNaN, 0.5f, 1.0f, kInf, 0.0f, 0.0f, 0.3f, 0.0f, 0.0f, 0.0f, kNaN};
  writePng(file("bad.png"), image, PngEncoding::Linear);
  EXPECT_EQ(readRaw(file("bad.png")).samples, (Bytes{255, 0, 255, 255, 255, 0, 255, 255, 255, 0, 255, 255}));

  // A grey image cannot show magenta, so one with bad values is written as RGB.
  ImageF grey(2, 1, {"Y"});
  grey.pixels = {0.5f, kNaN};
  for (PngEncoding encoding : {PngEncoding::Linear, PngEncoding::Srgb, PngEncoding::Tonemapped}) {
    writePng(file("bad-grey.png"), grey, encoding);
    const RawImage raw = readRaw(file("bad-grey.png"));
    ASSERT_EQ(raw.components, 3);
    EXPECT_EQ(raw.samples[0], raw.samples[1]);
    EXPECT_EQ(raw.samples[0], raw.samples[2]);
    EXPECT_EQ(Bytes(raw.samples.begin() + 3, raw.samples.end()), (Bytes{255, 0, 255}));
  }
}

TEST_F(ImageIoTest, PngGreyReadsAsRgbAndGreyAlphaAsRgba) {
  const Bytes grey = {0, 128, 255, 64};
  ASSERT_TRUE(stbi_write_png(file("grey.png").c_str(), 2, 2, 1, grey.data(), 2));
  const ImageF image = readImage(file("grey.png"));
  ASSERT_EQ(image.channels, (std::vector<std::string>{"R", "G", "B"}));
  for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(image.at(1, 0, c), shared::srgbDecode(128.0f / 255.0f));
  EXPECT_FLOAT_EQ(image.at(0, 1, 2), 1.0f);

  const Bytes greyAlpha = {200, 51, 10, 255};
  ASSERT_TRUE(stbi_write_png(file("grey-alpha.png").c_str(), 2, 1, 2, greyAlpha.data(), 4));
  const ImageF withAlpha = readImage(file("grey-alpha.png"));
  ASSERT_EQ(withAlpha.channels, (std::vector<std::string>{"R", "G", "B", "A"}));
  EXPECT_FLOAT_EQ(withAlpha.at(0, 0, 1), shared::srgbDecode(200.0f / 255.0f));
  EXPECT_FLOAT_EQ(withAlpha.at(0, 0, 3), 51.0f / 255.0f);
  EXPECT_FLOAT_EQ(withAlpha.at(1, 0, 3), 1.0f);
}

TEST_F(ImageIoTest, Png16BitReadKeepsFullPrecision) {
  // RGBA: colour is sRGB-decoded from v / 65535, alpha is v / 65535.
  const std::vector<std::uint16_t> rgba = {0, 1, 32768, 65535, 12345, 65535, 257, 1000};
  writeBytes(file("rgba16.png"), buildPng16(2, 1, 6, rgba));
  const ImageF image = readImage(file("rgba16.png"));
  ASSERT_EQ(image.channels, (std::vector<std::string>{"R", "G", "B", "A"}));
  for (int c = 0; c < 3; ++c) {
    EXPECT_FLOAT_EQ(image.at(0, 0, c), shared::srgbDecode(rgba[std::size_t(c)] / 65535.0f)) << c;
    EXPECT_FLOAT_EQ(image.at(1, 0, c), shared::srgbDecode(rgba[std::size_t(4 + c)] / 65535.0f)) << c;
  }
  EXPECT_FLOAT_EQ(image.at(0, 0, 3), 1.0f);
  EXPECT_FLOAT_EQ(image.at(1, 0, 3), 1000.0f / 65535.0f);
  // 1/65535 would be lost by any 8-bit path.
  EXPECT_GT(image.at(0, 0, 1), 0.0f);

  const std::vector<std::uint16_t> grey = {0, 30000, 65535};
  writeBytes(file("grey16.png"), buildPng16(1, 3, 0, grey));
  const ImageF greyImage = readImage(file("grey16.png"));
  ASSERT_EQ(greyImage.channels, (std::vector<std::string>{"R", "G", "B"}));
  ASSERT_EQ(greyImage.height, 3);
  for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(greyImage.at(0, 1, c), shared::srgbDecode(30000.0f / 65535.0f));
}

TEST_F(ImageIoTest, PngTruncatedFileThrows) {
  const fs::path path = file("whole.png");
  writePng(path, randomImage(48, 48, {"R", "G", "B"}, 0.0f, 1.0f, 9), PngEncoding::Linear);
  const std::size_t size = fs::file_size(path);
  // size - 12 drops exactly the IEND chunk: the pixel data is whole, the file is not.
  expectTruncationsThrow(path, {5, 20, 40, size / 2, size - 100, size - 12});
}

TEST_F(ImageIoTest, PngOversizeImageThrows) {
  const fs::path path = file("wide.png");
  const Bytes row(70000, 128);
  ASSERT_TRUE(stbi_write_png(path.c_str(), 70000, 1, 1, row.data(), 70000));
  const std::string message = errorOf([&] { readImage(path); });
  expectContains(message, path.string());
  expectContains(message, "70000x1");
}

// ============================================================== JPEG

TEST_F(ImageIoTest, JpegReadDecodesToLinear) {
  const Bytes flat(32 * 16 * 3, 128);
  const fs::path path = file("grey.jpg");
  ASSERT_TRUE(stbi_write_jpg(path.c_str(), 32, 16, 3, flat.data(), 100));
  const RawImage raw = readRaw(path);
  const ImageF image = readImage(path);
  ASSERT_EQ(image.width, 32);
  ASSERT_EQ(image.height, 16);
  ASSERT_EQ(image.channels, (std::vector<std::string>{"R", "G", "B"}));
  ASSERT_EQ(image.pixels.size(), raw.samples.size());
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    EXPECT_NEAR(image.pixels[i], shared::srgbDecode(128.0f / 255.0f), 2.0f / 255.0f) << i;
    EXPECT_FLOAT_EQ(image.pixels[i], shared::srgbDecode(raw.samples[i] / 255.0f)) << i;
  }
}

TEST_F(ImageIoTest, JpegTruncatedFileThrows) {
  Bytes noise(64 * 64 * 3);
  std::mt19937 rng(10);
  for (std::uint8_t& v : noise) v = std::uint8_t(rng());
  const fs::path path = file("whole.jpg");
  ASSERT_TRUE(stbi_write_jpg(path.c_str(), 64, 64, 3, noise.data(), 90));
  const std::size_t size = fs::file_size(path);
  // size - 2 removes just the end-of-image marker.
  expectTruncationsThrow(path, {3, 100, size / 2, size - 2, size - 1});
}

// ============================================================== Radiance HDR

// Radiance stores a shared exponent and 8-bit mantissas, so every channel is
// exact to about 1% of the pixel's largest channel.
void expectHdrRoundTrip(const fs::path& path, int width, int height, unsigned seed) {
  const std::vector<float> values = randomValues(std::size_t(width) * height * 3, 0.01f, 100.0f, seed);
  ASSERT_TRUE(stbi_write_hdr(path.c_str(), width, height, 3, values.data()));
  const ImageF image = readImage(path);
  ASSERT_EQ(image.width, width);
  ASSERT_EQ(image.height, height);
  ASSERT_EQ(image.channels, (std::vector<std::string>{"R", "G", "B"}));
  for (std::size_t p = 0; p < values.size(); p += 3) {
    const float largest = std::max({values[p], values[p + 1], values[p + 2]});
    for (std::size_t c = 0; c < 3; ++c) EXPECT_NEAR(image.pixels[p + c], values[p + c], 0.01f * largest) << p;
  }
}

TEST_F(ImageIoTest, HdrRoundTripIsWithinRgbePrecision) {
  expectHdrRoundTrip(file("rle.hdr"), 40, 7, 11);  // stb run-length encodes widths 8 to 32767
  expectHdrRoundTrip(file("flat.hdr"), 5, 3, 12);  // and stores narrower images flat
}

TEST_F(ImageIoTest, HdrTruncatedFileThrows) {
  const std::vector<float> values = randomValues(40 * 20 * 3, 0.0f, 10.0f, 13);
  const fs::path rle = file("rle.hdr");
  ASSERT_TRUE(stbi_write_hdr(rle.c_str(), 40, 20, 3, values.data()));
  const std::size_t rleSize = fs::file_size(rle);
  expectTruncationsThrow(rle, {10, 60, rleSize / 2, rleSize - 1});

  // Flat pixels are read four bytes at a time; cutting inside the last one is the
  // hardest case to notice.
  const fs::path flat = file("flat.hdr");
  ASSERT_TRUE(stbi_write_hdr(flat.c_str(), 5, 4, 3, values.data()));
  const std::size_t flatSize = fs::file_size(flat);
  expectTruncationsThrow(flat, {flatSize / 2, flatSize - 5, flatSize - 4, flatSize - 3, flatSize - 2, flatSize - 1});
}

// A hand-built file pins the decoding itself: Radiance's mantissa names the
// centre of its bucket, value = (m + 0.5) * 2^(e - 136).
Bytes radianceFile(const std::string& resolution, const Bytes& pixels) {
  const std::string header = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n" + resolution + "\n";
  Bytes bytes(header.begin(), header.end());
  bytes.insert(bytes.end(), pixels.begin(), pixels.end());
  return bytes;
}

TEST_F(ImageIoTest, HdrDecodesRgbeExactlyAndHonoursBottomUpRows) {
  const Bytes pixels = {128, 64, 0, 129, /* next row */ 255, 1, 10, 120};
  writeBytes(file("top.hdr"), radianceFile("-Y 2 +X 1", pixels));
  const ImageF top = readImage(file("top.hdr"));
  ASSERT_EQ(top.width, 1);
  ASSERT_EQ(top.height, 2);
  EXPECT_FLOAT_EQ(top.at(0, 0, 0), 128.5f / 128.0f);
  EXPECT_FLOAT_EQ(top.at(0, 0, 1), 64.5f / 128.0f);
  EXPECT_FLOAT_EQ(top.at(0, 0, 2), 0.5f / 128.0f);
  EXPECT_FLOAT_EQ(top.at(0, 1, 0), 255.5f * std::ldexp(1.0f, 120 - 136));

  writeBytes(file("bottom.hdr"), radianceFile("+Y 2 +X 1", pixels));
  const ImageF bottom = readImage(file("bottom.hdr"));
  EXPECT_EQ(bottom.at(0, 0, 0), top.at(0, 1, 0));
  EXPECT_EQ(bottom.at(0, 1, 0), top.at(0, 0, 0));

  // Exponent 0 means black, whatever the mantissas say.
  writeBytes(file("black.hdr"), radianceFile("-Y 1 +X 1", {200, 200, 200, 0}));
  EXPECT_EQ(readImage(file("black.hdr")).at(0, 0, 1), 0.0f);
}

TEST_F(ImageIoTest, HdrCorruptRunsAndHeadersAreRefused) {
  // A zero count never advances the scanline (the stb bug that made us write our own).
  // Both files are padded to the 12 bytes the smallest 8-pixel scanline takes,
  // so the run, not the size, is what is wrong with them.
  Bytes zeroCount = {2, 2, 0, 8, 0, 0, 0, 0, 0, 0, 0, 0};
  writeBytes(file("zero.hdr"), radianceFile("-Y 1 +X 8", zeroCount));
  expectContains(errorOf([&] { readImage(file("zero.hdr")); }), "corrupt run-length scanline");

  Bytes overrun = {2, 2, 0, 8, 128 + 9, 1, 0, 0, 0, 0, 0, 0};  // a run of 9 in a scanline of 8
  writeBytes(file("overrun.hdr"), radianceFile("-Y 1 +X 8", overrun));
  expectContains(errorOf([&] { readImage(file("overrun.hdr")); }), "corrupt run-length scanline");

  writeBytes(file("xyze.hdr"), Bytes{'#', '?', 'R', 'A', 'D', 'I', 'A', 'N', 'C',  'E', '\n',
                                     'F', 'O', 'R', 'M', 'A', 'T', '=', 'X', '\n', '\n'});
  expectContains(errorOf([&] { readImage(file("xyze.hdr")); }), "unsupported Radiance pixel format 'X'");

  writeBytes(file("sideways.hdr"), radianceFile("+X 1 -Y 1", {1, 1, 1, 128}));
  expectContains(errorOf([&] { readImage(file("sideways.hdr")); }), "unsupported Radiance orientation");

  writeBytes(file("huge.hdr"), radianceFile("-Y 70000 +X 1", {}));
  expectContains(errorOf([&] { readImage(file("huge.hdr")); }), "70000");

  writeBytes(file("noend.hdr"), Bytes{'#', '?', 'R', 'G', 'B', 'E', '\n', 'A'});
  expectContains(errorOf([&] { readImage(file("noend.hdr")); }), "header does not end");
}

// Peak resident memory of this process so far, in bytes.
std::size_t peakResidentBytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return std::size_t(usage.ru_maxrss) * 1024;
}

TEST_F(ImageIoTest, HdrDeclaringMorePixelsThanItsBytesHoldIsRefusedBeforeAllocating) {
  // 68 bytes declaring 16000x8000 pixels: decoding it would allocate (and
  // zero) 1.5 GB of floats before noticing the data ends.
  const std::size_t peakBefore = peakResidentBytes();
  writeBytes(file("liar.hdr"), radianceFile("-Y 8000 +X 16000", Bytes(20, 7)));
  const std::string message = errorOf([&] { readImage(file("liar.hdr")); });
  expectContains(message, "liar.hdr");
  expectContains(message, "16000x8000");
  expectContains(message, "the file has 20");
  EXPECT_LT(peakResidentBytes() - peakBefore, std::size_t(256) << 20) << "pixels were allocated before the check";

  // A declared size far beyond the pixel limit is refused as such (24 GiB of floats otherwise).
  writeBytes(file("giant.hdr"), radianceFile("-Y 32768 +X 65536", Bytes(20, 7)));
  expectContains(errorOf([&] { readImage(file("giant.hdr")); }), "more than 268435456 pixels");

  // An honest file of the smallest size run-length encoding allows still reads:
  // one row of 254 pixels, each component two runs of 127.
  Bytes row = {2, 2, 0, 254};
  for (int component = 0; component < 4; ++component)
    for (int run = 0; run < 2; ++run) row.insert(row.end(), {128 + 127, std::uint8_t(component == 3 ? 128 : 64)});
  writeBytes(file("smallest.hdr"), radianceFile("-Y 1 +X 254", row));
  const ImageF smallest = readImage(file("smallest.hdr"));
  EXPECT_EQ(smallest.width, 254);
  EXPECT_FLOAT_EQ(smallest.at(253, 0, 0), 64.5f / 256.0f);
}

TEST_F(ImageIoTest, DecodeRgba8FromMemoryKeepsBytesAndRefusesTruncation) {
  const fs::path path = file("texture.png");
  const Bytes pixels = {10, 20, 30, 40, 50, 60, 70, 80};
  ASSERT_TRUE(stbi_write_png(path.c_str(), 2, 1, 4, pixels.data(), 8));
  const Bytes encoded = readBytes(path);
  const Rgba8Image image = decodeRgba8(encoded, "texture.png", 16);
  EXPECT_EQ(image.width, 2);
  EXPECT_EQ(image.height, 1);
  EXPECT_EQ(image.rgba8, std::vector<std::uint8_t>(pixels.begin(), pixels.end())) << "no sRGB decoding";
  const Bytes cut(encoded.begin(), encoded.end() - 12);
  expectContains(errorOf([&] { decodeRgba8(cut, "inside scene.glb", 16); }), "inside scene.glb");
  expectContains(errorOf([&] { decodeRgba8(Bytes{'G', 'I', 'F'}, "x", 16); }), "not a PNG or JPEG");
}

// A PNG of just its header, claiming width x height RGBA pixels.
Bytes pngHeaderOnly(std::uint32_t width, std::uint32_t height) {
  Bytes png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  Bytes header;
  putBigEndian32(header, width);
  putBigEndian32(header, height);
  header.insert(header.end(), {8, 6, 0, 0, 0});
  pngChunk(png, "IHDR", header);
  pngChunk(png, "IEND", {});
  return png;
}

// A 20000 x 20000 texture would be 1.6 GB of pixels: it is refused from its
// header with both sizes, not decoded first and then called corrupt.
TEST_F(ImageIoTest, DecodeRgba8RefusesImagesOverItsLimitFromTheHeader) {
  EXPECT_EQ(errorOf([&] { decodeRgba8(pngHeaderOnly(20000, 20000), "huge.png", 16384); }),
            "huge.png: image size 20000x20000 is over the limit of 16384 pixels a side");
  EXPECT_EQ(errorOf([&] { decodeRgba8(pngHeaderOnly(3, 20000), "tall.png", 16384); }),
            "tall.png: image size 3x20000 is over the limit of 16384 pixels a side");
  // At the limit an image decodes.
  const fs::path path = file("wide.png");
  const Bytes pixels(4 * 4, 200);
  ASSERT_TRUE(stbi_write_png(path.c_str(), 4, 1, 4, pixels.data(), 16));
  EXPECT_EQ(decodeRgba8(readBytes(path), "wide.png", 4).width, 4);
  EXPECT_NE(errorOf([&] { decodeRgba8(readBytes(path), "wide.png", 3); }).find("4x1 is over the limit of 3"),
            std::string::npos);
  const fs::path jpeg = file("wide.jpg");
  ASSERT_TRUE(stbi_write_jpg(jpeg.c_str(), 4, 1, 4, pixels.data(), 90));
  EXPECT_EQ(errorOf([&] { decodeRgba8(readBytes(jpeg), "wide.jpg", 3); }),
            "wide.jpg: image size 4x1 is over the limit of 3 pixels a side");
}

// rgba8Info reads from the header alone what decodeRgba8 would make and the
// memory decoding takes, so the textures of a glTF are added up before any
// is decoded (issue 46: a 261 KB PNG of 16384 x 16384 took 2.1 GB); it
// refuses what decodeRgba8 refuses from the header, with the same message.
TEST_F(ImageIoTest, Rgba8InfoIsWhatDecodeRgba8MakesFromTheHeaderAlone) {
  const fs::path path = file("texture.png");
  const Bytes pixels(3 * 2 * 4, 77);
  ASSERT_TRUE(stbi_write_png(path.c_str(), 3, 2, 4, pixels.data(), 12));
  const Bytes encoded = readBytes(path);
  const Rgba8Info info = rgba8Info(encoded, "texture.png", 16);
  const Rgba8Image image = decodeRgba8(encoded, "texture.png", 16);
  EXPECT_EQ(info.width, image.width);
  EXPECT_EQ(info.height, image.height);
  EXPECT_EQ(info.imageBytes(), image.rgba8.size());
  EXPECT_GT(info.decoderBytes, encoded.size()) << "stb holds the compressed data and the samples";

  // A grey 16384 x 16384 PNG whose data ends after one row: only its header is read.
  const Rgba8Info huge = rgba8Info(testing::zeroPng(16384, 16384, 1), "huge.png", 16384);
  EXPECT_EQ(huge.width, 16384);
  EXPECT_EQ(huge.height, 16384);
  EXPECT_EQ(huge.imageBytes(), 16384ull * 16384 * 4);
  EXPECT_GE(huge.decoderBytes, 16384ull * 16384 * (1 + 4)) << "the grey samples and stb's RGBA copy of them";

  EXPECT_EQ(errorOf([&] { rgba8Info(pngHeaderOnly(20000, 20000), "huge.png", 16384); }),
            errorOf([&] { decodeRgba8(pngHeaderOnly(20000, 20000), "huge.png", 16384); }));
  const Bytes gif = {'G', 'I', 'F'};
  EXPECT_EQ(errorOf([&] { rgba8Info(gif, "x", 16); }), errorOf([&] { decodeRgba8(gif, "x", 16); }));
}

// ============================================================== APNG

struct ParsedChunk {
  std::string type;
  Bytes data;
};

std::uint32_t bigEndian(const std::uint8_t* p) {
  return (std::uint32_t(p[0]) << 24) | (std::uint32_t(p[1]) << 16) | (std::uint32_t(p[2]) << 8) | std::uint32_t(p[3]);
}

// Splits a PNG file into chunks, checking every CRC with zlib's crc32.
std::vector<ParsedChunk> parseChunks(const Bytes& file) {
  std::vector<ParsedChunk> chunks;
  EXPECT_EQ(Bytes(file.begin(), file.begin() + 8), (Bytes{0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'}));
  for (std::size_t at = 8; at + 12 <= file.size();) {
    const std::uint32_t length = bigEndian(&file[at]);
    const std::uint32_t crc = bigEndian(&file[at + 8 + length]);
    EXPECT_EQ(crc, std::uint32_t(::crc32(0, &file[at + 4], uInt(length + 4)))) << "chunk at " << at;
    chunks.push_back({std::string(file.begin() + long(at + 4), file.begin() + long(at + 8)),
                      Bytes(file.begin() + long(at + 8), file.begin() + long(at + 8 + length))});
    at += 12 + length;
  }
  return chunks;
}

Bytes chunkBytes(const char* type, const Bytes& data) {
  Bytes out = {std::uint8_t(data.size() >> 24), std::uint8_t(data.size() >> 16), std::uint8_t(data.size() >> 8),
               std::uint8_t(data.size())};
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data.begin(), data.end());
  const auto crc = std::uint32_t(::crc32(0, out.data() + 4, uInt(data.size() + 4)));
  for (int i = 3; i >= 0; --i) out.push_back(std::uint8_t(crc >> (8 * i)));
  return out;
}

TEST_F(ImageIoTest, ApngHoldsEveryFrameInOrderWithValidChunks) {
  std::vector<ImageF> frames;
  for (float shade : {0.0f, 0.5f, 1.0f}) {
    ImageF frame(5, 3, {"R", "G", "B"});
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 5; ++x) {
        frame.at(x, y, 0) = shade;
        frame.at(x, y, 1) = float(x) / 4.0f;
        frame.at(x, y, 2) = 1.0f - shade;
      }
    frames.push_back(frame);
  }
  const fs::path path = file("anim.png");
  writeApng(path, frames, 25.0f);
  const std::vector<ParsedChunk> chunks = parseChunks(readBytes(path));
  ASSERT_GE(chunks.size(), 9u);
  EXPECT_EQ(chunks[0].type, "IHDR");
  ASSERT_EQ(chunks[1].type, "acTL");
  EXPECT_EQ(bigEndian(&chunks[1].data[0]), 3u) << "frame count";
  EXPECT_EQ(chunks.back().type, "IEND");

  // Sequence numbers count up across fcTL and fdAT; frame 2's data makes a PNG
  // of its own that decodes to frame 2's pixels.
  std::uint32_t expectedSequence = 0;
  std::vector<Bytes> frameData(3);
  int frame = -1;
  for (const ParsedChunk& chunk : chunks) {
    if (chunk.type == "fcTL") {
      EXPECT_EQ(bigEndian(&chunk.data[0]), expectedSequence++);
      EXPECT_EQ(bigEndian(&chunk.data[4]), 5u);
      EXPECT_EQ((chunk.data[20] << 8) | chunk.data[21], 40) << "1000/25 ms delay numerator";
      ++frame;
    } else if (chunk.type == "fdAT") {
      EXPECT_EQ(bigEndian(&chunk.data[0]), expectedSequence++);
      frameData[std::size_t(frame)].insert(frameData[std::size_t(frame)].end(), chunk.data.begin() + 4,
                                           chunk.data.end());
    } else if (chunk.type == "IDAT") {
      EXPECT_EQ(frame, 0) << "only the first frame is stored as IDAT";
      frameData[0].insert(frameData[0].end(), chunk.data.begin(), chunk.data.end());
    }
  }
  EXPECT_EQ(frame, 2);
  for (std::size_t f = 0; f < 3; ++f) {
    Bytes png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    const Bytes header = chunkBytes("IHDR", chunks[0].data), data = chunkBytes("IDAT", frameData[f]),
                end = chunkBytes("IEND", {});
    png.insert(png.end(), header.begin(), header.end());
    png.insert(png.end(), data.begin(), data.end());
    png.insert(png.end(), end.begin(), end.end());
    const Rgba8Image decoded = decodeRgba8(png, "frame " + std::to_string(f), 1024);
    EXPECT_EQ(int(decoded.rgba8[0]), int(std::lround(frames[f].at(0, 0, 0) * 255.0f))) << f;
    EXPECT_EQ(int(decoded.rgba8[2]), int(std::lround(frames[f].at(0, 0, 2) * 255.0f))) << f;
    EXPECT_EQ(int(decoded.rgba8[4 * 4 + 1]), 255) << "x = 4 is full green";
  }

  std::vector<ImageF> mixed = {frames[0], ImageF(4, 3, {"R", "G", "B"})};
  expectContains(errorOf([&] { writeApng(file("mixed.png"), mixed, 25.0f); }), "frame 1 is 4x3");
  EXPECT_FALSE(fs::exists(file("mixed.png"))) << "no half file";
}

// ============================================================== headers alone

// readImageInfo says what readImage will return, for every format, so that
// commands can work out the memory of their images before decoding them.
TEST_F(ImageIoTest, ImageInfoIsWhatReadImageMakes) {
  writePng(file("rgb.png"), randomImage(13, 7, {"R", "G", "B"}, 0.0f, 1.0f, 1), PngEncoding::Linear);
  writePng(file("grey.png"), randomImage(5, 9, {"Y"}, 0.0f, 1.0f, 2), PngEncoding::Linear);
  writeBytes(file("greyalpha16.png"), buildPng16(3, 2, 4, std::vector<std::uint16_t>(12, 40000)));
  const Bytes flat(32 * 16 * 3, 128);
  ASSERT_TRUE(stbi_write_jpg(file("grey.jpg").c_str(), 32, 16, 3, flat.data(), 90));
  const std::vector<float> radiance(11 * 6 * 3, 2.5f);
  ASSERT_TRUE(stbi_write_hdr(file("sky.hdr").c_str(), 11, 6, 3, radiance.data()));
  writeExr(file("layers.exr"), randomImage(6, 4, {"R", "G", "B", "A", "Z"}, 0.0f, 1.0f, 3));
  writeExr(file("depth.exr"), randomImage(6, 4, {"viewZ"}, 0.0f, 1.0f, 4));
  writeExr(file("alpha.exr"), randomImage(6, 4, {"A"}, 0.0f, 1.0f, 5));
  for (const char* name :
       {"rgb.png", "grey.png", "greyalpha16.png", "grey.jpg", "sky.hdr", "layers.exr", "depth.exr", "alpha.exr"}) {
    SCOPED_TRACE(name);
    const ImageInfo info = readImageInfo(file(name));
    const ImageF image = readImage(file(name));
    EXPECT_EQ(info.width, image.width);
    EXPECT_EQ(info.height, image.height);
    EXPECT_EQ(info.channels, image.channelCount());
    EXPECT_EQ(info.channelNames, image.channels) << "a map of alpha alone is told from grey by its header";
    EXPECT_EQ(info.imageBytes(), image.pixels.size() * sizeof(float));
    EXPECT_GT(info.readBytes(), info.imageBytes()) << "decoding needs something beside the image";
  }
}

// A 16384 x 16384 PNG in a few hundred bytes (its data ends after one row):
// the header is all readImageInfo reads, so it reports the size that
// readImage, decoding, refuses.
TEST_F(ImageIoTest, ImageInfoReadsOnlyTheHeader) {
  writeBytes(file("huge.png"), testing::zeroPng(16384, 16384, 1));
  const ImageInfo info = readImageInfo(file("huge.png"));
  EXPECT_EQ(info.width, 16384);
  EXPECT_EQ(info.height, 16384);
  EXPECT_EQ(info.channels, 3u);
  EXPECT_GE(info.readBytes(), 16384ull * 16384 * 3 * sizeof(float));
  expectContains(errorOf([&] { readImage(file("huge.png")); }), "cannot decode");
}

// A file readImage refuses from its header gets the same message from
// readImageInfo: a command that looks at headers first says what it always said.
TEST_F(ImageIoTest, ImageInfoRefusesWhatReadImageRefusesWithTheSameMessage) {
  writeBytes(file("empty.png"), {});
  writeBytes(file("gif.png"), Bytes{'G', 'I', 'F', '8', '9', 'a', 1, 0, 1, 0, 0, 0, 0});
  const Bytes row(70000, 128);
  ASSERT_TRUE(stbi_write_png(file("wide.png").c_str(), 70000, 1, 1, row.data(), 70000));
  writeBytes(file("cut.png"), Bytes{0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H'});
  const std::string header = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n";
  const auto hdr = [&](const std::string& resolution, std::size_t pixelBytes) {
    Bytes bytes(header.begin(), header.end());
    bytes.insert(bytes.end(), resolution.begin(), resolution.end());
    bytes.resize(bytes.size() + pixelBytes, 128);
    return bytes;
  };
  writeBytes(file("sideways.hdr"), hdr("+X 4 -Y 2\n", 32));
  writeBytes(file("short.hdr"), hdr("-Y 2000 +X 4000\n", 64));
  writeBytes(file("wide.exr"), buildExr(0, 0, 70000, 1, {{"Y", ExrType::Half, 1, [](int, int) { return 1.0f; }}}));
  for (const char* name :
       {"absent.exr", "empty.png", "gif.png", "wide.png", "cut.png", "sideways.hdr", "short.hdr", "wide.exr"}) {
    SCOPED_TRACE(name);
    const std::string message = errorOf([&] { readImage(file(name)); });
    expectContains(message, file(name).string());
    EXPECT_EQ(errorOf([&] { readImageInfo(file(name)); }), message);
  }
  EXPECT_EQ(errorOf([&] { readImageInfo(dir_); }), errorOf([&] { readImage(dir_); }));
}

// Radiance headers are read from the file's first mebibyte, and from all of
// it when they are longer.
TEST_F(ImageIoTest, ImageInfoFindsTheEndOfALongRadianceHeader) {
  std::string header = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n";
  for (int line = 0; line < 400; ++line) header += "COMMENT=" + std::string(4000, 'x') + "\n";
  header += "\n-Y 2 +X 3\n";
  Bytes bytes(header.begin(), header.end());
  for (int i = 0; i < 6; ++i) bytes.insert(bytes.end(), {128, 64, 32, 129});
  writeBytes(file("long.hdr"), bytes);
  ASSERT_GT(bytes.size(), std::size_t(1) << 20);
  const ImageInfo info = readImageInfo(file("long.hdr"));
  EXPECT_EQ(info.width, 3);
  EXPECT_EQ(info.height, 2);
  EXPECT_GE(info.decoderBytes, bytes.size()) << "the decoder holds the whole file";
}

// Pictures made as bytes (compare's error map, sheet) are written as they
// are: the same file writePng makes of the same values, without a float copy.
TEST_F(ImageIoTest, PngBytesAreWrittenAsTheyAre) {
  const ImageF image = randomImage(9, 5, {"R", "G", "B"}, 0.0f, 1.0f, 6);
  std::vector<std::uint8_t> bytes;
  for (float v : image.pixels) bytes.push_back(displayByte(v));
  writePngBytes(file("bytes.png"), 9, 5, 3, bytes);
  writePng(file("floats.png"), image, PngEncoding::Linear);
  EXPECT_EQ(readBytes(file("bytes.png")), readBytes(file("floats.png")));
  const RawImage raw = readRaw(file("bytes.png"));
  EXPECT_EQ(raw.samples, bytes);
  EXPECT_EQ(displayByte(-1.0f), 0);
  EXPECT_EQ(displayByte(2.0f), 255);
  expectContains(errorOf([&] { writePngBytes(file("short.png"), 9, 5, 3, Bytes(10)); }), "needs 135 bytes");
  expectContains(errorOf([&] { writePngBytes(file("five.png"), 1, 1, 5, Bytes(5)); }), "5 components");
  EXPECT_FALSE(fs::exists(file("short.png")));
}

// ============================================================== bad files

TEST_F(ImageIoTest, UnknownFormatThrows) {
  const fs::path path = file("image.png");  // the extension must not matter
  writeBytes(path, Bytes{'G', 'I', 'F', '8', '9', 'a', 1, 0, 1, 0, 0, 0, 0});
  const std::string message = errorOf([&] { readImage(path); });
  EXPECT_EQ(message, path.string() + ": unsupported image format (expected EXR, HDR, PNG or JPEG)");

  writeBytes(file("tiny"), Bytes{0x89, 'P'});
  expectContains(errorOf([&] { readImage(file("tiny")); }), "unsupported image format");
}

TEST_F(ImageIoTest, MissingFileThrows) {
  const fs::path path = file("absent.exr");
  EXPECT_EQ(errorOf([&] { readImage(path); }), path.string() + ": no such file");
}

TEST_F(ImageIoTest, EmptyFileThrows) {
  const fs::path path = file("empty.exr");
  writeBytes(path, {});
  EXPECT_EQ(errorOf([&] { readImage(path); }), path.string() + ": empty file");
}

TEST_F(ImageIoTest, DirectoryThrows) {
  expectContains(errorOf([&] { readImage(dir_); }), "is a directory");
}

// ============================================================== writing

TEST_F(ImageIoTest, WriteZeroSizeImageThrows) {
  const ImageF empty(0, 4, {"R", "G", "B"});
  expectContains(errorOf([&] { writeExr(file("empty.exr"), empty); }), "0x4");
  expectContains(errorOf([&] { writePng(file("empty.png"), empty); }), "0x4");
  EXPECT_TRUE(folderEntries().empty());
}

TEST_F(ImageIoTest, WriteInconsistentImageThrows) {
  ImageF shortPixels(4, 4, {"R", "G", "B"});
  shortPixels.pixels.pop_back();
  expectContains(errorOf([&] { writeExr(file("a.exr"), shortPixels); }), "needs 48 values but has 47");
  expectContains(errorOf([&] { writePng(file("a.png"), shortPixels); }), "needs 48 values but has 47");

  const ImageF twice(2, 2, {"R", "R"});
  expectContains(errorOf([&] { writeExr(file("b.exr"), twice); }), "channel \"R\" twice");
  const ImageF unnamed(2, 2, {"R", ""});
  expectContains(errorOf([&] { writeExr(file("c.exr"), unnamed); }), "empty channel name");
  const ImageF noChannels(2, 2, {});
  expectContains(errorOf([&] { writePng(file("d.png"), noChannels); }), "no channels");
  EXPECT_TRUE(folderEntries().empty());
}

TEST_F(ImageIoTest, WriteIntoMissingDirectoryThrowsAndCreatesNothing) {
  const ImageF image(2, 2, {"R", "G", "B"});
  const fs::path missing = file("missing");
  const std::string exrMessage = errorOf([&] { writeExr(missing / "out.exr", image); });
  expectContains(exrMessage, (missing / "out.exr").string());
  expectContains(exrMessage, "directory " + missing.string() + " does not exist");
  expectContains(errorOf([&] { writePng(missing / "out.png", image); }), "does not exist");
  EXPECT_FALSE(fs::exists(missing));
  EXPECT_TRUE(folderEntries().empty());
}

TEST_F(ImageIoTest, AtomicWriteLeavesNoTemporaryFiles) {
  const ImageF first = randomImage(8, 8, {"R", "G", "B"}, 0.0f, 1.0f, 14);
  const ImageF second = randomImage(8, 8, {"R", "G", "B"}, 0.0f, 1.0f, 15);
  writeExr(file("out.exr"), first);
  writeExr(file("out.exr"), second);  // replaces the first
  writePng(file("out.png"), first);
  writePng(file("out.png"), second);
  EXPECT_EQ(folderEntries(), (std::vector<std::string>{"out.exr", "out.png"}));
  EXPECT_EQ(readImage(file("out.exr")).pixels, second.pixels);

  // A write that fails at the final rename (the target is a folder) cleans up too.
  fs::create_directory(file("taken.exr"));
  expectContains(errorOf([&] { writeExr(file("taken.exr"), first); }), file("taken.exr").string());
  EXPECT_EQ(folderEntries(), (std::vector<std::string>{"out.exr", "out.png", "taken.exr"}));
}

TEST_F(ImageIoTest, WritePngRejectsBadExposure) {
  const ImageF image(1, 1, {"R", "G", "B"});
  expectContains(errorOf([&] { writePng(file("a.png"), image, PngEncoding::Tonemapped, kNaN); }), "exposure");
  expectContains(errorOf([&] { writePng(file("a.png"), image, PngEncoding::Tonemapped, -1.0f); }), "exposure");
  EXPECT_TRUE(folderEntries().empty());
}

}  // namespace
}  // namespace bounce::io

TEST(ImageF, FirstChannelsKeepsTheirValuesAndNames) {
  bounce::io::ImageF rgba(2, 1, {"R", "G", "B", "A"});
  for (std::size_t i = 0; i < rgba.pixels.size(); ++i) rgba.pixels[i] = float(i);
  const bounce::io::ImageF rgb = bounce::io::firstChannels(rgba, 3);
  EXPECT_EQ(rgb.channels, (std::vector<std::string>{"R", "G", "B"}));
  EXPECT_EQ(rgb.pixels, (std::vector<float>{0, 1, 2, 4, 5, 6}));
  EXPECT_EQ(bounce::io::firstChannels(rgb, 8).channelCount(), 3u) << "asking for more keeps what there is";
}

// Image file I/O: OpenEXR for .exr, stb for PNG/JPEG, our own decoder for
// Radiance .hdr (radiance_hdr.cpp).
//
// Two rules shape everything here:
// - A damaged file must fail loudly. Decoders (stb especially) like to return a
//   partial image for a truncated file, so every read goes through code that
//   notices when the decoder wants bytes the file does not have.
// - A failed write must never leave a half file where a good one is expected,
//   so files are encoded in memory, written beside the target and renamed.
#include "io/image_io.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfCompression.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfRgbaFile.h>
#include <OpenEXR/ImfStdIO.h>
#include <fcntl.h>
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <new>
#include <random>
#include <set>
#include <span>
#include <string_view>
#include <system_error>

#include "io/radiance_hdr.h"
#include "shared/color.glsl"

namespace bounce::io {
namespace {

namespace fs = std::filesystem;

// Larger than any texture or frame we have a use for, small enough that width *
// height * channels * sizeof(float) cannot overflow size_t; anything beyond it is
// a corrupt header, not an image.
constexpr std::int64_t kMaxSide = 65536;

// The longest channel name OpenEXR stores (Imf::Name silently truncates longer ones).
constexpr std::size_t kMaxExrChannelNameLength = 255;

// ACES' rational fit squares its input, so radiance * exposure beyond about 1e19
// overflows float and the tonemap returns NaN. The fit is saturated (pure white)
// long before this value, so clamping here changes no output byte.
constexpr float kTonemapInputLimit = 1.0e6f;

[[noreturn]] void fail(const fs::path& path, const std::string& reason) {
  throw ImageIoError(path.string() + ": " + reason);
}

std::string sizeText(std::int64_t width, std::int64_t height) {
  return std::to_string(width) + "x" + std::to_string(height);
}

void checkReadSize(const fs::path& path, std::int64_t width, std::int64_t height) {
  if (width <= 0 || height <= 0) fail(path, "image has zero size (" + sizeText(width, height) + ")");
  if (width > kMaxSide || height > kMaxSide) {
    fail(path, "image size " + sizeText(width, height) + " is larger than " + std::to_string(kMaxSide) +
                   " pixels a side (corrupt header?)");
  }
  if (width * height > kMaxImagePixels)
    fail(path,
         "image size " + sizeText(width, height) + " is more than " + std::to_string(kMaxImagePixels) + " pixels");
}

// --- reading: file access and format detection

enum class FileFormat { Exr, Hdr, Png, Jpeg, Unknown };

bool startsWith(const std::vector<unsigned char>& bytes, std::string_view prefix) {
  return bytes.size() >= prefix.size() &&
         std::equal(prefix.begin(), prefix.end(), bytes.begin(),
                    [](char a, unsigned char b) { return static_cast<unsigned char>(a) == b; });
}

FileFormat detectFormat(const std::vector<unsigned char>& head) {
  using namespace std::string_view_literals;
  if (startsWith(head, "\x76\x2f\x31\x01"sv)) return FileFormat::Exr;
  if (startsWith(head, "\x89PNG"sv)) return FileFormat::Png;
  if (startsWith(head, "\xff\xd8\xff"sv)) return FileFormat::Jpeg;
  if (startsWith(head, "#?RADIANCE"sv) || startsWith(head, "#?RGBE"sv)) return FileFormat::Hdr;
  return FileFormat::Unknown;
}

// Checks that the path names a readable regular file, so the common mistakes get
// a plain message rather than a decoder's.
void checkReadableFile(const fs::path& path) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (status.type() == fs::file_type::not_found) fail(path, "no such file");
  if (ec) fail(path, "cannot access (" + ec.message() + ")");
  if (status.type() == fs::file_type::directory) fail(path, "is a directory, not an image file");
  if (status.type() != fs::file_type::regular) fail(path, "is not a regular file");
}

// Reads at most maxBytes from the start of the file (everything when maxBytes is 0).
std::vector<unsigned char> readFileBytes(const fs::path& path, std::size_t maxBytes = 0) {
  std::ifstream file(path, std::ios::binary);
  if (!file) fail(path, std::string("cannot open (") + std::strerror(errno) + ")");
  std::vector<unsigned char> bytes;
  if (maxBytes == 0) {
    bytes.assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
  } else {
    bytes.resize(maxBytes);
    file.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(maxBytes));
    bytes.resize(std::size_t(file.gcount()));
  }
  if (file.bad()) fail(path, "read error");
  return bytes;
}

// --- reading: OpenEXR

// Which file channel lands in which output channel.
struct ExrChannelPlan {
  std::vector<std::string> outputNames;
  std::vector<std::string> sourceNames;  // file channel for each output channel
  bool greyFromY = false;                // output channels 1 and 2 are copies of 0 (Y)
};

ExrChannelPlan planExrChannels(const std::vector<std::string>& fileNames) {
  const std::set<std::string> names(fileNames.begin(), fileNames.end());
  const auto has = [&](const char* name) { return names.count(name) != 0; };
  ExrChannelPlan plan;
  if (has("R") && has("G") && has("B")) {
    // OpenEXR lists channels alphabetically (A, B, G, R); colour comes back in
    // the order everyone expects, and any other channels follow so none is lost.
    plan.sourceNames = {"R", "G", "B"};
    if (has("A")) plan.sourceNames.push_back("A");
    for (const std::string& name : fileNames) {
      if (std::find(plan.sourceNames.begin(), plan.sourceNames.end(), name) == plan.sourceNames.end()) {
        plan.sourceNames.push_back(name);
      }
    }
    plan.outputNames = plan.sourceNames;
  } else if (has("Y") && names.size() == (has("A") ? 2u : 1u)) {
    plan.greyFromY = true;
    plan.sourceNames = {"Y", "", ""};
    plan.outputNames = {"R", "G", "B"};
    if (has("A")) {
      plan.sourceNames.push_back("A");
      plan.outputNames.push_back("A");
    }
  } else {
    plan.sourceNames = fileNames;
    plan.outputNames = fileNames;
  }
  return plan;
}

// Luminance/chroma files (RY, BY channels, usually subsampled) need OpenEXR's
// RGBA interface, which reconstructs RGB from them.
ImageF readExrLuminanceChroma(const fs::path& path) {
  Imf::RgbaInputFile file(path.c_str());
  const Imath::Box2i dataWindow = file.dataWindow();
  const std::int64_t width = std::int64_t(dataWindow.max.x) - dataWindow.min.x + 1;
  const std::int64_t height = std::int64_t(dataWindow.max.y) - dataWindow.min.y + 1;
  checkReadSize(path, width, height);
  if (!file.isComplete()) fail(path, "truncated EXR file (some pixel data is missing)");

  const bool hasAlpha = (file.channels() & Imf::WRITE_A) != 0;
  std::vector<Imf::Rgba> rgba(std::size_t(width * height));
  // RgbaInputFile wants the address pixel (0, 0) would have; Slice::Make computes
  // it without overflowing when the data window lies far from the origin.
  const Imf::Slice origin =
      Imf::Slice::Make(Imf::HALF, rgba.data(), dataWindow, sizeof(Imf::Rgba), sizeof(Imf::Rgba) * std::size_t(width));
  file.setFrameBuffer(reinterpret_cast<Imf::Rgba*>(origin.base), 1, std::size_t(width));
  file.readPixels(dataWindow.min.y, dataWindow.max.y);

  ImageF image(int(width), int(height),
               hasAlpha ? std::vector<std::string>{"R", "G", "B", "A"} : std::vector<std::string>{"R", "G", "B"});
  std::size_t out = 0;
  for (const Imf::Rgba& pixel : rgba) {
    image.pixels[out++] = pixel.r;
    image.pixels[out++] = pixel.g;
    image.pixels[out++] = pixel.b;
    if (hasAlpha) image.pixels[out++] = pixel.a;
  }
  return image;
}

// What readExr and readExrInfo both take from a header: the data window's
// size (checked against the limits) and the channels, by name.
struct ExrLayout {
  std::int64_t width = 0, height = 0;
  std::vector<std::string> channels;
  bool subsampled = false;  // a channel sampled every other pixel or row
};

ExrLayout exrLayout(const fs::path& path, const Imf::Header& header) {
  ExrLayout layout;
  const Imath::Box2i dataWindow = header.dataWindow();
  layout.width = std::int64_t(dataWindow.max.x) - dataWindow.min.x + 1;
  layout.height = std::int64_t(dataWindow.max.y) - dataWindow.min.y + 1;
  checkReadSize(path, layout.width, layout.height);
  for (auto it = header.channels().begin(); it != header.channels().end(); ++it) {
    layout.channels.emplace_back(it.name());
    layout.subsampled = layout.subsampled || it.channel().xSampling != 1 || it.channel().ySampling != 1;
  }
  if (layout.channels.empty()) fail(path, "EXR file has no channels");
  return layout;
}

ImageF readExr(const fs::path& path) {
  Imf::InputFile file(path.c_str());
  const Imf::Header& header = file.header();
  const Imath::Box2i dataWindow = header.dataWindow();
  const ExrLayout layout = exrLayout(path, header);
  const std::int64_t width = layout.width, height = layout.height;
  const std::vector<std::string>& fileNames = layout.channels;
  const bool subsampled = layout.subsampled;
  const bool luminanceChroma =
      std::any_of(fileNames.begin(), fileNames.end(), [](const std::string& n) { return n == "RY" || n == "BY"; });
  if (luminanceChroma) return readExrLuminanceChroma(path);
  if (subsampled) fail(path, "EXR channels with x/y subsampling are not supported");

  // Checked before reading: OpenEXR would fill missing chunks with zeros or
  // throw a message about scan line numbers, neither of which says "truncated".
  if (!file.isComplete()) fail(path, "truncated EXR file (some pixel data is missing)");

  const ExrChannelPlan plan = planExrChannels(fileNames);
  ImageF image(int(width), int(height), plan.outputNames);
  const std::size_t channelCount = plan.outputNames.size();
  const std::size_t xStride = sizeof(float) * channelCount;
  const std::size_t yStride = xStride * std::size_t(width);
  Imf::FrameBuffer frameBuffer;
  for (std::size_t c = 0; c < channelCount; ++c) {
    if (plan.sourceNames[c].empty()) continue;
    // Slice::Make offsets the base pointer by the data window origin (which need
    // not be 0,0) without overflowing; OpenEXR converts half/uint to float.
    frameBuffer.insert(plan.sourceNames[c],
                       Imf::Slice::Make(Imf::FLOAT, image.pixels.data() + c, dataWindow, xStride, yStride));
  }
  file.setFrameBuffer(frameBuffer);
  file.readPixels(dataWindow.min.y, dataWindow.max.y);

  if (plan.greyFromY) {
    for (std::size_t i = 0; i < image.pixels.size(); i += channelCount) {
      image.pixels[i + 1] = image.pixels[i];
      image.pixels[i + 2] = image.pixels[i];
    }
  }
  return image;
}

// Scanlines in one chunk of a scanline file (the OpenEXR file layout's table).
std::uint64_t scanlinesPerChunk(Imf::Compression compression) {
  switch (compression) {
    case Imf::NO_COMPRESSION:
    case Imf::RLE_COMPRESSION:
    case Imf::ZIPS_COMPRESSION:
      return 1;
    case Imf::ZIP_COMPRESSION:
    case Imf::PXR24_COMPRESSION:
      return 16;
    case Imf::PIZ_COMPRESSION:
    case Imf::B44_COMPRESSION:
    case Imf::B44A_COMPRESSION:
    case Imf::DWAA_COMPRESSION:
      return 32;
    default:
      return 256;  // DWAB, and the most any compression uses
  }
}

// What readExr will make of the file, from its header: the channels it
// returns and, beside them, OpenEXR's buffers for a chunk of scanlines or a
// row of tiles (compressed and decompressed), or the half-float RGBA copy of
// a luminance/chroma file.
ImageInfo readExrInfo(const fs::path& path) {
  Imf::InputFile file(path.c_str());
  const Imf::Header& header = file.header();
  const ExrLayout layout = exrLayout(path, header);
  const std::int64_t width = layout.width, height = layout.height;
  const std::vector<std::string>& fileNames = layout.channels;
  const bool subsampled = layout.subsampled;
  ImageInfo info{int(width), int(height), 0, 0, {}};
  const auto has = [&](const char* name) {
    return std::find(fileNames.begin(), fileNames.end(), name) != fileNames.end();
  };
  if (has("RY") || has("BY")) {
    info.channelNames = {"R", "G", "B"};
    if (has("A")) info.channelNames.push_back("A");
    info.channels = info.channelNames.size();
    info.decoderBytes = info.pixels() * sizeof(Imf::Rgba);
    return info;
  }
  if (subsampled) fail(path, "EXR channels with x/y subsampling are not supported");
  info.channelNames = planExrChannels(fileNames).outputNames;
  info.channels = info.channelNames.size();
  const std::uint64_t chunkRows = header.hasTileDescription()
                                      ? std::min<std::uint64_t>(header.tileDescription().ySize, std::uint64_t(height))
                                      : scanlinesPerChunk(header.compression());
  info.decoderBytes = 2 * chunkRows * std::uint64_t(width) * fileNames.size() * sizeof(float);
  return info;
}

// --- reading: stb (PNG, JPEG)

// An stb read callback over an in-memory file that records whether the decoder
// ever wanted bytes beyond its end. stb fills such reads with zeros and often
// returns a "successful" partial image, so this is how truncation is caught.
//
// stb asks for bytes in two ways: refills of its internal buffer, always of the
// same size (the very first read is one), which legitimately come up short at the
// end of the data; and exact reads (stbi__getn) for a known number of bytes,
// which must never come up short. A short read of a different size than the
// first is therefore an exact read that ran off the end.
class StbMemoryReader {
 public:
  explicit StbMemoryReader(std::span<const unsigned char> bytes) : bytes_(bytes) {}

  static const stbi_io_callbacks& callbacks() {
    static const stbi_io_callbacks kCallbacks = {&StbMemoryReader::read, &StbMemoryReader::skip, &StbMemoryReader::eof};
    return kCallbacks;
  }

  bool readPastEnd() const { return readPastEnd_; }

 private:
  static int read(void* user, char* data, int size) {
    auto& self = *static_cast<StbMemoryReader*>(user);
    if (size <= 0) return 0;
    const std::size_t remaining = self.bytes_.size() - self.position_;
    const std::size_t count = std::min(remaining, std::size_t(size));
    if (self.refillSize_ == 0) self.refillSize_ = size;
    if (remaining == 0 || (count < std::size_t(size) && size != self.refillSize_)) self.readPastEnd_ = true;
    std::memcpy(data, self.bytes_.data() + self.position_, count);
    self.position_ += count;
    return int(count);
  }

  static void skip(void* user, int n) {
    auto& self = *static_cast<StbMemoryReader*>(user);
    if (n < 0) {
      self.position_ -= std::min(self.position_, std::size_t(-std::int64_t(n)));
      return;
    }
    if (std::size_t(n) > self.bytes_.size() - self.position_) self.readPastEnd_ = true;
    self.position_ = std::min(self.bytes_.size(), self.position_ + std::size_t(n));
  }

  static int eof(void* user) {
    const auto& self = *static_cast<StbMemoryReader*>(user);
    return self.position_ >= self.bytes_.size() ? 1 : 0;
  }

  std::span<const unsigned char> bytes_;
  std::size_t position_ = 0;
  int refillSize_ = 0;
  bool readPastEnd_ = false;
};

struct StbFree {
  void operator()(void* pixels) const { stbi_image_free(pixels); }
};

// Runs one stb call over a fresh reader and turns every kind of failure into an
// ImageIoError. stbCall(callbacks, user) returns the decoded pixels (or nullptr).
template <typename T, typename Call>
std::unique_ptr<T, StbFree> callStb(const fs::path& path, std::span<const unsigned char> bytes, Call&& stbCall) {
  StbMemoryReader reader(bytes);
  std::unique_ptr<T, StbFree> pixels(stbCall(&StbMemoryReader::callbacks(), &reader));
  if (reader.readPastEnd()) fail(path, "truncated or corrupt (decoder read past end of file)");
  if (!pixels) {
    const char* reason = stbi_failure_reason();
    fail(path, std::string("cannot decode (") + (reason ? reason : "unknown reason") + ")");
  }
  return pixels;
}

std::vector<std::string> stbChannelNames(int components) {
  // Grey becomes RGB and grey+alpha RGBA, so callers only ever see colour.
  if (components == 2 || components == 4) return {"R", "G", "B", "A"};
  return {"R", "G", "B"};
}

// Copies an stb pixel array into an RGB(A) image, expanding grey and decoding
// colour (not alpha) with the given per-value functions.
template <typename T, typename ColourFn, typename AlphaFn>
ImageF convertStbPixels(const T* pixels, int width, int height, int components, ColourFn&& colour, AlphaFn&& alpha) {
  ImageF image(width, height, stbChannelNames(components));
  const std::size_t pixelCount = std::size_t(width) * std::size_t(height);
  const bool grey = components <= 2;
  const bool hasAlpha = components == 2 || components == 4;
  float* out = image.pixels.data();
  for (std::size_t i = 0; i < pixelCount; ++i) {
    const T* in = pixels + i * std::size_t(components);
    for (int c = 0; c < 3; ++c) *out++ = colour(in[grey ? 0 : c]);
    if (hasAlpha) *out++ = alpha(in[components - 1]);
  }
  return image;
}

// What a PNG or JPEG header says, read without decoding a pixel.
struct StbHeader {
  int width = 0;
  int height = 0;
  int components = 0;
  bool sixteenBit = false;
};

StbHeader readStbHeader(const fs::path& path, const std::vector<unsigned char>& bytes, FileFormat format) {
  if (bytes.size() > std::size_t(INT32_MAX)) fail(path, "file too large for the PNG/JPEG decoder");
  // The size comes from the header first, so a corrupt one cannot make the
  // decoder allocate gigabytes.
  StbHeader header;
  {
    StbMemoryReader reader(bytes);
    const int ok = stbi_info_from_callbacks(&StbMemoryReader::callbacks(), &reader, &header.width, &header.height,
                                            &header.components);
    if (reader.readPastEnd()) fail(path, "truncated or corrupt (decoder read past end of file)");
    if (!ok) {
      const char* reason = stbi_failure_reason();
      fail(path, std::string("cannot decode header (") + (reason ? reason : "unknown reason") + ")");
    }
  }
  checkReadSize(path, header.width, header.height);
  StbMemoryReader probe(bytes);
  header.sixteenBit =
      format == FileFormat::Png && stbi_is_16_bit_from_callbacks(&StbMemoryReader::callbacks(), &probe) != 0;
  return header;
}

ImageF readWithStb(const fs::path& path, FileFormat format) {
  const std::vector<unsigned char> bytes = readFileBytes(path);
  const StbHeader header = readStbHeader(path, bytes, format);
  int width = header.width;
  int height = header.height;
  int components = header.components;

  if (header.sixteenBit) {
    auto pixels = callStb<stbi_us>(path, bytes, [&](const stbi_io_callbacks* io, void* user) {
      return stbi_load_16_from_callbacks(io, user, &width, &height, &components, 0);
    });
    // A table keeps the per-pixel pow() out of large images; it is still the
    // shared srgbDecode that fills it.
    std::vector<float> decode(65536);
    for (std::size_t v = 0; v < decode.size(); ++v) decode[v] = shared::srgbDecode(float(v) / 65535.0f);
    return convertStbPixels(
        pixels.get(), width, height, components, [&](stbi_us v) { return decode[v]; },
        [](stbi_us v) { return float(v) / 65535.0f; });
  }

  auto pixels = callStb<stbi_uc>(path, bytes, [&](const stbi_io_callbacks* io, void* user) {
    return stbi_load_from_callbacks(io, user, &width, &height, &components, 0);
  });
  std::array<float, 256> decode{};
  for (std::size_t v = 0; v < decode.size(); ++v) decode[v] = shared::srgbDecode(float(v) / 255.0f);
  return convertStbPixels(
      pixels.get(), width, height, components, [&](stbi_uc v) { return decode[v]; },
      [](stbi_uc v) { return float(v) / 255.0f; });
}

void checkFinite(const fs::path& path, const ImageF& image) {
  std::size_t badCount = 0;
  std::size_t firstBad = 0;
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    if (!std::isfinite(image.pixels[i])) {
      if (badCount == 0) firstBad = i;
      ++badCount;
    }
  }
  if (badCount == 0) return;
  const std::size_t channelCount = image.channelCount();
  const std::size_t pixel = firstBad / channelCount;
  fail(path, std::to_string(badCount) + (badCount == 1 ? " non-finite value" : " non-finite values") +
                 " (NaN or Inf), first at pixel (" + std::to_string(pixel % std::size_t(image.width)) + ", " +
                 std::to_string(pixel / std::size_t(image.width)) + ") channel " +
                 image.channels[firstBad % channelCount]);
}

// --- writing

// Rejects images that are inconsistent or that readImage would refuse, so a
// bad ImageF is reported at the write that produced it rather than later.
void validateForWrite(const fs::path& path, const ImageF& image) {
  if (image.width <= 0 || image.height <= 0) {
    fail(path, "cannot write an image of size " + sizeText(image.width, image.height));
  }
  if (image.width > kMaxSide || image.height > kMaxSide) {
    fail(path, "cannot write an image of size " + sizeText(image.width, image.height) + " (more than " +
                   std::to_string(kMaxSide) + " pixels a side)");
  }
  if (image.channels.empty()) fail(path, "cannot write an image with no channels");
  std::set<std::string> seen;
  for (const std::string& name : image.channels) {
    if (name.empty()) fail(path, "cannot write an image with an empty channel name");
    if (!seen.insert(name).second) fail(path, "cannot write an image with channel \"" + name + "\" twice");
  }
  const std::size_t expected = std::size_t(image.width) * std::size_t(image.height) * image.channels.size();
  if (image.pixels.size() != expected) {
    fail(path, "image " + sizeText(image.width, image.height) + " with " + std::to_string(image.channels.size()) +
                   " channels needs " + std::to_string(expected) + " values but has " +
                   std::to_string(image.pixels.size()));
  }
}

}  // namespace

TemporaryFile createTemporaryBeside(const fs::path& target) {
  // The name carries 64 random bits, not the process id: a name someone can
  // predict is a name someone can plant a link at. O_EXCL with O_NOFOLLOW
  // then makes the open fail on anything already there, a link included,
  // instead of writing through it.
  std::random_device random;
  for (int attempt = 0; attempt < 16; ++attempt) {
    const std::uint64_t bits = (std::uint64_t(random()) << 32) ^ std::uint64_t(random());
    char suffix[24];
    std::snprintf(suffix, sizeof suffix, ".tmp-%016llx", static_cast<unsigned long long>(bits));
    fs::path name = target;
    name += suffix;
    const int fd = ::open(name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd >= 0) return {std::move(name), fd, 0};
    if (errno != EEXIST) return {std::move(name), -1, errno};
  }
  return {target, -1, EEXIST};
}

void moveIntoPlace(const fs::path& temporary, const fs::path& target) {
  // rename() would replace a link at the target with the file, not write
  // through it, but the link is the user's, and so is anything that is not
  // a regular file: neither is replaced.
  struct stat status {};
  std::string refusal;
  if (::lstat(target.c_str(), &status) == 0) {
    if (S_ISLNK(status.st_mode))
      refusal = "is a symbolic link; not replaced (Bounce writes regular files only, never through or over a link)";
    else if (S_ISDIR(status.st_mode))
      refusal = "is a folder; not replaced";
    else if (!S_ISREG(status.st_mode))
      refusal = "is not a regular file; not replaced";
  }
  if (refusal.empty() && ::rename(temporary.c_str(), target.c_str()) != 0)
    refusal = std::string("cannot move the written file into place (") + std::strerror(errno) + ")";
  if (!refusal.empty()) {
    ::unlink(temporary.c_str());
    fail(target, refusal);
  }
}

void writeFileAtomically(const fs::path& path, const void* data, std::size_t size) {
  if (path.empty() || !path.has_filename()) fail(path, "not a file path");
  const fs::path parent = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  std::error_code ec;
  const fs::file_status parentStatus = fs::status(parent, ec);
  if (parentStatus.type() == fs::file_type::not_found) {
    fail(path, "directory " + parent.string() + " does not exist");
  }
  if (parentStatus.type() != fs::file_type::directory) fail(path, parent.string() + " is not a directory");

  const TemporaryFile temporary = createTemporaryBeside(path);
  if (temporary.fd < 0)
    fail(path, "cannot create " + temporary.path.string() + " to write it into first (" +
                   std::strerror(temporary.error) + ")");
  const auto* bytes = static_cast<const char*>(data);
  std::size_t written = 0;
  int error = 0;
  while (written < size) {
    const ssize_t n = ::write(temporary.fd, bytes + written, size - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      error = n < 0 ? errno : EIO;
      break;
    }
    written += std::size_t(n);
  }
  // close reports what a network file system kept back until then.
  if (::close(temporary.fd) != 0 && error == 0) error = errno;
  if (error != 0) {
    ::unlink(temporary.path.c_str());
    fail(path, std::string("cannot write (") + std::strerror(error) + ")");
  }
  moveIntoPlace(temporary.path, path);
}

namespace {

// The colour of one pixel of an image with 1 to 4 channels.
glm::vec3 pixelColour(const float* in, std::size_t channelCount) {
  if (channelCount == 1) return glm::vec3(in[0]);
  if (channelCount == 2) return glm::vec3(in[0], in[1], 0.0f);  // e.g. motion vectors: x in red, y in green
  return glm::vec3(in[0], in[1], in[2]);
}

glm::vec3 encodeForDisplay(glm::vec3 rgb, PngEncoding encoding, float exposure) {
  switch (encoding) {
    case PngEncoding::Tonemapped:
      return shared::displayEncode(glm::min(rgb, glm::vec3(kTonemapInputLimit / exposure)), exposure);
    case PngEncoding::Srgb:
      return shared::srgbEncode(glm::clamp(rgb, 0.0f, 1.0f));
    case PngEncoding::Linear:
      break;
  }
  return glm::clamp(rgb, 0.0f, 1.0f);
}

std::uint8_t toByte(float v) { return std::uint8_t(std::floor(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f)); }

}  // namespace

ImageF::ImageF(int w, int h, std::vector<std::string> channelNames)
    : width(w), height(h), channels(std::move(channelNames)) {
  if (w < 0 || h < 0) throw std::invalid_argument("ImageF: negative size " + sizeText(w, h));
  pixels.assign(std::size_t(w) * std::size_t(h) * channels.size(), 0.0f);
}

Rgba8Info rgba8Info(std::span<const unsigned char> bytes, const std::string& name, int maxSide) {
  const fs::path path(name);
  const bool png = bytes.size() >= 4 && std::memcmp(bytes.data(), "\x89PNG", 4) == 0;
  const bool jpeg = bytes.size() >= 3 && std::memcmp(bytes.data(), "\xff\xd8\xff", 3) == 0;
  if (!png && !jpeg) fail(path, "not a PNG or JPEG image");
  if (bytes.size() > std::size_t(INT32_MAX)) fail(path, "file too large for the PNG/JPEG decoder");
  const auto refuseOverLimit = [&](std::int64_t width, std::int64_t height) {
    if (width > maxSide || height > maxSide)
      fail(path, "image size " + sizeText(width, height) + " is over the limit of " + std::to_string(maxSide) +
                     " pixels a side");
  };
  // stb calls the header of a PNG with more than 2^30 bytes of pixels
  // corrupt, so a PNG's size is read from its IHDR chunk (always the first) here.
  if (png && bytes.size() >= 24 && std::memcmp(bytes.data() + 12, "IHDR", 4) == 0) {
    const auto bigEndian32 = [&](std::size_t at) {
      return std::int64_t(bytes[at]) << 24 | std::int64_t(bytes[at + 1]) << 16 | std::int64_t(bytes[at + 2]) << 8 |
             std::int64_t(bytes[at + 3]);
    };
    refuseOverLimit(bigEndian32(16), bigEndian32(20));
  }
  int width = 0, height = 0, components = 0;
  {
    StbMemoryReader reader(bytes);
    const int ok = stbi_info_from_callbacks(&StbMemoryReader::callbacks(), &reader, &width, &height, &components);
    if (reader.readPastEnd() || !ok) fail(path, "truncated or corrupt header");
  }
  refuseOverLimit(width, height);
  checkReadSize(path, width, height);
  StbMemoryReader probe(bytes);
  const bool sixteenBit = png && stbi_is_16_bit_from_callbacks(&StbMemoryReader::callbacks(), &probe) != 0;
  // stb copies a PNG's compressed data out of the file, inflates its rows
  // (the samples and a filter byte a row), unfilters them into a second
  // buffer of samples and converts those to RGBA in a third, which
  // decodeRgba8 copies into the image it returns: at most two of those
  // three buffers live at once.
  const std::uint64_t pixels = std::uint64_t(width) * std::uint64_t(height);
  const std::uint64_t samples = pixels * std::uint64_t(components) * (sixteenBit ? 2 : 1) + std::uint64_t(height);
  return {width, height, bytes.size() + std::max(2 * samples, samples + 4 * pixels)};
}

Rgba8Image decodeRgba8(std::span<const unsigned char> bytes, const std::string& name, int maxSide) {
  const fs::path path(name);
  const Rgba8Info info = rgba8Info(bytes, name, maxSide);
  int width = info.width, height = info.height, components = 0;
  auto pixels = callStb<stbi_uc>(path, bytes, [&](const stbi_io_callbacks* io, void* user) {
    return stbi_load_from_callbacks(io, user, &width, &height, &components, 4);
  });
  Rgba8Image image{width, height, {}};
  image.rgba8.assign(pixels.get(), pixels.get() + std::size_t(width) * std::size_t(height) * 4);
  return image;
}

std::string memoryText(std::uint64_t bytes) {
  const char* units[] = {"bytes", "KiB", "MiB", "GiB", "TiB"};
  double value = double(bytes);
  int unit = 0;
  while (value >= 1024.0 && unit < 4) {
    value /= 1024.0;
    ++unit;
  }
  char text[32];
  if (unit == 0)
    std::snprintf(text, sizeof text, "%llu bytes", static_cast<unsigned long long>(bytes));
  else
    std::snprintf(text, sizeof text, value < 10.0 ? "%.1f %s" : "%.0f %s", value, units[unit]);
  return text;
}

void refuseOverMemoryLimit(const fs::path& file, std::uint64_t bytes, const std::string& what) {
  if (bytes <= kImageMemoryLimit) return;
  fail(file, what + " needs about " + memoryText(bytes) + " of memory, more than the limit of " +
                 memoryText(kImageMemoryLimit) + " (docs/reliability.md)");
}

bool holdsRadiance(const fs::path& path) {
  try {
    const FileFormat format = detectFormat(readFileBytes(path, 16));
    return format == FileFormat::Exr || format == FileFormat::Hdr;
  } catch (const std::exception&) {
    return false;
  }
}

ImageInfo readImageInfo(const fs::path& path) {
  checkReadableFile(path);
  try {
    const std::vector<unsigned char> head = readFileBytes(path, 16);
    if (head.empty()) fail(path, "empty file");
    const FileFormat format = detectFormat(head);
    if (format == FileFormat::Unknown) fail(path, "unsupported image format (expected EXR, HDR, PNG or JPEG)");
    std::error_code ec;
    const std::uint64_t fileSize = fs::file_size(path, ec);
    if (ec) fail(path, "cannot access (" + ec.message() + ")");
    if (format == FileFormat::Exr) return readExrInfo(path);
    if (format == FileFormat::Hdr) {
      // Radiance headers are a few short lines; a file whose header is longer
      // than the first mebibyte is read whole to find its end.
      constexpr std::size_t kHeaderProbe = std::size_t(1) << 20;
      RadianceHeader header;
      try {
        header = readRadianceHeader(path, readFileBytes(path, kHeaderProbe), fileSize, int(kMaxSide), kMaxImagePixels);
      } catch (const ImageIoError&) {
        if (fileSize <= kHeaderProbe) throw;
        header = readRadianceHeader(path, readFileBytes(path), fileSize, int(kMaxSide), kMaxImagePixels);
      }
      // The decoder holds the whole file and one scanline of RGBE.
      return {header.width, header.height, 3, fileSize + 4 * std::uint64_t(header.width), {"R", "G", "B"}};
    }
    const StbHeader header = readStbHeader(path, readFileBytes(path), format);
    // stb holds the file, its inflated or decoded samples and the pixels it
    // makes of them (twice the samples when a PNG is interlaced), the last
    // until they are converted to float.
    const std::uint64_t samples = std::uint64_t(header.width) * std::uint64_t(header.height) *
                                  std::uint64_t(header.components) * (header.sixteenBit ? 2 : 1);
    const std::vector<std::string> names = stbChannelNames(header.components);
    return {header.width, header.height, names.size(), 2 * fileSize + 3 * samples, names};
  } catch (const ImageIoError&) {
    throw;
  } catch (const std::bad_alloc&) {
    fail(path, "out of memory while reading the header");
  } catch (const std::exception& e) {
    fail(path, std::string("cannot read EXR (") + e.what() + ")");
  }
}

ImageF readImage(const fs::path& path, bool allowNonFinite) {
  checkReadableFile(path);
  ImageF image;
  try {
    const std::vector<unsigned char> head = readFileBytes(path, 16);
    if (head.empty()) fail(path, "empty file");
    const FileFormat format = detectFormat(head);
    if (format == FileFormat::Unknown) {
      fail(path, "unsupported image format (expected EXR, HDR, PNG or JPEG)");
    }
    if (format == FileFormat::Exr) {
      image = readExr(path);
    } else if (format == FileFormat::Hdr) {
      image = decodeRadianceHdr(path, readFileBytes(path), int(kMaxSide), kMaxImagePixels);
    } else {
      image = readWithStb(path, format);
    }
  } catch (const ImageIoError&) {
    throw;
  } catch (const std::bad_alloc&) {
    fail(path, "out of memory while reading");
  } catch (const std::exception& e) {
    // OpenEXR reports through Iex exceptions, which derive from std::exception.
    fail(path, std::string("cannot read EXR (") + e.what() + ")");
  }
  if (!allowNonFinite) checkFinite(path, image);
  return image;
}

void writeExr(const fs::path& path, const ImageF& image) {
  validateForWrite(path, image);
  for (const std::string& name : image.channels) {
    if (name.size() > kMaxExrChannelNameLength) fail(path, "EXR channel name too long: \"" + name + "\"");
  }
  std::string encoded;
  try {
    Imf::Header header(image.width, image.height);
    header.compression() = Imf::ZIP_COMPRESSION;
    for (const std::string& name : image.channels) header.channels().insert(name, Imf::Channel(Imf::FLOAT));

    const std::size_t channelCount = image.channels.size();
    const std::size_t xStride = sizeof(float) * channelCount;
    const std::size_t yStride = xStride * std::size_t(image.width);
    Imf::FrameBuffer frameBuffer;
    for (std::size_t c = 0; c < channelCount; ++c) {
      frameBuffer.insert(image.channels[c],
                         Imf::Slice::Make(Imf::FLOAT, image.pixels.data() + c, header.dataWindow(), xStride, yStride));
    }
    // Encoded in memory: OutputFile's destructor writes the offset table and
    // swallows any error doing so, which on a real file could leave a corrupt
    // file that looks written.
    Imf::StdOSStream stream;
    {
      Imf::OutputFile file(stream, header);
      file.setFrameBuffer(frameBuffer);
      file.writePixels(image.height);
    }
    encoded = stream.str();
  } catch (const std::exception& e) {
    fail(path, std::string("cannot encode EXR (") + e.what() + ")");
  }
  writeFileAtomically(path, encoded.data(), encoded.size());
}

ImageF firstChannels(const ImageF& image, std::size_t count) {
  count = std::min(count, image.channelCount());
  std::vector<std::string> names(image.channels.begin(), image.channels.begin() + long(count));
  ImageF out(image.width, image.height, names);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      for (std::size_t c = 0; c < count; ++c) out.at(x, y, int(c)) = image.at(x, y, int(c));
  return out;
}

std::uint8_t displayByte(float value) { return toByte(value); }

glm::vec3 displayColour(const float* pixel, std::size_t channelCount, PngEncoding encoding, float exposure) {
  const glm::vec3 rgb = pixelColour(pixel, channelCount);
  const bool bad = !std::isfinite(rgb.x) || !std::isfinite(rgb.y) || !std::isfinite(rgb.z);
  return bad ? glm::vec3(1.0f, 0.0f, 1.0f) : encodeForDisplay(rgb, encoding, exposure);
}

ImageF toDisplay(const ImageF& image, PngEncoding encoding, float exposure) {
  ImageF display(image.width, image.height, {"R", "G", "B"});
  const std::size_t channelCount = image.channelCount();
  for (std::size_t i = 0; i < std::size_t(image.width) * std::size_t(image.height); ++i) {
    const glm::vec3 encoded = displayColour(image.pixels.data() + i * channelCount, channelCount, encoding, exposure);
    for (int c = 0; c < 3; ++c) display.pixels[i * 3 + std::size_t(c)] = encoded[c];
  }
  return display;
}

void writePng(const fs::path& path, const ImageF& image, PngEncoding encoding, float exposure) {
  validateForWrite(path, image);
  if (encoding == PngEncoding::Tonemapped && !(std::isfinite(exposure) && exposure >= 0.0f)) {
    fail(path, "exposure must be finite and non-negative (got " + std::to_string(exposure) + ")");
  }
  const std::size_t channelCount = image.channelCount();
  const std::size_t pixelCount = std::size_t(image.width) * std::size_t(image.height);
  const bool hasAlpha = channelCount == 4;
  bool anyNonFinite = false;
  for (float v : image.pixels) anyNonFinite = anyNonFinite || !std::isfinite(v);
  // A grey image with bad values is written as RGB so the magenta shows.
  const int outComponents = hasAlpha ? 4 : (channelCount == 1 && !anyNonFinite ? 1 : 3);

  const auto encode = [&](glm::vec3 rgb) { return encodeForDisplay(rgb, encoding, exposure); };

  std::vector<std::uint8_t> bytes(pixelCount * std::size_t(outComponents));
  std::uint8_t* out = bytes.data();
  for (std::size_t i = 0; i < pixelCount; ++i) {
    const float* in = image.pixels.data() + i * channelCount;
    const glm::vec3 rgb = pixelColour(in, channelCount);
    const float alpha = hasAlpha ? in[3] : 1.0f;
    const bool bad = !std::isfinite(rgb.x) || !std::isfinite(rgb.y) || !std::isfinite(rgb.z) || !std::isfinite(alpha);
    if (bad) {
      const std::uint8_t magenta[4] = {255, 0, 255, 255};
      out = std::copy_n(magenta, outComponents, out);
      continue;
    }
    const glm::vec3 encoded = encode(rgb);
    *out++ = toByte(encoded.x);
    if (outComponents >= 3) {
      *out++ = toByte(encoded.y);
      *out++ = toByte(encoded.z);
    }
    if (hasAlpha) *out++ = toByte(alpha);
  }

  writePngBytes(path, image.width, image.height, outComponents, bytes);
}

void writePngBytes(const fs::path& path, int width, int height, int components, std::span<const std::uint8_t> bytes) {
  if (width <= 0 || height <= 0 || width > kMaxSide || height > kMaxSide)
    fail(path, "cannot write an image of size " + sizeText(width, height));
  if (components < 1 || components > 4)
    fail(path, "cannot write a PNG of " + std::to_string(components) + " components");
  if (bytes.size() != std::size_t(width) * std::size_t(height) * std::size_t(components))
    fail(path, "image " + sizeText(width, height) + " of " + std::to_string(components) + " components needs " +
                   std::to_string(std::size_t(width) * std::size_t(height) * std::size_t(components)) +
                   " bytes but has " + std::to_string(bytes.size()));
  std::vector<std::uint8_t> encodedPng;
  const auto append = [](void* context, void* data, int size) {
    auto& buffer = *static_cast<std::vector<std::uint8_t>*>(context);
    const auto* begin = static_cast<const std::uint8_t*>(data);
    buffer.insert(buffer.end(), begin, begin + size);
  };
  const int ok =
      stbi_write_png_to_func(append, &encodedPng, width, height, components, bytes.data(), width * components);
  if (!ok || encodedPng.empty()) fail(path, "cannot encode PNG");
  writeFileAtomically(path, encodedPng.data(), encodedPng.size());
}

std::uint64_t pngWriteBytes(std::uint64_t pixels, int components) { return 4 * pixels * std::uint64_t(components + 1); }

namespace {

// PNG chunk CRC (ISO 3309, as in the PNG specification's sample code).
std::uint32_t pngCrc(const std::uint8_t* data, std::size_t size, std::uint32_t crc = 0xffffffffu) {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t n = 0; n < 256; ++n) {
      std::uint32_t c = n;
      for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xedb88320u ^ (c >> 1) : c >> 1;
      t[n] = c;
    }
    return t;
  }();
  for (std::size_t i = 0; i < size; ++i) crc = table[(crc ^ data[i]) & 0xffu] ^ (crc >> 8);
  return crc;
}

void appendBigEndian(std::vector<std::uint8_t>& out, std::uint32_t value, int bytes = 4) {
  for (int i = bytes - 1; i >= 0; --i) out.push_back(std::uint8_t(value >> (8 * i)));
}

void appendChunk(std::vector<std::uint8_t>& out, const char type[4], const std::vector<std::uint8_t>& data) {
  appendBigEndian(out, std::uint32_t(data.size()));
  const std::size_t typeStart = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data.begin(), data.end());
  appendBigEndian(out, pngCrc(out.data() + typeStart, data.size() + 4) ^ 0xffffffffu);
}

struct PngChunk {
  std::string type;
  std::vector<std::uint8_t> data;
};

// The chunks of a PNG that stb just wrote (trusted input: no checks beyond bounds).
std::vector<PngChunk> pngChunks(const std::vector<std::uint8_t>& png) {
  std::vector<PngChunk> chunks;
  std::size_t at = 8;
  while (at + 12 <= png.size()) {
    const std::uint32_t length = (std::uint32_t(png[at]) << 24) | (std::uint32_t(png[at + 1]) << 16) |
                                 (std::uint32_t(png[at + 2]) << 8) | std::uint32_t(png[at + 3]);
    if (at + 12 + length > png.size()) break;
    chunks.push_back({std::string(png.begin() + long(at + 4), png.begin() + long(at + 8)),
                      std::vector<std::uint8_t>(png.begin() + long(at + 8), png.begin() + long(at + 8 + length))});
    at += 12 + length;
  }
  return chunks;
}

}  // namespace

void writeApng(const fs::path& path, const std::vector<ImageF>& frames, float framesPerSecond) {
  if (frames.empty()) fail(path, "an animation needs at least one frame");
  if (!(framesPerSecond > 0.0f && framesPerSecond <= 1000.0f))
    fail(path, "frames per second must be in (0, 1000] (got " + std::to_string(framesPerSecond) + ")");
  const int width = frames.front().width, height = frames.front().height;
  std::vector<std::uint8_t> out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  std::uint32_t sequence = 0;
  // Delays as a fraction of a second: 1000 / (1000 * fps) keeps e.g. 30 fps exact enough.
  const std::uint16_t delayDenominator = 1000;
  const auto delayNumerator = std::uint16_t(std::clamp(std::lround(1000.0f / framesPerSecond), 1l, 65535l));
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const ImageF& frame = frames[f];
    validateForWrite(path, frame);
    if (frame.width != width || frame.height != height || frame.channelCount() != 3)
      fail(path, "frame " + std::to_string(f) + " is " + sizeText(frame.width, frame.height) + " with " +
                     std::to_string(frame.channelCount()) + " channels; every frame must be RGB " +
                     sizeText(width, height));
    std::vector<std::uint8_t> bytes(frame.pixels.size());
    for (std::size_t i = 0; i < bytes.size(); ++i)
      bytes[i] = std::isfinite(frame.pixels[i]) ? toByte(frame.pixels[i]) : std::uint8_t(i % 3 == 1 ? 0 : 255);
    std::vector<std::uint8_t> png;
    const auto append = [](void* context, void* data, int size) {
      auto& buffer = *static_cast<std::vector<std::uint8_t>*>(context);
      buffer.insert(buffer.end(), static_cast<const std::uint8_t*>(data),
                    static_cast<const std::uint8_t*>(data) + size);
    };
    if (!stbi_write_png_to_func(append, &png, width, height, 3, bytes.data(), width * 3) || png.empty())
      fail(path, "cannot encode frame " + std::to_string(f));
    const std::vector<PngChunk> chunks = pngChunks(png);
    if (f == 0) {
      appendChunk(out, "IHDR", chunks.front().data);
      std::vector<std::uint8_t> animation;
      appendBigEndian(animation, std::uint32_t(frames.size()));
      appendBigEndian(animation, 0);  // loop for ever
      appendChunk(out, "acTL", animation);
    }
    std::vector<std::uint8_t> control;
    appendBigEndian(control, sequence++);
    appendBigEndian(control, std::uint32_t(width));
    appendBigEndian(control, std::uint32_t(height));
    appendBigEndian(control, 0);  // x offset
    appendBigEndian(control, 0);  // y offset
    appendBigEndian(control, delayNumerator, 2);
    appendBigEndian(control, delayDenominator, 2);
    control.push_back(0);  // dispose: none
    control.push_back(0);  // blend: source
    appendChunk(out, "fcTL", control);
    for (const PngChunk& chunk : chunks) {
      if (chunk.type != "IDAT") continue;
      if (f == 0) {
        appendChunk(out, "IDAT", chunk.data);  // the first frame doubles as the still image
      } else {
        std::vector<std::uint8_t> data;
        appendBigEndian(data, sequence++);
        data.insert(data.end(), chunk.data.begin(), chunk.data.end());
        appendChunk(out, "fdAT", data);
      }
    }
  }
  appendChunk(out, "IEND", {});
  writeFileAtomically(path, out.data(), out.size());
}

}  // namespace bounce::io

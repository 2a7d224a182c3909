// Image files: read EXR (every compression OpenEXR supports), Radiance .hdr,
// PNG and JPEG into linear float; write PNG (8-bit sRGB, tonemapped or not)
// and multi-channel float EXR. No Vulkan here: this layer sits beside gpu/.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace bounce::io {

// Any problem with an image file. what() always names the file and the reason.
class ImageIoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A linear float image with interleaved, named channels
// (pixel (x, y) channel c is pixels[(y * width + x) * channels.size() + c];
// row 0 is the top row).
struct ImageF {
  int width = 0;
  int height = 0;
  std::vector<std::string> channels;  // e.g. {"R", "G", "B", "A"} or {"viewZ"}
  std::vector<float> pixels;

  ImageF() = default;
  ImageF(int w, int h, std::vector<std::string> channelNames);

  std::size_t channelCount() const { return channels.size(); }
  float& at(int x, int y, int c) { return pixels[(std::size_t(y) * width + x) * channels.size() + c]; }
  float at(int x, int y, int c) const { return pixels[(std::size_t(y) * width + x) * channels.size() + c]; }
};

// How a float image becomes 8-bit PNG values.
enum class PngEncoding {
  Tonemapped,  // exposure, ACES fitted tonemap, sRGB encode (for radiance)
  Srgb,        // sRGB encode of values clamped to [0,1] (for albedo-like data)
  Linear,      // values clamped to [0,1] and stored as they are (for masks, plots)
};

// The most pixels an image file may hold (16384 x 16384, 4 GiB as float
// RGBA); a larger declared size is refused before anything is allocated.
constexpr std::int64_t kMaxImagePixels = std::int64_t(1) << 28;

// Reads an image; the format is chosen by the file's signature (not its
// extension). PNG/JPEG are decoded from sRGB to linear; EXR/HDR are linear.
// Channels come back as {"R","G","B"} or {"R","G","B","A"} (a single-channel
// EXR keeps its own channel name). Throws ImageIoError for missing, unreadable,
// truncated or unsupported files, zero or absurd sizes (more than 65536 pixels
// a side or kMaxImagePixels in all), and, unless allowNonFinite, any NaN or Inf value (naming the first
// bad pixel and the count).
ImageF readImage(const std::filesystem::path& path, bool allowNonFinite = false);

// What readImage would make of a file, from its header alone: nothing is
// decoded, so a command can work out the memory its images will take before
// it reads them (docs/reliability.md).
struct ImageInfo {
  int width = 0;
  int height = 0;
  std::size_t channels = 0;        // of the ImageF readImage returns
  std::uint64_t decoderBytes = 0;  // what decoding needs beside that image (file bytes, decoded samples), at most
  std::vector<std::string> channelNames;  // those channels, as readImage names them

  std::uint64_t pixels() const { return std::uint64_t(width) * std::uint64_t(height); }
  // The ImageF's pixels.
  std::uint64_t imageBytes() const { return pixels() * channels * sizeof(float); }
  // The most readImage holds at once while it reads the file.
  std::uint64_t readBytes() const { return imageBytes() + decoderBytes; }
};

// Reads a file's header as readImage does, with the same errors for a file
// that is missing, empty, of an unknown format or with a header readImage
// refuses (a corrupt one, a size of zero or over the limits above). A file
// whose pixels are damaged passes: only readImage finds that.
ImageInfo readImageInfo(const std::filesystem::path& path);

// The most memory a command may plan for its images at once: 2 GiB. A small
// file can declare a huge image (a 261 KB PNG of 16384 x 16384 zeros), so
// commands work out their peak from the headers (readImageInfo) and refuse
// beyond this before decoding, rather than let the kernel end the process,
// or another one (docs/reliability.md says what each command counts).
inline constexpr std::uint64_t kImageMemoryLimit = std::uint64_t(2) << 30;

// Bytes as people read them: "1.3 GiB", "640 MiB", "12 KiB".
std::string memoryText(std::uint64_t bytes);

// Throws ImageIoError "FILE: WHAT needs about 9.6 GiB of memory, more than
// the limit of 2.0 GiB (docs/reliability.md)" when bytes is over
// kImageMemoryLimit; `what` says what for ("comparing two 16384x16384 images").
void refuseOverMemoryLimit(const std::filesystem::path& file, std::uint64_t bytes, const std::string& what);

// Whether a file holds linear radiance (EXR, Radiance HDR) rather than
// display values (PNG, JPEG), by its signature as readImage decides; false
// for a file that cannot be read.
bool holdsRadiance(const std::filesystem::path& path);

// 8-bit RGBA pixels exactly as stored (no sRGB decoding), for textures.
struct Rgba8Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba8;  // width * height * 4, row 0 at the top
};

// Decodes a PNG or JPEG held in memory (e.g. inside a .glb) to RGBA8, with the
// same refusal of truncated or corrupt data as readImage. An image wider or
// taller than maxSide pixels is refused from its header, before a pixel is
// decoded ("image size 20000x20000 is over the limit of 16384 pixels a
// side"). `name` is used in the error message.
Rgba8Image decodeRgba8(std::span<const unsigned char> bytes, const std::string& name, int maxSide);

// What decodeRgba8 would make of the bytes, from the image's header alone,
// with the same errors for a header it refuses (not a PNG or JPEG, corrupt,
// over maxSide): nothing is decoded, so a caller can add up the memory its
// textures will take before it decodes any (docs/reliability.md).
struct Rgba8Info {
  int width = 0;
  int height = 0;
  std::uint64_t decoderBytes = 0;  // what decoding holds beside the result, at most (its copy of the file, samples)

  std::uint64_t imageBytes() const { return std::uint64_t(width) * std::uint64_t(height) * 4; }
};
Rgba8Info rgba8Info(std::span<const unsigned char> bytes, const std::string& name, int maxSide);

// A new, empty file beside `target`, "<target>.tmp-<16 random hex digits>",
// and its descriptor, open for writing (the caller closes it and removes or
// renames the file). Created exclusively (O_CREAT | O_EXCL | O_NOFOLLOW)
// under a name no one can predict: a file or a symbolic link planted at a
// name in the folder is never opened, so nothing is written through it.
// Never throws: `fd` is -1 and `error` the errno when it cannot be created.
struct TemporaryFile {
  std::filesystem::path path;
  int fd = -1;
  int error = 0;
};
TemporaryFile createTemporaryBeside(const std::filesystem::path& target);

// Renames `temporary` to `target`, which must be missing or a regular file:
// a symbolic link, a folder or anything else there is refused (ImageIoError
// "<target>: is a symbolic link; not replaced..."), never replaced, and the
// temporary is then removed.
void moveIntoPlace(const std::filesystem::path& temporary, const std::filesystem::path& target);

// Writes the bytes to a temporary file beside the target (createTemporaryBeside)
// and renames it into place (moveIntoPlace): a reader sees the old file or the
// complete new one, never a half file, a failed write removes its temporary,
// and a link at the target or at any temporary name is never written through.
// For any file, not only images. Throws ImageIoError "<path>: <reason>" (a
// folder that does not exist or cannot be written, a full disk, a symbolic
// link or a folder at the target).
void writeFileAtomically(const std::filesystem::path& path, const void* data, std::size_t size);

// Writes float32 channels with their names (ZIP compression). The file is
// written beside the target and renamed into place, so a failed write never
// leaves a half file. Throws ImageIoError.
void writeExr(const std::filesystem::path& path, const ImageF& image);

// The first `count` channels of an image (all of them when it has fewer),
// with their names: e.g. RGB without the alpha a GPU image carries.
ImageF firstChannels(const ImageF& image, std::size_t count);

// What writePng would show, as RGB display values in [0,1] (non-finite
// pixels magenta), e.g. to lay several images out on one contact sheet.
ImageF toDisplay(const ImageF& image, PngEncoding encoding, float exposure = 1.0f);

// The display colour of one pixel of a 1- to 4-channel image (its first
// channels, as toDisplay reads them): what toDisplay and writePng make of it.
glm::vec3 displayColour(const float* pixel, std::size_t channelCount, PngEncoding encoding, float exposure = 1.0f);

// A display value as writePng stores it: clamped to [0,1], in 8 bits.
std::uint8_t displayByte(float value);

// Writes 8-bit samples as they are (components 1 grey, 2 grey and alpha, 3
// RGB, 4 RGBA; rows top to bottom) as a PNG; writePng's atomic write and
// errors. For pictures made as bytes, which then need no float copy.
void writePngBytes(const std::filesystem::path& path, int width, int height, int components,
                   std::span<const std::uint8_t> bytes);

// The bytes writePngBytes needs at most beside the samples it is given, for
// an image of `pixels` pixels of `components` bytes: the filtered rows and
// the compressed stream (at worst larger than the samples), twice.
std::uint64_t pngWriteBytes(std::uint64_t pixels, int components);

// Writes an 8-bit PNG (RGB, or RGBA when the image has 4 channels; one channel
// becomes grey). Same atomic write and errors as writeExr.
void writePng(const std::filesystem::path& path, const ImageF& image, PngEncoding encoding = PngEncoding::Tonemapped,
              float exposure = 1.0f);

// Writes an animated PNG (APNG, looping) of RGB display values in [0,1]
// (e.g. from toDisplay), all frames the same size. Viewers without APNG
// support show the first frame. Same atomic write and errors as writePng.
void writeApng(const std::filesystem::path& path, const std::vector<ImageF>& frames, float framesPerSecond);

}  // namespace bounce::io

// The cases of the bad-input corpus (bad_input_corpus.h), by kind of input.
// Each section builds its cases from a valid input and one thing done wrong
// to it, so a case's name says exactly what it tests.
#include "bad_input_corpus.h"

#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "bounce/gi_settings.h"
#include "io/image_io.h"

namespace bounce::testing {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Bytes = std::vector<std::uint8_t>;

void writeBytes(const fs::path& path, const Bytes& bytes) {
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

void writeText(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

// Names are test names: letters, digits and underscores only.
std::string identifier(std::string text) {
  for (char& c : text)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return text;
}

std::string repeated(const std::string& text, int count) {
  std::string out;
  out.reserve(text.size() * std::size_t(count));
  for (int i = 0; i < count; ++i) out += text;
  return out;
}

// {"a":{"a":...1...}} nested `depth` deep.
std::string nestedObjects(int depth) { return repeated("{\"a\":", depth) + "1" + std::string(std::size_t(depth), '}'); }

class CorpusBuilder {
 public:
  std::vector<CorpusCase> cases;

  // A case whose one input is a text file.
  void textFile(const std::string& name, const std::string& file, std::string text, std::vector<std::string> arguments,
                const std::string& mentions, Outcome outcome = Outcome::Error) {
    add(
        name, file, [file, text = std::move(text)](const fs::path& dir) { writeText(dir / file, text); },
        std::move(arguments), mentions, outcome);
  }

  void binaryFile(const std::string& name, const std::string& file, Bytes bytes, std::vector<std::string> arguments,
                  const std::string& mentions, Outcome outcome = Outcome::Error) {
    add(
        name, file, [file, bytes = std::move(bytes)](const fs::path& dir) { writeBytes(dir / file, bytes); },
        std::move(arguments), mentions, outcome);
  }

  void add(const std::string& name, const std::string& file, std::function<void(const fs::path&)> write,
           std::vector<std::string> arguments, const std::string& mentions, Outcome outcome = Outcome::Error) {
    cases.push_back({identifier(name), std::move(write), std::move(arguments), outcome, file, mentions});
  }
};

// ---------------------------------------------------------------- GI settings files

void settingsFiles(CorpusBuilder& corpus) {
  const auto settings = [&](const std::string& name, std::string text, const std::string& mentions) {
    corpus.textFile("settings_" + name, "settings.json", std::move(text),
                    {"render", "cornell", "--gi-settings", "{dir}/settings.json", "--out", "{out}"}, mentions);
  };
  settings("not_json", "spatial_radius = 4", "parse error");
  settings("empty", "", "parse error");
  settings("truncated", R"({"diffuse": {"spatial_radius": 4)", "parse error");
  settings("trailing_comma", R"({"seed": 3,})", "parse error");
  settings("top_level_array", "[1, 2]", "the top level is a JSON array");
  settings("top_level_number", "24", "the top level is a JSON number");
  settings("top_level_null", "null", "the top level is a JSON null");
  settings("number_overflow", R"({"seed": 1e400})", "number overflow");
  settings("invalid_utf8_key", "{\"se\xff\xfe\": 1}", "parse error");
  settings("nested_100000", nestedObjects(100000), "nested deeper than 64 levels");
  settings("nested_arrays_100000", std::string(100000, '[') + std::string(100000, ']'), "nested deeper than 64 levels");
  settings("key_twice", R"({"seed": 1, "seed": 2})", "gi.seed is given more than once");
  settings("nested_and_dotted", R"({"diffuse": {"spatial_radius": 4}, "diffuse.spatial_radius": 5})", "more than once");
  settings("unknown_key", R"({"diffuse": {"spatial_radios": 4}})", "did you mean gi.diffuse.spatial_radius");
  settings("unknown_branch", R"({"diffuser": {"spatial_radius": 4}})", "unknown setting");
  settings("no_candidates",
           R"({"diffuse": {"screen_candidates": 0, "bright_candidates": 0, "environment_candidates": 0}})", "all 0");
  // Every key, given a value of each wrong kind: the file and the key are named.
  for (const gi::SettingInfo& info : gi::settingKeys()) {
    // Nest the key as a file would: {"diffuse": {"spatial_radius": V}}.
    const auto file = [&](const json& value) {
      json root = json::object();
      json* at = &root;
      std::string rest = info.key;
      for (std::size_t dot = rest.find('.'); dot != std::string::npos; dot = rest.find('.')) {
        at = &(*at)[rest.substr(0, dot)];
        rest = rest.substr(dot + 1);
      }
      (*at)[rest] = value;
      return root.dump();
    };
    const std::string key = "gi." + info.key;
    settings(info.key + "_array", file(json::array({1})), key + ": got a JSON array");
    settings(info.key + "_null", file(nullptr), key + ": got a JSON null");
    settings(info.key + "_word", file("banana"), "invalid value \"banana\" for " + key);
    if (info.type.starts_with("uint") || info.type.starts_with("float")) {
      settings(info.key + "_negative", file(-1), "for " + key);
      settings(info.key + "_huge", file(1e30), "for " + key);
    }
  }
}

// ---------------------------------------------------------------- camera keyframe files

void cameraFiles(CorpusBuilder& corpus) {
  const auto camera = [&](const std::string& name, std::string text, const std::string& mentions) {
    corpus.textFile("camera_" + name, "camera.json", std::move(text),
                    {"render", "cornell", "--camera", "{dir}/camera.json", "--frames", "3", "--out", "{out}"},
                    mentions);
  };
  const std::string good = R"({"time": 0, "position": [0, 1, 4], "target": [0, 1, 0]})";
  const auto keys = [](const std::string& list) { return "{\"keyframes\": [" + list + "]}"; };
  camera("not_json", "keyframes:", "invalid JSON");
  camera("empty_file", "", "invalid JSON");
  camera("top_level_array", "[" + good + "]", "expected an object");
  camera("no_keyframes", "{}", "\"keyframes\" must be an array");
  camera("keyframes_object", R"({"keyframes": {"time": 0}})", "\"keyframes\" must be an array");
  camera("keyframes_empty", keys(""), "\"keyframes\" is empty");
  camera("unknown_top_field", R"({"keyframes": [], "loop": true})", "unknown field 'loop'");
  camera("keyframe_number", keys("5"), "expected an object");
  camera("missing_time", keys(R"({"position": [0, 1, 4], "target": [0, 1, 0]})"), "missing 'time'");
  camera("missing_position", keys(R"({"time": 0, "target": [0, 1, 0]})"), "missing 'position'");
  camera("missing_target", keys(R"({"time": 0, "position": [0, 1, 4]})"), "missing 'target'");
  camera("time_string", keys(R"({"time": "0", "position": [0, 1, 4], "target": [0, 1, 0]})"), "'time'");
  camera("time_overflows_float", keys(R"({"time": 1e39, "position": [0, 1, 4], "target": [0, 1, 0]})"), "'time'");
  camera("position_two_numbers", keys(R"({"time": 0, "position": [0, 1], "target": [0, 1, 0]})"), "'position'");
  camera("position_string", keys(R"({"time": 0, "position": [0, "1", 4], "target": [0, 1, 0]})"), "'position'");
  camera("position_overflows_float", keys(R"({"time": 0, "position": [0, 1e39, 4], "target": [0, 1, 0]})"),
         "'position'");
  camera("target_nested", keys(R"({"time": 0, "position": [0, 1, 4], "target": [[0], 1, 0]})"), "'target'");
  camera("fov_zero", keys(R"({"time": 0, "position": [0, 1, 4], "target": [0, 1, 0], "fovY": 0})"), "fovY");
  camera("fov_180", keys(R"({"time": 0, "position": [0, 1, 4], "target": [0, 1, 0], "fovY": 180})"), "fovY");
  camera("fov_negative", keys(R"({"time": 0, "position": [0, 1, 4], "target": [0, 1, 0], "fovY": -30})"), "fovY");
  camera("up_zero", keys(R"({"time": 0, "position": [0, 1, 4], "target": [0, 1, 0], "up": [0, 0, 0]})"), "zero vector");
  camera("up_parallel", keys(R"({"time": 0, "position": [0, 4, 0], "target": [0, 0, 0]})"), "parallel");
  camera("position_is_target", keys(R"({"time": 0, "position": [1, 1, 1], "target": [1, 1, 1]})"), "same point");
  camera("times_decrease", keys(good + R"(, {"time": -1, "position": [0, 1, 5], "target": [0, 1, 0]})"),
         "strictly increase");
  camera("times_repeat", keys(good + ", " + good), "strictly increase");
  camera("cut_not_bool", keys(R"({"time": 0, "position": [0, 1, 4], "target": [0, 1, 0], "cut": 1})"), "'cut'");
  camera("unknown_keyframe_field", keys(R"({"time": 0, "position": [0, 1, 4], "target": [0, 1, 0], "fov": 30})"),
         "unknown field 'fov'");
  camera("nested_100000", nestedObjects(100000), "");
  // Every key is fine, but the path between two passes through its target
  // (frame 1, at 0.5 s) or looks straight down the up vector there: found
  // before any frame is rendered, naming the frame.
  corpus.textFile(
      "camera_path_passes_through_target", "camera.json",
      keys(R"({"time": 0, "position": [0, 1, 4], "target": [0, 1, 0]},
                          {"time": 1, "position": [0, 1, -4], "target": [0, 1, 0]})"),
      {"render", "cornell", "--camera", "{dir}/camera.json", "--fps", "2", "--frames", "3", "--out", "{out}"},
      "frame 1");
  corpus.textFile(
      "camera_path_looks_along_up", "camera.json", keys(R"({"time": 0, "position": [1, 5, 0], "target": [0, 1, 0]},
                          {"time": 1, "position": [-1, 5, 0], "target": [0, 1, 0]})"),
      {"render", "cornell", "--camera", "{dir}/camera.json", "--fps", "2", "--frames", "3", "--out", "{out}"},
      "frame 1");
}

// ---------------------------------------------------------------- environment maps

// A Radiance file: header, resolution line, then `pixels` as they are.
Bytes radianceFile(const std::string& resolution, const Bytes& pixels, const std::string& format = "32-bit_rle_rgbe") {
  const std::string header = "#?RADIANCE\nFORMAT=" + format + "\n\n" + resolution + "\n";
  Bytes bytes(header.begin(), header.end());
  bytes.insert(bytes.end(), pixels.begin(), pixels.end());
  return bytes;
}

// A flat (not run-length encoded) grey Radiance map of width x height.
Bytes flatRadiance(int width, int height) {
  Bytes pixels;
  for (int i = 0; i < width * height; ++i) pixels.insert(pixels.end(), {128, 128, 128, 129});
  return radianceFile("-Y " + std::to_string(height) + " +X " + std::to_string(width), pixels);
}

void environmentMaps(CorpusBuilder& corpus) {
  const auto map = [&](const std::string& name, const std::string& file, Bytes bytes, const std::string& mentions,
                       Outcome outcome = Outcome::Error) {
    corpus.binaryFile("env_" + name, file, std::move(bytes),
                      {"render", "cornell", "--env", "{dir}/" + file, "--no-sun", "--out", "{out}"}, mentions, outcome);
  };
  const Bytes good = flatRadiance(16, 8);
  map("hdr_valid_control", "env.hdr", good, "", Outcome::FiniteImage);
  for (std::size_t keep : {std::size_t(0), std::size_t(5), std::size_t(11), good.size() / 2, good.size() - 1})
    map("hdr_cut_to_" + std::to_string(keep) + "_bytes", "env.hdr", Bytes(good.begin(), good.begin() + long(keep)),
        keep == 0   ? "empty file"
        : keep < 10 ? "unsupported image format"
                    : "truncated");
  map("hdr_bad_signature", "env.hdr", Bytes{'#', '?', 'H', 'D', 'R', '\n', '\n'}, "unsupported image format");
  map("hdr_unknown_format", "env.hdr", radianceFile("-Y 1 +X 2", Bytes(8, 128), "32-bit_rle_xyze"),
      "unsupported Radiance pixel format");
  map("hdr_resolution_garbage", "env.hdr", radianceFile("-Y two +X 4", Bytes(32, 128)), "corrupt resolution line");
  map("hdr_sideways", "env.hdr", radianceFile("+X 4 -Y 2", Bytes(32, 128)), "unsupported Radiance orientation");
  map("hdr_zero_size", "env.hdr", radianceFile("-Y 0 +X 0", {}), "zero size");
  map("hdr_negative_size", "env.hdr", radianceFile("-Y -2 +X 4", {}), "zero size");
  map("hdr_declares_1_5_gb", "env.hdr", radianceFile("-Y 8000 +X 16000", Bytes(20, 7)), "16000x8000");
  map("hdr_declares_24_gib", "env.hdr", radianceFile("-Y 32768 +X 65536", Bytes(20, 7)), "more than");
  map("hdr_side_over_limit", "env.hdr", radianceFile("-Y 2 +X 70000", Bytes(20, 7)), "70000");
  map("hdr_zero_run", "env.hdr", radianceFile("-Y 1 +X 8", {2, 2, 0, 8, 0, 0, 0, 0, 0, 0, 0, 0}),
      "corrupt run-length scanline");
  map("hdr_run_past_scanline", "env.hdr", radianceFile("-Y 1 +X 8", {2, 2, 0, 8, 128 + 9, 1, 0, 0, 0, 0, 0, 0}),
      "corrupt run-length scanline");
  map("hdr_wrong_encoded_width", "env.hdr", radianceFile("-Y 1 +X 8", {2, 2, 0, 9, 0, 0, 0, 0, 0, 0, 0, 0}),
      "encoded width");
  map("hdr_header_never_ends", "env.hdr", Bytes{'#', '?', 'R', 'G', 'B', 'E', '\n', 'A', 'B'}, "header does not end");
  map(
      "hdr_header_line_too_long", "env.hdr",
      [] {
        std::string text = "#?RADIANCE\n" + std::string(5000, 'x') + "\n\n-Y 1 +X 2\n";
        return Bytes(text.begin(), text.end());
      }(),
      "longer than 4096");
  map("hdr_not_equirect", "env.hdr", flatRadiance(12, 12), "not an equirectangular map");
  map("hdr_too_small", "env.hdr", flatRadiance(4, 2), "too small for an environment map");
  map("text_named_exr", "env.exr", Bytes{'h', 'e', 'l', 'l', 'o'}, "unsupported image format");
  map("exr_magic_then_nothing", "env.exr", Bytes{0x76, 0x2f, 0x31, 0x01}, "env.exr");
  map("png_magic_then_nothing", "env.png", Bytes{0x89, 'P', 'N', 'G'}, "env.png");
  map("jpeg_magic_then_nothing", "env.jpg", Bytes{0xff, 0xd8, 0xff}, "env.jpg");
  map("empty_exr", "env.exr", {}, "empty file");

  // EXR maps holding values no environment may have.
  const auto exrMap = [&](const std::string& name, float value, const std::string& mentions, Outcome outcome) {
    corpus.add(
        "env_exr_" + name, "env.exr",
        [value](const fs::path& dir) {
          io::ImageF image(8, 4, {"R", "G", "B"});
          for (float& v : image.pixels) v = 0.5f;
          image.at(3, 1, 1) = value;
          io::writeExr(dir / "env.exr", image);
        },
        {"render", "cornell", "--env", "{dir}/env.exr", "--no-sun", "--out", "{out}"}, mentions, outcome);
  };
  exrMap("nan", std::numeric_limits<float>::quiet_NaN(), "NaN", Outcome::Error);
  exrMap("infinity", std::numeric_limits<float>::infinity(), "Inf", Outcome::Error);
  exrMap("largest_float", std::numeric_limits<float>::max(), "", Outcome::FiniteImage);
  exrMap("negative", -5.0f, "", Outcome::FiniteImage);

  // Not files at all.
  corpus.add(
      "env_is_a_folder", "env.exr", [](const fs::path& dir) { fs::create_directories(dir / "env.exr"); },
      {"render", "cornell", "--env", "{dir}/env.exr", "--out", "{out}"}, "is a directory");
  corpus.add(
      "env_missing", "missing.hdr", [](const fs::path&) {},
      {"render", "cornell", "--env", "{dir}/missing.hdr", "--out", "{out}"}, "no such file");
}

// ---------------------------------------------------------------- option values

void optionValues(CorpusBuilder& corpus) {
  struct Option {
    std::string name;
    std::vector<std::string> arguments;
    std::string mentions;
  };
  const std::vector<Option> options = {
      {"width_zero", {"--width", "0"}, "--width"},
      {"width_huge", {"--width", "99999999999"}, "--width"},
      {"height_negative", {"--height", "-4"}, "--height"},
      {"frames_zero", {"--frames", "0"}, "--frames"},
      {"frames_text", {"--frames", "ten"}, "--frames"},
      {"exposure_nan", {"--exposure", "nan"}, "--exposure"},
      {"exposure_inf", {"--exposure", "inf"}, "--exposure"},
      {"exposure_overflow", {"--exposure", "1e309"}, "--exposure"},
      {"fps_nan", {"--fps", "nan"}, "--fps"},
      {"fps_zero", {"--fps", "0"}, "--fps"},
      {"env_intensity_negative", {"--env-intensity", "-1"}, "--env-intensity"},
      {"env_intensity_nan", {"--env-intensity", "nan"}, "--env-intensity"},
      {"env_rotation_inf", {"--env-rotation", "inf"}, "--env-rotation"},
      {"sun_elevation_91", {"--sun-elevation", "91"}, "--sun-elevation"},
      {"sun_azimuth_nan", {"--sun-azimuth", "nan"}, "--sun-azimuth"},
      {"no_sun_and_elevation", {"--no-sun", "--sun-elevation", "30"}, "--no-sun"},
      {"gi_unknown_mode", {"--gi", "sideways"}, "--gi"},
      {"gi_setting_unknown", {"--gi.diffuse.spatial_radios", "3"}, "did you mean gi.diffuse.spatial_radius"},
      {"gi_setting_out_of_range", {"--gi.diffuse.spatial_radius", "1e9"}, "gi.diffuse.spatial_radius"},
      {"gi_setting_nan", {"--gi.diffuse.visibility_thickness", "nan"}, "gi.diffuse.visibility_thickness"},
      {"gi_seed_negative", {"--gi.seed", "-1"}, "gi.seed"},
      {"gi_seed_over_32_bits", {"--gi.seed", "4294967296"}, "gi.seed"},
      {"gi_bool_word", {"--gi.restir", "sometimes"}, "gi.restir"},
      {"gi_enum_word", {"--gi.diffuse.target", "blue"}, "gi.diffuse.target"},
      {"gi_warmup_huge", {"--gi-warmup", "99999999"}, "--gi-warmup"},
      {"aov_unknown", {"--aov", "colour"}, "unknown image 'colour'"},
      {"dump_frame_past_end", {"--dump-stages", "--dump-frames", "7"}, "--dump-frames 7"},
      {"cut_frame_past_end", {"--cut-frames", "7"}, "--cut-frames 7"},
      {"device_out_of_range", {"--device", "99"}, "device 99 does not exist"},
      {"camera_unknown", {"--camera", "sideways"}, "neither a preset"},
      {"scene_unknown", {"no-such-scene"}, "neither a built-in scene"},
  };
  for (const Option& option : options) {
    std::vector<std::string> arguments = {"render", "--out", "{out}"};
    arguments.insert(arguments.end(), option.arguments.begin(), option.arguments.end());
    corpus.add(
        "option_" + option.name, "", [](const fs::path&) {}, arguments, option.mentions);
  }
  corpus.add(
      "reference_frame_wraps", "", [](const fs::path&) {},
      {"reference", "cornell", "--frame", "4294967295", "--out", "{out}/ref.exr"}, "--frame");
  corpus.add(
      "reference_out_not_exr", "", [](const fs::path&) {}, {"reference", "cornell", "--out", "{out}/ref.png"},
      "must name an .exr file");
  corpus.add(
      "compare_missing", "", [](const fs::path&) {}, {"compare", "{dir}/a.exr", "{dir}/b.exr"}, "a.exr");
  corpus.add(
      "compare_max_flip_nan", "", [](const fs::path&) {},
      {"compare", "{dir}/a.exr", "{dir}/b.exr", "--max-flip", "nan"}, "--max-flip");
}

}  // namespace

const std::vector<CorpusCase>& badInputCorpus() {
  static const std::vector<CorpusCase> corpus = [] {
    CorpusBuilder builder;
    settingsFiles(builder);
    cameraFiles(builder);
    environmentMaps(builder);
    optionValues(builder);
    return std::move(builder.cases);
  }();
  return corpus;
}

}  // namespace bounce::testing

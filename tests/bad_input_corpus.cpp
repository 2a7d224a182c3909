// The cases of the bad-input corpus (bad_input_corpus.h), by kind of input.
// Each section builds its cases from a valid input and one thing done wrong
// to it, so a case's name says exactly what it tests.
#include "bad_input_corpus.h"
#include "bad_input_corpus_builder.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <tuple>
#include <utility>

#include <sys/stat.h>

#include <nlohmann/json.hpp>

#include "bounce/gi_settings.h"
#include "gltf_builder.h"
#include "io/image_io.h"
#include "zero_png.h"

namespace bounce::testing {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Bytes = std::vector<std::uint8_t>;

using corpus_files::identifier;
using corpus_files::writeBytes;
using corpus_files::writeText;

std::string repeated(const std::string& text, int count) {
  std::string out;
  out.reserve(text.size() * std::size_t(count));
  for (int i = 0; i < count; ++i) out += text;
  return out;
}

// {"a":{"a":...1...}} nested `depth` deep.
std::string nestedObjects(int depth) { return repeated("{\"a\":", depth) + "1" + std::string(std::size_t(depth), '}'); }

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
      gi::Settings probe;
      bool negativeAccepted = true;  // a scale may be negative (it flips an axis)
      try {
        gi::applySetting(probe, info.key, "-1");
      } catch (const std::exception&) {
        negativeAccepted = false;
      }
      if (!negativeAccepted) settings(info.key + "_negative", file(-1), "for " + key);
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
  map("hdr_zero_size", "env.hdr", radianceFile("-Y 0 +X 0", {}), "no pixels");
  map("hdr_negative_size", "env.hdr", radianceFile("-Y -2 +X 4", {}), "no pixels (4x-2)");
  map("hdr_declares_1_5_gb", "env.hdr", radianceFile("-Y 8000 +X 16000", Bytes(20, 7)), "16000x8000");
  map("hdr_declares_24_gib", "env.hdr", radianceFile("-Y 32768 +X 65536", Bytes(20, 7)), "more than");
  map("hdr_side_over_limit", "env.hdr", radianceFile("-Y 2 +X 70000", Bytes(20, 7)), "70000");
  // A first scanline that is corrupt, in a file long enough for the 8x4
  // map it declares (the smallest equirect): the decoder, not the size check, refuses it.
  const auto fourScanlines = [](Bytes first) {
    first.resize(4 * 8 * 4 / 2);
    return first;
  };
  map("hdr_zero_run", "env.hdr", radianceFile("-Y 4 +X 8", fourScanlines({2, 2, 0, 8, 0, 0, 0, 0, 0, 0, 0, 0})),
      "corrupt run-length scanline");
  map("hdr_run_past_scanline", "env.hdr", radianceFile("-Y 4 +X 8", fourScanlines({2, 2, 0, 8, 128 + 9, 1, 0, 0, 0, 0, 0, 0})),
      "corrupt run-length scanline");
  map("hdr_wrong_encoded_width", "env.hdr", radianceFile("-Y 4 +X 8", fourScanlines({2, 2, 0, 9, 0, 0, 0, 0, 0, 0, 0, 0})),
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
  exrMap("largest_float", std::numeric_limits<float>::max(), "1 texel too bright, first at pixel (3, 1) channel G",
         Outcome::Error);
  exrMap("negative", -5.0f, "1 texel of negative radiance, first at pixel (3, 1) channel G: -5", Outcome::Error);

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

// ---------------------------------------------------------------- viewer scripts

// bounce view's scripts: commands that parse but fail at run time, after
// frames are in flight (the GPU must be idle before the session's objects
// are destroyed), and script files that are not regular files.
void viewerScripts(CorpusBuilder& corpus) {
  const auto view = [](bool gi) {
    std::vector<std::string> arguments = {"view",     "cornell",          "--headless", "--width", "16", "--height",
                                          "12",       "--script",         "{dir}/s.txt", "--out",   "{out}"};
    if (!gi) arguments.insert(arguments.end(), {"--gi", "off"});
    return arguments;
  };
  struct RuntimeFailure {
    std::string name;
    std::string script;  // "{dir}" is replaced by the case's folder when it is written
    bool gi;
    std::string mentions;
  };
  const std::vector<RuntimeFailure> failures = {
      {"unknown_setting", "wait 1\nset foo.bar 1\n", false, "s.txt:2: unknown setting gi.foo.bar"},
      {"unknown_setting_gi_on", "wait 2\nset diffuse.nope 1\n", true, "s.txt:2: unknown setting"},
      {"inspect_outside", "wait 1\ninspect 16 0\n", false, "s.txt:2: pixel (16, 0) is outside the 16x12 frame"},
      {"click_outside", "wait 1\nclick 0 12\n", false, "is outside the 16x12 frame"},
      {"stage_unknown", "wait 1\nstage nope\n", false, "s.txt:2: no image 'nope'"},
      {"stage_unknown_gi_on", "wait 1\nstages a\nstage nope\n", true, "s.txt:3: no image 'nope'"},
      {"save_gltf_existing", "wait 1\nsave-gltf existing.gltf\n", false, "exists; not overwritten"},
      {"other_settings_deep", "wait 1\nother-settings {dir}/deep.json\n", false, "nested deeper than 64 levels"},
      {"other_settings_deep_gi_on", "wait 1\nother-settings {dir}/deep.json\n", true, "nested deeper than 64 levels"},
      {"other_settings_missing", "wait 1\nother-settings {dir}/none.json\n", true, "no such file"},
      {"measure_without_reference", "wait 1\nmeasure\n", false, "no reference to measure against"},
      {"material_not_picked", "wait 1\nmaterial roughness 0.5\n", false, "no material is picked"},
  };
  for (const RuntimeFailure& failure : failures) {
    corpus.add(
        "script_runtime_" + failure.name, "s.txt",
        [script = failure.script](const fs::path& dir) {
          std::string text = script;
          for (std::size_t at = text.find("{dir}"); at != std::string::npos; at = text.find("{dir}"))
            text.replace(at, 5, dir.string());
          writeText(dir / "s.txt", text);
          writeText(dir / "deep.json", nestedObjects(100));
          fs::create_directories(dir / "out");
          writeText(dir / "out" / "existing.gltf", "{}");
        },
        view(failure.gi), failure.mentions);
  }
  corpus.add(
      "script_fifo", "s.txt", [](const fs::path& dir) { ::mkfifo((dir / "s.txt").c_str(), 0600); }, view(false),
      "not a regular file");
  corpus.add(
      "script_folder", "s.txt", [](const fs::path& dir) { fs::create_directories(dir / "s.txt"); }, view(false),
      "not a regular file");
}

// ---------------------------------------------------------------- glTF and GLB scenes

// The valid scene every glTF case breaks one thing of: a textured unit quad
// facing +Z, a camera looking at it from 3 m, a point light in front of it.
// Accessors: 0 POSITION, 1 NORMAL, 2 TEXCOORD_0, 3 indices.
gltf::GltfBuilder baseScene() {
  gltf::GltfBuilder builder;
  json& doc = builder.doc();
  const int positions = builder.floats(gltf::kQuadPositions, "VEC3");
  const int normals = builder.floats(gltf::kQuadNormals, "VEC3");
  const int texcoords = builder.floats({0, 0, 1, 0, 1, 1, 0, 1}, "VEC2");
  const int indices = builder.addAccessor(gltf::kQuadIndices, gltf::kUnsignedInt, "SCALAR");
  json primitive = {{"attributes", {{"POSITION", positions}, {"NORMAL", normals}, {"TEXCOORD_0", texcoords}}},
                    {"indices", indices},
                    {"material", 0}};
  doc["meshes"] = json::array({{{"name", "quad"}, {"primitives", json::array({primitive})}}});
  json pbr = {{"baseColorFactor", {1, 1, 1, 1}},
              {"baseColorTexture", {{"index", 0}}},
              {"metallicFactor", 0.0},
              {"roughnessFactor", 0.6}};
  doc["materials"] = json::array({{{"name", "painted"}, {"pbrMetallicRoughness", pbr}}});
  doc["textures"] = json::array({{{"source", 0}, {"sampler", 0}}});
  doc["samplers"] = json::array({json::object()});
  doc["images"] = json::array({{{"uri", "texture.png"}}});
  doc["cameras"] = json::array({{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.05}}}}});
  doc["extensionsUsed"] = json::array({"KHR_lights_punctual"});
  json light = {{"type", "point"}, {"intensity", 5.0}, {"color", {1, 1, 1}}};
  doc["extensions"]["KHR_lights_punctual"]["lights"] = json::array({light});
  json lamp = {{"name", "lamp"}, {"translation", {0.5, 0.5, 2}}};
  lamp["extensions"]["KHR_lights_punctual"]["light"] = 0;
  doc["nodes"] = json::array(
      {{{"name", "quad"}, {"mesh", 0}}, {{"name", "camera"}, {"camera", 0}, {"translation", {0.5, 0.5, 3}}}, lamp});
  doc["scenes"] = json::array({{{"nodes", {0, 1, 2}}}});
  doc["scene"] = 0;
  return builder;
}

void writeTexture(const fs::path& dir) {
  std::vector<std::uint8_t> rgba(4 * 4 * 4);
  for (std::size_t i = 0; i < rgba.size(); ++i) rgba[i] = std::uint8_t(i % 4 == 3 ? 255 : 60 + i * 3);
  const std::vector<std::uint8_t> png = gltf::encodePng(4, 4, rgba);
  writeBytes(dir / "texture.png", png);
}

// A string value that writeGltfCase replaces by 15,000 nested objects in the
// written text: a json value that deep would itself overflow the stack when
// copied (nlohmann copies recursively), before the importer ever saw it.
const std::string kDeepMarker = "@@nested 15000 levels@@";

// The base scene as scene.gltf + scene.bin + texture.png, `change` applied
// to its JSON (buffers included) and `bin` to its buffer's bytes.
void writeGltfCase(const fs::path& dir, const std::function<void(json&)>& change,
                   const std::function<void(Bytes&)>& changeBin = {}) {
  gltf::GltfBuilder builder = baseScene();
  json doc = builder.doc();
  Bytes bin = builder.bin();
  doc["buffers"] = {{{"byteLength", bin.size()}, {"uri", "scene.bin"}}};
  if (change) change(doc);
  if (changeBin) changeBin(bin);
  writeBytes(dir / "scene.bin", bin);
  writeTexture(dir);
  std::string text = doc.dump(1);
  if (const std::size_t at = text.find("\"" + kDeepMarker + "\""); at != std::string::npos)
    text.replace(at, kDeepMarker.size() + 2, nestedObjects(15000));
  writeText(dir / "scene.gltf", text);
}

// The base scene as scene.glb (buffer in its BIN chunk), then `change` to its bytes.
void writeGlbCase(const fs::path& dir, const std::function<void(Bytes&)>& change) {
  baseScene().writeGlb(dir / "scene.glb");
  writeTexture(dir);
  std::ifstream in(dir / "scene.glb", std::ios::binary);
  Bytes bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  if (change) change(bytes);
  writeBytes(dir / "scene.glb", bytes);
}

void setU32(Bytes& bytes, std::size_t at, std::uint32_t value) {
  for (int b = 0; b < 4; ++b) bytes[at + std::size_t(b)] = std::uint8_t(value >> (8 * b));
}

// A float stored in the buffer's bytes (floats are little-endian in glTF).
void setFloat(Bytes& bytes, std::size_t at, float value) {
  std::uint32_t bits;
  std::memcpy(&bits, &value, 4);
  setU32(bytes, at, bits);
}

// The name a JSON pointer's last step gives its property in messages:
// "/meshes/0/primitives/0/mode" -> "mode", "/scenes/0/nodes/0" -> "nodes".
std::string propertyName(const std::string& pointer) {
  std::vector<std::string> steps;
  for (std::size_t at = 1; at <= pointer.size();) {
    const std::size_t next = std::min(pointer.find('/', at), pointer.size());
    steps.push_back(pointer.substr(at, next - at));
    at = next + 1;
  }
  while (steps.size() > 1 && std::all_of(steps.back().begin(), steps.back().end(), ::isdigit)) steps.pop_back();
  return steps.back();
}

void gltfScenes(CorpusBuilder& corpus) {
  const std::vector<std::string> render = {"render", "{dir}/scene.gltf", "--out", "{out}"};
  const auto scene = [&](const std::string& name, std::function<void(json&)> change, const std::string& mentions,
                         Outcome outcome = Outcome::Error, std::function<void(Bytes&)> changeBin = {}) {
    corpus.add(
        "gltf_" + name, "scene.gltf",
        [change, changeBin](const fs::path& dir) { writeGltfCase(dir, change, changeBin); }, render, mentions, outcome);
  };
  const auto set = [](const std::string& pointer, json value) {
    return [pointer, value](json& doc) { doc[json::json_pointer(pointer)] = value; };
  };
  const auto erase = [](const std::string& pointer) {
    return [pointer](json& doc) {
      const json::json_pointer at(pointer);
      doc[at.parent_pointer()].erase(at.back());
    };
  };
  scene("valid_control", {}, "", Outcome::FiniteImage);

  // Every property the importer reads, given a value of another JSON type:
  // the message names the property.
  const std::vector<std::string> typed = {
      "/asset",
      "/asset/version",
      "/scene",
      "/scenes",
      "/scenes/0/nodes",
      "/nodes",
      "/nodes/0/mesh",
      "/nodes/0/name",
      "/nodes/2/extensions",
      "/nodes/1/camera",
      "/nodes/1/translation",
      "/nodes/2/extensions/KHR_lights_punctual",
      "/meshes",
      "/meshes/0/primitives",
      "/meshes/0/primitives/0/attributes",
      "/meshes/0/primitives/0/attributes/POSITION",
      "/meshes/0/primitives/0/indices",
      "/meshes/0/primitives/0/material",
      "/accessors",
      "/accessors/0/bufferView",
      "/accessors/0/componentType",
      "/accessors/0/count",
      "/accessors/0/type",
      "/bufferViews",
      "/bufferViews/0/buffer",
      "/bufferViews/0/byteOffset",
      "/bufferViews/0/byteLength",
      "/buffers",
      "/buffers/0/uri",
      "/buffers/0/byteLength",
      "/materials",
      "/materials/0/pbrMetallicRoughness",
      "/materials/0/pbrMetallicRoughness/metallicFactor",
      "/materials/0/pbrMetallicRoughness/roughnessFactor",
      "/materials/0/pbrMetallicRoughness/baseColorTexture",
      "/materials/0/pbrMetallicRoughness/baseColorTexture/index",
      "/materials/0/name",
      "/textures",
      "/textures/0/source",
      "/textures/0/sampler",
      "/samplers",
      "/images",
      "/images/0/uri",
      "/cameras",
      "/cameras/0/type",
      "/cameras/0/perspective",
      "/cameras/0/perspective/yfov",
      "/cameras/0/perspective/znear",
      "/extensionsUsed",
  };
  const json base = [] {
    json doc = baseScene().doc();
    doc["buffers"] = {{{"byteLength", 1}, {"uri", "scene.bin"}}};
    return doc;
  }();
  for (const std::string& pointer : typed) {
    const json& value = base.at(json::json_pointer(pointer));
    // Two values of other types than the one the property has.
    std::vector<std::pair<std::string, json>> wrong;
    if (!value.is_string()) wrong.emplace_back("string", "seven");
    if (!value.is_number()) wrong.emplace_back("number", 7);
    if (value.is_string() || value.is_number()) wrong.emplace_back("object", json{{"a", 1}});
    if (value.is_object()) wrong.emplace_back("array", json::array({1}));
    if (value.is_array()) wrong.emplace_back("bool", true);
    for (const auto& [kind, replacement] : wrong)
      scene("type" + pointer + "_" + kind, set(pointer, replacement), propertyName(pointer));
  }
  // Indices (non-negative integers that fit an int): a negative, a fraction
  // and one past what exists.
  const std::vector<std::string> indices = {
      "/scene",
      "/scenes/0/nodes/0",
      "/nodes/0/mesh",
      "/nodes/1/camera",
      "/nodes/2/extensions/KHR_lights_punctual/light",
      "/meshes/0/primitives/0/attributes/POSITION",
      "/meshes/0/primitives/0/attributes/NORMAL",
      "/meshes/0/primitives/0/indices",
      "/meshes/0/primitives/0/material",
      "/accessors/0/bufferView",
      "/bufferViews/0/buffer",
      "/materials/0/pbrMetallicRoughness/baseColorTexture/index",
      "/textures/0/source",
      "/textures/0/sampler",
  };
  for (const std::string& pointer : indices) {
    scene("index_negative" + pointer, set(pointer, -1), propertyName(pointer));
    scene("index_fraction" + pointer, set(pointer, 1.5), propertyName(pointer));
    const bool light = pointer.ends_with("/light");
    const bool indicesAccessor = pointer.ends_with("/indices");
    scene("index_past_the_end" + pointer, set(pointer, 99),
          light             ? "names a light that does not exist"
          : indicesAccessor ? "indices accessor out of bounds"
                            : "99");
  }

  // The document as a whole.
  scene("no_asset", erase("/asset"), "asset is missing");
  scene("version_1", set("/asset/version", "1.0"), "glTF version 1.0 is not supported");
  scene("min_version_2_1", set("/asset/minVersion", "2.1"), "2.1");
  scene("required_extension", set("/extensionsRequired", {"KHR_draco_mesh_compression"}),
        "requires glTF extensions this importer does not support: KHR_draco_mesh_compression");
  scene("extras_nested_15000", set("/extras", kDeepMarker), "nested deeper than 64 levels");
  scene("extensions_nested_15000", set("/nodes/0/extensions", {{"EXT_deep", kDeepMarker}}),
        "nested deeper than 64 levels");
  corpus.textFile("gltf_not_json", "scene.gltf", "A scene, honest", render, "not valid JSON");
  // Text that starts with the GLB magic is read as a GLB container.
  corpus.textFile("gltf_text_with_glb_magic", "scene.gltf", "glTF 2.0, honest", render, "truncated GLB header");
  corpus.textFile("gltf_empty_file", "scene.gltf", "", render, "scene.gltf");
  corpus.textFile("gltf_array", "scene.gltf", "[]", render, "not a glTF file");
  corpus.textFile("gltf_truncated_json", "scene.gltf", R"({"asset": {"version": "2.0"}, "nodes": [)", render,
                  "not valid JSON");
  corpus.textFile("gltf_only_asset", "scene.gltf", R"({"asset": {"version": "2.0"}})", render, "",
                  Outcome::FiniteImage);
  corpus.binaryFile("gltf_binary_garbage", "scene.gltf", Bytes{0x00, 0xff, 0x13, 0x37, 0x00, 0x42}, render,
                    "not valid JSON");
  corpus.add(
      "gltf_is_a_folder", "scene.gltf", [](const fs::path& dir) { fs::create_directories(dir / "scene.gltf"); }, render,
      "not a regular file");
  corpus.add(
      "gltf_missing", "scene.gltf", [](const fs::path&) {}, render, "file not found");

  // The node graph.
  scene("node_child_missing", set("/nodes/0/children", {3}), "child 3 does not exist");
  scene(
      "node_cycle",
      [](json& doc) {
        doc["nodes"][0]["children"] = {1};
        doc["nodes"][1]["children"] = {0};
        doc["scenes"][0]["nodes"] = {2};
      },
      "cycle");
  scene(
      "node_two_parents",
      [](json& doc) {
        doc["nodes"].push_back({{"name", "a"}, {"children", {0}}});
        doc["nodes"].push_back({{"name", "b"}, {"children", {0}}});
      },
      "more than one parent");
  scene("node_own_child", set("/nodes/0/children", {0}), "node 0");
  scene("node_child_twice", set("/nodes/1/children", {0, 0}), "twice");
  scene(
      "node_chain_20000",
      [](json& doc) {
        for (int i = 0; i < 20000; ++i)
          doc["nodes"].push_back({{"children", {int(doc["nodes"].size()) + 1}}, {"translation", {0, 0, -1e-5}}});
        doc["nodes"].push_back({{"mesh", 0}});
        doc["scenes"][0]["nodes"] = {1, 2, 3};
      },
      "", Outcome::FiniteImage);
  scene("translation_overflows_float", set("/nodes/0/translation", {0, 1e39, 0}), "translation is out of range");
  scene("scale_overflows_float", set("/nodes/0/scale", {1e39, 1, 1}), "scale is out of range");
  scene("scale_tiny", set("/nodes/0/scale", {1e-13, 1e-13, 1e-13}), "", Outcome::FiniteImage);
  scene("scale_zero", set("/nodes/0/scale", {0, 0, 0}), "", Outcome::FiniteImage);
  scene("matrix_15_numbers", set("/nodes/0/matrix", json(std::vector<double>(15, 0.0))), "matrix must have 16 numbers");
  scene("matrix_overflows_float", set("/nodes/0/matrix", {1e39, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}),
        "matrix is out of range");
  scene("rotation_zero", set("/nodes/0/rotation", {0, 0, 0, 0}), "not a unit quaternion");
  scene("rotation_three_numbers", set("/nodes/0/rotation", {0, 0, 1}), "rotation must have 4 numbers");

  // Cameras.
  scene("camera_yfov_pi", set("/cameras/0/perspective/yfov", 3.14159265), "yfov");
  scene("camera_yfov_zero", set("/cameras/0/perspective/yfov", 0), "yfov");
  scene("camera_znear_zero", set("/cameras/0/perspective/znear", 0), "znear");
  scene("camera_type_unknown", set("/cameras/0/type", "fisheye"), "Invalid camera type: \"fisheye\"");
  scene("camera_orthographic_only",
        set("/cameras/0",
            {{"type", "orthographic"}, {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"zfar", 9}, {"znear", 0.1}}}}),
        "", Outcome::FiniteImage);
  scene("camera_far_away", set("/nodes/1/translation", {0, 0, 1e19}), "1e+18");

  // Lights and materials.
  scene("light_type_unknown", set("/extensions/KHR_lights_punctual/lights/0/type", "laser"),
        "unknown light type 'laser'");
  scene("light_type_missing", erase("/extensions/KHR_lights_punctual/lights/0/type"), "type must be a string");
  scene("light_intensity_word", set("/extensions/KHR_lights_punctual/lights/0/intensity", "bright"), "",
        Outcome::FiniteImage);
  scene("light_colour_word", set("/extensions/KHR_lights_punctual/lights/0/color", "red"), "", Outcome::FiniteImage);
  scene("light_intensity_negative", set("/extensions/KHR_lights_punctual/lights/0/intensity", -5), "negative");
  scene("light_intensity_3e38", set("/extensions/KHR_lights_punctual/lights/0/intensity", 3e38), "above 1e+20");
  scene("light_intensity_overflows_float", set("/extensions/KHR_lights_punctual/lights/0/intensity", 1e39),
        "intensity");
  scene("light_spot_cones_inverted",
        set("/extensions/KHR_lights_punctual/lights/0",
            {{"type", "spot"}, {"intensity", 5}, {"spot", {{"innerConeAngle", 0.8}, {"outerConeAngle", 0.4}}}}),
        "cone angles");
  scene("light_spot_without_spot", set("/extensions/KHR_lights_punctual/lights/0/type", "spot"), "spot");
  scene("lights_not_an_array", set("/extensions/KHR_lights_punctual/lights", {{"type", "point"}}),
        "lights must be an array");
  scene(
      "sun_3e38",
      [](json& doc) {
        doc["extensions"]["KHR_lights_punctual"]["lights"][0] = {{"type", "directional"}, {"intensity", 3e38}};
      },
      "above 1e+20");
  scene("base_colour_three_numbers", set("/materials/0/pbrMetallicRoughness/baseColorFactor", {1, 0, 0}), "",
        Outcome::FiniteImage);
  scene("base_colour_overflows_float", set("/materials/0/pbrMetallicRoughness/baseColorFactor", {1e39, 0, 0, 1}),
        "baseColorFactor is out of range");
  scene(
      "emission_above_limit",
      [](json& doc) {
        doc["materials"][0]["emissiveFactor"] = {1, 1, 1};
        doc["extensionsUsed"].push_back("KHR_materials_emissive_strength");
        doc["materials"][0]["extensions"] = {{"KHR_materials_emissive_strength", {{"emissiveStrength", 1e30}}}};
      },
      "above 1e+20");
  scene(
      "emissive_strength_negative",
      [](json& doc) {
        doc["materials"][0]["extensions"] = {{"KHR_materials_emissive_strength", {{"emissiveStrength", -1}}}};
      },
      "emissiveStrength");
  scene("alpha_mode_unknown", set("/materials/0/alphaMode", "SOMETIMES"), "unknown alphaMode 'SOMETIMES'");
  scene("alpha_cutoff_negative", set("/materials/0/alphaCutoff", -0.5), "alphaCutoff");
  scene("emissive_factor_two_numbers", set("/materials/0/emissiveFactor", {1, 1}), "emissiveFactor");

  // Primitives and accessors.
  scene("primitive_mode_unknown", set("/meshes/0/primitives/0/mode", 7), "unknown primitive mode 7");
  scene("primitive_points_only", set("/meshes/0/primitives/0/mode", 0), "", Outcome::FiniteImage);
  scene("primitive_without_position", erase("/meshes/0/primitives/0/attributes/POSITION"), "", Outcome::FiniteImage);
  scene("mesh_without_primitives", set("/meshes/0/primitives", json::array()), "", Outcome::FiniteImage);
  scene("position_as_vec2", set("/accessors/0/type", "VEC2"), "expected VEC3");
  scene("position_as_doubles", set("/accessors/0/componentType", 5130), "POSITION");
  scene("position_normalized_floats", set("/accessors/0/normalized", true), "", Outcome::FiniteImage);
  scene("accessor_count_past_view", set("/accessors/0/count", 1000000), "do not fit in bufferView");
  scene("accessor_count_zero", set("/accessors/0/count", 0), "has no elements");
  scene("accessor_offset_past_view", set("/accessors/0/byteOffset", 4000), "do not fit in bufferView");
  scene("accessor_type_unknown", set("/accessors/0/type", "VEC5"), "Got \"VEC5\"");
  scene("accessor_count_over_int", set("/accessors/0/count", std::int64_t(3000000000)), "3000000000");
  scene(
      "accessor_huge_count_no_view",
      [](json& doc) {
        doc["accessors"][1] = {{"componentType", 5126}, {"count", 2000000000}, {"type", "VEC3"}};
      },
      "too many elements");
  scene("view_stride_too_small", set("/bufferViews/0/byteStride", 4), "byteStride 4 is invalid");
  scene("view_stride_too_large", set("/bufferViews/0/byteStride", 256), "byteStride");
  scene("view_past_buffer", set("/bufferViews/0/byteLength", 100000), "runs past the end of its buffer");
  scene("view_offset_past_buffer", set("/bufferViews/0/byteOffset", 100000), "bufferView");
  scene("buffer_longer_than_file", set("/buffers/0/byteLength", 100000), "scene.gltf");
  scene("index_past_vertices", {}, "out of range for 4 vertices", Outcome::Error,
        [](Bytes& bin) { setU32(bin, 4 * 12 + 4 * 12 + 4 * 8 + 4, 99); });
  scene("position_nan", {}, "NaN or infinite", Outcome::Error,
        [](Bytes& bin) { setFloat(bin, 4, std::numeric_limits<float>::quiet_NaN()); });
  scene("position_infinite", {}, "NaN or infinite", Outcome::Error,
        [](Bytes& bin) { setFloat(bin, 0, std::numeric_limits<float>::infinity()); });
  // A vertex far out makes a huge triangle, seen from the file's own camera.
  scene("position_1e30", {}, "", Outcome::FiniteImage, [](Bytes& bin) { setFloat(bin, 0, 1e30f); });
  scene("texcoord_infinite", {}, "TEXCOORD_0", Outcome::Error,
        [](Bytes& bin) { setFloat(bin, 4 * 12 + 4 * 12, -std::numeric_limits<float>::infinity()); });
  scene("normals_zero", {}, "", Outcome::FiniteImage, [](Bytes& bin) {
    for (std::size_t at = 4 * 12; at < 4 * 12 + 4 * 12; at += 4) setFloat(bin, at, 0.0f);
  });
  scene("normals_nan", {}, "", Outcome::FiniteImage, [](Bytes& bin) {
    for (std::size_t at = 4 * 12; at < 4 * 12 + 4 * 12; at += 4) setFloat(bin, at, std::nanf(""));
  });
  scene("indices_as_floats", set("/accessors/3/componentType", 5126), "indices");
  const auto sparse = [](json value) { return [value](json& doc) { doc["accessors"][0]["sparse"] = value; }; };
  scene("sparse_count_over_int",
        sparse({{"count", std::int64_t(3000000000)},
                {"indices", {{"bufferView", 3}, {"componentType", 5125}}},
                {"values", {{"bufferView", 0}}}}),
        "3000000000");
  scene("sparse_count_past_accessor",
        sparse(
            {{"count", 9}, {"indices", {{"bufferView", 3}, {"componentType", 5125}}}, {"values", {{"bufferView", 0}}}}),
        "sparse count 9");
  scene("sparse_indices_not_increasing",
        sparse(
            {{"count", 4}, {"indices", {{"bufferView", 3}, {"componentType", 5125}}}, {"values", {{"bufferView", 0}}}}),
        "not increasing");
  scene("sparse_index_type_float",
        sparse(
            {{"count", 1}, {"indices", {{"bufferView", 3}, {"componentType", 5126}}}, {"values", {{"bufferView", 0}}}}),
        "sparse indices");
  scene("sparse_offset_over_int",
        sparse({{"count", 1},
                {"indices", {{"bufferView", 3}, {"componentType", 5125}, {"byteOffset", std::int64_t(4294967296)}}},
                {"values", {{"bufferView", 0}}}}),
        "4294967296");

  // Where the buffer and the texture come from.
  for (const auto& [name, uri, mentions] : std::vector<std::tuple<std::string, std::string, std::string>>{
           {"parent", "../../../../../../etc/passwd", "outside the glTF file's folder"},
           {"encoded_parent", "%2e%2e/%2e%2e/%2e%2e/%2e%2e/etc/passwd", "outside the glTF file's folder"},
           {"encoded_slashes", "..%2F..%2F..%2Fetc%2Fpasswd", "outside the glTF file's folder"},
           {"absolute", "/etc/passwd", "outside the glTF file's folder"},
           {"nul", "scene.bin%00.png", "NUL"},
           {"missing", "nowhere.bin", "nowhere.bin"},
           {"folder", ".", "is not a regular file (a folder)"},
           {"bad_base64", "data:application/octet-stream;base64,!!!!", "scene.gltf"},
           {"short_data", "data:application/octet-stream;base64,AAAA", "scene.gltf"},
       }) {
    scene("buffer_uri_" + name, set("/buffers/0/uri", uri), mentions);
    scene("image_uri_" + name, set("/images/0/uri", uri), name == "short_data" ? "texture" : mentions);
  }
  // A file outside the folder is refused alike whether it exists or not, and
  // its bytes never reach the message.
  corpus.add(
      "gltf_buffer_uri_outside_existing", "scene.gltf",
      [](const fs::path& dir) {
        writeGltfCase(dir, [](json& doc) { doc["buffers"][0]["uri"] = "../secret.bin"; });
        writeText(dir.parent_path() / "secret.bin", "SECRET-BYTES-SECRET-BYTES-SECRET-BYTES");
      },
      render, "outside the glTF file's folder");
  // A FIFO would block the read until something writes to it.
  for (const char* kind : {"buffers", "images"})
    corpus.add(
        std::string("gltf_") + kind + "_uri_fifo", "scene.gltf",
        [kind](const fs::path& dir) {
          writeGltfCase(dir, [kind](json& doc) { doc[kind][0]["uri"] = "pipe"; });
          ::mkfifo((dir / "pipe").c_str(), 0600);
        },
        render, "is not a regular file (a FIFO)");
  corpus.add(
      "gltf_buffer_symlink_out", "scene.gltf",
      [](const fs::path& dir) {
        writeGltfCase(dir, [](json& doc) { doc["buffers"][0]["uri"] = "link.bin"; });
        fs::create_symlink("/etc/passwd", dir / "link.bin");
      },
      render, "outside the glTF file's folder");
  const auto image = [&](const std::string& name, std::function<void(const fs::path&)> write,
                         const std::string& mentions) {
    corpus.add(
        "gltf_texture_" + name, "scene.gltf",
        [write](const fs::path& dir) {
          writeGltfCase(dir, {});
          write(dir / "texture.png");
        },
        render, mentions);
  };
  image(
      "not_an_image", [](const fs::path& path) { writeText(path, "a picture of a cat"); }, "not a PNG or JPEG");
  image(
      "empty", [](const fs::path& path) { writeText(path, ""); }, "texture");
  image(
      "png_truncated",
      [](const fs::path& path) {
        std::vector<std::uint8_t> rgba(64 * 64 * 4, 90);
        Bytes png = gltf::encodePng(64, 64, rgba);
        png.resize(png.size() / 2);
        writeBytes(path, png);
      },
      "texture");
  image(
      "png_20000_square",
      [](const fs::path& path) {
        // A PNG signature and an IHDR chunk declaring 20000x20000, then nothing.
        Bytes png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R'};
        for (std::uint32_t side : {20000u, 20000u})
          for (int b = 3; b >= 0; --b) png.push_back(std::uint8_t(side >> (8 * b)));
        png.insert(png.end(), {8, 6, 0, 0, 0, 0, 0, 0, 0});
        writeBytes(path, png);
      },
      "over the limit of 16384");
  image(
      "jpeg_garbage",
      [](const fs::path& path) {
        writeBytes(path, Bytes{0xff, 0xd8, 0xff, 0xe0, 1, 2, 3});
      },
      "texture");
  scene("texture_without_image", erase("/textures/0/source"), "", Outcome::FiniteImage);

  // Animations.
  const auto animation = [](json samplerInput, json channel) {
    return [samplerInput, channel](json& doc) {
      doc["animations"] = {{{"samplers", {{{"input", samplerInput}, {"output", 0}}}}, {"channels", {channel}}}};
    };
  };
  scene("animation_target_missing_node",
        animation(0, {{"sampler", 0}, {"target", {{"node", 99}, {"path", "translation"}}}}), "node 99 does not exist");
  scene("animation_sampler_missing", animation(0, {{"sampler", 5}, {"target", {{"node", 0}, {"path", "translation"}}}}),
        "sampler");
  scene("animation_input_not_scalar",
        animation(0, {{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}), "input");
  scene("animation_weights_only", animation(0, {{"sampler", 0}, {"target", {{"node", 0}, {"path", "weights"}}}}), "",
        Outcome::FiniteImage);
  scene("skin", set("/nodes/0/skin", 0), "skin");

  // GLB containers: the base scene with its BIN chunk, then one thing broken.
  const std::vector<std::string> renderGlb = {"render", "{dir}/scene.glb", "--out", "{out}"};
  const auto glb = [&](const std::string& name, std::function<void(Bytes&)> change, const std::string& mentions,
                       Outcome outcome = Outcome::Error) {
    corpus.add(
        "glb_" + name, "scene.glb", [change](const fs::path& dir) { writeGlbCase(dir, change); }, renderGlb, mentions,
        outcome);
  };
  glb("valid_control", {}, "", Outcome::FiniteImage);
  glb(
      "version_1", [](Bytes& b) { setU32(b, 4, 1); }, "GLB container version 1 is not 2");
  glb(
      "length_past_file", [](Bytes& b) { setU32(b, 8, std::uint32_t(b.size() + 100)); }, "truncated GLB");
  glb(
      "json_chunk_past_file", [](Bytes& b) { setU32(b, 12, std::uint32_t(b.size())); }, "runs past the end");
  glb(
      "json_chunk_not_json", [](Bytes& b) { setU32(b, 16, 0x12345678); }, "not JSON");
  glb(
      "json_chunk_empty", [](Bytes& b) { setU32(b, 12, 0); }, "the GLB JSON chunk is empty");
  glb(
      "bin_chunk_wrong_type",
      [](Bytes& b) {
        const std::size_t bin = 20 + std::size_t(b[12] | b[13] << 8 | b[14] << 16 | b[15] << 24);
        setU32(b, bin + 4, 0x11111111);
      },
      "not BIN");
  glb(
      "bin_chunk_past_file",
      [](Bytes& b) {
        const std::size_t bin = 20 + std::size_t(b[12] | b[13] << 8 | b[14] << 16 | b[15] << 24);
        setU32(b, bin, std::uint32_t(b.size()));
      },
      "BIN chunk runs past the end");
  glb(
      "json_garbage", [](Bytes& b) { std::fill(b.begin() + 20, b.begin() + 40, std::uint8_t('#')); }, "not valid JSON");
  for (std::size_t keep : {4u, 12u, 19u, 30u, 200u})
    glb(
        "cut_to_" + std::to_string(keep) + "_bytes", [keep](Bytes& b) { b.resize(keep); }, "scene.glb");
  glb(
      "cut_one_byte_short", [](Bytes& b) { b.pop_back(); }, "truncated GLB");
  corpus.add(
      "glb_deep_json", "scene.glb",
      [](const fs::path& dir) {
        // A GLB of one JSON chunk, written by hand (see kDeepMarker).
        std::string text = R"({"asset": {"version": "2.0"}, "extras": )" + nestedObjects(15000) + "}";
        while (text.size() % 4 != 0) text += ' ';
        Bytes glb = {'g', 'l', 'T', 'F'};
        glb.resize(20);
        setU32(glb, 4, 2);
        setU32(glb, 8, std::uint32_t(20 + text.size()));
        setU32(glb, 12, std::uint32_t(text.size()));
        setU32(glb, 16, 0x4E4F534A);
        glb.insert(glb.end(), text.begin(), text.end());
        writeBytes(dir / "scene.glb", glb);
      },
      renderGlb, "nested deeper than 64 levels");
}

// ---------------------------------------------------------------- glTF, camera files and labels, round 2

// Issue 28's second round: values glTF or JSON allow to be written but give
// no meaning (factors outside [0, 1], a light range of 0, a root listed many
// times, a key given twice), a camera file over the keyframe limit, and a
// sheet label the font cannot draw.
void gltfAndCameraRound2(CorpusBuilder& corpus) {
  const std::vector<std::string> render = {"render", "{dir}/scene.gltf", "--out", "{out}"};
  const auto scene = [&](const std::string& name, std::function<void(json&)> change, const std::string& mentions,
                         Outcome outcome = Outcome::Error) {
    corpus.add(
        "gltf_" + name, "scene.gltf", [change](const fs::path& dir) { writeGltfCase(dir, change); }, render, mentions,
        outcome);
  };
  // Clamped into [0, 1] with a warning: the render goes on.
  const std::vector<std::pair<std::string, std::function<void(json&)>>> factors = {
      {"base_colour_five",
       [](json& d) {
         d["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = {5, 5, 5, 1};
       }},
      {"base_colour_negative",
       [](json& d) {
         d["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = {-1, 0.5, 0.5, 1};
       }},
      {"roughness_negative", [](json& d) { d["materials"][0]["pbrMetallicRoughness"]["roughnessFactor"] = -0.5; }},
      {"metallic_two", [](json& d) { d["materials"][0]["pbrMetallicRoughness"]["metallicFactor"] = 2; }},
      {"emissive_two",
       [](json& d) {
         d["materials"][0]["emissiveFactor"] = {2, 1, 1};
       }},
      {"emissive_negative",
       [](json& d) {
         d["materials"][0]["emissiveFactor"] = {-1, 0, 0};
       }},
  };
  for (const auto& [name, change] : factors) scene("factor_" + name, change, "", Outcome::FiniteImage);
  scene(
      "light_range_zero", [](json& d) { d["extensions"]["KHR_lights_punctual"]["lights"][0]["range"] = 0; },
      "range 0 must be above 0");
  scene(
      "root_listed_200000_times", [](json& d) { d["scenes"][0]["nodes"] = json(std::vector<int>(200000, 0)); },
      "lists node 0 more than once");

  const auto camera = [&](const std::string& name, std::string text, const std::string& mentions) {
    corpus.textFile("camera_" + name, "camera.json", std::move(text),
                    {"render", "cornell", "--camera", "{dir}/camera.json", "--frames", "3", "--out", "{out}"},
                    mentions);
  };
  camera("key_twice", R"({"keyframes": [{"time": 0, "time": 1, "position": [0, 1, 4], "target": [0, 1, 0]}]})",
         "keyframe 0: 'time' is given more than once");
  camera("keyframes_twice", R"({"keyframes": [], "keyframes": []})", "'keyframes' is given more than once");
  std::string many = "{\"keyframes\": [";
  for (int k = 0; k <= 100000; ++k)
    many.append(k ? "," : "")
        .append("{\"time\": ")
        .append(std::to_string(k))
        .append(R"(, "position": [0, 1, 4], "target": [0, 1, 0]})");
  camera("keyframes_100001", many + "]}", "more than 100000 keyframes");

  corpus.add(
      "sheet_label_not_drawable", "",
      [](const fs::path& dir) {
        io::ImageF image(4, 4, {"R", "G", "B"});
        io::writePng(dir / "a.png", image, io::PngEncoding::Srgb);
      },
      {"sheet", "{dir}/a.png", "--label", "caf\xc3\xa9", "--out", "{dir}/sheet.png"}, "--label");
}

// ---------------------------------------------------------------- images and metrics

// Images that are cheap on disk and huge in memory, maps too bright for
// float radiance, and output names that do not match what is written
// (issue 28, items 5, 9 and 11).
void imageAndMetricInputs(CorpusBuilder& corpus) {
  // 16384 x 16384 declared in 300 bytes (the data ends after a row): refused
  // from the header, before decoding, with the memory it would need.
  const Bytes hugePng = zeroPng(16384, 16384, 1);
  corpus.binaryFile("compare_png_declares_16384_squared", "huge.png", hugePng,
                    {"compare", "{dir}/huge.png", "{dir}/huge.png"}, "needs about");
  corpus.binaryFile("compare_sequence_png_declares_16384_squared", "huge.png", hugePng,
                    {"compare", "--sequence", "{dir}/huge.png", "{dir}/huge.png"}, "needs about");
  corpus.binaryFile("sheet_png_declares_16384_squared", "huge.png", hugePng,
                    {"sheet", "{dir}/huge.png", "--out", "{out}/sheet.png"}, "needs about");
  corpus.add(
      "compare_test_declares_16384_squared_against_a_small_reference", "huge.png",
      [hugePng](const fs::path& dir) {
        writeBytes(dir / "huge.png", hugePng);
        writeBytes(dir / "small.png", zeroPng(8, 8, 8));
      },
      {"compare", "{dir}/small.png", "{dir}/huge.png"}, "is 16384x16384 but the reference is 8x8");
  corpus.binaryFile("env_png_declares_16384x8192_rgba", "env.png", zeroPng(16384, 8192, 1, 4),
                    {"render", "cornell", "--env", "{dir}/env.png", "--no-sun", "--out", "{out}"},
                    "preparing a 16384x8192 environment map needs about");
  corpus.binaryFile("env_png_declares_16384_squared", "env.png", hugePng,
                    {"render", "cornell", "--env", "{dir}/env.png", "--no-sun", "--out", "{out}"},
                    "16384x16384 is not an equirectangular map");

  // Radiance texels beyond the brightest light: exponent 255 is 1.7e38,
  // which times an intensity of 4 overflowed and blacked out the map.
  const auto rgbeMap = [](std::uint8_t mantissa, std::uint8_t exponent) {
    Bytes pixels;
    for (int i = 0; i < 16 * 8; ++i) pixels.insert(pixels.end(), {mantissa, mantissa, mantissa, exponent});
    return radianceFile("-Y 8 +X 16", pixels);
  };
  const auto envCase = [&](const std::string& name, const std::string& file, Bytes bytes,
                           std::vector<std::string> extra, const std::string& mentions) {
    std::vector<std::string> arguments = {"render", "sun-room", "--env", "{dir}/" + file, "--no-sun", "--out", "{out}"};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    corpus.binaryFile(name, file, std::move(bytes), arguments, mentions);
  };
  envCase("env_hdr_exponent_255", "env.hdr", rgbeMap(255, 255), {}, "128 texels too bright, first at pixel (0, 0)");
  envCase("env_hdr_exponent_255_times_4", "env.hdr", rgbeMap(255, 255), {"--env-intensity", "4"},
          "times the intensity 4");
  envCase("env_hdr_exponent_200", "env.hdr", rgbeMap(128, 200), {}, "is above 1e+20");
  envCase("env_hdr_1e19_times_100", "env.hdr", rgbeMap(128, 192), {"--env-intensity", "100"},
          "times the intensity 100");
  corpus.add(
      "env_exr_3e38_everywhere", "env.exr",
      [](const fs::path& dir) {
        io::ImageF image(16, 8, {"R", "G", "B"});
        for (float& v : image.pixels) v = 3.0e38f;
        io::writeExr(dir / "env.exr", image);
      },
      {"render", "sun-room", "--env", "{dir}/env.exr", "--no-sun", "--out", "{out}"}, "too bright");

  // Output names that say another format than the one written.
  const auto reference = [](const fs::path& dir) { writeBytes(dir / "a.png", zeroPng(8, 8, 8)); };
  corpus.add("sheet_out_named_exr", "x.exr", reference, {"sheet", "{dir}/a.png", "--out", "{out}/x.exr"},
             "must name a .png file");
  corpus.add("compare_error_map_named_exr", "map.exr", reference,
             {"compare", "{dir}/a.png", "{dir}/a.png", "--error-map", "{out}/map.exr"}, "must name a .png file");
  corpus.add("compare_json_named_png", "values.png", reference,
             {"compare", "{dir}/a.png", "{dir}/a.png", "--json", "{out}/values.png"}, "must name a .json file");
  corpus.add(
      "bench_json_named_csv", "bench.csv", [](const fs::path&) {}, {"bench", "cornell", "--json", "{out}/bench.csv"},
      "must name a .json file");
}

}  // namespace

const std::vector<CorpusCase>& badInputCorpus() {
  static const std::vector<CorpusCase> corpus = [] {
    CorpusBuilder builder;
    settingsFiles(builder);
    cameraFiles(builder);
    environmentMaps(builder);
    optionValues(builder);
    viewerScripts(builder);
    gltfScenes(builder);
    gltfAndCameraRound2(builder);
    imageAndMetricInputs(builder);
    outputFolderCases(builder);
    sceneMemoryCases(builder);
    ghostingCases(builder);
    scriptAndCompareCases(builder);
    return std::move(builder.cases);
  }();
  return corpus;
}

}  // namespace bounce::testing

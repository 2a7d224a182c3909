// The corpus's output-folder cases (issue 46): records, links, FIFOs and
// temporary files that must never lead bounce to touch a file outside the
// folder, or one inside it that Bounce did not write.
#include <sys/stat.h>

#include <fstream>
#include <initializer_list>
#include <iterator>
#include <tuple>

#include "bad_input_corpus_builder.h"
#include "gltf_builder.h"

namespace bounce::testing {

namespace {

namespace fs = std::filesystem;

std::string contents(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// "" when `file` still holds `bytes` (a victim, outside the output folder
// or put in it by the user), else what became of it.
std::string unchanged(const fs::path& file, const std::string& bytes) {
  std::error_code error;
  if (!fs::is_regular_file(fs::symlink_status(file, error)))
    return file.string() + " is gone or no longer a regular file";
  const std::string now = contents(file);
  return now == bytes ? "" : file.string() + " changed: it held \"" + bytes + "\", now " + std::to_string(now.size()) + " bytes";
}

std::string stillLinked(const fs::path& link, const fs::path& target) {
  std::error_code error;
  if (!fs::is_symlink(fs::symlink_status(link, error))) return link.string() + " is no longer a symbolic link";
  return fs::read_symlink(link, error) == target ? "" : link.string() + " leads elsewhere now";
}

std::string firstOf(std::initializer_list<std::string> problems) {
  for (const std::string& problem : problems)
    if (!problem.empty()) return problem;
  return "";
}

// A unit quad with a 4x4 texture, a camera and a point light: a scene
// whose glTF export writes a texture beside the .gltf and its .bin.
void writeTexturedQuad(const fs::path& file) {
  gltf::GltfBuilder builder;
  gltf::json& doc = builder.doc();
  gltf::json primitive = gltf::quadPrimitive(builder);
  primitive["attributes"]["TEXCOORD_0"] = builder.floats({0, 0, 1, 0, 1, 1, 0, 1}, "VEC2");
  primitive["material"] = 0;
  builder.addMeshNode(primitive);
  doc["materials"] = gltf::json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
  doc["textures"] = gltf::json::array({{{"source", 0}}});
  doc["images"] = gltf::json::array({{{"uri", "texture.png"}}});
  doc["cameras"] = gltf::json::array({{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.05}}}}});
  builder.add("nodes", {{"camera", 0}, {"translation", {0.5, 0.5, 3}}});
  doc["extensionsUsed"] = gltf::json::array({"KHR_lights_punctual"});
  doc["extensions"]["KHR_lights_punctual"]["lights"] =
      gltf::json::array({{{"type", "point"}, {"intensity", 5.0}, {"color", {1, 1, 1}}}});
  gltf::json lamp = {{"translation", {0.5, 0.5, 2}}};
  lamp["extensions"]["KHR_lights_punctual"]["light"] = 0;
  builder.add("nodes", lamp);
  doc["scenes"] = gltf::json::array({{{"nodes", {0, 1, 2}}}});
  doc["scene"] = 0;
  std::vector<std::uint8_t> rgba(4 * 4 * 4, 200);
  const std::vector<std::uint8_t> png = gltf::encodePng(4, 4, rgba);
  corpus_files::writeBytes(file.parent_path() / "texture.png", png);
  builder.writeGltf(file, true);
}

const std::vector<std::string> kRender = {"render", "cornell", "--frames", "1", "--gi", "off", "--out", "{out}"};

}  // namespace

void outputFolderCases(CorpusBuilder& corpus) {
  using corpus_files::writeText;

  // D1: a recorded entry through a link to a folder outside: the earlier
  // run's "file" was removed there. Now reported and left as it is.
  for (const auto& [command, arguments] :
       {std::pair{std::string("render"), kRender},
        std::pair{std::string("brdf_viz"),
                  std::vector<std::string>{"brdf-viz", "--size", "32", "--frames", "1", "--out", "{out}"}}})
    corpus
        .add(
            "output_record_entry_through_a_link_" + command, "",
            [](const fs::path& dir) {
              fs::create_directories(dir / "victims");
              writeText(dir / "victims" / "keep.txt", "x\n");
              fs::create_directories(dir / "out");
              fs::create_directory_symlink(dir / "victims", dir / "out" / "evil");
              writeText(dir / "out" / ".bounce-written", "evil/keep.txt\n");
            },
            arguments, "", Outcome::Completes)
        .check = [](const fs::path& dir) {
      return firstOf({unchanged(dir / "victims" / "keep.txt", "x\n"),
                      stillLinked(dir / "out" / "evil", dir / "victims")});
    };

  // D2: frames/ a link to a folder outside, whose frame0000.png was
  // replaced. A link where the run writes is refused by name.
  corpus
      .add(
          "output_frames_folder_a_link", "out/frames",
          [](const fs::path& dir) {
            fs::create_directories(dir / "victims");
            writeText(dir / "victims" / "frame0000.png", "x\n");
            fs::create_directories(dir / "out");
            fs::create_directory_symlink(dir / "victims", dir / "out" / "frames");
            writeText(dir / "out" / ".bounce-written", "frames/frame0000.png\n");
          },
          {"render", "cornell", "--frames", "2", "--gi", "off", "--out", "{out}"}, "is a symbolic link")
      .check = [](const fs::path& dir) { return unchanged(dir / "victims" / "frame0000.png", "x\n"); };

  // D4, the link itself: render.exr, once written by Bounce (recorded), now
  // a link to a file outside. Renaming over it would leave the user's link
  // gone; it is refused by name, --overwrite or not.
  for (const bool overwrite : {false, true}) {
    std::vector<std::string> arguments = kRender;
    if (overwrite) arguments.push_back("--overwrite");
    corpus
        .add(
            std::string("output_recorded_render_exr_a_link") + (overwrite ? "_overwrite" : ""), "out/render.exr",
            [](const fs::path& dir) {
              writeText(dir / "victim.exr", "x\n");
              fs::create_directories(dir / "out");
              fs::create_symlink(dir / "victim.exr", dir / "out" / "render.exr");
              writeText(dir / "out" / ".bounce-written", "render.png\nrender.exr\n");
            },
            arguments, "is a symbolic link")
        .check = [](const fs::path& dir) {
      return firstOf({unchanged(dir / "victim.exr", "x\n"), stillLinked(dir / "out" / "render.exr", dir / "victim.exr")});
    };
  }

  // D5: save-gltf replaced the .bin and the textures beside a .gltf name
  // that did not exist yet; every file it would write is looked at first.
  // cornell has no texture; the textured quad's export writes y.texture0.png.
  for (const auto& [planted, scene] : {std::pair{"y.bin", "cornell"}, std::pair{"y.texture0.png", "{dir}/quad.gltf"}})
    corpus
        .add(
            std::string("output_save_gltf_over_") + planted, planted,
            [planted = std::string(planted)](const fs::path& dir) {
              writeTexturedQuad(dir / "quad.gltf");
              fs::create_directories(dir / "s");
              writeText(dir / "s" / planted, "notes\n");
              writeText(dir / "sg.txt", "wait 1\nsave-gltf y.gltf\n");
            },
            {"view", scene, "--headless", "--script", "{dir}/sg.txt", "--width", "16", "--height", "16", "--out",
             "{dir}/s"},
            "exists; not overwritten")
        .check = [planted = std::string(planted)](const fs::path& dir) {
      std::error_code error;
      return firstOf({unchanged(dir / "s" / planted, "notes\n"),
                      fs::exists(dir / "s" / "y.gltf", error) ? "wrote y.gltf anyway" : ""});
    };

  // D6: reference kept no record and replaced OUT.json and the G-buffer's
  // files beside OUT.exr, whoever had put them there.
  corpus
      .add(
          "output_reference_json_not_written_by_bounce", "v.json",
          [](const fs::path& dir) { writeText(dir / "v.json", "mine\n"); }, {"reference", "cornell", "--out", "{dir}/v.exr"},
          "no Bounce run wrote it")
      .check = [](const fs::path& dir) { return unchanged(dir / "v.json", "mine\n"); };
  corpus
      .add(
          "output_reference_gbuffer_not_written_by_bounce", "v.gbuffer/albedo.exr",
          [](const fs::path& dir) {
            fs::create_directories(dir / "v.gbuffer");
            writeText(dir / "v.gbuffer" / "albedo.exr", "mine\n");
          },
          {"reference", "cornell", "--out", "{dir}/v.exr"}, "no Bounce run wrote it")
      .check = [](const fs::path& dir) { return unchanged(dir / "v.gbuffer" / "albedo.exr", "mine\n"); };

  // H1, M1: the record a FIFO (the open blocked for ever), a link to
  // /dev/zero (read without end: 16 GB in a minute) or a 2 GB sparse file:
  // refused by name from what lstat says, before it is opened or read.
  const auto record = [&](const std::string& name, std::function<void(const fs::path&)> make,
                          const std::string& mentions) {
    CorpusCase& c = corpus.add(
        name, ".bounce-written",
        [make](const fs::path& dir) {
          fs::create_directories(dir / "out");
          make(dir / "out" / ".bounce-written");
        },
        kRender, mentions);
    c.maxSeconds = 5.0;
    c.maxMegabytes = 500;
  };
  record(
      "output_record_a_fifo", [](const fs::path& file) { ::mkfifo(file.c_str(), 0600); }, "is a FIFO");
  record(
      "output_record_a_link_to_dev_zero", [](const fs::path& file) { fs::create_symlink("/dev/zero", file); },
      "is a symbolic link");
  record(
      "output_record_sparse_2GB",
      [](const fs::path& file) {
        writeText(file, "render.png\n");
        fs::resize_file(file, std::uintmax_t(2) << 30);
      },
      "more than the 16 MiB");

  // U6: a line naming the folder itself ("." or "frames/..") made every
  // later run fail ("cannot remove this file of an earlier run"), with
  // --overwrite too. Reported and ignored; the record is then Bounce's own.
  for (const auto& [name, line, overwrite] :
       {std::tuple{"dot", ".", false}, std::tuple{"dot_overwrite", ".", true},
        std::tuple{"frames_dot_dot", "frames/..", false}}) {
    std::vector<std::string> arguments = kRender;
    if (overwrite) arguments.push_back("--overwrite");
    corpus
        .add(
            std::string("output_record_line_") + name, "",
            [line = std::string(line)](const fs::path& dir) {
              fs::create_directories(dir / "out" / "frames");
              writeText(dir / "out" / ".bounce-written", line + "\n");
            },
            arguments, "", Outcome::Completes)
        .check = [line = std::string(line)](const fs::path& dir) {
      const std::string text = contents(dir / "out" / ".bounce-written");
      if (text.find("\nrender.png\n") == std::string::npos) return "the record does not list render.png:\n" + text;
      if (text.find("\n" + line + "\n") != std::string::npos) return "the record still holds \"" + line + "\"";
      return std::string();
    };
  }
}

}  // namespace bounce::testing

#include "viewer/script.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <glm/glm.hpp>

#include "util/parse_number.h"
#include "util/printable.h"

namespace bounce::viewer {
namespace {

using Kind = ScriptCommand::Kind;

constexpr double kMaxFrames = 100000.0;
constexpr std::array<std::string_view, 7> kKeys = {"w", "a", "s", "d", "q", "e", "shift"};

struct Syntax {
  std::string_view name;
  Kind kind;
};
constexpr std::array<Syntax, 23> kCommands = {{{"wait", Kind::Wait},
                                               {"key", Kind::Key},
                                               {"look", Kind::Look},
                                               {"camera", Kind::Camera},
                                               {"pose", Kind::Pose},
                                               {"play", Kind::Play},
                                               {"click", Kind::Click},
                                               {"set", Kind::Set},
                                               {"gi", Kind::Gi},
                                               {"material", Kind::Material},
                                               {"screenshot", Kind::Screenshot},
                                               {"stages", Kind::Stages},
                                               {"window", Kind::Window},
                                               {"split", Kind::Split},
                                               {"other-settings", Kind::OtherSettings},
                                               {"panels", Kind::Panels},
                                               {"timings", Kind::Timings},
                                               {"frames", Kind::Frames},
                                               {"measure", Kind::Measure},
                                               {"stage", Kind::Stage},
                                               {"inspect", Kind::Inspect},
                                               {"save-gltf", Kind::SaveGltf},
                                               {"quit", Kind::Quit}}};

// The most a `camera` or `pose` line's view may turn in the viewer's hands:
// about two pixels of a 1080-line frame at a 60 degree field of view.
constexpr double kMaxTurnDegrees = 0.1;

// The fly camera keeps its target one unit ahead of its position in 32-bit
// floats (FlyCamera::setPose): far from the origin that step is rounded to
// the floats' spacing there, which turns the view, and where it rounds to
// nothing the direction is NaN. Returns how many degrees the view the line
// asks for turns as the camera keeps it, or NaN when it is lost.
double keptTurnDegrees(const std::vector<double>& n) {
  const glm::vec3 position{float(n[0]), float(n[1]), float(n[2])};
  const glm::vec3 target{float(n[3]), float(n[4]), float(n[5])};
  const glm::vec3 kept = (position + glm::normalize(target - position)) - position;
  if (!(glm::length(kept) > 0.5f)) return std::nan("");
  const glm::dvec3 wanted = glm::normalize(glm::dvec3(n[3] - n[0], n[4] - n[1], n[5] - n[2]));
  const double cosine = glm::dot(wanted, glm::normalize(glm::dvec3(kept)));
  return glm::degrees(std::acos(std::clamp(cosine, -1.0, 1.0)));
}

std::vector<std::string> splitWords(std::string_view line) {
  std::vector<std::string> words;
  std::istringstream stream{std::string(line)};
  for (std::string word; stream >> word;) words.push_back(word);
  return words;
}

class LineParser {
 public:
  LineParser(const std::string& source, int line, std::vector<std::string> words)
      : source_(source), line_(line), words_(std::move(words)) {}

  // The words quoted in `problem` are the user's: printable() shows their
  // control bytes as \xNN rather than letting them cut or garble the line.
  [[noreturn]] void fail(const std::string& problem) const {
    throw std::runtime_error(util::printable(source_ + ":" + std::to_string(line_) + ": " + problem));
  }
  void expectArguments(std::size_t count, const char* usage) const {
    if (words_.size() - 1 != count)
      fail("'" + words_[0] + "' takes " + std::to_string(count) + " argument" + (count == 1 ? "" : "s") + " (" + usage +
           "), got " + std::to_string(words_.size() - 1));
  }
  double number(std::size_t index, double low, double high) const {
    const std::string& word = words_[index];
    const std::optional<double> parsed = util::parseFiniteNumber(word);
    if (!parsed) fail("'" + word + "' is not a number");
    const double value = *parsed;
    if (value < low || value > high) fail(word + " is out of range [" + format(low) + ", " + format(high) + "]");
    return value;
  }
  double count(std::size_t index) const {
    const double value = number(index, 1.0, kMaxFrames);
    if (value != std::floor(value)) fail("'" + words_[index] + "' is not a whole number of frames");
    return value;
  }
  const std::vector<std::string>& words() const { return words_; }

 private:
  static std::string format(double v) {
    std::ostringstream out;
    out << v;
    return out.str();
  }
  const std::string& source_;
  int line_;
  std::vector<std::string> words_;
};

ScriptCommand parseLine(const LineParser& p, int line) {
  const std::vector<std::string>& w = p.words();
  const Syntax* syntax = nullptr;
  for (const Syntax& s : kCommands)
    if (s.name == w[0]) syntax = &s;
  if (!syntax) {
    std::string known;
    for (const Syntax& s : kCommands) known += (known.empty() ? "" : ", ") + std::string(s.name);
    p.fail("unknown command '" + w[0] + "' (known: " + known + ")");
  }
  ScriptCommand command;
  command.kind = syntax->kind;
  command.line = line;
  constexpr double kHuge = 1.0e9;
  switch (syntax->kind) {
    case Kind::Wait:
      p.expectArguments(1, "frames");
      command.numbers = {p.count(1)};
      break;
    case Kind::Key:
      p.expectArguments(2, "key, frames");
      if (!isScriptKey(w[1])) p.fail("unknown key '" + w[1] + "' (keys: w, a, s, d, q, e, shift)");
      command.words = {w[1]};
      command.numbers = {p.count(2)};
      break;
    case Kind::Look:
      p.expectArguments(2, "dx, dy in pixels");
      command.numbers = {p.number(1, -kHuge, kHuge), p.number(2, -kHuge, kHuge)};
      break;
    case Kind::Play:
      p.expectArguments(1, "frames");
      command.numbers = {p.count(1)};
      break;
    case Kind::Camera:
    case Kind::Pose:
      p.expectArguments(6, "position x y z, target x y z");
      for (std::size_t i = 1; i <= 6; ++i) command.numbers.push_back(p.number(i, -kHuge, kHuge));
      if (command.numbers[0] == command.numbers[3] && command.numbers[1] == command.numbers[4] &&
          command.numbers[2] == command.numbers[5])
        p.fail("the camera's position and target are the same point");
      if (const double turn = keptTurnDegrees(command.numbers); !(turn <= kMaxTurnDegrees)) {
        std::ostringstream where;
        where << "the camera at (" << command.numbers[0] << ", " << command.numbers[1] << ", " << command.numbers[2]
              << ") is too far from the origin for the viewer, which keeps its target one unit ahead in 32-bit "
                 "floats: ";
        if (std::isnan(turn))
          where << "the view direction is lost to rounding there";
        else
          where << "rounding would turn the view by " << turn << " degrees (at most " << kMaxTurnDegrees << ")";
        p.fail(where.str() + "; move the scene or the camera nearer the origin");
      }
      break;
    case Kind::Click:
    case Kind::Inspect:
      p.expectArguments(2, "pixel x, y of the frame");
      command.numbers = {p.number(1, 0.0, kHuge), p.number(2, 0.0, kHuge)};
      break;
    case Kind::Set:
      p.expectArguments(2, "key, value");
      command.words = {w[1], w[2]};
      break;
    case Kind::Gi:
      p.expectArguments(1, "off, screen-only or hybrid");
      if (w[1] != "off" && w[1] != "screen-only" && w[1] != "hybrid")
        p.fail("'gi' takes off, screen-only or hybrid, not '" + w[1] + "'");
      command.words = {w[1]};
      break;
    case Kind::Material: {
      if (w.size() < 2)
        p.fail("'material' takes a field (base_color, roughness, metallic, emission, emission_strength) and its value");
      const std::string& field = w[1];
      const bool colour = field == "base_color" || field == "emission";
      if (!colour && field != "roughness" && field != "metallic" && field != "emission_strength")
        p.fail("unknown material field '" + field + "' (base_color, roughness, metallic, emission, emission_strength)");
      p.expectArguments(colour ? 4 : 2, colour ? "field, r g b" : "field, value");
      const double high = field == "emission" || field == "emission_strength" ? kHuge : 1.0;
      for (std::size_t i = 2; i < w.size(); ++i) command.numbers.push_back(p.number(i, 0.0, high));
      command.words = {field};
      break;
    }
    case Kind::Screenshot:
    case Kind::Stages:
    case Kind::Window: {
      p.expectArguments(1, "a file name without folders");
      const std::string& name = w[1];
      if (name == "." || name == ".." || name.find('/') != std::string::npos || name.find('\\') != std::string::npos)
        p.fail("'" + name + "' is not a plain file name (no folders; it goes into the --out folder)");
      command.words = {name};
      break;
    }
    case Kind::Split:
      p.expectArguments(1, "none, gi-off, other or reference");
      if (w[1] != "none" && w[1] != "gi-off" && w[1] != "other" && w[1] != "reference")
        p.fail("'split' takes none, gi-off, other or reference, not '" + w[1] + "'");
      command.words = {w[1]};
      break;
    case Kind::Panels:
    case Kind::Frames:
      p.expectArguments(1, "on or off");
      if (w[1] != "on" && w[1] != "off") p.fail("'" + w[0] + "' takes on or off, not '" + w[1] + "'");
      command.words = {w[1]};
      break;
    case Kind::Timings:
      p.expectArguments(1, "a label for the printed line");
      command.words = {w[1]};
      break;
    case Kind::OtherSettings:
      p.expectArguments(1, "a JSON settings file");
      command.words = {w[1]};
      break;
    case Kind::Stage:
      p.expectArguments(1, "an image's name, or final");
      command.words = {w[1]};
      break;
    case Kind::SaveGltf: {
      p.expectArguments(1, "a file name ending in .gltf or .glb, without folders");
      const std::string& name = w[1];
      // The extension must follow a name: ".glb" alone is no file name.
      const bool gltf = (name.ends_with(".gltf") && name.size() > 5) || (name.ends_with(".glb") && name.size() > 4);
      if (!gltf || name.find('/') != std::string::npos || name.find('\\') != std::string::npos)
        p.fail("'" + name + "' is not a plain file name ending in .gltf or .glb");
      command.words = {name};
      break;
    }
    case Kind::Measure:
    case Kind::Quit:
      p.expectArguments(0, "none");
      break;
  }
  return command;
}

}  // namespace

bool isScriptKey(std::string_view name) {
  for (std::string_view key : kKeys)
    if (key == name) return true;
  return false;
}

std::vector<ScriptCommand> parseScript(std::string_view text, const std::string& source) {
  std::vector<ScriptCommand> commands;
  int line = 0;
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view content = text.substr(start, end - start);
    ++line;
    if (const std::size_t hash = content.find('#'); hash != std::string_view::npos) content = content.substr(0, hash);
    // A NUL is never part of a command, and every message that quoted the
    // word holding it would end there ("unknown command 'screen"): the line
    // is refused whole, shown with the NUL made visible.
    if (const std::size_t nul = content.find('\0'); nul != std::string_view::npos)
      throw std::runtime_error(source + ":" + std::to_string(line) + ": a NUL byte at column " +
                               std::to_string(nul + 1) + " of '" + util::printable(content) +
                               "' (shown as \\x00): a script is text");
    std::vector<std::string> words = splitWords(content);
    if (!words.empty()) commands.push_back(parseLine(LineParser(source, line, std::move(words)), line));
    start = end + 1;
  }
  return commands;
}

std::vector<ScriptCommand> loadScript(const std::filesystem::path& file) {
  // A FIFO would block the viewer before its window opens and /dev/zero
  // would fill the memory: a script is a regular file of bounded size.
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(file, error);
  if (!std::filesystem::exists(status))
    throw std::runtime_error(file.string() + ": cannot read the script (no such file)");
  if (!std::filesystem::is_regular_file(status)) throw std::runtime_error(file.string() + ": not a regular file");
  const std::uintmax_t size = std::filesystem::file_size(file, error);
  if (error) throw std::runtime_error(file.string() + ": cannot read the script (" + error.message() + ")");
  if (size > kMaxScriptBytes)
    throw std::runtime_error(file.string() + ": the script has " + std::to_string(size) + " bytes; at most " +
                             std::to_string(kMaxScriptBytes) + " are read");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error(file.string() + ": cannot read the script (not readable)");
  std::string text(std::size_t(size), '\0');
  in.read(text.data(), std::streamsize(size));
  if (in.bad() || std::uintmax_t(in.gcount()) != size)
    throw std::runtime_error(file.string() + ": reading the script failed");
  return parseScript(text, file.string());
}

}  // namespace bounce::viewer

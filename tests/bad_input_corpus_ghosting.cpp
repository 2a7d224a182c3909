// The corpus's ghosting cases (issue 46): events that change nothing, tiny
// frames, black references.
#include <fstream>

#include <nlohmann/json.hpp>

#include "bad_input_corpus_builder.h"

namespace bounce::testing {

namespace {

namespace fs = std::filesystem;

// An option value's mistake: no input file, only the phrase.
void mistake(CorpusBuilder& corpus, const std::string& name, std::vector<std::string> arguments,
             const std::string& mentions) {
  arguments.insert(arguments.end(), {"--out", "{out}"});
  corpus.add(
      name, "", [](const fs::path&) {}, std::move(arguments), mentions);
}

// "" when every frame's indirect diffuse mean over a black reference is
// null in ghosting.json (undefined, as denoise writes it), else what is not.
std::string undefinedOverABlackReference(const fs::path& dir) {
  std::ifstream stream(dir / "out" / "ghosting.json");
  if (!stream) return "no ghosting.json written";
  const nlohmann::json json = nlohmann::json::parse(stream, nullptr, false);
  if (json.is_discarded()) return "ghosting.json is not JSON";
  if (json["reference_mean"]["indirect_diffuse"] != 0.0)
    return "the 1x1 reference's indirect diffuse is " + json["reference_mean"]["indirect_diffuse"].dump() +
           ", not black: the case tests nothing";
  for (const nlohmann::json& frame : json["frames"])
    if (!frame["indirect_diffuse"]["mean_over_reference"].is_null())
      return "frame " + frame["frame"].dump() + ": mean_over_reference " +
             frame["indirect_diffuse"]["mean_over_reference"].dump() + " over a black reference, not null";
  if (!json["settled"]["indirect_diffuse"]["mean_over_reference"].is_null())
    return "the settled frame's mean_over_reference is not null over a black reference";
  return "";
}

}  // namespace

void ghostingCases(CorpusBuilder& corpus) {
  const std::vector<std::string> sun = {"ghosting", "sun-room", "--event", "sun"};
  const auto with = [](std::vector<std::string> base, std::initializer_list<std::string> more) {
    base.insert(base.end(), more);
    return base;
  };
  // S3: events that change nothing, refused as --sun-jump 0 is.
  mistake(corpus, "ghosting_sun_below_the_horizon", with(sun, {"--sun-elevation", "-90"}), "below the horizon");
  mistake(corpus, "ghosting_sun_turned_at_the_zenith", with(sun, {"--sun-elevation", "90", "--sun-jump", "90"}),
          "stands at the zenith");
  mistake(corpus, "ghosting_sun_jump_lost_to_precision", with(sun, {"--sun-jump", "1e-30"}),
          "azimuth 105 -> 105): nothing changes");
  mistake(corpus, "ghosting_cut_without_gi", {"ghosting", "cornell", "--event", "cut", "--gi", "off"},
          "--event cut measures the GI");
  mistake(corpus, "ghosting_light_without_gi",
          {"ghosting", "cornell", "--event", "light", "--gi", "off", "--light-change", "cornell light:emission=0,0,0"},
          "--event light measures the GI");
  // U1: the example names cornell's lamp as it is named, and a lamp named
  // wrongly is answered with the scene's own lamps.
  mistake(corpus, "ghosting_light_without_a_change", {"ghosting", "cornell", "--event", "light"},
          "'cornell light:emission=0,0,0' switches cornell's lamp off");
  mistake(corpus, "ghosting_light_change_of_a_lamp_not_there",
          {"ghosting", "cornell", "--event", "light", "--light-change", "light:emission=0,0,0"},
          "its lamps (materials that emit light) are 'cornell light'");
  // S2: at 1x1 the reference's indirect diffuse is black: the share of it
  // is undefined (null), not 0 (which reads as "none of the light found").
  corpus
      .add(
          "ghosting_cut_over_a_black_reference", "", [](const fs::path&) {},
          {"ghosting",        "cornell", "--event",     "cut",  "--width",       "1", "--height", "1",
           "--reference-spp", "1",       "--gi-warmup", "1",    "--event-frame", "2", "--after",  "1",
           "--settle",        "1",       "--out",       "{out}"},
          "", Outcome::Completes)
      .check = undefinedOverABlackReference;
}

}  // namespace bounce::testing

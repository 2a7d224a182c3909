// util::parseJson (src/util/json_parse.h): the depth limit users' JSON files
// are read under, the events its observers see, and that it builds the same
// value as nlohmann's own parser.
#include "util/json_parse.h"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace bounce::util {
namespace {

using nlohmann::json;

std::string nestedArrays(int depth) { return std::string(std::size_t(depth), '[') + std::string(std::size_t(depth), ']'); }

// Through iterators, as the glTF importer reads (the settings reader's
// stream is tested once: each input adapter is compiled anew, which costs
// the sanitizer build more than all these tests run).
template <class Observer = NoJsonObserver>
json parse(std::string text, int maxDepth, Observer&& observer = {}) {
  return parseJson(text.begin(), text.end(), maxDepth, std::forward<Observer>(observer));
}

TEST(JsonParse, BuildsTheSameValueAsNlohmann) {
  const std::string text =
      R"({"a": [1, -2, 3.5, "x", true, null, {"b": [[], {}]}], "c": {"d": 18446744073709551615}, "e": ""})";
  EXPECT_EQ(parse(text, 64), json::parse(text));
  std::istringstream stream(text);
  EXPECT_EQ(parseJson(stream, 64), json::parse(text));
}

TEST(JsonParse, TheLimitIsTheNumberOfContainersOpenAtOnce) {
  EXPECT_EQ(parse(nestedArrays(64), 64).dump(), nestedArrays(64));
  try {
    parse(nestedArrays(65), 64);
    FAIL() << "65 levels were accepted";
  } catch (const JsonTooDeep& e) {
    EXPECT_STREQ(e.what(), "JSON nested deeper than 64 levels");
  }
  // Objects count as arrays do, and closing one makes room again.
  EXPECT_THROW(parse(R"({"a": {"b": {"c": 1}}})", 2), JsonTooDeep);
  EXPECT_NO_THROW(parse(R"([{"a": [1]}, {"b": [2]}, [[3]]])", 3));
  // Refused as soon as the limit is passed: the rest need not even be JSON.
  EXPECT_THROW(parse(std::string(100000, '[') + "not json", 64), JsonTooDeep);
}

TEST(JsonParse, BadJsonThrowsNlohmannsParseError) {
  EXPECT_THROW(parse(std::string(R"({"a": [1, 2})"), 64), json::parse_error);
  EXPECT_THROW(parse(std::string(""), 64), json::parse_error);
  EXPECT_THROW(parse(std::string("[1] 2"), 64), json::parse_error);
}

TEST(JsonParse, TheObserverSeesObjectsAndKeysInOrder) {
  struct Recorder {
    std::vector<std::string> events;
    void objectStart() { events.push_back("{"); }
    void objectEnd() { events.push_back("}"); }
    void key(const std::string& name) { events.push_back(name); }
  } recorder;
  parse(std::string(R"({"a": 1, "b": [{"c": {}}, 2], "d": {"e": null}})"), 64, recorder);
  const std::vector<std::string> expected = {"{", "a", "b", "{", "c", "{", "}", "}", "d", "{", "e", "}", "}"};
  EXPECT_EQ(recorder.events, expected);
}

// nlohmann's parse callback searched the enclosing array each time an object
// in it closed; this array of 200,000 objects took minutes that way under
// AddressSanitizer. Its elements all arrive, in order.
TEST(JsonParse, AWideArrayOfObjectsArrivesWhole) {
  constexpr int kElements = 200000;
  std::string text = "[";
  for (int i = 0; i < kElements; ++i) text += (i ? ",{\"i\":" : "{\"i\":") + std::to_string(i) + "}";
  text += "]";
  const json value = parse(text, 64);
  ASSERT_EQ(value.size(), std::size_t(kElements));
  EXPECT_EQ(value.front().at("i"), 0);
  EXPECT_EQ(value.back().at("i"), kElements - 1);
}

}  // namespace
}  // namespace bounce::util

// util::printable: user text in one-line messages (src/util/printable.h).
#include <gtest/gtest.h>

#include <string>

#include "util/printable.h"

namespace bounce::util {
namespace {

using namespace std::string_literals;

TEST(Printable, PlainTextIsUnchanged) {
  EXPECT_EQ(printable("scene.gltf: accessor 3 is out of range"), "scene.gltf: accessor 3 is out of range");
  EXPECT_EQ(printable("caf\xc3\xa9.gltf"), "caf\xc3\xa9.gltf");  // UTF-8 is kept
  EXPECT_EQ(printable(""), "");
}

TEST(Printable, TerminalEscapesAreShownNotObeyed) {
  const std::string hostile = "\x1b]0;PWNED\x07\x1b[2J";
  const std::string shown = printable("uri '" + hostile + "'");
  EXPECT_EQ(shown, "uri '\\x1b]0;PWNED\\x07\\x1b[2J'");
  for (const char c : shown) EXPECT_GE(static_cast<unsigned char>(c), 0x20);
}

TEST(Printable, NulNewlineAndDeleteAreEscapedSoTheMessageStaysOneWholeLine) {
  EXPECT_EQ(printable("a\0b"s), "a\\x00b");
  EXPECT_EQ(printable("line\nnext\r\t\x7f"), "line\\x0anext\\x0d\\x09\\x7f");
}

TEST(Printable, ALongTokenIsCutToItsHeadAndTail) {
  const std::string token = "<" + std::string(1'000'000, 'x') + ">";
  const std::string shown = printable("no command " + token + " here");
  EXPECT_LT(shown.size(), 400u);
  EXPECT_TRUE(shown.starts_with("no command <xxx")) << shown;
  EXPECT_TRUE(shown.ends_with("xxx> here")) << shown;
  EXPECT_NE(shown.find("...[999762 bytes]..."), std::string::npos) << shown;
  // A token at the limit is whole.
  const std::string atLimit(kLongestPrintedToken, 'y');
  EXPECT_EQ(printable(atLimit), atLimit);
  EXPECT_NE(printable(atLimit + "y"), atLimit + "y");
}

}  // namespace
}  // namespace bounce::util

// Text that leaves the server: server/wire_text.h. The replacement follows the Unicode standard's
// "maximal subpart" practice (section 3.9, table 3-8's example), and every output is checked
// against nlohmann's strict serialiser as an independent judge of validity.
#include "server/wire_text.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tests/support/hostile_json.h"

namespace incise::server {
namespace {

const std::string kFffd = "\xEF\xBF\xBD";

TEST(WireText, ValidTextPassesUnchanged) {
  for (const std::string& text : std::vector<std::string>{
           "", "plain ASCII", "caf\xC3\xA9", "\xE2\x82\xAC 5", "\xF0\x9F\xA9\xBA stethoscope",
           "\xED\x9F\xBF", "\xEE\x80\x80", "\xF4\x8F\xBF\xBF", std::string("nul\0inside", 10)}) {
    EXPECT_TRUE(is_valid_utf8(text)) << text;
    EXPECT_EQ(valid_utf8(text), text);
    EXPECT_TRUE(test::is_utf8(text)) << "the oracle disagrees on " << text;
  }
}

TEST(WireText, EachMaximalSubpartBecomesOneReplacement) {
  struct Case {
    std::string in, out;
  };
  const Case cases[] = {
      {"\xFF", kFffd},
      {"a\x80z", "a" + kFffd + "z"},
      {"\xC0\xAF", kFffd + kFffd},              // overlong '/': C0 is never a lead byte
      {"\xE0\x80\xAF", kFffd + kFffd + kFffd},  // overlong: E0 needs A0..BF next
      {"\xF0\x80\x80\xAF", kFffd + kFffd + kFffd + kFffd},
      {"\xED\xA0\x80", kFffd + kFffd + kFffd},              // U+D800, a surrogate
      {"\xF4\x90\x80\x80", kFffd + kFffd + kFffd + kFffd},  // past U+10FFFF
      {"\xF5\x80", kFffd + kFffd},
      {"\xE2\x82", kFffd},  // truncated: one subpart
      {"\xE2\x82z", kFffd + "z"},
      {"\xF0\x9F\xA9", kFffd},
      // Table 3-8 of the standard: 61 F1 80 80 E1 80 C2 62 80 63 80 BF 64.
      {"\x61\xF1\x80\x80\xE1\x80\xC2\x62\x80\x63\x80\xBF\x64",
       "a" + kFffd + kFffd + kFffd + "b" + kFffd + "c" + kFffd + kFffd + "d"},
  };
  for (const auto& c : cases) {
    EXPECT_FALSE(is_valid_utf8(c.in));
    EXPECT_FALSE(test::is_utf8(c.in));
    const auto out = valid_utf8(c.in);
    EXPECT_EQ(out, c.out);
    EXPECT_TRUE(is_valid_utf8(out));
    EXPECT_TRUE(test::is_utf8(out));
  }
}

TEST(WireText, EveryByteStringOfUpToThreeBytesComesOutValid) {
  // Exhaustive over 1..2 bytes, and over 3 bytes with a lead byte from each class.
  std::string text;
  for (int a = 0; a < 256; ++a) {
    for (int b = 0; b < 256; ++b) {
      text = {static_cast<char>(a), static_cast<char>(b)};
      ASSERT_TRUE(test::is_utf8(valid_utf8(text))) << a << " " << b;
      ASSERT_EQ(is_valid_utf8(text), test::is_utf8(text)) << a << " " << b;
      for (const int c : {0x41, 0x80, 0xA0, 0xBF, 0xE0, 0xFF}) {
        text = {static_cast<char>(a), static_cast<char>(b), static_cast<char>(c)};
        ASSERT_TRUE(test::is_utf8(valid_utf8(text))) << a << " " << b << " " << c;
        ASSERT_EQ(is_valid_utf8(text), test::is_utf8(text)) << a << " " << b << " " << c;
      }
    }
  }
}

TEST(WireText, ClipCutsBeforeAWholeCodePointAndMarksTheCut) {
  EXPECT_EQ(clip_utf8("short", 10), "short");
  EXPECT_EQ(clip_utf8("0123456789abc", 10), "0123456...");
  // A two-byte character across the cut is dropped whole.
  const std::string umlauts = "\xC3\xBC\xC3\xBC\xC3\xBC\xC3\xBC\xC3\xBC";  // 10 bytes
  EXPECT_EQ(clip_utf8(umlauts, 9), "\xC3\xBC\xC3\xBC\xC3\xBC...");
  EXPECT_EQ(clip_utf8(umlauts, 8), "\xC3\xBC\xC3\xBC...");
  // Without room for "...", the cut is bare.
  EXPECT_EQ(clip_utf8(umlauts, 5), "\xC3\xBC\xC3\xBC");
  // Invalid bytes are replaced before the length is judged.
  const auto reason = close_reason_text(std::string(200, '\xFF'));
  EXPECT_LE(reason.size(), kMaxCloseReasonBytes);
  EXPECT_TRUE(test::is_utf8(reason));
  EXPECT_TRUE(reason.starts_with(kFffd + kFffd));
}

TEST(WireText, DumpReplacesWhatTheStrictSerialiserRefuses) {
  const nlohmann::json value = {{"error", "no such endpoint: GET /api/\xFF"},
                                {"ok", "caf\xC3\xA9"}};
  EXPECT_THROW((void)value.dump(), nlohmann::json::type_error);
  const auto text = dump_json(value);
  const auto back = nlohmann::json::parse(text);
  EXPECT_EQ(back["error"], "no such endpoint: GET /api/" + kFffd);
  EXPECT_EQ(back["ok"], "caf\xC3\xA9");
}

}  // namespace
}  // namespace incise::server

namespace incise::server {
namespace {

TEST(PlainText, RefusesControlCharactersAndDirectionOverrides) {
  EXPECT_TRUE(is_plain_text("Station 1, room 2", false));
  EXPECT_TRUE(is_plain_text("Gr\xC3\xBC\xC3\x9F Gott \xE2\x80\x94 caf\xC3\xA9", false));  // ü ß — é
  EXPECT_FALSE(is_plain_text(std::string("Bad\0name", 8), false));
  EXPECT_FALSE(is_plain_text("tab\there", false));
  EXPECT_FALSE(is_plain_text("del\x7F", false));
  EXPECT_FALSE(is_plain_text("c1 \xC2\x85 next line", false));
  EXPECT_TRUE(is_plain_text("no-break\xC2\xA0space", false));
  // U+202E RIGHT-TO-LEFT OVERRIDE shows "report\u202Efdp.exe" as "reportexe.pdf".
  EXPECT_FALSE(
      is_plain_text("report\xE2\x80\xAE"
                    "fdp.exe",
                    false));
  EXPECT_FALSE(is_plain_text("\xE2\x80\xAA embedding", false));  // U+202A
  EXPECT_FALSE(is_plain_text("\xE2\x81\xA6 isolate", false));    // U+2066
  EXPECT_FALSE(is_plain_text("\xE2\x81\xA9", false));            // U+2069
  EXPECT_TRUE(is_plain_text("\xE2\x80\xA9", false));  // U+2029 is not a direction control
  // A note may break lines and hold tabs; never other controls.
  EXPECT_TRUE(is_plain_text("first line\nsecond\tline", true));
  EXPECT_FALSE(is_plain_text("first line\nsecond\tline", false));
  EXPECT_FALSE(is_plain_text("bell\a", true));
  EXPECT_FALSE(is_plain_text("carriage\rreturn", true));
}

TEST(QueryValue, FindsTheFirstPairWithTheKey) {
  EXPECT_EQ(query_value("fps=20&scene=a%2Fb&scene=c", "scene"), "a%2Fb");
  EXPECT_EQ(query_value("fps=20", "fps"), "20");
  EXPECT_EQ(query_value("fps=", "fps"), "");
  EXPECT_EQ(query_value("fpsx=1&xfps=2", "fps"), std::nullopt);
  EXPECT_EQ(query_value("", "fps"), std::nullopt);
  EXPECT_EQ(query_value("fps", "fps"), std::nullopt);  // no '='
}

TEST(PercentDecoded, DecodesHexPairsAndPlusAndRefusesBrokenOnes) {
  EXPECT_EQ(percent_decoded("scenes%2Fcalibration%2fcube.json"), "scenes/calibration/cube.json");
  EXPECT_EQ(percent_decoded("a+b%20c"), "a b c");
  EXPECT_EQ(percent_decoded("%41"), "A");  // at the very end
  EXPECT_EQ(percent_decoded("%00"), std::string(1, '\0'));
  EXPECT_EQ(percent_decoded(""), "");
  for (const char* broken : {"%", "%4", "%4g", "%g4", "abc%", "%%41"}) {
    EXPECT_EQ(percent_decoded(broken), std::nullopt) << broken;
  }
}

}  // namespace
}  // namespace incise::server

#include "base/json_value.h"

#include <gtest/gtest.h>

#include <random>
#include <string>

namespace fly {
namespace {

JsonValue parse(std::string_view text) {
  return parseJson(text, "t.json").root;
}

// Parses `text`, expecting an InputError at "t.json:<where>" (line:column) whose message contains `message`.
void expectError(std::string_view text, const std::string& where, const std::string& message) {
  SCOPED_TRACE(std::string(text.substr(0, 80)));
  try {
    parseJson(text, "t.json");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    const std::string at = "t.json:" + where;
    EXPECT_EQ(what.substr(0, at.size() + 1), at + (e.location().jsonPath.empty() ? ":" : " "))
        << what.substr(0, 300);
    EXPECT_NE(what.find(message), std::string::npos) << what.substr(0, 300);
  }
}

TEST(JsonValue, ParsesScalars) {
  EXPECT_TRUE(parse("null").isNull());
  EXPECT_TRUE(parse(" true ").boolean());
  EXPECT_FALSE(parse("false").boolean());
  EXPECT_EQ(parse("\"abc\"").string(), "abc");

  const JsonValue zero = parse("-0");
  EXPECT_TRUE(zero.isInteger());
  EXPECT_EQ(zero.integer(), 0);

  const JsonValue n = parse("-12.5e-1");
  EXPECT_DOUBLE_EQ(n.number(), -1.25);
  EXPECT_FALSE(n.isInteger());
  EXPECT_FALSE(parse("1.0").isInteger());
  EXPECT_FALSE(parse("1e2").isInteger());
  EXPECT_DOUBLE_EQ(parse("1E+2").number(), 100.0);

  // 2^53 + 1 is not a double, but it is exact as an integer.
  const JsonValue big = parse("9007199254740993");
  ASSERT_TRUE(big.isInteger());
  EXPECT_EQ(big.integer(), 9007199254740993);
  // Beyond int64: still a number, no longer an integer.
  const JsonValue huge = parse("18446744073709551616");
  EXPECT_FALSE(huge.isInteger());
  EXPECT_DOUBLE_EQ(huge.number(), 18446744073709551616.0);
}

TEST(JsonValue, DecodesEscapesAndUtf8) {
  EXPECT_EQ(parse(R"("\"\\\/\b\f\n\r\t")").string(), "\"\\/\b\f\n\r\t");
  EXPECT_EQ(parse(R"("\u00e4\u00C4")").string(), "\xC3\xA4\xC3\x84");
  EXPECT_EQ(parse(R"("\u20AC")").string(), "\xE2\x82\xAC");
  EXPECT_EQ(parse(R"("\uD83D\uDE00")").string(), "\xF0\x9F\x98\x80");  // U+1F600 from a surrogate pair
  EXPECT_EQ(parse(R"("a\u0000b")").string(), std::string("a\0b", 3));
  EXPECT_EQ(parse("\"Ä€😀\"").string(), "Ä€😀");
}

TEST(JsonValue, KeepsStructureAndKeyOrder) {
  const JsonValue v = parse(R"({"z": 1, "a": [true, null, {"k": "v"}], "m": {}})");
  ASSERT_TRUE(v.isObject());
  ASSERT_EQ(v.members().size(), 3u);
  EXPECT_EQ(v.members()[0].key, "z");
  EXPECT_EQ(v.members()[1].key, "a");
  EXPECT_EQ(v.members()[2].key, "m");
  const JsonValue& a = v.find("a")->value;
  ASSERT_EQ(a.elements().size(), 3u);
  EXPECT_TRUE(a.elements()[1].isNull());
  EXPECT_EQ(a.elements()[2].find("k")->value.string(), "v");
  EXPECT_EQ(a.elements()[2].find("k")->value.path(), "/a/2/k");
  EXPECT_TRUE(v.find("m")->value.members().empty());
  EXPECT_EQ(v.find("missing"), nullptr);
  EXPECT_TRUE(parse("[]").elements().empty());
}

TEST(JsonValue, LocationsOfNestedKeysAndValues) {
  // Columns count code points: "Ä" is two bytes but one column.
  const std::string text =
      "{\n"
      "  \"sky\": {\n"
      "    \"Ä\": 1,\n"
      "\t\"sun\" :  true\n"
      "  },\n"
      "  \"a/b~c\": [ 1,\n"
      "     [2] ]\n"
      "}\n";
  const JsonDocument doc = parseJson(text, "scene.json");
  EXPECT_EQ(doc.root.position().line, 1);
  EXPECT_EQ(doc.root.position().column, 1);
  EXPECT_EQ(doc.root.path(), "");

  const JsonMember& sky = doc.root.members()[0];
  EXPECT_EQ(sky.keyPosition.line, 2);
  EXPECT_EQ(sky.keyPosition.column, 3);
  EXPECT_EQ(sky.value.position().line, 2);
  EXPECT_EQ(sky.value.position().column, 10);
  EXPECT_EQ(sky.value.path(), "/sky");

  const JsonMember& ae = sky.value.members()[0];
  EXPECT_EQ(ae.key, "Ä");
  EXPECT_EQ(ae.keyPosition.line, 3);
  EXPECT_EQ(ae.keyPosition.column, 5);
  EXPECT_EQ(ae.value.position().column, 10);
  const JsonMember& sun = sky.value.members()[1];
  EXPECT_EQ(sun.keyPosition.line, 4);
  EXPECT_EQ(sun.keyPosition.column, 2);  // after a tab
  EXPECT_EQ(sun.value.position().column, 11);
  EXPECT_EQ(sun.value.path(), "/sky/sun");

  const JsonMember& ab = doc.root.members()[1];
  EXPECT_EQ(ab.value.path(), "/a~1b~0c");
  const JsonValue& inner = ab.value.elements()[1].elements()[0];
  EXPECT_EQ(inner.position().line, 7);
  EXPECT_EQ(inner.position().column, 7);
  EXPECT_EQ(inner.path(), "/a~1b~0c/1/0");

  const SourceLocation keyLoc = doc.locationOf(sun);
  EXPECT_EQ(keyLoc.str(), "scene.json:4:2 (at /sky/sun)");
  EXPECT_EQ(doc.locationOf(sun.value).str(), "scene.json:4:11 (at /sky/sun)");
}

TEST(JsonValue, SkipsByteOrderMark) {
  const JsonDocument doc = parseJson("\xEF\xBB\xBF{\"a\": 1}", "t.json");
  EXPECT_EQ(doc.root.members()[0].keyPosition.column, 2);
  expectError("\xEF\xBB\xBF{\"a\" 1}", "1:6", "expected ':' after key \"a\"");
}

TEST(JsonValue, SyntaxErrorsNameLineColumnAndExpectation) {
  expectError("", "1:1", "the document is empty");
  expectError("  \n ", "2:2", "the document is empty");
  expectError("{\n  \"site\": {}\n  \"sky\": {}\n}", "3:3",
              "expected ',' or '}' after the value of key \"site\"");
  expectError("{\"a\": 1,\n}", "1:8", "trailing comma after the last member");
  expectError("[1, 2, ]", "1:6", "trailing comma after the last element");
  expectError("{\"a\": \"abc", "1:7", "unterminated string");
  expectError("{\"a\": \"abc\n\"}", "1:7", "unterminated string (it reaches the end of the line)");
  expectError("{\"a\": [1, 2", "1:12", "unexpected end of file; expected ',' or ']' after element 1");
  expectError("{\"a\": ", "1:7", "unexpected end of file; expected a value for key \"a\"");
  expectError("{\"a\": 1", "1:8", "unexpected end of file; expected ',' or '}'");
  expectError("[1 2]", "1:4", "expected ',' or ']' after element 0 of the array; got '2'");
  expectError("{a: 1}", "1:2", "expected a key in double quotes; got 'a'");
  expectError("{'a': 1}", "1:2", "expected a key in double quotes");
  expectError("{\"a\": 'x'}", "1:7", "strings must be in double quotes");
  expectError("{\"a\" 1}", "1:6", "expected ':' after key \"a\"; got '1'");
  expectError("{\"a\": tru}", "1:7", "unexpected word \"tru\"; expected a value for key \"a\"");
  expectError("{\"a\": True}", "1:7", "unexpected word \"True\"");
  expectError("[NaN]", "1:2", "NaN and Infinity are not JSON numbers");
  expectError("[-Infinity]", "1:2", "NaN and Infinity are not JSON numbers");
  expectError("[01]", "1:3", "leading zeros are not allowed");
  expectError("[1.]", "1:4", "expected a digit after the decimal point");
  expectError("[1e]", "1:4", "expected a digit in the exponent");
  expectError("[-]", "1:3", "expected a digit after '-'");
  expectError("[+1]", "1:2", "must not start with '+'");
  expectError("[.5]", "1:2", "must start with a digit");
  expectError("[1e999]", "1:2", "out of the range of a double");
  expectError("{} {}", "1:4", "after the end of the JSON document");
  expectError("{\"a\": 1} // note", "1:10", "comments are not allowed");
  expectError("[\n /* x */ 1]", "2:2", "comments are not allowed");
  expectError("[\"a\\qb\"]", "1:4", "invalid escape \\'q'");
  expectError("[\"\\u12G4\"]", "1:3", "expected 4 hexadecimal digits after \\u");
  expectError("[\"x\\uD800\"]", "1:4", "unpaired UTF-16 surrogate \\uD800");
  expectError("[\"\\uDC00\"]", "1:3", "unpaired UTF-16 surrogate \\uDC00");
  expectError("[\"\\uD800\\u0041\"]", "1:3", "unpaired UTF-16 surrogate");
  expectError("[\"a\tb\"]", "1:4", "control character U+0009 inside a string");
  expectError("[\"\xC3\x28\"]", "1:3", "invalid UTF-8");
  expectError("[\"\xED\xA0\x80\"]", "1:3", "invalid UTF-8");  // a surrogate encoded in UTF-8
  expectError("[1, \xC3\xA4]", "1:5", "unexpected character U+00E4");
  expectError("{\n\"a\": 1,\n\"b\": 2,\n  \"a\": 3}", "4:3",
              "duplicate key \"a\"; it is first given at line 2, column 1");
}

TEST(JsonValue, ErrorsCarryPathAndHint) {
  try {
    parseJson("{\"models\": [{\"file\": \"a\"\n \"name\": \"b\"}]}", "s.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.location().line, 2);
    EXPECT_EQ(e.location().column, 2);
    EXPECT_EQ(e.location().jsonPath, "/models/0");
    EXPECT_EQ(e.hint(), "a comma is missing between two members");
  }
  try {
    parseJson("{\"a\": [1,\n{\"b\": 2", "s.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(e.hint().find("the object opened at line 2, column 1 is not closed"), std::string::npos)
        << e.hint();
  }
}

TEST(JsonValue, DepthIsCapped) {
  const auto nested = [](int depth) { return std::string(depth, '[') + std::string(depth, ']'); };
  EXPECT_NO_THROW(parse(nested(kJsonMaxDepth)));
  expectError(nested(kJsonMaxDepth + 1), "1:" + std::to_string(kJsonMaxDepth + 1),
              "nested more than 256 levels");
  // Far deeper input, unbalanced, still fails cleanly instead of exhausting the stack.
  expectError(std::string(1000000, '['), "1:257", "nested more than");
  expectError(std::string(100000, '{'), "1:2", "expected a key");
}

TEST(JsonValue, TruncationsAndCorruptionsNeverCrash) {
  const std::string doc = R"({
  "fly": 1,
  "models": [{"file": "house.gltf", "translation": [1.5, -2e1, 0], "scale": 1}],
  "site": {"latitude": 60.17, "longitude": 24.94, "timeZone": "Europe/Helsinki"},
  "text": "tab\t quote\" \u00e4 \uD83D\uDE00 ä",
  "flags": [true, false, null, {}, []]
})";
  ASSERT_NO_THROW(parse(doc));
  for (size_t n = 0; n < doc.size(); ++n) {
    // Every proper prefix of this document is incomplete.
    EXPECT_THROW(parse(doc.substr(0, n)), InputError) << "prefix of " << n << " bytes";
  }
  std::mt19937 rng(12345);
  std::uniform_int_distribution<size_t> where(0, doc.size() - 1);
  std::uniform_int_distribution<int> byte(0, 255);
  for (int i = 0; i < 5000; ++i) {
    std::string s = doc;
    for (int k = 0; k < 1 + i % 4; ++k) s[where(rng)] = static_cast<char>(byte(rng));
    try {
      parse(s);
    } catch (const InputError&) {
      // Expected for most corruptions; what matters is that nothing else happens.
    }
  }
}

}  // namespace
}  // namespace fly

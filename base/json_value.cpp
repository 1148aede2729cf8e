#include "base/json_value.h"

#include <cassert>
#include <charconv>
#include <cstdio>
#include <unordered_map>
#include <utility>

namespace fly {

// --- JsonValue -------------------------------------------------------------------------------------------

bool JsonValue::boolean() const {
  assert(type_ == Type::kBool);
  return bool_;
}

double JsonValue::number() const {
  assert(type_ == Type::kNumber);
  return number_;
}

bool JsonValue::isInteger() const {
  return type_ == Type::kNumber && isInteger_;
}

int64_t JsonValue::integer() const {
  assert(isInteger());
  return integer_;
}

const std::string& JsonValue::string() const {
  assert(type_ == Type::kString);
  return string_;
}

const std::vector<JsonValue>& JsonValue::elements() const {
  assert(type_ == Type::kArray);
  return elements_;
}

const std::vector<JsonMember>& JsonValue::members() const {
  assert(type_ == Type::kObject);
  return members_;
}

const JsonMember* JsonValue::find(std::string_view key) const {
  for (const JsonMember& m : members()) {
    if (m.key == key) return &m;
  }
  return nullptr;
}

std::string JsonValue::describe() const {
  switch (type_) {
    case Type::kNull:
      return "null";
    case Type::kBool:
      return bool_ ? "true" : "false";
    case Type::kNumber:
      return "a number";
    case Type::kString:
      return "a string";
    case Type::kArray:
      return "an array";
    case Type::kObject:
      return "an object";
  }
  return "an unknown value";
}

SourceLocation JsonDocument::locationOf(const JsonValue& value) const {
  return {fileName, value.position().line, value.position().column, value.path()};
}

SourceLocation JsonDocument::locationOf(const JsonMember& member) const {
  return {fileName, member.keyPosition.line, member.keyPosition.column, member.value.path()};
}

std::string jsonPointerToken(std::string_view key) {
  std::string s;
  s.reserve(key.size());
  for (char c : key) {
    if (c == '~') {
      s += "~0";
    } else if (c == '/') {
      s += "~1";
    } else {
      s += c;
    }
  }
  return s;
}

// --- Parser ----------------------------------------------------------------------------------------------

namespace {

bool isDigit(char c) {
  return c >= '0' && c <= '9';
}
bool isWordChar(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || isDigit(c) || c == '_';
}

int hexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

void appendUtf8(std::string& s, uint32_t cp) {
  if (cp < 0x80) {
    s += static_cast<char>(cp);
  } else if (cp < 0x800) {
    s += static_cast<char>(0xC0 | (cp >> 6));
    s += static_cast<char>(0x80 | (cp & 0x3F));
  } else if (cp < 0x10000) {
    s += static_cast<char>(0xE0 | (cp >> 12));
    s += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    s += static_cast<char>(0x80 | (cp & 0x3F));
  } else {
    s += static_cast<char>(0xF0 | (cp >> 18));
    s += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
    s += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    s += static_cast<char>(0x80 | (cp & 0x3F));
  }
}

// Length of the well-formed UTF-8 sequence starting at text[pos] (Unicode 15, table 3-7), or 0 when
// ill-formed.
size_t utf8SequenceLength(std::string_view text, size_t pos) {
  const auto byte = [&](size_t i) { return i < text.size() ? static_cast<unsigned char>(text[i]) : 0u; };
  const unsigned b0 = byte(pos);
  if (b0 < 0x80) return 1;
  const auto cont = [&](size_t i, unsigned lo = 0x80, unsigned hi = 0xBF) {
    const unsigned b = byte(pos + i);
    return b >= lo && b <= hi;
  };
  if (b0 >= 0xC2 && b0 <= 0xDF) return cont(1) ? 2 : 0;
  if (b0 >= 0xE0 && b0 <= 0xEF) {
    const unsigned lo = b0 == 0xE0 ? 0xA0 : 0x80;
    const unsigned hi = b0 == 0xED ? 0x9F : 0xBF;  // ED A0..BF would encode surrogates
    return cont(1, lo, hi) && cont(2) ? 3 : 0;
  }
  if (b0 >= 0xF0 && b0 <= 0xF4) {
    const unsigned lo = b0 == 0xF0 ? 0x90 : 0x80;
    const unsigned hi = b0 == 0xF4 ? 0x8F : 0xBF;  // beyond U+10FFFF otherwise
    return cont(1, lo, hi) && cont(2) && cont(3) ? 4 : 0;
  }
  return 0;
}

std::string quoted(std::string_view s) {
  return "\"" + std::string(s) + "\"";
}

std::string formatPosition(JsonPosition p) {
  return "line " + std::to_string(p.line) + ", column " + std::to_string(p.column);
}

}  // namespace

// Recursive descent over the text, tracking line and column. Not in the anonymous namespace: JsonValue names
// it as a friend.
class JsonParser {
 public:
  JsonParser(std::string_view text, const std::string& fileName) : text_(text), fileName_(fileName) {}

  JsonValue parseDocument() {
    // A byte-order mark is not JSON, but editors on Windows write one; it occupies no column.
    if (text_.substr(0, 3) == "\xEF\xBB\xBF") pos_ = 3;
    skipWhitespace("");
    if (atEnd()) {
      fail(here(), "", "the document is empty; expected a JSON value",
           "a scene file is a JSON object: { \"fly\": 1, ... }");
    }
    JsonValue root;
    parseValue(root, "", "a JSON value");
    skipWhitespace("");
    if (!atEnd()) {
      fail(here(), "", "unexpected " + describeHere() + " after the end of the JSON document",
           "a JSON file holds a single value; check for a bracket closed too early or text after the last "
           "'}'");
    }
    return root;
  }

 private:
  // Innermost open array or object, for "the object opened at ... is not closed".
  struct Open {
    char bracket;
    JsonPosition position;
  };

  bool atEnd() const { return pos_ >= text_.size(); }
  char peek() const { return atEnd() ? '\0' : text_[pos_]; }
  char peekAt(size_t offset) const { return pos_ + offset < text_.size() ? text_[pos_ + offset] : '\0'; }
  JsonPosition here() const { return {line_, column_}; }

  // Moves over one byte. UTF-8 continuation bytes do not start a new column.
  void advance() {
    const char c = text_[pos_++];
    if (c == '\n') {
      ++line_;
      column_ = 1;
    } else if ((static_cast<unsigned char>(c) & 0xC0) != 0x80) {
      ++column_;
    }
  }

  [[noreturn]] void fail(JsonPosition at, const std::string& path, const std::string& message,
                         std::string hint = {}) const {
    throw InputError(SourceLocation{fileName_, at.line, at.column, path}, message, std::move(hint));
  }

  // The hint for an early end of file: which bracket is still open.
  std::string truncationHint() const {
    std::string hint = "the file ends early; it may be truncated";
    if (!open_.empty()) {
      const Open& o = open_.back();
      hint += std::string("; the ") + (o.bracket == '{' ? "object" : "array") + " opened at " +
              formatPosition(o.position) + " is not closed";
    }
    return hint;
  }

  // What the character at the current position is, for messages: 'x', U+00E4 or "end of file".
  std::string describeHere() const {
    if (atEnd()) return "end of file";
    const unsigned char c = static_cast<unsigned char>(peek());
    if (c == '\'') return "a single quote (')";
    if (c >= 0x20 && c < 0x7F) return std::string("'") + static_cast<char>(c) + "'";
    char buf[32];
    if (c < 0x80) {
      std::snprintf(buf, sizeof buf, "character U+%04X", c);
      return buf;
    }
    const size_t n = utf8SequenceLength(text_, pos_);
    if (n == 0) {
      std::snprintf(buf, sizeof buf, "byte 0x%02X (not UTF-8)", c);
      return buf;
    }
    uint32_t cp = c & (0xFF >> (n + 1));
    for (size_t i = 1; i < n; ++i) cp = (cp << 6) | (static_cast<unsigned char>(text_[pos_ + i]) & 0x3F);
    std::snprintf(buf, sizeof buf, "character U+%04X", cp);
    return buf;
  }

  void skipWhitespace(const std::string& path) {
    while (!atEnd()) {
      const char c = peek();
      if (c == ' ' || c == '\t' || c == '\n' || c == '\r') {
        advance();
      } else if (c == '/' && (peekAt(1) == '/' || peekAt(1) == '*')) {
        fail(here(), path, "comments are not allowed in JSON", "remove the comment");
      } else {
        return;
      }
    }
  }

  void parseValue(JsonValue& out, std::string path, const std::string& expected) {
    out.position_ = here();
    out.path_ = std::move(path);
    if (atEnd()) fail(here(), out.path_, "unexpected end of file; expected " + expected, truncationHint());
    const char c = peek();
    if (c == '{') return parseObject(out);
    if (c == '[') return parseArray(out);
    if (c == '"') {
      out.type_ = JsonValue::Type::kString;
      out.string_ = parseString(out.path_);
      return;
    }
    if (c == '-' || isDigit(c)) return parseNumber(out);
    if (isWordChar(c)) return parseWord(out, expected);
    if (c == '\'') {
      fail(here(), out.path_, "strings must be in double quotes (\"), not single quotes (')",
           "write \"text\" instead of 'text'");
    }
    if (c == '+') fail(here(), out.path_, "a number must not start with '+'", "remove the '+'");
    if (c == '.') {
      fail(here(), out.path_, "a number must start with a digit", "write 0.5 instead of .5");
    }
    fail(here(), out.path_, "unexpected " + describeHere() + "; expected " + expected);
  }

  void enter(char bracket) {
    if (static_cast<int>(open_.size()) >= kJsonMaxDepth) {
      // No JSON path: at this depth it would be hundreds of characters of "/0/0/0...".
      fail(here(), "",
           "arrays and objects are nested more than " + std::to_string(kJsonMaxDepth) + " levels deep",
           "the document is probably malformed; fly's files nest only a few levels");
    }
    open_.push_back({bracket, here()});
    advance();
  }

  void parseObject(JsonValue& out) {
    out.type_ = JsonValue::Type::kObject;
    enter('{');
    std::unordered_map<std::string, JsonPosition> seen;
    skipWhitespace(out.path_);
    if (peek() == '}') {
      advance();
      open_.pop_back();
      return;
    }
    for (;;) {
      JsonMember m;
      m.keyPosition = here();
      if (peek() != '"') {
        if (atEnd())
          fail(here(), out.path_, "unexpected end of file; expected a key in double quotes",
               truncationHint());
        if (isWordChar(peek()) || peek() == '\'') {
          fail(here(), out.path_, "expected a key in double quotes; got " + describeHere(),
               "object keys are written in double quotes: \"key\": value");
        }
        fail(here(), out.path_, "expected a key in double quotes; got " + describeHere());
      }
      m.key = parseString(out.path_);
      const std::string memberPath = out.path_ + "/" + jsonPointerToken(m.key);
      if (const auto it = seen.find(m.key); it != seen.end()) {
        fail(m.keyPosition, memberPath,
             "duplicate key " + quoted(m.key) + "; it is first given at " + formatPosition(it->second),
             "give each key once");
      }
      seen.emplace(m.key, m.keyPosition);
      skipWhitespace(out.path_);
      if (peek() != ':') {
        if (atEnd()) {
          fail(here(), out.path_, "unexpected end of file; expected ':' after key " + quoted(m.key),
               truncationHint());
        }
        fail(here(), out.path_, "expected ':' after key " + quoted(m.key) + "; got " + describeHere());
      }
      advance();
      skipWhitespace(memberPath);
      parseValue(m.value, memberPath, "a value for key " + quoted(m.key));
      out.members_.push_back(std::move(m));
      skipWhitespace(out.path_);
      const std::string& key = out.members_.back().key;
      if (peek() == '}') {
        advance();
        open_.pop_back();
        return;
      }
      if (peek() != ',') {
        const std::string expected = "expected ',' or '}' after the value of key " + quoted(key);
        if (atEnd()) fail(here(), out.path_, "unexpected end of file; " + expected, truncationHint());
        fail(here(), out.path_, expected + "; got " + describeHere(),
             peek() == '"' ? "a comma is missing between two members" : "");
      }
      const JsonPosition comma = here();
      advance();
      skipWhitespace(out.path_);
      if (peek() == '}') {
        fail(comma, out.path_, "trailing comma after the last member of the object",
             "JSON allows no comma before '}'; remove it");
      }
    }
  }

  void parseArray(JsonValue& out) {
    out.type_ = JsonValue::Type::kArray;
    enter('[');
    skipWhitespace(out.path_);
    if (peek() == ']') {
      advance();
      open_.pop_back();
      return;
    }
    for (;;) {
      const size_t index = out.elements_.size();
      out.elements_.emplace_back();
      parseValue(out.elements_.back(), out.path_ + "/" + std::to_string(index),
                 "a value (element " + std::to_string(index) + " of the array)");
      skipWhitespace(out.path_);
      if (peek() == ']') {
        advance();
        open_.pop_back();
        return;
      }
      if (peek() != ',') {
        const std::string expected =
            "expected ',' or ']' after element " + std::to_string(index) + " of the array";
        if (atEnd()) fail(here(), out.path_, "unexpected end of file; " + expected, truncationHint());
        fail(here(), out.path_, expected + "; got " + describeHere());
      }
      const JsonPosition comma = here();
      advance();
      skipWhitespace(out.path_);
      if (peek() == ']') {
        fail(comma, out.path_, "trailing comma after the last element of the array",
             "JSON allows no comma before ']'; remove it");
      }
    }
  }

  // At the opening quote; returns the decoded UTF-8 text and leaves the position after the closing quote.
  std::string parseString(const std::string& path) {
    const JsonPosition start = here();
    const auto unterminated = [&](const std::string& why) {
      fail(start, path, "unterminated string" + why,
           "close the string with \"; a line break inside a string is written \\n");
    };
    advance();
    std::string s;
    for (;;) {
      if (atEnd()) unterminated(" (it reaches the end of the file)");
      const char c = peek();
      const unsigned char u = static_cast<unsigned char>(c);
      if (c == '"') {
        advance();
        return s;
      }
      if (c == '\n' || c == '\r') unterminated(" (it reaches the end of the line)");
      if (u < 0x20) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "control character U+%04X inside a string", u);
        fail(here(), path, buf, c == '\t' ? "write a tab as \\t" : "write it as an escape, \\u00XX");
      }
      if (c == '\\') {
        parseEscape(s, path);
        continue;
      }
      if (u >= 0x80) {
        const size_t n = utf8SequenceLength(text_, pos_);
        if (n == 0) {
          fail(here(), path, "invalid UTF-8 in a string (" + describeHere() + ")", "save the file as UTF-8");
        }
        s.append(text_.substr(pos_, n));
        for (size_t i = 0; i < n; ++i) advance();
        continue;
      }
      s += c;
      advance();
    }
  }

  void parseEscape(std::string& s, const std::string& path) {
    const JsonPosition start = here();
    advance();            // the backslash
    if (atEnd()) return;  // the caller reports the unterminated string
    const char c = peek();
    switch (c) {
      case '"':
        s += '"';
        break;
      case '\\':
        s += '\\';
        break;
      case '/':
        s += '/';
        break;
      case 'b':
        s += '\b';
        break;
      case 'f':
        s += '\f';
        break;
      case 'n':
        s += '\n';
        break;
      case 'r':
        s += '\r';
        break;
      case 't':
        s += '\t';
        break;
      case 'u': {
        advance();
        uint32_t cp = parseHex4(start, path);
        if (cp >= 0xDC00 && cp <= 0xDFFF) failSurrogate(start, path, cp);
        if (cp >= 0xD800 && cp <= 0xDBFF) {
          if (peek() != '\\' || peekAt(1) != 'u') failSurrogate(start, path, cp);
          const JsonPosition low = here();
          advance();
          advance();
          const uint32_t lo = parseHex4(low, path);
          if (lo < 0xDC00 || lo > 0xDFFF) failSurrogate(start, path, cp);
          cp = 0x10000 + ((cp - 0xD800) << 10) + (lo - 0xDC00);
        }
        appendUtf8(s, cp);
        return;  // parseHex4 moved past the digits
      }
      default:
        fail(start, path, "invalid escape \\" + describeHere() + " in a string",
             "the escapes are \\\" \\\\ \\/ \\b \\f \\n \\r \\t and \\uXXXX; write a backslash as \\\\");
    }
    advance();
  }

  // Four hex digits at the current position (after "\u"); `escape` is where the backslash was.
  uint32_t parseHex4(JsonPosition escape, const std::string& path) {
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i) {
      const int h = hexValue(peek());
      if (atEnd() || h < 0) {
        fail(escape, path, "expected 4 hexadecimal digits after \\u", "write e.g. \\u00E4 for ä");
      }
      v = (v << 4) | static_cast<uint32_t>(h);
      advance();
    }
    return v;
  }

  [[noreturn]] void failSurrogate(JsonPosition at, const std::string& path, uint32_t cp) const {
    char buf[64];
    std::snprintf(buf, sizeof buf, "unpaired UTF-16 surrogate \\u%04X in a string", cp);
    fail(at, path, buf,
         "a character beyond U+FFFF is written as a pair (\\uD83D\\uDE00) or directly in UTF-8");
  }

  void parseNumber(JsonValue& out) {
    const size_t begin = pos_;
    const JsonPosition start = here();
    const auto bad = [&](const std::string& what, const std::string& hint) {
      fail(here(), out.path_, "invalid number: " + what, hint);
    };
    if (peek() == '-') advance();
    if (!isDigit(peek())) {
      if (isWordChar(peek())) {
        fail(start, out.path_, "NaN and Infinity are not JSON numbers", "give a finite number");
      }
      bad("expected a digit after '-'", "");
    }
    if (peek() == '0' && isDigit(peekAt(1))) {
      advance();
      bad("leading zeros are not allowed", "write 7 instead of 07");
    }
    while (isDigit(peek())) advance();
    bool integral = true;
    if (peek() == '.') {
      integral = false;
      advance();
      if (!isDigit(peek())) bad("expected a digit after the decimal point", "write 1.0 or 1, not 1.");
      while (isDigit(peek())) advance();
    }
    if (peek() == 'e' || peek() == 'E') {
      integral = false;
      advance();
      if (peek() == '+' || peek() == '-') advance();
      if (!isDigit(peek())) bad("expected a digit in the exponent", "write e.g. 1e-3");
      while (isDigit(peek())) advance();
    }
    const char* first = text_.data() + begin;
    const char* last = text_.data() + pos_;
    out.type_ = JsonValue::Type::kNumber;
    const auto [end, ec] = std::from_chars(first, last, out.number_);
    if (ec != std::errc() || end != last) {
      fail(start, out.path_, "number " + std::string(first, last) + " is out of the range of a double",
           "doubles reach about ±1.8e308, and the smallest non-zero magnitude is about 4.9e-324");
    }
    if (integral) {
      const auto [iend, iec] = std::from_chars(first, last, out.integer_);
      out.isInteger_ = iec == std::errc() && iend == last;
    }
  }

  // true, false, null, or a word that is none of them.
  void parseWord(JsonValue& out, const std::string& expected) {
    const size_t begin = pos_;
    const JsonPosition start = here();
    while (isWordChar(peek())) advance();
    const std::string_view word = text_.substr(begin, pos_ - begin);
    if (word == "true" || word == "false") {
      out.type_ = JsonValue::Type::kBool;
      out.bool_ = word == "true";
    } else if (word == "null") {
      out.type_ = JsonValue::Type::kNull;
    } else if (word == "NaN" || word == "Infinity" || word == "inf" || word == "nan") {
      fail(start, out.path_, "NaN and Infinity are not JSON numbers", "give a finite number");
    } else {
      fail(start, out.path_, "unexpected word " + quoted(word) + "; expected " + expected,
           "text values must be in double quotes; the literals are true, false and null (lower case)");
    }
  }

  std::string_view text_;
  const std::string& fileName_;
  size_t pos_ = 0;
  int line_ = 1;
  int column_ = 1;
  std::vector<Open> open_;
};

JsonDocument parseJson(std::string_view text, const std::string& fileName) {
  JsonDocument doc;
  doc.fileName = fileName;
  doc.root = JsonParser(text, fileName).parseDocument();
  return doc;
}

}  // namespace fly

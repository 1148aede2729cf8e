// A JSON (RFC 8259) document model that remembers where each value and each object key was written: line and
// column (1-based) and its JSON path, so that scene-file errors can point at the offending text.
// nlohmann::json keeps no positions, hence this small parser of our own.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "base/error.h"

namespace fly {

struct JsonMember;

// A position in the source text. Lines are counted at '\n'; columns count Unicode code points (not bytes), so
// they match what an editor shows for UTF-8 text (a tab counts as one column).
struct JsonPosition {
  int line = 0;    // 1-based
  int column = 0;  // 1-based
};

class JsonValue {
 public:
  enum class Type : uint8_t { kNull, kBool, kNumber, kString, kArray, kObject };

  Type type() const { return type_; }
  bool isNull() const { return type_ == Type::kNull; }
  bool isBool() const { return type_ == Type::kBool; }
  bool isNumber() const { return type_ == Type::kNumber; }
  bool isString() const { return type_ == Type::kString; }
  bool isArray() const { return type_ == Type::kArray; }
  bool isObject() const { return type_ == Type::kObject; }

  // Typed access; calling one on a value of another type is a programming error (debug assertion).
  bool boolean() const;
  double number() const;  // the nearest double
  // True when the number was written as an integer (no fraction, no exponent) that fits in int64; integer()
  // then returns it exactly, beyond the 2^53 that a double holds exactly.
  bool isInteger() const;
  int64_t integer() const;
  const std::string& string() const;  // UTF-8, escapes decoded
  const std::vector<JsonValue>& elements() const;
  const std::vector<JsonMember>& members() const;  // in the order written; keys are unique

  // The member with this key, or nullptr (objects only).
  const JsonMember* find(std::string_view key) const;

  JsonPosition position() const { return position_; }
  // JSON Pointer (RFC 6901) of this value from the document root, e.g. "/models/0/file"; "" for the root.
  const std::string& path() const { return path_; }

  // "a string", "a number", "an object", "an array", "true", "false" or "null", for "...; got a string".
  std::string describe() const;

 private:
  friend class JsonParser;

  Type type_ = Type::kNull;
  bool bool_ = false;
  bool isInteger_ = false;
  double number_ = 0.0;
  int64_t integer_ = 0;
  std::string string_;
  std::vector<JsonValue> elements_;
  std::vector<JsonMember> members_;
  JsonPosition position_;
  std::string path_;
};

struct JsonMember {
  std::string key;
  JsonPosition keyPosition;  // of the key's opening quote
  JsonValue value;
};

// A parsed document and the file it came from, to build error locations.
struct JsonDocument {
  std::string fileName;
  JsonValue root;

  // file:line:column of the value, with its JSON path.
  SourceLocation locationOf(const JsonValue& value) const;
  // file:line:column of the member's key, with the member's JSON path.
  SourceLocation locationOf(const JsonMember& member) const;
};

// Deepest nesting of arrays and objects accepted; deeper input is rejected rather than risking the stack.
inline constexpr int kJsonMaxDepth = 256;

// Parses a whole document (a UTF-8 byte-order mark is skipped). Throws InputError with `fileName`, the line
// and column, the JSON path of the enclosing value, what was expected and a hint, for: syntax errors,
// duplicate keys, invalid UTF-8, unpaired surrogates, numbers beyond the range of a double, nesting deeper
// than kJsonMaxDepth.
JsonDocument parseJson(std::string_view text, const std::string& fileName);

// A JSON Pointer reference token for `key`: '~' → "~0", '/' → "~1" (RFC 6901).
std::string jsonPointerToken(std::string_view key);

}  // namespace fly

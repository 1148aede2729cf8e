#include "base/error.h"

#include <cstdio>

namespace fly {

std::string SourceLocation::str() const {
  std::string s = file;
  if (line > 0) {
    s += ":" + std::to_string(line);
    if (column > 0) s += ":" + std::to_string(column);
  }
  if (!jsonPath.empty()) s += " (at " + jsonPath + ")";
  return s;
}

namespace {
std::string formatInputError(const SourceLocation& loc, const std::string& message, const std::string& hint) {
  std::string s = loc.str();
  if (!s.empty()) s += ": ";
  s += message;
  if (!hint.empty()) s += "\n  hint: " + hint;
  return s;
}
}  // namespace

InputError::InputError(SourceLocation location, const std::string& message, std::string hint)
    : std::runtime_error(formatInputError(location, message, hint)),
      location_(std::move(location)),
      message_(message),
      hint_(std::move(hint)) {}

std::string printableExcerpt(std::string_view text, size_t maxChars) {
  std::string out;
  for (size_t i = 0; i < text.size() && i < maxChars; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02X", static_cast<unsigned>(c));
      out += buf;
    }
  }
  if (text.size() > maxChars) out += "...";
  return out;
}

}  // namespace fly

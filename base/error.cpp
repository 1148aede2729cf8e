#include "base/error.h"

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

}  // namespace fly

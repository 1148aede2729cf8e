#include "sdb/photometric_text.h"

#include <cmath>
#include <cstdio>

#include "base/error.h"

namespace fly::sdb {

std::string_view trimBlanks(std::string_view s) {
  const auto isSpace = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; };
  while (!s.empty() && isSpace(s.front())) s.remove_prefix(1);
  while (!s.empty() && isSpace(s.back())) s.remove_suffix(1);
  return s;
}

std::string quotedExcerpt(std::string_view s) { return "'" + printableExcerpt(s) + "'"; }

std::string formatNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, (v == std::floor(v) && std::abs(v) < 1e15) ? "%.0f" : "%g", v);
  return buf;
}

}  // namespace fly::sdb

#include "base/log.h"

#include <cstdio>
#include <mutex>

namespace fly::log {
namespace {

std::mutex& mutex() {
  static std::mutex m;
  return m;
}

Level g_level = Level::kInfo;

void stderrSink(Level level, std::string_view message) {
  const char* prefix = "";
  if (level == Level::kWarning) prefix = "warning: ";
  if (level == Level::kError) prefix = "error: ";
  std::fprintf(stderr, "%s%.*s\n", prefix, static_cast<int>(message.size()), message.data());
}

Sink& sink() {
  static Sink s = stderrSink;
  return s;
}

}  // namespace

void setLevel(Level l) {
  std::lock_guard lock(mutex());
  g_level = l;
}

Level level() {
  std::lock_guard lock(mutex());
  return g_level;
}

Sink setSink(Sink s) {
  std::lock_guard lock(mutex());
  Sink previous = std::move(sink());
  sink() = s ? std::move(s) : Sink(stderrSink);
  return previous;
}

void write(Level l, std::string_view message) {
  std::lock_guard lock(mutex());
  if (l < g_level) return;
  sink()(l, message);
}

}  // namespace fly::log

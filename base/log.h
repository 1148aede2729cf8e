// Logging to stderr with levels; tests replace the sink to see what was reported.
#pragma once

#include <functional>
#include <string_view>

namespace fly::log {

enum class Level { kDebug, kInfo, kWarning, kError };

using Sink = std::function<void(Level, std::string_view message)>;

// Messages below this level are dropped (default kInfo).
void setLevel(Level level);
Level level();

// Replaces where messages go (default: stderr, prefixed "warning: " / "error: "). Returns the previous sink.
Sink setSink(Sink sink);

void write(Level level, std::string_view message);
inline void debug(std::string_view m) { write(Level::kDebug, m); }
inline void info(std::string_view m) { write(Level::kInfo, m); }
inline void warn(std::string_view m) { write(Level::kWarning, m); }
inline void error(std::string_view m) { write(Level::kError, m); }

}  // namespace fly::log

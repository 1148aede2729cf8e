// Reading inputs with clear errors, and writing outputs atomically (temporary file, then rename).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

namespace fly {

// Throws InputError naming `path` unless it exists, is a regular file (not a directory) and, unless
// `allowEmpty`, is not empty. `what` names the kind of file in the message ("scene file", "IES file").
void checkInputFile(const std::filesystem::path& path, std::string_view what, bool allowEmpty = false);

// Reads a whole file after checkInputFile(); throws InputError on read failure.
std::string readInputFile(const std::filesystem::path& path, std::string_view what, bool allowEmpty = false);

// Writes `bytes` to `path` so that readers see either the old file or the whole new one: the data goes to a
// temporary file in the same directory, is flushed to disk and renamed into place. Throws std::runtime_error.
void writeFileAtomic(const std::filesystem::path& path, std::string_view bytes);

}  // namespace fly

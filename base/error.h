// Errors that reach the user: bad input (exit 3) and wrong usage (exit 2), each with a location and a hint.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

namespace fly {

// Process exit codes of every fly command (README, `fly --help`).
enum ExitCode : int {
  kExitOk = 0,
  kExitFailure = 1,   // anything else: internal error, I/O failure while writing
  kExitUsage = 2,     // wrong command-line usage
  kExitBadInput = 3,  // a scene, glTF, IES, weather file or value that cannot be used
};

// Where in an input a problem was found. Every field is optional except the file.
struct SourceLocation {
  std::string file;      // path as the user gave it
  int line = 0;          // 1-based; 0 = unknown
  int column = 0;        // 1-based; 0 = unknown
  std::string jsonPath;  // JSON pointer-like path, e.g. "/models/0/translation"; empty = none

  // "file:line:column (at /json/path)" with the unknown parts left out.
  std::string str() const;
};

// Bad input: the message says what is wrong, the hint how to fix it.
class InputError : public std::runtime_error {
 public:
  InputError(SourceLocation location, const std::string& message, std::string hint = {});

  const SourceLocation& location() const { return location_; }
  const std::string& message() const { return message_; }
  const std::string& hint() const { return hint_; }

 private:
  SourceLocation location_;
  std::string message_;
  std::string hint_;
};

// Wrong command-line usage (unknown flag, missing argument, malformed value).
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Text from an input file as it may appear in a message: at most `maxChars` characters ("..." after a cut),
// bytes outside printable ASCII written as \xNN, so that a binary file does not garble the terminal.
std::string printableExcerpt(std::string_view text, size_t maxChars = 40);

}  // namespace fly

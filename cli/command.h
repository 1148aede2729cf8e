// How sub-commands plug into the fly program: each adds its CLI11 sub-command and returns what runs it.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace fly::cli {

// The program's version, as `fly --version` prints it and outputs record it.
inline constexpr const char* kFlyVersion = "0.1.0";

// Runs a parsed sub-command; returns the process exit code (base/error.h). May throw InputError (exit 3),
// UsageError (exit 2) or any other exception (exit 1); main() reports them.
struct Command {
  CLI::App* sub = nullptr;
  std::function<int()> run;
};

Command addInfoCommand(CLI::App& app);
Command addSunCommand(CLI::App& app);
Command addSkyCommand(CLI::App& app);
Command addIlluminanceCommand(CLI::App& app);
Command addDaylightFactorCommand(CLI::App& app);
Command addBakeCommand(CLI::App& app);
Command addProbeCommand(CLI::App& app);
Command addRenderCommand(CLI::App& app);
Command addViewCommand(CLI::App& app);

}  // namespace fly::cli

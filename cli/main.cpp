// The fly program: sub-commands, option parsing and the mapping of errors to exit codes.
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "base/error.h"
#include "base/log.h"
#include "cli/command.h"
#include "cli/image_decoder_module.h"
#include "cli/image_metadata.h"
#include "sdb/gltf_import.h"

namespace {

constexpr const char* kFooter =
    "Exit codes: 0 success, 1 other failure, 2 usage error, 3 bad input (scene, glTF, IES or weather file).\n"
    "Units: lengths in metres, luminance in cd/m², illuminance in lux, intensity in cd, flux in lm.\n"
    "Run 'fly COMMAND --help' for a command's options.";

int run(int argc, char** argv) {
  fly::cli::recordCommandLine(argc, argv);
  CLI::App app(
      "fly: physically based daylight and artificial light for buildings and products.\n"
      "Bakes global illumination into light maps and shows it in real time.",
      "fly");
  app.footer(kFooter);
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("fly ") + fly::cli::kFlyVersion);
  bool verbose = false;
  bool quiet = false;
  app.add_flag("-v,--verbose", verbose, "print debug messages");
  app.add_flag("-q,--quiet", quiet, "print errors only (no warnings)");

  const std::vector<fly::cli::Command> commands = {
      fly::cli::addInfoCommand(app),
      fly::cli::addSunCommand(app),
      fly::cli::addSkyCommand(app),
      fly::cli::addIlluminanceCommand(app),
      fly::cli::addDaylightFactorCommand(app),
      fly::cli::addBakeCommand(app),
      fly::cli::addProbeCommand(app),
      fly::cli::addRenderCommand(app),
      fly::cli::addViewCommand(app),
  };

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);  // prints the message
    return fly::kExitUsage;
  }
  // glTF textures in every format OpenImageIO reads (PNG, JPEG, WebP, HDR, EXR, TIFF), not only PNG and JPEG;
  // OpenImageIO is loaded on the first texture.
  fly::sdb::setImageDecoder(&fly::cli::decodeImageThroughModule);
  if (verbose) fly::log::setLevel(fly::log::Level::kDebug);
  if (quiet) fly::log::setLevel(fly::log::Level::kError);
  for (const fly::cli::Command& c : commands) {
    if (c.sub->parsed()) return c.run();
  }
  return fly::kExitUsage;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const fly::InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return fly::kExitBadInput;
  } catch (const fly::UsageError& e) {
    std::fprintf(stderr, "error: %s\nRun 'fly --help' for usage.\n", e.what());
    return fly::kExitUsage;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return fly::kExitFailure;
  }
}

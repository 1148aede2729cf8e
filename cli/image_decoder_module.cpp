#include "cli/image_decoder_module.h"

#include <dlfcn.h>

#include <filesystem>
#include <stdexcept>

#include "sdb/oiio_image_decoder.h"

namespace fly::cli {

namespace {

struct LoadedDecoder {
  sdb::DecodeImageFunction decode = nullptr;
  sdb::DecodeFloatImageFunction decodeFloat = nullptr;
  std::string error;  // why it could not be loaded
};

// The module's file name (FLY_OIIO_DECODER_MODULE, from cli/CMakeLists.txt), in the folder of the running
// executable (/proc/self/exe).
LoadedDecoder load() {
  LoadedDecoder r;
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  const std::filesystem::path module = (ec ? std::filesystem::path() : exe.parent_path()) / FLY_OIIO_DECODER_MODULE;
  // The module is never unloaded: the decoder it returns stays in use until the process ends.
  void* handle = dlopen(module.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* reason = dlerror();  // names the file
    r.error = reason ? reason : module.string() + ": dlopen failed";
    return r;
  }
  using Entry = sdb::DecodeImageFunction (*)();
  using FloatEntry = sdb::DecodeFloatImageFunction (*)();
  const auto entry = reinterpret_cast<Entry>(dlsym(handle, sdb::kOiioDecoderModuleSymbol));
  const auto floatEntry = reinterpret_cast<FloatEntry>(dlsym(handle, sdb::kOiioFloatModuleSymbol));
  if (!entry || !floatEntry) {
    r.error = module.string() + " has no symbol " + (entry ? sdb::kOiioFloatModuleSymbol : sdb::kOiioDecoderModuleSymbol);
    return r;
  }
  r.decode = entry();
  r.decodeFloat = floatEntry();
  return r;
}

}  // namespace

// The module, loaded once (thread-safe); std::logic_error when it cannot be.
const LoadedDecoder& loadedModule() {
  static const LoadedDecoder loaded = load();
  if (!loaded.decode) {
    throw std::logic_error("fly cannot load its texture decoder module (" + loaded.error +
                           "); it is built beside the fly program: rebuild fly (scripts/build fly)");
  }
  return loaded;
}

sdb::Texture decodeImageThroughModule(std::span<const uint8_t> encoded, size_t maxBytes,
                                      std::vector<std::string>& notes) {
  return loadedModule().decode(encoded, maxBytes, notes);
}

sdb::FloatRgbImage decodeFloatImageThroughModule(std::span<const uint8_t> encoded, size_t maxBytes) {
  return loadedModule().decodeFloat(encoded, maxBytes);
}

}  // namespace fly::cli

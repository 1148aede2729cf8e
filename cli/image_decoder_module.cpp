#include "cli/image_decoder_module.h"

#include <dlfcn.h>

#include <filesystem>
#include <stdexcept>

#include "sdb/oiio_image_decoder.h"

namespace fly::cli {

namespace {

struct LoadedDecoder {
  sdb::DecodeImageFunction decode = nullptr;
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
  const auto entry = reinterpret_cast<Entry>(dlsym(handle, sdb::kOiioDecoderModuleSymbol));
  if (!entry) {
    r.error = module.string() + " has no symbol " + sdb::kOiioDecoderModuleSymbol;
    return r;
  }
  r.decode = entry();
  return r;
}

}  // namespace

sdb::Texture decodeImageThroughModule(std::span<const uint8_t> encoded, size_t maxBytes,
                                      std::vector<std::string>& notes) {
  static const LoadedDecoder loaded = load();
  if (!loaded.decode) {
    throw std::logic_error("fly cannot load its texture decoder module (" + loaded.error +
                           "); it is built beside the fly program: rebuild fly (scripts/build fly)");
  }
  return loaded.decode(encoded, maxBytes, notes);
}

}  // namespace fly::cli

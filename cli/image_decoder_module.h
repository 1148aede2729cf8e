// The fly program's glTF texture decoder: OpenImageIO's (sdb/oiio_image_decoder.h), loaded from its shared
// module beside the fly executable the first time a texture is decoded, so that runs that decode no texture
// never load OpenImageIO and its ~260 shared libraries (about 0.7 s of every start-up when linked directly).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "sdb/oiio_image_decoder.h"
#include "sdb/texture.h"

namespace fly::cli {

// An sdb::ImageDecoder. Loads the module once (thread-safe); fails with std::logic_error naming the module's
// path and the loader's reason when it cannot be loaded (an installation fault, not bad input), and otherwise
// behaves exactly as sdb::decodeImageOiio.
sdb::Texture decodeImageThroughModule(std::span<const uint8_t> encoded, size_t maxBytes,
                                      std::vector<std::string>& notes);
// The module's float decoder (sdb::decodeFloatImageOiio: Radiance HDR and OpenEXR, values as stored), loaded
// and failing alike.
sdb::FloatRgbImage decodeFloatImageThroughModule(std::span<const uint8_t> encoded, size_t maxBytes);

}  // namespace fly::cli

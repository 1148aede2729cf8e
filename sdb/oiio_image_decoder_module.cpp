// The entry point of the OpenImageIO decoder module (oiio_image_decoder.h, kOiioDecoderModuleSymbol).
#include "sdb/oiio_image_decoder.h"

extern "C" __attribute__((visibility("default"))) fly::sdb::DecodeImageFunction flyOiioImageDecoder() {
  return &fly::sdb::decodeImageOiio;
}

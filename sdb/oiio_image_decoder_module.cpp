// The entry points of the OpenImageIO decoder module (oiio_image_decoder.h, kOiioDecoderModuleSymbol and
// kOiioFloatModuleSymbol).
#include "sdb/oiio_image_decoder.h"

extern "C" __attribute__((visibility("default"))) fly::sdb::DecodeImageFunction flyOiioImageDecoder() {
  return &fly::sdb::decodeImageOiio;
}

extern "C" __attribute__((visibility("default"))) fly::sdb::DecodeFloatImageFunction flyOiioFloatImageDecoder() {
  return &fly::sdb::decodeFloatImageOiio;
}

#include "sdb/site.h"

namespace fly::sdb {

const char* skyModelName(SkyModel m) {
  switch (m) {
    case SkyModel::kNone: return "none";
    case SkyModel::kCie: return "cie";
    case SkyModel::kPerez: return "perez";
    case SkyModel::kClear: return "clear";
  }
  return "unknown";
}

}  // namespace fly::sdb

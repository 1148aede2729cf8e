#include "sdb/site.h"

namespace fly::sdb {

const char* skyModelName(SkyModel m) {
  switch (m) {
    case SkyModel::kNone: return "none";
    case SkyModel::kCie: return "cie";
    case SkyModel::kPerez: return "perez";
    case SkyModel::kClear: return "clear";
    case SkyModel::kPreetham: return "preetham";
  }
  return "unknown";
}

std::string gridName(const Site& site) {
  switch (site.grid) {
    case Site::Grid::kNone: return "none";
    case Site::Grid::kUtm: return "utm:" + std::to_string(site.utmZone);
    case Site::Grid::kTransverseMercator: {
      std::string deg = std::to_string(site.gridCentralMeridianDeg);
      deg.erase(deg.find_last_not_of('0') + 1);
      if (deg.back() == '.') deg.pop_back();
      return "tm:" + deg;
    }
  }
  return "none";
}

}  // namespace fly::sdb

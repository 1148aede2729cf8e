#include "cli/storeys.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numeric>

#include "base/error.h"

namespace fly::cli {

namespace {

std::string metres(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g m", v);
  return buf;
}

}  // namespace

std::vector<Storey> gridStoreys(const std::vector<float>& floorHeightsM) {
  std::vector<size_t> order(floorHeightsM.size());
  std::iota(order.begin(), order.end(), size_t(0));
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return floorHeightsM[a] < floorHeightsM[b]; });
  std::vector<Storey> storeys;
  for (const size_t i : order) {
    const double h = floorHeightsM[i];
    if (storeys.empty() || h >= storeys.back().lowestFloorM + kMinStoreyHeightM) {
      storeys.push_back({h, h, h, {}});
    }
    storeys.back().highestFloorM = h;
    storeys.back().sensors.push_back(i);
  }
  size_t largest = 0;
  for (const Storey& s : storeys) largest = std::max(largest, s.sensors.size());
  for (size_t k = 0; k < storeys.size();) {
    if (storeys.size() == 1 || double(storeys[k].sensors.size()) >= kMinStoreyShare * double(largest)) {
      ++k;
      continue;
    }
    // Too small to be a storey: with the storey below (the lowest group, with the one above).
    const size_t into = k > 0 ? k - 1 : 1;
    Storey& target = storeys[into];
    target.sensors.insert(target.sensors.end(), storeys[k].sensors.begin(), storeys[k].sensors.end());
    target.lowestFloorM = std::min(target.lowestFloorM, storeys[k].lowestFloorM);
    target.highestFloorM = std::max(target.highestFloorM, storeys[k].highestFloorM);
    storeys.erase(storeys.begin() + std::ptrdiff_t(k));
    if (k > 0) --k;
  }
  for (Storey& s : storeys) {
    std::sort(s.sensors.begin(), s.sensors.end());
    std::map<long, size_t> count;  // sensors per floor height in whole centimetres
    for (const size_t i : s.sensors) ++count[std::lround(double(floorHeightsM[i]) * 100.0)];
    const auto most = std::max_element(count.begin(), count.end(),
                                       [](const auto& a, const auto& b) { return a.second < b.second; });
    s.mainFloorM = double(most->first) / 100.0;
  }
  return storeys;
}

size_t storeyAt(const std::vector<Storey>& storeys, double heightM) {
  for (size_t k = storeys.size(); k-- > 0;) {
    if (heightM >= storeys[k].lowestFloorM) {
      if (k + 1 == storeys.size() && heightM >= storeys[k].highestFloorM + kMinStoreyHeightM) break;
      return k;
    }
  }
  std::string floors;
  for (const Storey& s : storeys) floors += (floors.empty() ? "" : ", ") + metres(s.mainFloorM);
  throw UsageError("--storey " + metres(heightM) + ": no storey of the grid has its floors there; its " +
                   std::to_string(storeys.size()) + (storeys.size() == 1 ? " storey has" : " storeys have") +
                   " floors at y = " + floors + " (give one of these heights)");
}

}  // namespace fly::cli

#include "base/tone_map.h"

#include <algorithm>
#include <cmath>

namespace fly {

double autoExposureEv100(std::span<const float> luminanceCdM2) {
  std::vector<float> v;
  v.reserve(luminanceCdM2.size());
  for (float l : luminanceCdM2) {
    if (std::isfinite(l) && l > 0.0f) v.push_back(l);
  }
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t lo = v.size() * 5 / 100;
  const size_t hi = std::max(lo + 1, v.size() * 95 / 100);
  double sumLog = 0.0;
  for (size_t i = lo; i < hi; ++i) sumLog += std::log(double(v[i]));
  const double logAverage = std::exp(sumLog / double(hi - lo));
  constexpr double kS = 100.0;  // ISO speed of EV100
  constexpr double kK = 12.5;   // reflected-light meter calibration constant
  return std::log2(logAverage * kS / kK);
}

Rgb toneMap(const Rgb& radianceCdM2, double ev100, ToneOperator op) {
  const double lMax = 1.2 * std::exp2(ev100);
  const Rgb x = glm::max(radianceCdM2, Rgb(0.0f)) * float(1.0 / lMax);
  if (op == ToneOperator::kReinhard) return x / (Rgb(1.0f) + x);
  return glm::min(x, Rgb(1.0f));
}

uint8_t encodeSrgb8(float displayValue) {
  const float v = std::clamp(displayValue, 0.0f, 1.0f);
  const float s = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
  return static_cast<uint8_t>(std::lround(s * 255.0f));
}

std::vector<uint8_t> toneMapToSrgb8(std::span<const float> rgb, double ev100, ToneOperator op) {
  std::vector<uint8_t> out(rgb.size());
  for (size_t i = 0; i + 2 < rgb.size(); i += 3) {
    const Rgb d = toneMap(Rgb(rgb[i], rgb[i + 1], rgb[i + 2]), ev100, op);
    out[i] = encodeSrgb8(d.r);
    out[i + 1] = encodeSrgb8(d.g);
    out[i + 2] = encodeSrgb8(d.b);
  }
  return out;
}

}  // namespace fly

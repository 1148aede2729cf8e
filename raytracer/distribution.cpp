#include "raytracer/distribution.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace fly::raytracer {

Distribution1D::Distribution1D(std::span<const float> weights) : func_(weights.begin(), weights.end()) {
  if (func_.empty()) throw std::invalid_argument("Distribution1D: no weights");
  double sum = 0.0;
  for (size_t i = 0; i < func_.size(); ++i) {
    if (!std::isfinite(func_[i]) || func_[i] < 0.0f) {
      throw std::invalid_argument("Distribution1D: weight " + std::to_string(i) + " is " +
                                  std::to_string(func_[i]) + "; weights must be finite and >= 0");
    }
    sum += func_[i];
  }
  const auto n = static_cast<double>(func_.size());
  integral_ = sum / n;
  if (sum == 0.0) {
    std::fill(func_.begin(), func_.end(), 1.0f);
    sum = n;
  }
  pdfScale_ = static_cast<float>(n / sum);
  cdf_.resize(func_.size() + 1);
  double running = 0.0;
  for (size_t i = 0; i < func_.size(); ++i) {
    cdf_[i] = static_cast<float>(running / sum);
    running += func_[i];
  }
  cdf_.back() = 1.0f;
  invWidth_.resize(func_.size());
  for (size_t i = 0; i < func_.size(); ++i) {
    const float width = cdf_[i + 1] - cdf_[i];
    invWidth_[i] = width > 0.0f ? 1.0f / width : 0.0f;
  }
  invSize_ = static_cast<float>(1.0 / n);

  // The guide table: for each interval k, the smallest float u that guideInterval() puts in it, and that u's
  // bin (the largest i with cdf[i] ≤ u), found by one sweep since u grows with k. findBin's answer grows with
  // u, so every u of the interval has a bin between this and the next interval's.
  const auto size = static_cast<uint32_t>(func_.size());
  guideIntervals_ = kGuideIntervalsPerBin * size;
  guideScale_ = static_cast<float>(guideIntervals_);
  guide_.resize(size_t{guideIntervals_} + 1);
  uint32_t bin = 0;
  for (uint32_t k = 0; k < guideIntervals_; ++k) {
    float u = static_cast<float>(k) / guideScale_;
    while (u > 0.0f && guideInterval(std::nextafter(u, 0.0f)) >= k) u = std::nextafter(u, 0.0f);
    while (guideInterval(u) < k) u = std::nextafter(u, 1.0f);
    while (bin + 1 < size && cdf_[bin + 1] <= u) ++bin;
    guide_[k] = bin;
  }
  guide_[guideIntervals_] = size - 1;
}

Distribution1D::DiscreteSample Distribution1D::sampleDiscrete(float u) const {
  const uint32_t i = findBin(u);
  return {i, func_[i] * pdfScale_ / static_cast<float>(size()), remap(u, i)};
}

namespace {

std::vector<Distribution1D> rows(std::span<const float> values, uint32_t nu, uint32_t nv) {
  if (nu == 0 || nv == 0 || values.size() != static_cast<size_t>(nu) * nv) {
    throw std::invalid_argument("Distribution2D: " + std::to_string(values.size()) + " values for " +
                                std::to_string(nu) + " x " + std::to_string(nv) + " cells");
  }
  std::vector<Distribution1D> result;
  result.reserve(nv);
  for (uint32_t j = 0; j < nv; ++j) result.emplace_back(values.subspan(static_cast<size_t>(j) * nu, nu));
  return result;
}

std::vector<float> integrals(const std::vector<Distribution1D>& rowDistributions) {
  std::vector<float> result;
  result.reserve(rowDistributions.size());
  for (const Distribution1D& row : rowDistributions) result.push_back(static_cast<float>(row.integral()));
  return result;
}

}  // namespace

Distribution2D::Distribution2D(std::span<const float> values, uint32_t nu, uint32_t nv)
    : conditional_(rows(values, nu, nv)), marginal_(integrals(conditional_)) {}

}  // namespace fly::raytracer

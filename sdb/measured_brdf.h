// Isotropic measured BRDFs in the MERL format (Matusik, Pfister, Brand and McMillan 2003, "A Data-Driven
// Reflectance Model", SIGGRAPH; the format of the MERL BRDF database and its reference reader BRDFRead.cpp).
//
// A MERL file is three little-endian int32 dimensions (90, 90, 180) and then 3 · 90 · 90 · 180 doubles: the red,
// green and blue tables one after the other, each on the grid of base/brdf_table.h (indexed [θh][θd][φd], φd
// fastest), and stored values times the channel's scale (1/1500, 1.15/1500, 1.66/1500) are the BRDF in 1/sr.
// Reflectance is RGB in fly's linear Rec.709 with photometric luminance (docs/architecture.md), which is how
// fly reads the three channels.
#pragma once

#include <filesystem>
#include <functional>

#include "base/brdf_table.h"

namespace fly::sdb {

// The table, its half/difference angles and its interpolation are base's (base/brdf_table.h); the SDB adds
// the file format.
using fly::directionsOf;
using fly::HalfDiffAngles;
using fly::halfDiffAngles;
using MeasuredBrdf = fly::BrdfTable;

// MERL's per-channel scales from stored values to 1/sr (BRDFRead.cpp: RED_SCALE, GREEN_SCALE, BLUE_SCALE).
inline constexpr double kMerlChannelScale[3] = {1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0};

// Reads a MERL binary file. Throws InputError naming the file when it cannot be read, its dimensions are not
// 90 × 90 × 180, its size does not match them, or a value is NaN, infinite, or negative at a sample whose
// directions lie above the surface (the first one is named by channel and angles). Negative values at samples
// below the surface, which no measurement covers, read as 0.
MeasuredBrdf readMerlBrdf(const std::filesystem::path& file);

// Writes a MERL binary file (atomically) whose sample (i, j, k) is brdfPerSr(MeasuredBrdf::sampleAngles(i, j,
// k)) — for tables made from analytic BRDFs in tests and tools.
void writeMerlBrdf(const std::filesystem::path& file, const std::function<Rgb(const HalfDiffAngles&)>& brdfPerSr);

}  // namespace fly::sdb

// What `fly bake` and `fly illuminance` say when the user caps the bounces (--max-bounces, bake.maxBounces):
// the estimated share of the light the cap removes (raytracer/bounce_cap_bias.h), which the reported standard
// error does not contain.
#pragma once

#include <nlohmann/json.hpp>

#include "raytracer/bounce_cap_bias.h"

namespace fly::cli {

// Prints "warning: --max-bounces K removes about X % ± Y % of the light …" on stderr and returns the estimate
// as JSON (max_bounces, missing_rel, missing_rel_std_error, missing_rel_max, pilot_points,
// samples_per_point) for manifests.
nlohmann::json warnBounceCapBias(const raytracer::BounceCapBias& bias);

}  // namespace fly::cli

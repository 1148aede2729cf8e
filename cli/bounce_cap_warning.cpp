#include "cli/bounce_cap_warning.h"

#include <cstdio>

namespace fly::cli {

nlohmann::json warnBounceCapBias(const raytracer::BounceCapBias& bias) {
  std::fprintf(stderr,
               "warning: --max-bounces %u removes about %.3g %% ± %.2g %% of the light in all, up to about "
               "%.3g %% at single points (the paths longer than the cap, estimated at %u points with %u "
               "samples each); the standard errors do not include it. Leave the cap out for the unbiased "
               "result.\n",
               bias.maxBounces, 100.0 * bias.missingRel, 100.0 * bias.missingRelStdError,
               100.0 * bias.missingRelMax, bias.points, bias.samplesPerPoint);
  return {{"max_bounces", bias.maxBounces},
          {"missing_rel", bias.missingRel},
          {"missing_rel_std_error", bias.missingRelStdError},
          {"missing_rel_max", bias.missingRelMax},
          {"pilot_points", bias.points},
          {"samples_per_point", bias.samplesPerPoint}};
}

}  // namespace fly::cli

#include "base/math.h"

namespace fly {

bool isFinite(const mat4& m) {
  for (int c = 0; c < 4; ++c) {
    if (!isFinite(m[c])) return false;
  }
  return true;
}

}  // namespace fly

#include "multimodal_nvs/core/depth/look_alike_fill.hpp"

#include <cmath>
#include <cstddef>

namespace multimodal_nvs {

std::vector<int> nearestLookAlikes(const std::vector<int>& look_alike, int rows, int cols,
                                   int radius) {
  std::vector<int> out(look_alike.size(), -1);
  if (radius < 1 || rows < 1 || cols < 1 || look_alike.size() != std::size_t(rows) * cols)
    return out;
  const int side_row[4] = {0, 0, -1, 1}, side_col[4] = {-1, 1, 0, 0};
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      if (look_alike[std::size_t(r) * cols + c] >= 0) continue;
      int nearest = -1, nearest_steps = radius + 1;
      for (int side = 0; side < 4; ++side) {
        // Only nearer than the best so far can win (ties keep the earlier side).
        for (int t = 1; t < nearest_steps; ++t) {
          const int rr = r + side_row[side] * t, cc = c + side_col[side] * t;
          if (rr < 0 || cc < 0 || rr >= rows || cc >= cols) break;
          const int found = look_alike[std::size_t(rr) * cols + cc];
          if (found < 0) continue;
          nearest_steps = t;
          nearest = found;
          break;
        }
      }
      out[std::size_t(r) * cols + c] = nearest;
    }
  }
  return out;
}

int nodesWithin(double degrees, double step_px, double fx) {
  if (!(degrees > 0.0) || !(step_px > 0.0) || !(fx > 0.0)) return 0;
  const double node_deg = std::atan(step_px / fx) * 180.0 / 3.14159265358979323846;
  return static_cast<int>(std::floor(degrees / node_deg + 1e-9));
}

}  // namespace multimodal_nvs

#include "model_choices_json.hpp"

#include <cmath>

namespace multimodal_nvs {
namespace cli {

void addModelChoices(const DepthMapStats& s, json::Json& out) {
  if (s.ground_mode.empty()) return;
  out["ground_source"] = s.ground_source;
  out["ground_mode"] = s.ground_mode;
  out["ground_inlier_fraction"] = json::number(s.ground_inlier_fraction, 4);
  out["ground_scan_line_share"] = json::number(s.ground_scan_line_share, 4);
  out["ground_hidden_returns"] = s.ground_hidden_returns;
  out["ground_edge_ratio"] = json::number(s.ground_edge_ratio, 4);
  out["ground_single_scan_plane"] = s.ground_single_scan_plane;
  out["ground_camera_height"] = json::number(s.ground_camera_height, 4);
  out["ground_pitch_deg"] = json::number(s.ground_pitch_deg, 4);
  out["ground_roll_deg"] = json::number(s.ground_roll_deg, 4);
  if (s.guided_prior_weight < 0.0) return;  // not image_guided
  out["guided_return_density"] = json::number(s.guided_return_density, 4);
  out["guided_prior_weight"] = json::number(s.guided_prior_weight, 4);
  if (std::isfinite(s.guided_band_top_deg))
    out["guided_band_top_deg"] = json::number(s.guided_band_top_deg, 4);
}

}  // namespace cli
}  // namespace multimodal_nvs

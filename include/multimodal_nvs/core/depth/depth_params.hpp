#pragma once
// Every parameter of depth completion, with the reference's defaults and their validation.
#include <limits>
#include <string>

#include "multimodal_nvs/core/depth/gp/local_gp.hpp"

namespace multimodal_nvs {

enum class DepthModel {
  kLocalGpMle,   ///< reference default: local GP, marginal-likelihood length scale per set
  kKernel,       ///< reference fast mode: Gaussian kernel regression within the radius
  kGroundGp,     ///< beyond the paper: local GP on the residual around a ground-plane prior
  kImageGuided,  ///< beyond the paper: returns spread along the image's edges (image_guided_model)
  // Baselines (baselines.hpp), each with a documented variance:
  kNearest,   ///< depth of the angularly nearest sample, no radius limit
  kLinear,    ///< Delaunay triangulation in the angular domain, barycentric interpolation
  kIpBasic,   ///< morphological fill of the projected sparse depth (Ku et al. 2018), for LiDAR
  kConstant,  ///< the median depth everywhere
};

const char* toString(DepthModel model);
/// Throws InputError for an unknown name.
DepthModel parseDepthModel(const std::string& name);

/// How the targets are centred before regression: y = z - shift. Reference default: median of all
/// finite positive depths of the loaded points (also those outside the image).
struct DepthShift {
  enum class Mode { kMedian, kMean, kNone, kValue };
  Mode mode = Mode::kMedian;
  double value = 0.0;

  /// Accepts auto|median|mean|none|off|0|<number>; throws InputError otherwise.
  static DepthShift parse(const std::string& spec);
  std::string toString() const;
};

/// The road-aware prior of the `ground_gp` model: the ground plane below the horizon, a far depth
/// above it. Without a pose the camera is taken as level at `camera_height`.
struct GroundPriorParams {
  double camera_height = 1.3;                  ///< metres
  double up_x = 0.0, up_y = -1.0, up_z = 0.0;  ///< world up in the camera frame
  /// A camera without roll whose optical axis points `pitch_deg` above the road (positive: looking
  /// up; the ground_pitch_deg parameter and the tools' --camera-pitch-deg): an upward pitch tilts
  /// world up towards the optical axis.
  void setPitchDeg(double pitch_deg);
  /// The pitch of `up` (the inverse of setPitchDeg when there is no roll).
  double pitchDeg() const;
  double far_depth = 0.0;    ///< prior where neither ground nor samples say more; 0: median
  int surface_k = 8;         ///< nearest-surface prior: samples considered per pixel
  int surface_rank = 2;      ///< ... and which smallest depth among them (1 = minimum)
  int surface_step_px = 16;  ///< lattice step (image pixels) of the nearest-surface prior
  /// Nearest-surface prior with the camera image: each of the surface_k samples counts by how much
  /// its pixel's colour resembles the lattice node's (a Gaussian of this colour distance, 0..255
  /// per channel), and the rank becomes that share of the weight. 0: every sample counts the same.
  double surface_colour_sigma = 0.0;
  /// With surface_colour_sigma: the chosen return, when it looks like the node, continues as a
  /// wall along the view towards the image centre (SurfacePriorImage, capped at guided.far_depth).
  bool surface_colour_walls = true;
  /// With surface_colour_sigma: a lattice node that looks like none of its returns takes the
  /// look-alike return of the nearest node along its row or column, within this angle (degrees),
  /// that found one (a facade's windows its facade's: look_alike_fill.hpp). 0: off.
  double surface_colour_fill_deg = 0.0;
  double residual_amplitude = 1.0;       ///< GP amplitude of the residual (metres); 0: no GP
  double relative_sigma = 0.25;          ///< prior std as a fraction of its depth, at a sample ...
  double relative_sigma_per_deg = 0.10;  ///< ... growing with the angular distance to it
  /// Sparse (radar) or dense (LiDAR) input; auto: dense when the mean angular spacing of the
  /// samples in view is at most half the neighbourhood radius (ground_gp_model.cpp).
  enum class Input { kAuto, kSparse, kDense };
  Input input = Input::kAuto;
  /// Dense mode: two returns belong to one surface when their depths differ by at most this
  /// fraction (or both are ground returns); otherwise the edge between them is an occlusion edge.
  double dense_edge_ratio = 0.1;
  /// Dense mode: the edge ratio grows with the returns' mean angular spacing in view (degrees):
  /// at least this many times it. Neighbouring returns of one oblique surface (a facade along the
  /// street, the road) lie further apart in depth the further apart they lie in angle, so between
  /// the rings of a 16- or 32-beam LiDAR a fixed 10 % split single surfaces into "occlusion edges".
  /// 0.15: the fixed ratio at the 1-in-4 HDL-64 spacing (VoD, ~0.67 deg) it was chosen on;
  /// README, "The edge ratio follows the ring spacing". 0: dense_edge_ratio alone.
  double dense_edge_ratio_per_deg = 0.15;
  double dense_relative_sigma = 0.03;  ///< dense mode: prior std / depth inside a surface
  /// Dense mode with the camera image: in a triangle across an occlusion edge, each return's vote
  /// for the pixel's surface also counts by how much its pixel's colour resembles the pixel's (a
  /// Gaussian of this colour distance, 0..255 per channel, as surface_colour_sigma). 0: by angle
  /// alone.
  double dense_vote_colour_sigma = 40.0;
  /// ... with a say that grows with the pixel's distance to its nearest return: none within half
  /// this many image pixels, in full at this many. Next to returns the geometry decides (a
  /// return's pixel may lie a few pixels off its surface: the LiDAR's parallax, the calibration).
  double dense_vote_colour_px = 16.0;
  /// Dense mode: leave out the returns the camera cannot see (a scanner above or beside the camera
  /// sees past near objects; hidden_returns.hpp). Needs the scan's origin. Off by default: depth
  /// scored against projected LiDAR, which keeps those returns, loses by it (README); on in
  /// config/lidar.yaml, whose depth and conditioning frames are the camera's.
  bool drop_hidden_returns = false;
  /// Where the scan was taken, in the camera frame (metres): the sensor-to-camera transform's
  /// translation (tf, or the calibration's Tr_velo_to_cam). Set per scan by the node and the
  /// tools; unknown (a cloud already in the camera frame) means no return is dropped.
  bool scan_origin_known = false;
  double scan_origin_x = 0.0, scan_origin_y = 0.0, scan_origin_z = 0.0;
  /// Where camera_height and up come from: the parameters, or a pose (a pose file, tf) that set
  /// them (applyCameraPose). Reported with the plane actually used (ground_plane_estimate.hpp).
  enum class PlaneSource { kParameters, kPose, kReturns };
  PlaneSource plane_source = PlaneSource::kParameters;
  /// Fit the plane to the returns (RANSAC) and use it when they are LiDAR-precise; the given plane
  /// otherwise (ground_plane_estimate.hpp).
  bool estimate_plane = true;
  double plane_distance = 0.1;  ///< RANSAC inlier distance, metres
  /// Returns are LiDAR-precise (dense mode, plane from the returns) when at least this share of
  /// them, and at least 80, lie within plane_distance of one ground plane (measured: LiDAR
  /// 0.19-0.85, the lower ones dense by their scan lines; radar 0.02-0.19 on VoD, Astyx, nuScenes,
  /// synthetic radar up to 0.32).
  double precise_fraction = 0.25;
  /// With the camera image: the sky (image_guided's test and its guided.sky_* parameters) goes to
  /// the far clamp (guided.far_depth) with variance guided.sky_sigma^2. No return comes from the
  /// sky, and above the highest ring ground_gp would extend the nearest surface into it. LiDAR,
  /// all returns, synthetic validation: covered PSNR 24.51 -> 24.92 dB, coverage 0.58 -> 0.61.
  /// Off by default: where the input is thinner than the truth (LiDAR 1 in 4 against the rest),
  /// twigs against a pale sky above the highest input ring are taken for sky (Astyx MAE 1.19 ->
  /// 1.34 m); config/lidar.yaml, which feeds every return, turns it on.
  bool image_sky = false;
};

const char* toString(GroundPriorParams::Input input);
/// auto|sparse|dense; throws InputError otherwise.
GroundPriorParams::Input parseGroundInput(const std::string& name);

/// The `image_guided` model (image_guided_model.hpp): the returns and the ground prior are spread
/// by the fast global smoother guided by the camera image, so that depth changes only where the
/// image has an edge; the sky (no return can come from it) goes to the far clamp.
struct ImageGuidedParams {
  double lambda = 4000.0;    ///< smoothness weight of the fast global smoother
  double sigma_color = 8.0;  ///< image difference (8-bit units) that counts as an edge
  int iterations = 3;        ///< smoother iterations (each: one horizontal + vertical pass)
  /// The smoother runs on a grid this many times coarser than the output (1: the output grid)
  int smooth_scale = 1;
  double prior_weight = 1e-3;  ///< confidence of the ground/far prior per pixel (a return: 1)
  /// With ground_gp's prior (ground_gp_prior, sparse input): returns per square degree of the
  /// camera's view at which prior_weight holds; a frame with denser returns weighs the prior more,
  /// in proportion (priorWeightForDensity; 0: prior_weight as it is). That prior, a low order
  /// statistic of the nearest returns, sharpens as the returns get denser, while the mean that the
  /// smoother takes over many returns gathers more of a radar's returns from behind the surface.
  /// The own prior (dense input, LiDAR) keeps prior_weight. 0.1 is View-of-Delft's radar (0.09-0.10
  /// on its frames), where prior_weight was tuned; Astyx's 4D radar gives 0.5-1.0, nuScenes' front
  /// radar 0.03-0.04. Radar MAE m (stride 1) VoD 3.19 -> 3.19, Astyx 5.05 -> 4.43, nuScenes 6.22
  /// -> 6.01, synthetic dev novel views 21.97 -> 22.04 dB at the same coverage (README, "Depth that
  /// follows the image").
  double prior_reference_density = 0.1;
  /// With ground_gp's prior, on returns that measure elevation (not a 2D scanner's single scan
  /// plane): the prior weighs this many times more at pixels above the returns' band (above all
  /// but the highest 2 % of the returns, return_band.hpp; 1: the same weight everywhere). There
  /// the smoother could only carry the returns below upward along the image, an extrapolation,
  /// while ground_gp's prior extrapolates with the scene's geometry (a return that looks like the
  /// pixel continued as a wall along the view). Chosen on the synthetic dev scenes (covered PSNR
  /// dB / coverage / preview PSNR dB / MAE m: 1: 22.04 / 0.59 / 18.54 / 6.85, 10: 22.19 / 0.60 /
  /// 18.64 / 6.62, 30: 22.24 / 0.60 / 18.67 / 6.49); 10 because VoD's radar MAE (00549/01047,
  /// stride 2) moves 3.19 -> 3.20 m at 10 and 3.22 at 30 (README, "Depth that follows the
  /// image").
  double prior_weight_above_returns = 10.0;
  double far_depth = 100.0;  ///< metres: depth above the horizon and of the sky (GEN3C clamp)
  bool ground_prior = true;  ///< false: the prior is the median return depth everywhere
  /// true: where the ground prior is farther than the nearest return, that return's depth is the
  /// prior (a surface stands between the camera and the ground or the far clamp)
  bool surface_prior = true;
  /// true: a nearest return continues as a wall along the viewing direction (constant lateral
  /// offset) towards the image centre, instead of at its own depth (surface_prior must be on)
  bool lateral_prior = true;
  /// true: on sparse input (ground_gp's sparse mode, i.e. radar) the prior is ground_gp's
  /// prediction (same parameters) instead of the ground and surface prior above, and the smoother
  /// spreads the returns along the image on top of it; dense input (LiDAR) always takes the
  /// ground and surface prior
  bool ground_gp_prior = true;
  /// With ground_gp_prior: image pixels between the samples of ground_gp's prediction. At an
  /// output stride below it the prediction is made on a grid prior_step_px / stride times coarser
  /// (whole factors) and interpolated bilinearly, depth as its inverse. The prior is smooth but
  /// where the smoother puts the image's edges: at VoD 08350's full resolution (step 4) the
  /// model's depth moves by a median 4e-5 of itself, 0.04 % of the pixels by more than 1 %, and its
  /// time drops by a fifth (1: ground_gp at every output pixel). Step 8 (the default since 7
  /// December) takes another 2.5 ms (7 %) off that frame for radar MAE within 0.7 % (VoD +0.6 %,
  /// Astyx -0.5 %, nuScenes 0.0 %) and the same novel views (README, "Depth that follows the
  /// image").
  int prior_step_px = 8;
  /// With ground_gp_prior: ground_gp's ground.surface_colour_sigma for the prior (its
  /// nearest-surface prior weighs each return by how much its pixel's colour resembles the
  /// pixel's; 0: off). Chosen on the synthetic dev scenes (10 / 15 / 20 / 40: covered PSNR 20.41
  /// / 20.52 / 20.55 / 20.08 dB against 19.86 off); README, "Depth that follows the image". Not
  /// applied to returns on a single scan plane (a 2D radar: their pixel row is not measured).
  double prior_colour_sigma = 20.0;
  /// With ground_gp_prior: ground_gp's ground.surface_colour_walls for the prior (a return that
  /// looks like the pixel continues as a wall along the view; dev 20.54 -> 21.26 dB,
  /// docs/evaluation_history.md "The prior's colours").
  bool prior_colour_walls = true;
  /// With ground_gp_prior: ground_gp's ground.surface_colour_fill_deg for the prior. Chosen on the
  /// synthetic dev scenes (covered PSNR 21.26 dB off; 21.99 at 10 degrees, 8 nodes there, 16 at
  /// VoD's focal length); docs/evaluation_history.md, "Surfaces that look like none of their
  /// returns".
  double prior_colour_fill_deg = 10.0;
  bool edges = true;              ///< false: a uniform guide (no image edges; the ablation)
  bool sky = true;                ///< detect the sky and send it to far_depth
  double sky_gradient = 12.0;     ///< image gradient (8-bit units) that ends the sky in a column
  double sky_brightness = 120.0;  ///< the sky is at least this bright (8-bit gray)
  /// The sky is at most this much redder than blue (8-bit): real skies measured -140..+8 (95th
  /// percentile of the detected sky, VoD, Astyx, nuScenes); plain beige facades and signs more.
  double sky_max_warmth = 10.0;
  double sky_sigma = 1.0;               ///< std (metres) of the sky's depth
  double relative_sigma = 0.25;         ///< std / depth where only the prior speaks
  double return_relative_sigma = 0.05;  ///< std / depth at a return
  int splat_radius_px = 0;              ///< a return covers this many grid pixels around it

  /// Throws InputError naming the first bad parameter (`plane`: the ground it uses).
  void validate(const GroundPriorParams& plane) const;
};

/// Every parameter of depth completion, with the reference's defaults. The CLI flags, the YAML
/// files and dynamic_reconfigure all map onto this one struct.
struct DepthCompletionParams {
  DepthModel model = DepthModel::kLocalGpMle;
  double radius_deg = 2.0;
  LocalGpParams gp;
  GroundPriorParams ground;
  ImageGuidedParams guided;
  double kernel_length_scale_deg = 0.75;
  DepthShift shift;
  /// Keep this percentage of *all* grid pixels, those with the lowest variance (ties: row-major
  /// order). 100 keeps every prediction (the reference's behaviour).
  double retain_percent = 100.0;
  /// Predictions with a larger variance are not valid (reference: --var-threshold, default inf).
  double var_threshold = std::numeric_limits<double>::infinity();
  /// 0: exact (every sample within the radius). K > 0: the documented tile approximation for dense
  /// input: each tile of approx_tile x approx_tile grid pixels shares one set of at most K samples
  /// (the K nearest to the tile centre) and one length scale. ground_gp with 0 uses it with K = 8
  /// by itself when the neighbour sets are large (groundGpUsesTiles).
  int max_neighbors = 0;
  int approx_tile = 16;
  int threads = 0;  ///< 0: hardware concurrency

  /// Throws InputError naming the first bad parameter.
  void validate() const;
  /// Whether the model cannot run as asked without the camera image's pixels: image_guided,
  /// ground_gp's sky.
  bool needsImage() const {
    return model == DepthModel::kImageGuided ||
           (model == DepthModel::kGroundGp && ground.image_sky);
  }
  /// Whether the model has a ground plane (GroundPriorParams' height and up): ground_gp and
  /// image_guided.
  bool usesGroundPlane() const {
    return model == DepthModel::kGroundGp || model == DepthModel::kImageGuided;
  }
  /// Whether the model reads the camera image's pixels when it has them: needsImage(), and
  /// ground_gp's surface prior colours and (dense input) its occlusion vote's colours.
  bool readsImage() const {
    const bool vote_colours =
        ground.dense_vote_colour_sigma > 0.0 && ground.input != GroundPriorParams::Input::kSparse;
    return needsImage() ||
           (model == DepthModel::kGroundGp && (ground.surface_colour_sigma > 0.0 || vote_colours));
  }
};

}  // namespace multimodal_nvs

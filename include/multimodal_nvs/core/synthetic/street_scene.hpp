#pragma once
// A procedural street built from axis-aligned boxes on a ground plane: the geometry of the
// package's built-in synthetic data, with exact ray casting and a simple daylight shading model.
//
// World frame: x along the street, y to the left, z up (metres). The ground is the plane z = 0.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace multimodal_nvs {
namespace synthetic {

/// A deterministic random stream (splitmix64), identical on every platform and standard library.
class Random {
 public:
  explicit Random(std::uint64_t seed) : state_(seed) {}
  /// A stream derived from a seed and up to three labels (frame, sensor, ...).
  static Random derived(std::uint64_t seed, std::uint64_t a, std::uint64_t b = 0,
                        std::uint64_t c = 0);
  std::uint64_t next();
  double uniform();                      ///< [0, 1)
  double uniform(double lo, double hi);  ///< [lo, hi)
  double normal();                       ///< standard normal (Box-Muller)
  int index(int n);                      ///< [0, n)
  bool chance(double p) { return uniform() < p; }

 private:
  std::uint64_t state_;
};

/// What a surface is made of: chooses its texture and how radar and LiDAR see it.
enum class Material : std::uint8_t {
  kGround,    ///< the plane z = 0: asphalt with lane markings on the road, pavement elsewhere
  kSidewalk,  ///< raised pavement slab with a curb
  kFacade,    ///< building wall with windows and a door
  kCornice,   ///< stone band along the roof line
  kCarBody,
  kCarCabin,  ///< glass with pillars and a roof in body colour
  kTire,
  kPole,  ///< lamp posts, sign posts, bollards
  kLampHead,
  kSignPlate,
  kClothing,  ///< pedestrians: striped clothes, trousers
  kSkin,      ///< pedestrians' heads and hands
};

struct Box {
  Eigen::Vector3d min, max;
  Material material = Material::kGround;
  Eigen::Vector3f color{0.5f, 0.5f, 0.5f};  ///< base albedo (sRGB, 0..1)
  std::uint32_t variant = 0;                ///< per-object texture seed (window grid, ...)
  float window_spacing = 2.5f;              ///< facades: horizontal window pitch (m)
};

struct Ray {
  Eigen::Vector3d origin;
  Eigen::Vector3d direction;  ///< unit length
};

struct Hit {
  double t = 0.0;  ///< distance along the ray (the ray direction is unit length)
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< outward, unit
  int box = -1;                                       ///< -1: the ground plane
  Material material = Material::kGround;
};

/// Layout of the procedural street (all lengths in metres).
struct StreetLayout {
  double start_x = -40.0;       ///< the street begins here (behind the camera's start)
  double length = 260.0;        ///< and ends with a cross building at start_x + length
  double lane_width = 3.0;      ///< two driving lanes, |y| < lane_width
  double parking_width = 2.2;   ///< parking strip beyond each driving lane
  double sidewalk_width = 3.3;  ///< raised pavement between curb and facades
  double sidewalk_height = 0.12;
  double max_distance = 1500.0;  ///< rays that hit nothing nearer see the sky

  /// Extra occluders placed along [occluder_min_x, occluder_max_x] (the stretch the drive sees),
  /// from their own random stream: with all counts 0 the street is the same as without them.
  int extra_vehicles = 0;  ///< stopped cars, vans and trucks in both driving lanes
  int pedestrians = 0;     ///< standing or walking on the sidewalks; some cross the road ahead
  int extra_poles = 0;     ///< posts and thin trees at the curb
  double occluder_min_x = 4.0;
  double occluder_max_x = 80.0;
  /// Vehicles and crossing pedestrians stay out of the ego lane (y < 0) before this x, where the
  /// drive passes.
  double ego_lane_clear_until_x = 12.0;

  double curbY() const { return lane_width + parking_width; }
  double facadeY() const { return curbY() + sidewalk_width; }
};

/// The street: boxes in a bounding-volume hierarchy, the ground plane, the sun and the sky.
class SyntheticScene {
 public:
  /// Builds the street procedurally from `seed`; the same seed gives the same street.
  SyntheticScene(std::uint64_t seed, const StreetLayout& layout = StreetLayout());

  const StreetLayout& layout() const { return layout_; }
  const std::vector<Box>& boxes() const { return boxes_; }
  const Eigen::Vector3d& sunDirection() const { return sun_; }

  /// Nearest intersection within (t_min, t_max); false when the ray sees the sky. `hint` names a
  /// box that is likely hit (e.g. by the neighbouring pixel's ray): tested first, it narrows the
  /// search; the distance found is the same with or without it.
  bool intersect(const Ray& ray, Hit& hit, double t_min = 1e-6, double t_max = -1.0,
                 int hint = -1) const;
  /// True when anything blocks the segment (t_min, t_max) of the ray. `blocker` (optional, in and
  /// out): a box tested first, and the box that blocked this ray (-1: the ground).
  bool occluded(const Ray& ray, double t_min, double t_max, int* blocker = nullptr) const;

  /// Linear RGB radiance of a hit seen along `ray` (sun, sky light, shadows, glass reflections).
  /// `pixel_angle` (radians per pixel) fades texture detail finer than a pixel; 0 keeps it all.
  /// `shadow_hint` (optional, in and out) carries the last shadow caster from pixel to pixel.
  Eigen::Vector3f shade(const Ray& ray, const Hit& hit, double pixel_angle = 0.0,
                        int* shadow_hint = nullptr) const;
  /// Linear RGB radiance of the sky in direction `d`.
  Eigen::Vector3f sky(const Eigen::Vector3d& d) const;

  /// Radar reflectivity (probability scale, 0..1) and base radar cross-section (dBsm) of a
  /// material.
  static double radarReflectivity(Material m);
  static double radarCrossSectionDb(Material m);
  /// LiDAR reflectivity (0..1) of a hit, including texture (markings, glass).
  double lidarReflectivity(const Hit& hit) const;

 private:
  struct Node {
    Eigen::Vector3d min, max;
    int left = -1, right = -1;  ///< children, or -1 for a leaf
    int first = 0, count = 0;   ///< leaf: range in order_
  };
  bool cast(const Ray& ray, Hit& hit, double t_min, double t_max, bool any_hit, int hint) const;
  int buildNode(int first, int count, int depth);
  void buildHierarchy();
  void addBuildings(Random& rng, int side);
  void addCars(Random& rng, int side);
  void addCar(double x0, double yc, double length, double width, const Eigen::Vector3f& color,
              bool facing_plus_x);
  void addAxles(double x0, double y0, double y1, double length);
  void addStreetFurniture(Random& rng, int side);
  void addOccluders();
  void addPedestrian(Random& rng, double x, double y);

  /// sRGB albedo of a hit; `footprint` is the pixel size on the surface (m); sets `glass`.
  Eigen::Vector3f albedo(const Hit& hit, double footprint, bool& glass) const;

  StreetLayout layout_;
  std::uint64_t seed_;
  std::vector<Box> boxes_;
  std::vector<int> order_;
  std::vector<Node> nodes_;
  Eigen::Vector3d sun_;
};

/// Value noise in [0, 1] at a 2D position, smooth at unit scale; `seed` selects the pattern.
double valueNoise(double x, double y, std::uint64_t seed);
/// Sum of `octaves` value-noise layers (fractal), in [0, 1].
double fractalNoise(double x, double y, std::uint64_t seed, int octaves);

}  // namespace synthetic
}  // namespace multimodal_nvs

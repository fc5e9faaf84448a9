#include "multimodal_nvs/core/synthetic/street_scene.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace multimodal_nvs {
namespace synthetic {

// ---------------------------------------------------------------------------------------------
// Random numbers and noise

namespace {

std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

/// Uniform [0, 1) from integer lattice coordinates.
double latticeValue(std::int64_t x, std::int64_t y, std::uint64_t seed) {
  const std::uint64_t h =
      mix64(seed ^ mix64(static_cast<std::uint64_t>(x) * 0x9e3779b97f4a7c15ULL ^
                         mix64(static_cast<std::uint64_t>(y) + 0x632be59bd9b4e019ULL)));
  return static_cast<double>(h >> 11) * (1.0 / 9007199254740992.0);
}

double smooth(double t) {
  return t * t * (3.0 - 2.0 * t);
}
double clamp01(double v) {
  return std::min(1.0, std::max(0.0, v));
}
double smoothstep(double a, double b, double v) {
  return smooth(clamp01((v - a) / (b - a)));
}

Eigen::Vector3f toLinear(const Eigen::Vector3f& srgb) {
  return srgb.array().max(0.0f).pow(2.2f).matrix();
}

Eigen::Vector3f rgb(double r, double g, double b) {
  return Eigen::Vector3f(static_cast<float>(r), static_cast<float>(g), static_cast<float>(b));
}

/// A pattern line (1 inside) of half-width `half` around multiples of `period`, faded to its mean
/// coverage when a pixel covers more than the line.
double gridLine(double coord, double period, double half, double footprint) {
  const double d = std::abs(coord - period * std::round(coord / period));
  const double coverage = 2.0 * half / period;
  const double sharp = d < half ? 1.0 : 0.0;
  const double fade = smoothstep(half, 4.0 * half, footprint);
  return sharp * (1.0 - fade) + coverage * fade;
}

}  // namespace

Random Random::derived(std::uint64_t seed, std::uint64_t a, std::uint64_t b, std::uint64_t c) {
  return Random(
      mix64(mix64(mix64(seed ^ 0x5851f42d4c957f2dULL) ^ a) + mix64(b ^ 0x14057b7ef767814fULL)) ^
      mix64(c + 0x2545f4914f6cdd1dULL));
}

std::uint64_t Random::next() {
  state_ += 0x9e3779b97f4a7c15ULL;
  return mix64(state_);
}

double Random::uniform() {
  return static_cast<double>(next() >> 11) * (1.0 / 9007199254740992.0);
}

double Random::uniform(double lo, double hi) {
  return lo + (hi - lo) * uniform();
}

double Random::normal() {
  const double u1 = 1.0 - uniform();  // (0, 1]
  const double u2 = uniform();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

int Random::index(int n) {
  return std::min(n - 1, static_cast<int>(uniform() * n));
}

double valueNoise(double x, double y, std::uint64_t seed) {
  const double fx = std::floor(x), fy = std::floor(y);
  const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy);
  const double tx = smooth(x - fx), ty = smooth(y - fy);
  const double a = latticeValue(ix, iy, seed), b = latticeValue(ix + 1, iy, seed);
  const double c = latticeValue(ix, iy + 1, seed), d = latticeValue(ix + 1, iy + 1, seed);
  return (a + (b - a) * tx) * (1.0 - ty) + (c + (d - c) * tx) * ty;
}

double fractalNoise(double x, double y, std::uint64_t seed, int octaves) {
  double sum = 0.0, weight = 0.0, amplitude = 1.0;
  for (int o = 0; o < octaves; ++o) {
    sum += amplitude * valueNoise(x, y, seed + 7919ULL * o);
    weight += amplitude;
    amplitude *= 0.5;
    x *= 2.03;
    y *= 2.03;
  }
  return sum / weight;
}

// ---------------------------------------------------------------------------------------------
// Procedural layout

namespace {

const Eigen::Vector3f kWallColors[] = {
    rgb(0.55, 0.27, 0.20), rgb(0.45, 0.22, 0.17), rgb(0.62, 0.36, 0.26),
    rgb(0.84, 0.80, 0.70), rgb(0.90, 0.88, 0.84), rgb(0.72, 0.70, 0.66),
    rgb(0.86, 0.78, 0.56), rgb(0.38, 0.30, 0.27), rgb(0.60, 0.48, 0.40),
};
const Eigen::Vector3f kCarColors[] = {
    rgb(0.92, 0.92, 0.92), rgb(0.10, 0.10, 0.11), rgb(0.62, 0.64, 0.66), rgb(0.65, 0.08, 0.07),
    rgb(0.10, 0.20, 0.48), rgb(0.30, 0.31, 0.33), rgb(0.80, 0.80, 0.78), rgb(0.20, 0.32, 0.24),
};

Box makeBox(double x0, double y0, double z0, double x1, double y1, double z1, Material m,
            const Eigen::Vector3f& color, std::uint32_t variant = 0) {
  Box b;
  b.min = Eigen::Vector3d(std::min(x0, x1), std::min(y0, y1), std::min(z0, z1));
  b.max = Eigen::Vector3d(std::max(x0, x1), std::max(y0, y1), std::max(z0, z1));
  b.material = m;
  b.color = color;
  b.variant = variant;
  return b;
}

Eigen::Vector3f jitter(Random& rng, const Eigen::Vector3f& c, double amount) {
  const float k = static_cast<float>(1.0 + rng.uniform(-amount, amount));
  return (c * k).cwiseMin(1.0f);
}

}  // namespace

SyntheticScene::SyntheticScene(std::uint64_t seed, const StreetLayout& layout)
    : layout_(layout), seed_(seed) {
  sun_ = Eigen::Vector3d(0.45, 0.55, 0.70).normalized();
  Random rng = Random::derived(seed, 0x5ce7e);
  for (int side : {-1, 1}) {
    addBuildings(rng, side);
    addCars(rng, side);
    addStreetFurniture(rng, side);
  }
  // Cross buildings close the street at both ends, so every view has a finite depth along it.
  const double x_end = layout_.start_x + layout_.length;
  Box end = makeBox(x_end, -45, 0, x_end + 15, 45, 16, Material::kFacade, kWallColors[3],
                    static_cast<std::uint32_t>(rng.next()));
  boxes_.push_back(end);
  Box start = makeBox(layout_.start_x - 15, -45, 0, layout_.start_x - 3, 45, 13, Material::kFacade,
                      kWallColors[0], static_cast<std::uint32_t>(rng.next()));
  boxes_.push_back(start);
  addOccluders();
  buildHierarchy();
}

void SyntheticScene::addBuildings(Random& rng, int side) {
  const double x_end = layout_.start_x + layout_.length;
  double x = layout_.start_x;
  while (x < x_end) {
    if (rng.chance(0.12)) x += rng.uniform(1.5, 4.0);  // an alley
    const double width = std::min(rng.uniform(6.0, 14.0), x_end - x);
    if (width < 3.0) break;
    const double front = layout_.facadeY() + (rng.chance(0.5) ? 0.0 : rng.uniform(0.0, 0.6));
    const int floors = 1 + rng.index(5);
    const double height = 3.6 + 3.0 * floors + rng.uniform(0.3, 1.2);
    const double depth = 14.0;
    Box b = makeBox(x, side * front, 0.0, x + width, side * (front + depth), height,
                    Material::kFacade, jitter(rng, kWallColors[rng.index(9)], 0.08),
                    static_cast<std::uint32_t>(rng.next()));
    b.window_spacing = static_cast<float>(rng.uniform(2.1, 3.0));
    boxes_.push_back(b);
    if (rng.chance(0.7)) {  // cornice: a light stone band, slightly proud of the facade
      const Eigen::Vector3f stone = jitter(rng, rgb(0.86, 0.84, 0.78), 0.05);
      boxes_.push_back(makeBox(x, side * (front - 0.22), height - 0.55, x + width,
                               side * (front + 0.5), height - 0.2, Material::kCornice, stone));
    }
    x += width;
  }
}

void SyntheticScene::addCar(double x0, double yc, double length, double width,
                            const Eigen::Vector3f& color, bool facing_plus_x) {
  const double y0 = yc - 0.5 * width, y1 = yc + 0.5 * width;
  boxes_.push_back(makeBox(x0, y0, 0.30, x0 + length, y1, 0.98, Material::kCarBody, color));
  // The cabin sits towards the rear of the car.
  const double rear = facing_plus_x ? x0 : x0 + length;
  const double dir = facing_plus_x ? 1.0 : -1.0;
  boxes_.push_back(makeBox(rear + dir * 0.17 * length, y0 + 0.1, 0.98, rear + dir * 0.74 * length,
                           y1 - 0.1, 1.44, Material::kCarCabin, color));
  addAxles(x0, y0, y1, length);
}

void SyntheticScene::addAxles(double x0, double y0, double y1, double length) {
  // One box per axle: from the side it is the tyre, under the car it sits in the shadow.
  for (double fx : {0.18, 0.80}) {
    const double xc = x0 + fx * length;
    boxes_.push_back(makeBox(xc - 0.31, y0 + 0.04, 0.0, xc + 0.31, y1 - 0.04, 0.62, Material::kTire,
                             rgb(0.05, 0.05, 0.05)));
  }
}

void SyntheticScene::addCars(Random& rng, int side) {
  const double x_end = layout_.start_x + layout_.length - 10.0;
  const double lane_y = layout_.lane_width + 0.5 * layout_.parking_width;
  double x = layout_.start_x + 6.0;
  while (x < x_end) {
    if (rng.chance(0.22)) {
      x += rng.uniform(4.0, 9.0);
      continue;
    }
    const double length = rng.uniform(3.9, 4.8), width = rng.uniform(1.72, 1.9);
    const double yc = side * (lane_y + rng.uniform(-0.15, 0.15));
    addCar(x, yc, length, width, jitter(rng, kCarColors[rng.index(8)], 0.05), side < 0);
    x += length + rng.uniform(0.8, 2.6);
  }
  if (side > 0) {  // one car stopped in the oncoming lane ahead
    const double length = rng.uniform(4.0, 4.6);
    addCar(rng.uniform(28.0, 45.0), 0.5 * layout_.lane_width + rng.uniform(-0.2, 0.2), length, 1.8,
           kCarColors[rng.index(8)], false);
  }
}

void SyntheticScene::addStreetFurniture(Random& rng, int side) {
  const double x_end = layout_.start_x + layout_.length - 5.0;
  const double post_y = side * (layout_.curbY() + 0.45);
  const Eigen::Vector3f metal = rgb(0.22, 0.25, 0.24);
  // Street lamps: post, arm over the road, lamp head.
  for (double x = layout_.start_x + rng.uniform(3.0, 12.0); x < x_end; x += rng.uniform(18, 26)) {
    const double h = 6.0;
    boxes_.push_back(
        makeBox(x - 0.07, post_y - 0.07, 0.0, x + 0.07, post_y + 0.07, h, Material::kPole, metal));
    const double arm_end = post_y - side * 1.5;
    boxes_.push_back(
        makeBox(x - 0.04, post_y, h - 0.12, x + 0.04, arm_end, h - 0.04, Material::kPole, metal));
    boxes_.push_back(makeBox(x - 0.14, arm_end - 0.3, h - 0.3, x + 0.14, arm_end + 0.3, h - 0.1,
                             Material::kLampHead, rgb(0.75, 0.75, 0.72)));
  }
  // Traffic signs facing the oncoming traffic of their side.
  for (double x = layout_.start_x + rng.uniform(10.0, 30.0); x < x_end; x += rng.uniform(30, 55)) {
    const double y = side * (layout_.curbY() + 0.35);
    boxes_.push_back(makeBox(x - 0.035, y - 0.035, 0.0, x + 0.035, y + 0.035, 2.6, Material::kPole,
                             rgb(0.6, 0.62, 0.63)));
    const double face = side < 0 ? -1.0 : 1.0;  // plate in front of the post towards its traffic
    boxes_.push_back(makeBox(x + face * 0.04, y - 0.32, 1.95, x + face * 0.07, y + 0.32, 2.6,
                             Material::kSignPlate, rgb(0.05, 0.25, 0.65),
                             static_cast<std::uint32_t>(rng.next())));
  }
  // Bollards along some stretches of curb.
  for (double x = layout_.start_x + rng.uniform(5.0, 20.0); x < x_end; x += rng.uniform(25, 60)) {
    const int n = 3 + rng.index(5);
    for (int i = 0; i < n; ++i) {
      const double xb = x + 1.6 * i, y = side * (layout_.curbY() + 0.2);
      boxes_.push_back(makeBox(xb - 0.06, y - 0.06, 0.0, xb + 0.06, y + 0.06, 0.9, Material::kPole,
                               rgb(0.45, 0.12, 0.10)));
    }
  }
  // The raised sidewalk, in 10 m slabs so that the hierarchy stays tight.
  const double y_curb = layout_.curbY(), y_far = layout_.facadeY() + 1.0;
  for (double x = layout_.start_x; x < layout_.start_x + layout_.length; x += 10.0) {
    const double x1 = std::min(x + 10.0, layout_.start_x + layout_.length);
    boxes_.push_back(makeBox(x, side * y_curb, 0.0, x1, side * y_far, layout_.sidewalk_height,
                             Material::kSidewalk, rgb(0.62, 0.52, 0.47)));
  }
}

void SyntheticScene::addOccluders() {
  if (layout_.extra_vehicles <= 0 && layout_.pedestrians <= 0 && layout_.extra_poles <= 0) return;
  // A stream of its own: the street without occluders stays the same for every seed.
  Random rng = Random::derived(seed_, 0x0cc1d);
  const double x0 = layout_.occluder_min_x, x1 = std::max(x0 + 1.0, layout_.occluder_max_x);
  const double clear = layout_.ego_lane_clear_until_x;
  for (int i = 0; i < layout_.extra_vehicles; ++i) {
    // The oncoming lane anywhere; the ego lane only beyond the stretch the drive passes.
    const bool ego_lane = clear < x1 - 8.0 && rng.chance(0.5);
    const double x = ego_lane ? rng.uniform(clear, x1) : rng.uniform(x0, x1);
    const double yc = (ego_lane ? -0.5 : 0.5) * layout_.lane_width + rng.uniform(-0.25, 0.25);
    const Eigen::Vector3f color = jitter(rng, kCarColors[rng.index(8)], 0.05);
    const double kind = rng.uniform();
    if (kind < 0.55) {
      addCar(x, yc, rng.uniform(3.9, 4.8), rng.uniform(1.72, 1.9), color, ego_lane);
      continue;
    }
    // A van (one tall body) or a truck (cab and a box body, 3.4 m high).
    const bool truck = kind > 0.8;
    const double length = truck ? rng.uniform(7.0, 9.5) : rng.uniform(4.9, 5.9);
    const double width = truck ? 2.45 : 2.0;
    const double y0 = yc - 0.5 * width, y1 = yc + 0.5 * width;
    const double top = truck ? 3.4 : rng.uniform(2.0, 2.5);
    // Traffic in the ego lane drives away (+x), oncoming traffic towards the camera; the cab is
    // at the front.
    const double cab = truck ? 1.9 : 0.0;
    const double cab_x0 = ego_lane ? x + length - cab : x;
    const double body_x0 = ego_lane ? x : x + cab, body_x1 = body_x0 + length - cab;
    boxes_.push_back(makeBox(body_x0, y0, 0.45, body_x1, y1, top, Material::kCarBody,
                             truck ? jitter(rng, rgb(0.9, 0.9, 0.88), 0.05) : color));
    if (truck) {
      boxes_.push_back(makeBox(cab_x0, y0 + 0.05, 0.45, cab_x0 + cab, y1 - 0.05, 2.9,
                               Material::kCarBody, color));
    }
    addAxles(x, y0, y1, length);
  }
  for (int i = 0; i < layout_.pedestrians; ++i) {
    const double x = rng.uniform(x0, x1);
    const int side = rng.chance(0.5) ? 1 : -1;
    if (x > clear && rng.chance(0.25)) {  // crossing the road ahead
      addPedestrian(rng, x, rng.uniform(-layout_.curbY(), layout_.curbY()));
    } else {
      addPedestrian(rng, x,
                    side * (layout_.curbY() + rng.uniform(0.5, layout_.sidewalk_width - 0.5)));
    }
  }
  for (int i = 0; i < layout_.extra_poles; ++i) {
    const double x = rng.uniform(x0, x1);
    const double y = (rng.chance(0.5) ? 1 : -1) * (layout_.curbY() + rng.uniform(0.25, 1.4));
    const double r = rng.uniform(0.04, 0.16), h = rng.uniform(2.2, 5.0);
    const Eigen::Vector3f color = rng.chance(0.5) ? rgb(0.22, 0.25, 0.24) : rgb(0.35, 0.27, 0.2);
    boxes_.push_back(makeBox(x - r, y - r, 0.0, x + r, y + r, h, Material::kPole, color));
  }
}

void SyntheticScene::addPedestrian(Random& rng, double x, double y) {
  static const Eigen::Vector3f kShirts[] = {rgb(0.75, 0.12, 0.1),  rgb(0.15, 0.3, 0.6),
                                            rgb(0.9, 0.88, 0.82),  rgb(0.2, 0.45, 0.25),
                                            rgb(0.85, 0.65, 0.15), rgb(0.12, 0.12, 0.13)};
  static const Eigen::Vector3f kTrousers[] = {rgb(0.1, 0.12, 0.22), rgb(0.15, 0.15, 0.15),
                                              rgb(0.45, 0.38, 0.28)};
  const double h = rng.uniform(1.55, 1.95);
  // Walking along the street: shoulders across it (along y); crossing: shoulders along x.
  const bool along_x = std::abs(y) > layout_.curbY();
  auto part = [&](double across0, double across1, double depth, double z0, double z1, Material m,
                  const Eigen::Vector3f& color, std::uint32_t variant) {
    const double a0 = along_x ? y + across0 : x + across0, a1 = along_x ? y + across1 : x + across1;
    const double c = along_x ? x : y;
    if (along_x) {
      boxes_.push_back(makeBox(c - depth, a0, z0, c + depth, a1, z1, m, color, variant));
    } else {
      boxes_.push_back(makeBox(a0, c - depth, z0, a1, c + depth, z1, m, color, variant));
    }
  };
  const Eigen::Vector3f shirt = jitter(rng, kShirts[rng.index(6)], 0.08);
  const Eigen::Vector3f trousers = jitter(rng, kTrousers[rng.index(3)], 0.08);
  const Eigen::Vector3f skin = jitter(rng, rgb(0.78, 0.6, 0.48), 0.2);
  const auto variant = static_cast<std::uint32_t>(rng.next());
  const double hip = 0.48 * h, shoulder = 0.82 * h, stride = rng.uniform(0.0, 0.12);
  part(-0.17, -0.03, 0.09, 0.0, hip, Material::kClothing, trousers, 0);  // legs, mid-stride
  part(0.03, 0.17, 0.09 + stride, 0.0, hip, Material::kClothing, trousers, 0);
  part(-0.2, 0.2, 0.13, hip, shoulder, Material::kClothing, shirt, variant);               // torso
  part(-0.28, -0.2, 0.06, 0.5 * h, shoulder - 0.02, Material::kClothing, shirt, variant);  // arms
  part(0.2, 0.28, 0.06, 0.5 * h, shoulder - 0.02, Material::kClothing, shirt, variant);
  part(-0.1, 0.1, 0.11, shoulder + 0.02, h, Material::kSkin, skin, 0);  // head
}

// ---------------------------------------------------------------------------------------------
// Bounding-volume hierarchy and ray casting

void SyntheticScene::buildHierarchy() {
  order_.resize(boxes_.size());
  for (std::size_t i = 0; i < order_.size(); ++i)
    order_[i] = static_cast<int>(i);
  nodes_.clear();
  nodes_.reserve(2 * boxes_.size());
  if (!boxes_.empty()) buildNode(0, static_cast<int>(boxes_.size()), 0);
}

int SyntheticScene::buildNode(int first, int count, int depth) {
  Node node;
  node.min = boxes_[order_[first]].min;
  node.max = boxes_[order_[first]].max;
  for (int i = first + 1; i < first + count; ++i) {
    node.min = node.min.cwiseMin(boxes_[order_[i]].min);
    node.max = node.max.cwiseMax(boxes_[order_[i]].max);
  }
  const int index = static_cast<int>(nodes_.size());
  nodes_.push_back(node);
  if (count <= 2) {
    nodes_[index].first = first;
    nodes_[index].count = count;
    return index;
  }
  // Surface-area heuristic over the centroid order of each axis: a street is long and its two
  // sides face each other, so a plain median split leaves the empty road inside every node.
  auto area = [](const Eigen::Vector3d& mn, const Eigen::Vector3d& mx) {
    const Eigen::Vector3d e = (mx - mn).cwiseMax(0.0);
    return e.x() * e.y() + e.y() * e.z() + e.z() * e.x();
  };
  auto centroidLess = [&](int axis) {
    return [this, axis](int a, int b) {
      const double ca = boxes_[a].min[axis] + boxes_[a].max[axis];
      const double cb = boxes_[b].min[axis] + boxes_[b].max[axis];
      return ca < cb || (ca == cb && a < b);
    };
  };
  double best_cost = std::numeric_limits<double>::infinity();
  int best_axis = 0, best_split = count / 2;
  std::vector<double> right_area(count);
  for (int axis = 0; axis < 3; ++axis) {
    std::sort(order_.begin() + first, order_.begin() + first + count, centroidLess(axis));
    Eigen::Vector3d mn = boxes_[order_[first + count - 1]].min;
    Eigen::Vector3d mx = boxes_[order_[first + count - 1]].max;
    for (int i = count - 1; i >= 1; --i) {
      mn = mn.cwiseMin(boxes_[order_[first + i]].min);
      mx = mx.cwiseMax(boxes_[order_[first + i]].max);
      right_area[i] = area(mn, mx);
    }
    mn = boxes_[order_[first]].min;
    mx = boxes_[order_[first]].max;
    for (int i = 1; i < count; ++i) {  // left = [0, i), right = [i, count)
      const double cost = area(mn, mx) * i + right_area[i] * (count - i);
      if (cost < best_cost) {
        best_cost = cost;
        best_axis = axis;
        best_split = i;
      }
      mn = mn.cwiseMin(boxes_[order_[first + i]].min);
      mx = mx.cwiseMax(boxes_[order_[first + i]].max);
    }
  }
  if (depth > 40) {  // keeps the traversal stack bounded whatever the heuristic does
    (node.max - node.min).maxCoeff(&best_axis);
    best_split = count / 2;
  }
  std::sort(order_.begin() + first, order_.begin() + first + count, centroidLess(best_axis));
  const int mid = first + best_split;
  const int left = buildNode(first, mid - first, depth + 1);
  const int right = buildNode(mid, first + count - mid, depth + 1);
  nodes_[index].left = left;
  nodes_[index].right = right;
  return index;
}

namespace {

/// Slab test; returns the entry distance (or +inf) and the entry axis (-1: the ray starts inside).
/// A zero direction component gives an infinite inverse; the NaN of 0 * inf fails every
/// comparison below, which leaves that axis unconstrained, as it should be.
inline double slabEntry(const Eigen::Vector3d& mn, const Eigen::Vector3d& mx,
                        const Eigen::Vector3d& o, const Eigen::Vector3d& inv, double t_min,
                        double t_max, int* axis) {
  double t0 = t_min, t1 = t_max;
  int entry_axis = -1;
  for (int a = 0; a < 3; ++a) {
    double near = (mn[a] - o[a]) * inv[a];
    double far = (mx[a] - o[a]) * inv[a];
    if (inv[a] < 0.0) std::swap(near, far);
    if (near > t0) {
      t0 = near;
      entry_axis = a;
    }
    if (far < t1) t1 = far;
  }
  if (t0 > t1) return std::numeric_limits<double>::infinity();
  if (axis != nullptr) *axis = entry_axis;
  return t0;
}

}  // namespace

bool SyntheticScene::intersect(const Ray& ray, Hit& hit, double t_min, double t_max,
                               int hint) const {
  return cast(ray, hit, t_min, t_max, false, hint);
}

bool SyntheticScene::cast(const Ray& ray, Hit& hit, double t_min, double t_max, bool any_hit,
                          int hint) const {
  if (t_max < 0.0) t_max = layout_.max_distance;
  const Eigen::Vector3d& o = ray.origin;
  const Eigen::Vector3d& d = ray.direction;
  const Eigen::Vector3d inv = d.cwiseInverse();
  double best = t_max;
  int best_box = -2, best_axis = 2;
  if (d.z() < 0.0 && o.z() > 0.0) {
    const double t = -o.z() / d.z();
    if (t > t_min && t < best) {
      best = t;
      best_box = -1;
      if (any_hit) t_max = -1.0;  // blocked by the ground: no need to look further
    }
  }
  if (t_max >= 0.0 && hint >= 0 && hint < static_cast<int>(boxes_.size())) {
    int axis = -1;
    const double t = slabEntry(boxes_[hint].min, boxes_[hint].max, o, inv, t_min, best, &axis);
    if (t < best && axis >= 0) {
      best = t;
      best_box = hint;
      best_axis = axis;
      if (any_hit) t_max = -1.0;
    }
  }
  if (t_max >= 0.0 && !nodes_.empty() &&
      slabEntry(nodes_[0].min, nodes_[0].max, o, inv, t_min, best, nullptr) <= best) {
    // Stack of nodes with their entry distances; nearer children are visited first.
    struct Entry {
      int node;
      double t;
    };
    Entry stack[128];  // the hierarchy is at most ~50 levels deep (see buildNode)
    int top = 0;
    stack[top++] = {0, t_min};
    while (top > 0) {
      const Entry e = stack[--top];
      if (e.t > best) continue;
      const Node& node = nodes_[e.node];
      if (node.left < 0) {
        for (int i = node.first; i < node.first + node.count; ++i) {
          const Box& b = boxes_[order_[i]];
          int axis = -1;
          const double t = slabEntry(b.min, b.max, o, inv, t_min, best, &axis);
          // axis < 0: the ray starts inside the box; such hits are ignored.
          if (t < best && axis >= 0) {
            best = t;
            best_box = order_[i];
            best_axis = axis;
            if (any_hit) break;
          }
        }
        if (any_hit && best_box != -2) break;
        continue;
      }
      const double tl =
          slabEntry(nodes_[node.left].min, nodes_[node.left].max, o, inv, t_min, best, nullptr);
      const double tr =
          slabEntry(nodes_[node.right].min, nodes_[node.right].max, o, inv, t_min, best, nullptr);
      if (tl <= tr) {
        if (tr <= best) stack[top++] = {node.right, tr};
        if (tl <= best) stack[top++] = {node.left, tl};
      } else {
        if (tl <= best) stack[top++] = {node.left, tl};
        if (tr <= best) stack[top++] = {node.right, tr};
      }
    }
  }
  if (best_box == -2) return false;
  hit.t = best;
  hit.point = o + best * d;
  hit.box = best_box;
  if (best_box == -1) {
    hit.normal = Eigen::Vector3d::UnitZ();
    hit.material = Material::kGround;
  } else {
    hit.normal = Eigen::Vector3d::Zero();
    hit.normal[best_axis] = d[best_axis] > 0.0 ? -1.0 : 1.0;
    hit.material = boxes_[best_box].material;
  }
  return true;
}

bool SyntheticScene::occluded(const Ray& ray, double t_min, double t_max, int* blocker) const {
  Hit hit;
  if (!cast(ray, hit, t_min, t_max, true, blocker != nullptr ? *blocker : -1)) return false;
  if (blocker != nullptr) *blocker = hit.box;
  return true;
}

// ---------------------------------------------------------------------------------------------
// Appearance

Eigen::Vector3f SyntheticScene::sky(const Eigen::Vector3d& d) const {
  const Eigen::Vector3f horizon = toLinear(rgb(0.80, 0.86, 0.93));
  const Eigen::Vector3f zenith = toLinear(rgb(0.33, 0.53, 0.84));
  const double e = std::max(0.0, d.z());
  Eigen::Vector3f c = horizon + (zenith - horizon) * static_cast<float>(std::pow(e, 0.6));
  if (d.z() > 0.01) {  // clouds on a plane high above
    const double s = 1.0 / d.z();
    const double n = fractalNoise(0.9 * d.x() * s, 0.9 * d.y() * s, seed_ ^ 0xc10dULL, 5);
    const double cover = smoothstep(0.48, 0.72, n) * smoothstep(0.01, 0.15, d.z());
    c += (toLinear(rgb(0.97, 0.97, 0.98)) - c) * static_cast<float>(0.85 * cover);
  }
  const double cos_sun = std::max(0.0, d.dot(sun_));
  c += rgb(1.0, 0.95, 0.85) *
       static_cast<float>(0.25 * std::pow(cos_sun, 12.0) + 2.0 * std::pow(cos_sun, 600.0));
  return c;
}

Eigen::Vector3f SyntheticScene::albedo(const Hit& hit, double footprint, bool& glass) const {
  glass = false;
  const Eigen::Vector3d& p = hit.point;
  const Eigen::Vector3d& n = hit.normal;
  const std::uint64_t seed = seed_;
  switch (hit.material) {
    case Material::kGround: {
      const double ay = std::abs(p.y());
      const double grain = fractalNoise(p.x() * 3.0, p.y() * 3.0, seed ^ 0xa5, 3);
      const double patch = fractalNoise(p.x() * 0.15, p.y() * 0.3, seed ^ 0xb7, 3);
      if (ay < layout_.curbY()) {
        double v = 0.30 + 0.06 * (grain - 0.5) + 0.08 * (patch - 0.5);
        // Markings: dashed centre line (3 m on, 6 m off), solid lines between lane and parking.
        const double lx = p.x() - layout_.start_x;
        const bool dash_on = std::fmod(lx, 9.0) < 3.0;
        const double centre = ay < 0.07 && dash_on ? 1.0 : 0.0;
        const double edge = std::abs(ay - layout_.lane_width) < 0.06 ? 1.0 : 0.0;
        const double worn = 0.75 + 0.25 * grain;
        const double paint = std::max(centre, edge) * worn;
        v = v + (0.82 - v) * paint;
        return rgb(v, v, v * 1.02);
      }
      const double v = 0.30 + 0.1 * (grain - 0.5);
      return rgb(v * 0.9, v, v * 0.8);
    }
    case Material::kSidewalk: {
      if (n.z() < 0.5) return rgb(0.70, 0.69, 0.66);  // curb stone
      // Clinker pavers, 0.2 x 0.1 m, in a running bond.
      const double row = std::floor(p.y() / 0.1);
      const double shift = std::fmod(std::abs(row), 2.0) * 0.1;
      const double col = std::floor((p.x() + shift) / 0.2);
      const double tone =
          latticeValue(static_cast<std::int64_t>(col), static_cast<std::int64_t>(row), seed ^ 0x7a);
      const double joint = std::max(gridLine(p.y(), 0.1, 0.006, footprint),
                                    gridLine(p.x() + shift, 0.2, 0.006, footprint));
      const double fade = smoothstep(0.02, 0.12, footprint);
      const double t = 0.85 + 0.3 * (tone - 0.5) * (1.0 - fade);
      Eigen::Vector3f c = rgb(0.58 * t, 0.46 * t, 0.41 * t);
      return c * static_cast<float>(1.0 - 0.35 * joint);
    }
    case Material::kFacade: {
      const Box& b = boxes_[hit.box];
      const double weather = fractalNoise(p.x() * 0.6 + p.y() * 0.6, p.z() * 0.9, b.variant, 3);
      Eigen::Vector3f wall = b.color * static_cast<float>(0.9 + 0.2 * (weather - 0.5));
      if (n.z() > 0.5) return rgb(0.25, 0.24, 0.24);  // flat roof
      if (std::abs(n.y()) < 0.5) return wall * 0.9f;  // gable walls seen in gaps: no windows
      const double width = b.max.x() - b.min.x();
      const double u = p.x() - b.min.x();
      const double z = p.z();
      const double height = b.max.z() - b.min.z();
      // Plinth.
      if (z < 0.45) return wall * 0.6f;
      const double spacing = b.window_spacing;
      const int columns = std::max(1, static_cast<int>((width - 1.0) / spacing));
      const double margin = 0.5 * (width - columns * spacing);
      const double cu = u - margin;
      const int col = static_cast<int>(std::floor(cu / spacing));
      const double local_u = cu - (col + 0.5) * spacing;  // from the window axis
      const bool in_column = cu >= 0.0 && col < columns;
      double z0, z1, half_w;
      int floor_index;
      if (z < 3.6) {  // ground floor: shop windows and one door
        floor_index = 0;
        const int door_col = static_cast<int>(b.variant % static_cast<std::uint32_t>(columns));
        if (col == door_col) {
          z0 = 0.05;
          z1 = 2.3;
          half_w = 0.55;
          if (in_column && std::abs(local_u) < half_w && z < z1) {
            const Eigen::Vector3f wood =
                (b.variant & 1) ? rgb(0.22, 0.14, 0.09) : rgb(0.12, 0.2, 0.16);
            const double panel = std::abs(local_u) > half_w - 0.08 || z > z1 - 0.08 ? 0.7 : 1.0;
            return wood * static_cast<float>(panel);
          }
        }
        z0 = 0.8;
        z1 = 2.9;
        half_w = 0.5 * spacing - 0.35;
      } else {
        floor_index = 1 + static_cast<int>((z - 3.6) / 3.0);
        const double base = 3.6 + 3.0 * (floor_index - 1);
        if (base + 3.0 > height - 0.4) return wall;  // attic band below the roof line
        z0 = base + 0.9;
        z1 = base + 2.5;
        half_w = 0.6;
      }
      if (!in_column) return wall;
      const double du = std::abs(local_u), dz0 = z - z0, dz1 = z1 - z;
      // Sill below each window.
      if (du < half_w + 0.08 && dz0 < 0.0 && dz0 > -0.12) return rgb(0.82, 0.80, 0.76);
      if (du > half_w || dz0 < 0.0 || dz1 < 0.0) return wall;
      const double frame = 0.07;
      if (du > half_w - frame || dz0 < frame || dz1 < frame || std::abs(local_u) < 0.025 ||
          std::abs(z - (z0 + 0.7 * (z1 - z0))) < 0.025) {
        return rgb(0.92, 0.91, 0.88);  // white window frame, mullion and transom
      }
      glass = true;
      const double curtain = latticeValue(col, floor_index, b.variant);
      if (curtain < 0.3) return rgb(0.55, 0.50, 0.42);
      return rgb(0.06, 0.07, 0.08);
    }
    case Material::kCornice:
      return boxes_[hit.box].color;
    case Material::kCarBody: {
      const Box& b = boxes_[hit.box];
      if (p.z() < b.min.z() + 0.12 && n.z() < 0.5) return b.color * 0.35f;  // sill shadow line
      if (std::abs(n.x()) > 0.5 && p.z() > b.min.z() + 0.35 && p.z() < b.min.z() + 0.5) {
        // Lamps at the car's ends.
        const double yc = 0.5 * (b.min.y() + b.max.y());
        if (std::abs(std::abs(p.y() - yc) - 0.6) < 0.18) {
          const bool front = (n.x() > 0) == ((b.variant & 1) == 0);
          return front ? rgb(0.9, 0.9, 0.85) : rgb(0.7, 0.08, 0.05);
        }
      }
      return b.color;
    }
    case Material::kCarCabin: {
      const Box& b = boxes_[hit.box];
      if (n.z() > 0.5) return b.color;
      const double zr = (p.z() - b.min.z()) / (b.max.z() - b.min.z());
      double ur;
      if (std::abs(n.y()) > 0.5) {
        ur = (p.x() - b.min.x()) / (b.max.x() - b.min.x());
        if (ur < 0.07 || ur > 0.93 || std::abs(ur - 0.5) < 0.03) return b.color;
      } else {
        ur = (p.y() - b.min.y()) / (b.max.y() - b.min.y());
        if (ur < 0.06 || ur > 0.94) return b.color;
      }
      if (zr < 0.08 || zr > 0.9) return b.color;
      glass = true;
      return rgb(0.16, 0.19, 0.23);
    }
    case Material::kTire:
      return rgb(0.04, 0.04, 0.04);
    case Material::kPole:
    case Material::kLampHead:
      return boxes_[hit.box].color;
    case Material::kClothing: {
      // Every other shirt is striped (a texture edge that is no depth edge).
      const Box& b = boxes_[hit.box];
      if ((b.variant & 1) == 0) return b.color;
      const double stripe = gridLine(p.z(), 0.14, 0.035, footprint);
      return b.color * static_cast<float>(1.0 - 0.6 * stripe);
    }
    case Material::kSkin:
      return boxes_[hit.box].color;
    case Material::kSignPlate: {
      const Box& b = boxes_[hit.box];
      if (std::abs(n.x()) < 0.5) return rgb(0.5, 0.5, 0.5);
      const double yc = 0.5 * (b.min.y() + b.max.y()), zc = 0.5 * (b.min.z() + b.max.z());
      const double dy = std::abs(p.y() - yc), dz = std::abs(p.z() - zc);
      if (std::max(dy, dz) > 0.27) return rgb(0.93, 0.93, 0.93);  // white border
      // A white arrow or bar symbol on blue.
      if ((b.variant & 1) ? (dz < 0.06 && dy < 0.2) : (dy < 0.06 && dz < 0.2)) {
        return rgb(0.93, 0.93, 0.93);
      }
      return b.color;
    }
  }
  return rgb(0.5, 0.5, 0.5);
}

Eigen::Vector3f SyntheticScene::shade(const Ray& ray, const Hit& hit, double pixel_angle,
                                      int* shadow_hint) const {
  const Eigen::Vector3d& n = hit.normal;
  const double cos_view = std::max(0.05, std::abs(n.dot(ray.direction)));
  const double footprint = hit.t * pixel_angle / cos_view;
  bool glass = false;
  const Eigen::Vector3f base = toLinear(albedo(hit, footprint, glass));

  // Sun with hard shadows, sky light from above, a little bounce light from the street.
  const double cos_sun = n.dot(sun_);
  double direct = 0.0;
  if (cos_sun > 0.0) {
    const Ray shadow{hit.point + 1e-4 * n, sun_};
    if (!occluded(shadow, 1e-6, 400.0, shadow_hint)) direct = cos_sun;
  }
  const Eigen::Vector3f sun_color = rgb(1.0, 0.96, 0.88);
  const Eigen::Vector3f sky_color = toLinear(rgb(0.62, 0.72, 0.9));
  const float sky_light = static_cast<float>(0.42 * (0.55 + 0.45 * n.z()));
  const float bounce = static_cast<float>(0.12 * (0.5 - 0.5 * n.z()));
  Eigen::Vector3f light = sun_color * static_cast<float>(2.3 * direct) + sky_color * sky_light +
                          Eigen::Vector3f::Constant(bounce);
  Eigen::Vector3f c = base.cwiseProduct(light);

  const Eigen::Vector3d reflected = ray.direction - 2.0 * ray.direction.dot(n) * n;
  if (glass) {
    // Glass mirrors the sky (a cheap stand-in for the street opposite), stronger at grazing angles.
    const double fresnel = 0.12 + 0.88 * std::pow(1.0 - cos_view, 5.0);
    Eigen::Vector3f env = reflected.z() > 0.0 ? sky(reflected) : toLinear(rgb(0.3, 0.3, 0.3));
    c += env * static_cast<float>(0.55 * fresnel);
  } else if (hit.material == Material::kCarBody || hit.material == Material::kCarCabin) {
    const double spec = std::pow(std::max(0.0, reflected.dot(sun_)), 60.0) * (direct > 0 ? 1 : 0);
    c += sun_color * static_cast<float>(1.5 * spec);
    if (reflected.z() > 0.0) c += sky(reflected) * 0.06f;
  }
  // Aerial perspective.
  const float haze = static_cast<float>(1.0 - std::exp(-hit.t / 700.0));
  const Eigen::Vector3f horizon = toLinear(rgb(0.80, 0.86, 0.93));
  return c + (horizon - c) * haze;
}

double SyntheticScene::radarReflectivity(Material m) {
  switch (m) {
    case Material::kGround:
      return 0.004;
    case Material::kSidewalk:
      return 0.05;
    case Material::kFacade:
      return 0.10;
    case Material::kCornice:
      return 0.10;
    case Material::kCarBody:
      return 0.75;
    case Material::kCarCabin:
      return 0.45;
    case Material::kTire:
      return 0.35;
    case Material::kPole:
      return 0.8;
    case Material::kLampHead:
      return 0.6;
    case Material::kSignPlate:
      return 0.9;
    case Material::kClothing:
    case Material::kSkin:
      return 0.3;  // people reflect weakly (about -8 dBsm)
  }
  return 0.1;
}

double SyntheticScene::radarCrossSectionDb(Material m) {
  switch (m) {
    case Material::kGround:
      return -22.0;
    case Material::kSidewalk:
      return -15.0;
    case Material::kFacade:
      return -5.0;
    case Material::kCornice:
      return -8.0;
    case Material::kCarBody:
      return 8.0;
    case Material::kCarCabin:
      return 2.0;
    case Material::kTire:
      return -2.0;
    case Material::kPole:
      return 0.0;
    case Material::kLampHead:
      return -3.0;
    case Material::kSignPlate:
      return 5.0;
    case Material::kClothing:
    case Material::kSkin:
      return -8.0;
  }
  return -10.0;
}

double SyntheticScene::lidarReflectivity(const Hit& hit) const {
  bool glass = false;
  const Eigen::Vector3f a = albedo(hit, 0.0, glass);
  if (glass) return 0.04;
  if (hit.material == Material::kSignPlate) return 0.95;  // retro-reflective
  const double luminance = 0.2126 * a.x() + 0.7152 * a.y() + 0.0722 * a.z();
  return 0.08 + 0.7 * luminance;
}

}  // namespace synthetic
}  // namespace multimodal_nvs

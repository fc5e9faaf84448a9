#pragma once
// A patch of the image that looks like none of its nearest returns, inside a surface whose returns
// it does not share: a facade's windows, a sign on a wall, a shadow. The nearest-surface prior
// with colours gives such a node the plain order statistic of its nearest returns (usually a
// nearer object's, a parked car's below the facade) while the surface around it takes its
// look-alike returns: the window comes out metres in front of its own wall, and the depth steps
// at its outline cut the facade into pieces in the novel views (GEN3C's depth-edge filter drops
// the pixels at every step). A node enclosed by look-alike nodes belongs to the enclosing surface.
#include <vector>

namespace multimodal_nvs {

/// How many of a node's four sides (left, right, above, below) must hold a node with a look-alike
/// return for the node to count as enclosed: three, so that a window at the top or side of a
/// facade qualifies, but an object that merely stands in front of a surface (a car before a
/// facade, open to the road below and the street beside) does not.
constexpr int kEnclosingSides = 3;

/// For each lattice node (rows x cols, row-major) without a look-alike return of its own
/// (look_alike[node] < 0): the look-alike return of the nearest node along its row and column
/// that has one, when such nodes lie within `radius` nodes on at least kEnclosingSides of its four
/// sides; -1 otherwise, and for the nodes that have their own. Ties go to the first side in the
/// order left, right, above, below. Reads only the input: the result does not depend on the order
/// in which nodes are visited.
std::vector<int> enclosingLookAlikes(const std::vector<int>& look_alike, int rows, int cols,
                                     int radius);

/// The radius in lattice nodes of an angle: `degrees` over the angle between neighbouring nodes at
/// the image centre (`step_px` image pixels apart, focal length `fx` pixels), rounded down.
int nodesWithin(double degrees, double step_px, double fx);

}  // namespace multimodal_nvs

#pragma once
// A patch of the image that looks like none of its nearest returns: a facade's windows, a sign on
// a wall, a shadow, the far end of a facade whose returns are all near. The nearest-surface prior
// with colours gives such a lattice node the plain order statistic of its nearest returns (often
// a nearer object's: a parked car's below the facade), while the surface around it takes its
// look-alike returns: the window comes out metres in front of its own wall, and the depth steps at
// its outline cut the surface into pieces in the novel views. Such a node takes the look-alike
// return of the nearest node along its row or column that found one: the surface it lies in.
#include <vector>

namespace multimodal_nvs {

/// For each lattice node (rows x cols, row-major) without a look-alike return of its own
/// (look_alike[node] < 0): the look-alike return of the nearest node along its row and column
/// (left, right, above, below; ties in that order) within `radius` nodes that has one; -1 where
/// there is none, and for the nodes that have their own. Reads only the input: the result does
/// not depend on the order in which nodes are visited (a filled node passes nothing on).
std::vector<int> nearestLookAlikes(const std::vector<int>& look_alike, int rows, int cols,
                                   int radius);

/// The radius in lattice nodes of an angle: `degrees` over the angle between neighbouring nodes at
/// the image centre (`step_px` image pixels apart, focal length `fx` pixels), rounded down.
int nodesWithin(double degrees, double step_px, double fx);

}  // namespace multimodal_nvs

#pragma once
// How many `indirect` paths each pixel of a view traces when they are adaptive
// (RenderSettings::adaptive_first, surround-v5): every geometry pixel has traced `first`
// paths; the total each gets is in proportion to the standard deviation of a path there,
// which minimises the view's summed variance sum(sigma^2 / n) for the paths spent
// (Lagrange: n ~ sigma). sigma is estimated from the pixel's 3x3 neighbours alone (the
// mean of their first paths' sample variances), never from the pixel's own paths: a
// pixel whose own first paths missed a bright patch would otherwise stop early and be
// biased dark. With the count independent of the pixel's own paths the estimate stays
// unbiased (up to the pixel's 1 / pixels share in the common scale below). Noise is
// spatially smooth (a sunlit patch, a lamp's pool), so the neighbours see it too.
#include <cstdint>
#include <vector>

namespace nns::data {

// variance[i]: sample variance of pixel i's first paths (row-major width x height);
// geometry[i]: 0 for sky (no paths). Returns every pixel's total paths (0 for sky): at
// least `first`, at most `most`, k * sigma between, k chosen so the geometry pixels
// average `mean` (as near as rounding allows); a pixel without geometry neighbours
// gets `mean`. mean <= first gives every geometry pixel `first`.
std::vector<int> allot_paths(int width, int height, const std::vector<double>& variance,
                             const std::vector<uint8_t>& geometry, int first, int mean, int most);

}  // namespace nns::data

#include "common/Partition.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>

namespace hair
{

namespace
{
constexpr int Bits = 21; ///< per axis: a 63-bit index

/// The Hilbert index of the cell x (each < 2^Bits): Skilling's transform of the axes to
/// the curve's "transpose" (undo the excess work, then Gray-encode), its bits interleaved.
std::uint64_t hilbertIndex(std::uint32_t x[3])
{
  const std::uint32_t m = 1u << (Bits - 1);
  for (std::uint32_t q = m; q > 1; q >>= 1)
  {
    const std::uint32_t p = q - 1;
    for (int i = 0; i < 3; ++i)
    {
      if (x[i] & q)
      {
        x[0] ^= p; // invert
      }
      else
      {
        const std::uint32_t t = (x[0] ^ x[i]) & p; // exchange
        x[0] ^= t;
        x[i] ^= t;
      }
    }
  }
  for (int i = 1; i < 3; ++i)
  {
    x[i] ^= x[i - 1];
  }
  std::uint32_t t = 0;
  for (std::uint32_t q = m; q > 1; q >>= 1)
  {
    if (x[2] & q)
    {
      t ^= q - 1;
    }
  }
  std::uint64_t index = 0;
  for (int b = Bits - 1; b >= 0; --b)
  {
    for (int i = 0; i < 3; ++i)
    {
      index = (index << 1) | (((x[i] ^ t) >> b) & 1u);
    }
  }
  return index;
}
} // namespace

std::vector<std::size_t> spaceFillingOrder(const std::vector<Eigen::Vector3d>& points)
{
  std::vector<std::size_t> order(points.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  if (points.empty())
  {
    return order;
  }
  Eigen::Vector3d lo = points[0], hi = lo;
  for (const Eigen::Vector3d& p : points)
  {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  // One scale for the three axes (the cells are cubes), the box's longest side.
  const double side = std::max((hi - lo).maxCoeff(), 1e-300);
  const double cells = double((1u << Bits) - 1);
  std::vector<std::uint64_t> key(points.size());
  for (std::size_t k = 0; k < points.size(); ++k)
  {
    std::uint32_t x[3];
    for (int c = 0; c < 3; ++c)
    {
      const double u = std::isfinite(points[k][c]) ? (points[k][c] - lo[c]) / side : 0.0;
      x[c] = static_cast<std::uint32_t>(std::clamp(u, 0.0, 1.0) * cells);
    }
    key[k] = hilbertIndex(x);
  }
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return key[a] < key[b]; });
  return order;
}

std::vector<int> shareAlongCurve(const std::vector<Eigen::Vector3d>& points,
                                 const std::vector<double>& weights, int parts)
{
  std::vector<int> part(points.size(), 0);
  if (parts <= 1 || points.empty())
  {
    return part;
  }
  const std::vector<std::size_t> order = spaceFillingOrder(points);
  if (int(points.size()) <= parts)
  {
    // One point a part, the first parts empty (a run's rank 0, which writes what every rank
    // has, then holds no strand: the case the ranks must handle anyway).
    const int first = parts - int(points.size());
    for (std::size_t i = 0; i < order.size(); ++i)
    {
      part[order[i]] = first + int(i);
    }
    return part;
  }
  double total = 0;
  for (double w : weights)
  {
    total += w;
  }
  // A point goes to the part its weight's midpoint falls in: cuts within half a point's
  // weight of each share's boundary, never decreasing along the curve.
  double before = 0;
  for (std::size_t i = 0; i < order.size(); ++i)
  {
    const double w = weights[order[i]];
    const int p = static_cast<int>(std::floor((before + 0.5 * w) * parts / total));
    part[order[i]] = std::clamp(p, 0, parts - 1);
    before += w;
  }
  return part;
}

} // namespace hair

#include "common/Partition.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace hair
{

namespace
{
struct Bisection
{
  const std::vector<Eigen::Vector3d>& Points;
  const std::vector<double>& Weights;
  std::vector<int>& Part;

  /// Gives the points of [first, last) of `order` the parts firstPart … firstPart + parts − 1.
  void split(std::vector<int>& order, std::size_t first, std::size_t last, int firstPart, int parts)
  {
    if (parts == 1 || last - first == 0)
    {
      for (std::size_t i = first; i < last; ++i)
      {
        Part[order[i]] = firstPart;
      }
      return;
    }
    Eigen::Vector3d lo = Points[order[first]], hi = lo;
    double total = 0;
    for (std::size_t i = first; i < last; ++i)
    {
      lo = lo.cwiseMin(Points[order[i]]);
      hi = hi.cwiseMax(Points[order[i]]);
      total += Weights[order[i]];
    }
    int axis = 0;
    (hi - lo).maxCoeff(&axis);
    std::sort(order.begin() + std::ptrdiff_t(first), order.begin() + std::ptrdiff_t(last),
              [&](int a, int b)
              {
                const double xa = Points[a][axis], xb = Points[b][axis];
                return xa < xb || (xa == xb && a < b);
              });
    const int left = parts / 2;
    const double target = total * left / parts;
    // The cut c (points first … c − 1 on the left) whose left weight is closest to target.
    std::size_t cut = first;
    double below = 0, best = std::abs(target);
    for (std::size_t i = first; i < last; ++i)
    {
      below += Weights[order[i]];
      const double miss = std::abs(below - target);
      if (miss < best)
      {
        best = miss;
        cut = i + 1;
      }
    }
    split(order, first, cut, firstPart, left);
    split(order, cut, last, firstPart + left, parts - left);
  }
};
} // namespace

std::vector<int> bisect(const std::vector<Eigen::Vector3d>& points,
                        const std::vector<double>& weights, int parts)
{
  std::vector<int> part(points.size(), 0);
  if (parts <= 1 || points.empty())
  {
    return part;
  }
  std::vector<int> order(points.size());
  std::iota(order.begin(), order.end(), 0);
  Bisection b{points, weights, part};
  b.split(order, 0, order.size(), 0, parts);
  return part;
}

} // namespace hair

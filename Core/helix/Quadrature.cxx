#include "helix/Quadrature.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hair
{

namespace
{
std::array<GaussRule, MaxGaussPoints + 1> buildRules()
{
  std::array<GaussRule, MaxGaussPoints + 1> rules{};
  for (int n = 1; n <= MaxGaussPoints; ++n)
  {
    GaussRule& r = rules[n];
    r.points = n;
    for (int i = 0; i < (n + 1) / 2; ++i)
    {
      // Newton on P_n from Tricomi's estimate of the i-th root (descending in [−1, 1]).
      double x = std::cos(M_PI * (i + 0.75) / (n + 0.5));
      double dp = 1;
      for (int it = 0; it < 100; ++it)
      {
        double p0 = 1, p1 = x; // three-term recurrence for P_n(x) and P_{n−1}(x)
        for (int k = 2; k <= n; ++k)
        {
          const double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
          p0 = p1;
          p1 = p2;
        }
        const double pn = n == 1 ? x : p1, pm = n == 1 ? 1 : p0;
        dp = n * (x * pn - pm) / (x * x - 1);
        const double dx = pn / dp;
        x -= dx;
        if (std::abs(dx) < 1e-16)
          break;
      }
      const double w = 2 / ((1 - x * x) * dp * dp);
      // Map [−1, 1] → [0, 1]; root i and its mirror.
      r.x[i] = 0.5 * (1 - x);
      r.x[n - 1 - i] = 0.5 * (1 + x);
      r.w[i] = r.w[n - 1 - i] = 0.5 * w;
    }
    if (n % 2 == 1)
      r.x[n / 2] = 0.5; // the middle root is 0 exactly
  }
  return rules;
}
} // namespace

const GaussRule& gaussLegendre(int n)
{
  static const std::array<GaussRule, MaxGaussPoints + 1> rules = buildRules();
  return rules[std::clamp(n, 1, MaxGaussPoints)];
}

double gaussRemainderLog(int n)
{
  return 4 * std::lgamma(n + 1.0) - std::log(2.0 * n + 1) - 3 * std::lgamma(2.0 * n + 1);
}

double QuadratureChooser::defaultTolerance()
{
  return std::exp(gaussRemainderLog(4) + 8 * std::log(M_PI));
}

QuadratureChooser::QuadratureChooser(double tolerance, int minPoints, int maxPoints)
    : Tolerance(tolerance), MinPoints(std::clamp(minPoints, 1, MaxGaussPoints)),
      MaxPoints(std::clamp(maxPoints, MinPoints, MaxGaussPoints))
{
  for (int n = 1; n <= MaxGaussPoints; ++n)
    InverseThetaMax[n] = 1 / std::exp((std::log(tolerance) - gaussRemainderLog(n)) / (2 * n));
}

ElementRule QuadratureChooser::choose(double turning) const
{
  const double theta = 2 * std::abs(turning);
  ElementRule best;
  best.points = MinPoints;
  if (!std::isfinite(theta))
    return best; // a non-finite state is refused by the step; never index with it

  best.intervals = std::numeric_limits<int>::max();
  int bestSamples = std::numeric_limits<int>::max();
  for (int n = MinPoints; n <= MaxPoints; ++n)
  {
    const double m = std::ceil(theta * InverseThetaMax[n]); // a product: no division per n
    const int intervals = m < 1 ? 1 : (m > 1e6 ? 1000000 : static_cast<int>(m));
    const long samples = static_cast<long>(n) * intervals;
    if (samples < bestSamples)
    {
      bestSamples = static_cast<int>(samples);
      best.points = n;
      best.intervals = intervals;
    }
    if (intervals == 1)
      break; // more points on one interval only cost more
  }
  return best;
}

} // namespace hair

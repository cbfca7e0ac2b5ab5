#pragma once
// Gauss–Legendre rules and the choice of a rule per helical element.
//
// The integrands of an element (mass matrix, forces, velocity Jacobian) are products of
// the helix functions of appendix A: polynomials in u times cos and sin of Ω u, so their
// highest frequency is 2Ω. The n-point Gauss–Legendre rule on an interval of length h has
// the remainder h^(2n+1) (n!)⁴ / ((2n + 1) ((2n)!)³) f^(2n)(ξ) (Abramowitz & Stegun
// 25.4.30); with |f^(2n)| ≤ (2Ω)^(2n) max|f| its relative size is c_n θ^(2n), θ = 2Ω h.
// An element that turns Θ = Ω ℓ is cut into m equal intervals of n points each, choosing
// among n = 3 … MaxGaussPoints the pair with the fewest samples n·m whose bound
// c_n (2Θ/m)^(2n) stays below the tolerance. The default tolerance is the bound of the
// rule used before (4 points, Ω h ≤ π/2: c_4 π⁸ = 5.3e-6), so no element is integrated
// less accurately by that measure, while curly elements need far fewer samples
// (docs/super-helix.md, "Quadrature").
#include <array>

namespace hair
{

constexpr int MaxGaussPoints = 32;

/// Nodes (ascending) and weights of the n-point Gauss–Legendre rule on [0, 1].
struct GaussRule
{
  int points = 0;
  std::array<double, MaxGaussPoints> x{}, w{};
};

/// 1 <= n <= MaxGaussPoints; computed once (Newton on P_n, to round-off).
const GaussRule& gaussLegendre(int n);

/// log of c_n = (n!)⁴ / ((2n + 1) ((2n)!)³).
double gaussRemainderLog(int n);

/// n points on each of `intervals` equal intervals.
struct ElementRule
{
  int points = 4;
  int intervals = 1;
  int samples() const { return points * intervals; }
};

class QuadratureChooser
{
public:
  /// The bound of 4 Gauss points on every interval of Ω h ≤ π/2 (a quarter turn).
  static double defaultTolerance();
  /// The tolerances a strand accepts (StrandSpec::validate): below 1e-15 the bound is
  /// under round-off; above 1e-2 it no longer bounds anything useful.
  static constexpr double MinTolerance = 1e-15, MaxTolerance = 1e-2;
  /// minPoints >= 3 keeps straight elements exact: their integrands are polynomials of
  /// degree <= 5 (measured: M, f, C of a straight strand with 3 points agree with 12 to
  /// 8e-16; with 2 points they are 3e-5 off). minPoints = maxPoints = 4 with the default
  /// tolerance is the fixed rule of 4 points per π/2 of turning on every element.
  explicit QuadratureChooser(double tolerance = defaultTolerance(), int minPoints = 3,
                             int maxPoints = MaxGaussPoints);
  /// The cheapest rule for an element that turns `turning` = Ω ℓ radians.
  ElementRule choose(double turning) const;
  double tolerance() const { return Tolerance; }

private:
  double Tolerance;
  int MinPoints, MaxPoints;
  // 1 / (the largest θ = 2Ω h per rule size): choose() runs for every element at every step
  // (a division per rule size would be 1.4 % of a fuzzy step's time, perf cpu-clock samples).
  std::array<double, MaxGaussPoints + 1> InverseThetaMax{};
};

} // namespace hair

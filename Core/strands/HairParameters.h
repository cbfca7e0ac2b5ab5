#pragma once
// Physical parameters of one hair type, in SI units, and the four presets of the
// Super-Helices paper (Bertails, Audoly, Cani, Querleux, Leroy, Lévêque, ACM TOG 25(3),
// 2006, appendix B). Stiffness comes from an elliptic cross-section.
#include "common/Status.h"

#include <Eigen/Core>

namespace hair
{

enum class HairType
{
  Smooth = 0, ///< "Asian": straight, round
  Wavy = 1,   ///< "Caucasian 1"
  Curly = 2,  ///< "Caucasian 2"
  Fuzzy = 3   ///< "African"
};

const char* toString(HairType type);

struct HairParameters
{
  double radius = 50e-6;           ///< mean radius r of the cross-section [m]
  double ellipticity = 1.0;        ///< r_max / r_min >= 1
  double youngModulus = 1.0e9;     ///< E [Pa]
  double poissonRatio = 0.48;      ///< ν_P, in (-1, 0.5]
  double density = 1300.0;         ///< ρ [kg/m³]
  double helixRadius = 0.0;        ///< natural helix radius r_h [m]; 0: straight
  double helixStep = 0.0;          ///< natural helix step Δ_h [m]
  double internalFriction = 1e-10; ///< γ [kg·m³/s]
  double airFriction = 1e-5;       ///< ν [kg/(m·s)], drag per unit length and velocity
  /// Relative amplitude of the seeded random variation of the natural curvature and twist
  /// from element to element (uniform in [-v, v]); 0 disables it.
  double curvatureVariation = 0.0;

  static HairParameters preset(HairType type);
  /// The smooth preset's material with a round section and no natural curvature or
  /// variation: the straight fibre of the beam and contact checks.
  static HairParameters roundStraight();

  /// Names the first parameter that is out of range, what is wrong, and what to do.
  Status validate() const;

  double area() const;          ///< S = π a b
  double linearDensity() const; ///< ρ S [kg/m]
  /// (μ J, E I1, E I2): torsion about n0, bending about n1 and about n2 [N·m²].
  Eigen::Vector3d stiffness() const;
  /// Rotary inertia of the cross-section per unit length, ρ (I1 + I2, I1, I2) [kg·m]:
  /// about n0 (polar), about n1 and about n2 (I1, I2 as in stiffness()).
  Eigen::Vector3d rotaryInertia() const;
  /// (τⁿ, κ1ⁿ, κ2ⁿ) of the helix of radius helixRadius that advances helixStep per turn
  /// (exact helix geometry; the paper §4.2 names these two parameters).
  Eigen::Vector3d naturalCurvature() const;
  /// The largest natural bending curvature |(κ1ⁿ, κ2ⁿ)| an element can be given, its seeded
  /// variation included: (1 + |curvatureVariation|) times the helix's [1/m].
  double largestNaturalBending() const;
};

} // namespace hair

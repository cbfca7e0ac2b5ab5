#include "strands/HairParameters.h"

#include <cmath>
#include <sstream>

namespace hair
{

const char* toString(HairType type)
{
  switch (type)
  {
  case HairType::Smooth:
    return "smooth";
  case HairType::Wavy:
    return "wavy";
  case HairType::Curly:
    return "curly";
  case HairType::Fuzzy:
    return "fuzzy";
  }
  return "unknown";
}

HairParameters HairParameters::preset(HairType type)
{
  // Paper appendix B, converted to SI (µm → m, cm → m, GPa → Pa). γ and ν run from the
  // disciplined end of the paper's ranges (smooth) to the fuzzy end.
  HairParameters p;
  p.poissonRatio = 0.48;
  p.density = 1300.0;
  switch (type)
  {
  case HairType::Smooth:
    p.radius = 50e-6;
    p.ellipticity = 1.0;
    p.helixRadius = 0.0;
    p.helixStep = 0.0;
    p.youngModulus = 1.0e9;
    p.internalFriction = 5e-11;
    p.airFriction = 5e-6;
    break;
  case HairType::Wavy:
    p.radius = 35e-6;
    p.ellipticity = 1.1;
    p.helixRadius = 1.0e-2;
    p.helixStep = 0.5e-2;
    p.youngModulus = 2.0e9;
    p.internalFriction = 1e-10;
    p.airFriction = 1e-5;
    break;
  case HairType::Curly:
    p.radius = 50e-6;
    p.ellipticity = 1.1;
    p.helixRadius = 0.6e-2;
    p.helixStep = 0.5e-2;
    p.youngModulus = 1.5e9;
    p.internalFriction = 2e-10;
    p.airFriction = 2e-5;
    break;
  case HairType::Fuzzy:
    p.radius = 50e-6;
    p.ellipticity = 1.2;
    p.helixRadius = 0.1e-2;
    p.helixStep = 1.0e-2;
    p.youngModulus = 0.5e9;
    p.internalFriction = 5e-10;
    p.airFriction = 5e-5;
    break;
  }
  p.curvatureVariation = type == HairType::Smooth ? 0.0 : 0.05;
  return p;
}

HairParameters HairParameters::roundStraight()
{
  HairParameters p = preset(HairType::Smooth);
  p.ellipticity = 1;
  p.helixRadius = p.helixStep = 0;
  p.curvatureVariation = 0;
  return p;
}

namespace
{
Status bad(const char* name, double value, const char* expected, const char* advice)
{
  std::ostringstream s;
  s << "HairParameters: " << name << " = " << value << " is invalid: it must be " << expected
    << ". " << advice;
  return Status::Error(s.str());
}
} // namespace

Status HairParameters::validate() const
{
  if (!(std::isfinite(radius) && radius > 0))
    return bad("radius", radius, "a finite length > 0 in metres",
               "Give the mean fibre radius in metres (about 5e-5).");
  if (!(std::isfinite(ellipticity) && ellipticity >= 1))
    return bad("ellipticity", ellipticity, "finite and >= 1 (r_max / r_min)",
               "Use 1 for a round cross-section.");
  if (!(std::isfinite(youngModulus) && youngModulus > 0))
    return bad("youngModulus", youngModulus, "a finite pressure > 0 in pascals",
               "Hair is about 1e9 Pa.");
  if (!(std::isfinite(poissonRatio) && poissonRatio > -1 && poissonRatio <= 0.5))
    return bad("poissonRatio", poissonRatio, "in (-1, 0.5]", "Hair is about 0.48.");
  if (!(std::isfinite(density) && density > 0))
    return bad("density", density, "a finite density > 0 in kg/m³", "Hair is about 1300.");
  if (!(std::isfinite(helixRadius) && helixRadius >= 0))
    return bad("helixRadius", helixRadius, "a finite length >= 0 in metres",
               "Use 0 for straight hair.");
  if (!(std::isfinite(helixStep) && helixStep >= 0))
    return bad("helixStep", helixStep, "a finite length >= 0 in metres",
               "Use 0 for a planar curl.");
  if (!(std::isfinite(internalFriction) && internalFriction >= 0))
    return bad("internalFriction", internalFriction, "finite and >= 0 in kg·m³/s",
               "The paper uses 5e-11 to 5e-10.");
  if (!(std::isfinite(airFriction) && airFriction >= 0))
    return bad("airFriction", airFriction, "finite and >= 0 in kg/(m·s)",
               "The paper uses 5e-6 to 5e-5.");
  if (!(std::isfinite(curvatureVariation) && curvatureVariation >= 0 && curvatureVariation < 1))
    return bad("curvatureVariation", curvatureVariation, "in [0, 1)",
               "It is a relative amplitude; 0.05 is a small variation.");
  return Status::Ok();
}

double HairParameters::area() const
{
  const double a = radius * std::sqrt(ellipticity);
  const double b = radius / std::sqrt(ellipticity);
  return M_PI * a * b;
}

double HairParameters::linearDensity() const
{
  return density * area();
}

Eigen::Vector3d HairParameters::rotaryInertia() const
{
  const double a = radius * std::sqrt(ellipticity);
  const double b = radius / std::sqrt(ellipticity);
  const double i1 = M_PI * a * b * b * b / 4;
  const double i2 = M_PI * a * a * a * b / 4;
  return density * Eigen::Vector3d(i1 + i2, i1, i2);
}

Eigen::Vector3d HairParameters::stiffness() const
{
  // Semi-axis a along n1, b along n2. Bending about n1 involves the extent along n2.
  const double a = radius * std::sqrt(ellipticity);
  const double b = radius / std::sqrt(ellipticity);
  const double i1 = M_PI * a * b * b * b / 4;
  const double i2 = M_PI * a * a * a * b / 4;
  const double j = M_PI * a * a * a * b * b * b / (a * a + b * b);
  const double mu = youngModulus / (2 * (1 + poissonRatio));
  return Eigen::Vector3d(mu * j, youngModulus * i1, youngModulus * i2);
}

Eigen::Vector3d HairParameters::naturalCurvature() const
{
  if (helixRadius <= 0)
    return Eigen::Vector3d::Zero();
  // A rod of constant curvature κ and twist τ is a helix of radius κ/Ω² that advances
  // 2πτ/Ω² per turn (Ω² = κ² + τ²). Inverted exactly, with c = Δ_h/2π:
  // κ = r_h/(r_h² + c²), τ = c/(r_h² + c²). The design note's κ = 1/r_h, τ = Δ_h/(2π r_h²)
  // is the first-order form for c << r_h; for the fuzzy preset (c = 1.6 mm > r_h = 1 mm)
  // it gave a helix of radius 0.28 mm and step 2.8 mm instead of 1 mm and 1 cm.
  const double c = helixStep / (2 * M_PI);
  const double d = helixRadius * helixRadius + c * c;
  return Eigen::Vector3d(c / d, helixRadius / d, 0.0);
}

double HairParameters::largestNaturalBending() const
{
  const Eigen::Vector3d natural = naturalCurvature();
  return (1 + std::abs(curvatureVariation)) * std::hypot(natural[1], natural[2]);
}

} // namespace hair

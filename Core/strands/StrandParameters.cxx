#include "strands/StrandParameters.h"

#include <cmath>

namespace hair
{

namespace
{
/// The seed and the element count are integers stored as doubles (exact below 2⁵³).
std::uint32_t toSeed(double v)
{
  return v >= 0 && v < 4294967296.0 ? static_cast<std::uint32_t>(v) : 0;
}
int toCount(double v)
{
  return v >= 0 && v < 2147483648.0 ? static_cast<int>(v) : -1;
}
/// 1: sag-free; anything else (0, or a value a file should not hold) as grown.
RestShape toRestShape(double v)
{
  return v == 1 ? RestShape::SagFree : RestShape::AsGrown;
}
} // namespace

const std::array<StrandParameter, 14>& strandParameters()
{
  static const std::array<StrandParameter, 14> table = {{
      {"Length", "length", "m", [](const GuideStrand& g) { return g.length; },
       [](GuideStrand& g, double v) { g.length = v; }},
      {"NumberOfElements", "elements", "1", [](const GuideStrand& g) { return double(g.elements); },
       [](GuideStrand& g, double v) { g.elements = toCount(v); }},
      {"Radius", "radius", "m", [](const GuideStrand& g) { return g.hair.radius; },
       [](GuideStrand& g, double v) { g.hair.radius = v; }},
      {"Ellipticity", "ellipticity", "1", [](const GuideStrand& g) { return g.hair.ellipticity; },
       [](GuideStrand& g, double v) { g.hair.ellipticity = v; }},
      {"YoungModulus", "young_modulus", "Pa",
       [](const GuideStrand& g) { return g.hair.youngModulus; },
       [](GuideStrand& g, double v) { g.hair.youngModulus = v; }},
      {"PoissonRatio", "poisson_ratio", "1",
       [](const GuideStrand& g) { return g.hair.poissonRatio; },
       [](GuideStrand& g, double v) { g.hair.poissonRatio = v; }},
      {"Density", "density", "kg/m^3", [](const GuideStrand& g) { return g.hair.density; },
       [](GuideStrand& g, double v) { g.hair.density = v; }},
      {"HelixRadius", "helix_radius", "m", [](const GuideStrand& g) { return g.hair.helixRadius; },
       [](GuideStrand& g, double v) { g.hair.helixRadius = v; }},
      {"HelixStep", "helix_step", "m", [](const GuideStrand& g) { return g.hair.helixStep; },
       [](GuideStrand& g, double v) { g.hair.helixStep = v; }},
      {"InternalFriction", "internal_friction", "kg m^3/s",
       [](const GuideStrand& g) { return g.hair.internalFriction; },
       [](GuideStrand& g, double v) { g.hair.internalFriction = v; }},
      {"AirFriction", "air_friction", "kg/(m s)",
       [](const GuideStrand& g) { return g.hair.airFriction; },
       [](GuideStrand& g, double v) { g.hair.airFriction = v; }},
      {"CurvatureVariation", "curvature_variation", "1",
       [](const GuideStrand& g) { return g.hair.curvatureVariation; },
       [](GuideStrand& g, double v) { g.hair.curvatureVariation = v; }},
      {"Seed", "seed", "1", [](const GuideStrand& g) { return double(g.seed); },
       [](GuideStrand& g, double v) { g.seed = toSeed(v); }},
      {"RestShape", "rest_shape", "1",
       [](const GuideStrand& g) { return double(static_cast<int>(g.restShape)); },
       [](GuideStrand& g, double v) { g.restShape = toRestShape(v); }, true},
  }};
  return table;
}

const std::array<StrandVector, 3>& strandVectors()
{
  static const std::array<StrandVector, 3> table = {{
      {"RestRoot", "rest_root", "m", false, [](const GuideStrand& g) { return g.root; },
       [](GuideStrand& g, const Eigen::Vector3d& v) { g.root = v; }},
      {"RootNormal", "root_normal", "1", true, [](const GuideStrand& g) { return g.normal; },
       [](GuideStrand& g, const Eigen::Vector3d& v) { g.normal = v; }},
      {"GrowthDirection", "growth_direction", "1", true,
       [](const GuideStrand& g) { return g.growth; },
       [](GuideStrand& g, const Eigen::Vector3d& v) { g.growth = v; }},
  }};
  return table;
}

} // namespace hair

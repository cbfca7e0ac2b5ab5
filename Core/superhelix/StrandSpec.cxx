// What a strand is before it moves: StrandSpec::uniform and its checks, with messages that
// name the strand and say what to give instead (RootState's own are in scene/RigidMotion.cxx).
#include "superhelix/SuperHelix.h"

#include <cmath>
#include <sstream>
#include <string>

namespace hair
{

const char* toString(Integrator integrator)
{
  switch (integrator)
  {
  case Integrator::SemiImplicit:
    return "semi-implicit";
  case Integrator::Midpoint:
    return "midpoint";
  case Integrator::Bdf2:
    return "bdf2";
  }
  return "unknown";
}

Status checkIntegrator(Integrator integrator)
{
  if (integrator == Integrator::SemiImplicit || integrator == Integrator::Midpoint ||
      integrator == Integrator::Bdf2)
    return Status::Ok();
  return Status::Error("integrator = " + std::to_string(static_cast<int>(integrator)) +
                       " is not a time step; give 0 (semi-implicit, the paper's), 1 (midpoint, "
                       "second order) or 2 (BDF2, second order in contact).");
}

StrandSpec StrandSpec::uniform(double length, int elements, const HairParameters& hair)
{
  StrandSpec s;
  s.hair = hair;
  if (elements > 0)
    s.elementLengths.assign(static_cast<size_t>(elements), length / elements);
  return s;
}

Status StrandSpec::validate() const
{
  const std::string who = "strand '" + name + "' (id " + std::to_string(id) + "): ";
  if (elementLengths.empty())
    return Status::Error(
        who + "the number of elements N is 0; give at least one element length (N >= 1).");
  if (elementLengths.size() > 10000)
    return Status::Error(
        who + "N = " + std::to_string(elementLengths.size()) +
        " elements is more than 10000; the dense O(N²) model is meant for N <= 100.");
  for (size_t i = 0; i < elementLengths.size(); ++i)
  {
    const double l = elementLengths[i];
    if (!(std::isfinite(l) && l > 0))
    {
      std::ostringstream s;
      s << who << "element " << i << " has length " << l
        << "; every element length must be finite and > 0 metres.";
      return Status::Error(s.str());
    }
  }
  if (!restCurvature.empty())
  {
    if (restCurvature.size() != 3 * elementLengths.size())
      return Status::Error(who + "the rest curvature has " + std::to_string(restCurvature.size()) +
                           " values; give 3 per element (τ, κ1, κ2), " +
                           std::to_string(3 * elementLengths.size()) + " in all, or none.");
    for (double v : restCurvature)
      if (!std::isfinite(v))
        return Status::Error(who + "the rest curvature is not finite.");
  }
  Status st = hair.validate();
  if (!st)
    return Status::Error(who + st.message());
  if (!gravity.allFinite())
    return Status::Error(who + "gravity is not finite; give a vector in m/s².");
  if (!wind.allFinite())
    return Status::Error(who + "wind is not finite; give a velocity in m/s.");
  if (!tipForce.allFinite())
    return Status::Error(who + "the tip force is not finite; give a force in N.");
  if (!(quadratureTolerance >= QuadratureChooser::MinTolerance &&
        quadratureTolerance <= QuadratureChooser::MaxTolerance))
  {
    std::ostringstream s;
    s << who << "quadratureTolerance = " << quadratureTolerance << " is outside ["
      << QuadratureChooser::MinTolerance << ", " << QuadratureChooser::MaxTolerance
      << "]; the default " << QuadratureChooser::defaultTolerance()
      << " is the accuracy of a fixed rule of four points per π/2 of turning.";
    return Status::Error(s.str());
  }
  if (Status st = checkIntegrator(integrator); !st)
    return Status::Error(who + st.message());
  if (quadraturePoints != 0 && (quadraturePoints < 3 || quadraturePoints > MaxGaussPoints))
    return Status::Error(
        who + "quadraturePoints = " + std::to_string(quadraturePoints) +
        " is neither 0 (chosen per element) nor in [3, " + std::to_string(MaxGaussPoints) +
        "]; keep 0 unless reproducing a fixed rule of four points per π/2 of turning (4).");
  return Status::Ok();
}

} // namespace hair

#pragma once
// The test-name suffix of each time step (gtest parameter names: letters and digits only).
#include "superhelix/SuperHelix.h"

#include <string>

namespace hair
{

inline std::string integratorTestName(Integrator integrator)
{
  switch (integrator)
  {
  case Integrator::SemiImplicit:
    return "SemiImplicit";
  case Integrator::Midpoint:
    return "Midpoint";
  case Integrator::Bdf2:
    return "Bdf2";
  }
  return "Unknown";
}

} // namespace hair

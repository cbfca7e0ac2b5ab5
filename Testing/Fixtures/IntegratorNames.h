#pragma once
// The test-name suffix of each time step (gtest parameter names: letters and digits only),
// from the step's own name (toString): "semi-implicit" → "SemiImplicit", "bdf2" → "Bdf2".
#include "superhelix/SuperHelix.h"

#include <cctype>
#include <string>

namespace hair
{

inline std::string integratorTestName(Integrator integrator)
{
  std::string out;
  bool word = true;
  for (const char c : std::string(toString(integrator)))
  {
    if (c == '-')
    {
      word = true;
      continue;
    }
    out += word ? static_cast<char>(std::toupper(static_cast<unsigned char>(c))) : c;
    word = false;
  }
  return out;
}

} // namespace hair

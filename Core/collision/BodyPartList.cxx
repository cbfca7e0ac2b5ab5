#include "collision/BodyPartList.h"

#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>

namespace hair
{

Status readBodyParts(const std::string& path, std::vector<BodyPartSpec>& parts)
{
  std::ifstream in(path);
  if (!in)
  {
    return Status::Error("cannot open the body-part list '" + path + "': check the path.");
  }
  std::vector<BodyPartSpec> result;
  std::string line;
  int lineNo = 0;
  while (std::getline(in, line))
  {
    ++lineNo;
    if (auto hash = line.find('#'); hash != std::string::npos)
    {
      line.resize(hash);
    }
    std::istringstream s(line);
    BodyPartSpec part;
    std::string projection, maxRadius;
    if (!(s >> part.name))
    {
      continue;
    }
    TableSpec& t = part.spec;
    if (!(s >> projection >> t.frame.origin.x() >> t.frame.origin.y() >> t.frame.origin.z() >>
          t.frame.axis.x() >> t.frame.axis.y() >> t.frame.axis.z() >> t.frame.reference.x() >>
          t.frame.reference.y() >> t.frame.reference.z() >> t.azimuthSamples >> t.secondSamples >>
          t.heightMin >> t.heightMax >> maxRadius))
    {
      return Status::Error(
          "the body-part list '" + path + "', line " + std::to_string(lineNo) +
          ": expected 'name projection ox oy oz ax ay az rx ry rz azimuthSamples secondSamples "
          "hmin hmax maxRadius'.");
    }
    if (projection == "cylindrical")
    {
      t.projection = Projection::Cylindrical;
    }
    else if (projection == "spherical")
    {
      t.projection = Projection::Spherical;
    }
    else
    {
      return Status::Error("the body-part list '" + path + "', line " + std::to_string(lineNo) +
                           ": projection '" + projection +
                           "' is neither 'cylindrical' nor 'spherical'.");
    }
    t.maxRadius = maxRadius == "inf" ? std::numeric_limits<double>::infinity()
                                     : std::strtod(maxRadius.c_str(), nullptr);
    if (Status v = t.validate(); !v)
    {
      return Status::Error("the body-part list '" + path + "', line " + std::to_string(lineNo) +
                           " (" + part.name + "): " + v.message());
    }
    result.push_back(std::move(part));
  }
  if (result.empty())
  {
    return Status::Error("the body-part list '" + path + "' names no body part.");
  }
  parts = std::move(result);
  return Status::Ok();
}

} // namespace hair

#pragma once
// The list of a body's parts and their table specifications, as Data/body_parts.txt holds
// it for the bundled body.
#include "collision/CollisionTable.h"
#include "common/Status.h"

#include <string>
#include <vector>

namespace hair
{

/// A named body part's table specification, as listed in Data/body_parts.txt.
struct BodyPartSpec
{
  std::string name;
  TableSpec spec;
};

/// Reads a body-part list: one part a line,
///   name projection ox oy oz ax ay az rx ry rz azimuthSamples secondSamples hmin hmax maxRadius
/// projection is "cylindrical" or "spherical"; maxRadius "inf" for none; '#' starts a
/// comment.
Status readBodyParts(const std::string& path, std::vector<BodyPartSpec>& parts);

} // namespace hair

#include "model/StrandModel.h"

#include <cmath>

namespace hair
{

Status RunSettings::validate() const
{
  if (!(timeStep > 0) || !std::isfinite(timeStep))
  {
    return Status::Error("the time step must be a positive number of seconds (1/30 s is the "
                         "Super-Helix paper's).");
  }
  if (!(frameInterval > 0) || !std::isfinite(frameInterval))
  {
    return Status::Error("the frame interval must be a positive number of seconds.");
  }
  if (threads < 1)
  {
    return Status::Error("at least one thread is needed.");
  }
  return Status::Ok();
}

} // namespace hair

#include "ClumpScene.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace hair
{

ClumpSpec::ClumpSpec()
{
  hair = HairParameters::roundStraight();
}

Status ClumpSpec::validate() const
{
  auto bad = [](const std::string& what) { return Status::Error("clump: " + what); };
  if (count < 1 || count > 100000)
    return bad("count = " + std::to_string(count) + " is out of range; give 1 to 100000 strands.");
  if (elements < 1)
    return bad("elements = " + std::to_string(elements) + "; give at least one element.");
  for (auto [name, v] : {std::pair<const char*, double>{"discRadius", discRadius},
                         {"length", length},
                         {"rampTime", rampTime}})
    if (!(std::isfinite(v) && v > 0))
      return bad(std::string(name) + " = " + std::to_string(v) + " must be finite and > 0.");
  for (auto [name, v] : {std::pair<const char*, double>{"flowRate", flowRate},
                         {"amplitude", amplitude},
                         {"frequency", frequency},
                         {"startOscillation", startOscillation}})
    if (!(std::isfinite(v) && v >= 0))
      return bad(std::string(name) + " = " + std::to_string(v) + " must be finite and >= 0.");
  return hair.validate();
}

RigidMotion clumpRootMotion(const ClumpSpec& c)
{
  return RigidMotion::vertical(Eigen::Vector3d::UnitY(), c.amplitude, c.frequency)
      .during(c.startOscillation);
}

double clumpRootOffset(const ClumpSpec& c, double t)
{
  return clumpRootMotion(c).signal(t);
}

Status initializeClump(const ClumpSpec& c, std::vector<SuperHelix>& out)
{
  if (Status st = c.validate(); !st)
    return st;
  std::vector<SuperHelix> strands(c.count);
  const double golden = M_PI * (3 - std::sqrt(5.0));
  Eigen::Matrix3d frame; // tangent −y (hanging), a right-handed frame
  frame.col(0) = Eigen::Vector3d(0, -1, 0);
  frame.col(1) = frame.col(0).unitOrthogonal();
  frame.col(2) = frame.col(0).cross(frame.col(1));
  for (int i = 0; i < c.count; ++i)
  {
    // Sunflower pattern: evenly spread roots on the disc.
    const double rho = c.discRadius * std::sqrt((i + 0.5) / c.count), phi = i * golden;
    const Eigen::Vector3d root(rho * std::cos(phi), 0, rho * std::sin(phi));
    StrandSpec s = StrandSpec::uniform(c.length, c.elements, c.hair);
    s.id = i;
    s.name = "clump " + std::to_string(i);
    s.root = clumpRootMotion(c).carriedRoot(root, frame);
    const double beta = c.flowRate, ramp = c.rampTime;
    s.windField = [beta, ramp](const Eigen::Vector3d& x, double t)
    {
      const double b = beta * std::clamp(t / ramp, 0.0, 1.0);
      return Eigen::Vector3d(-b * x.x(), 0, -b * x.z());
    };
    if (Status st = strands[i].initialize(s); !st)
      return st;
  }
  out = std::move(strands);
  return Status::Ok();
}

} // namespace hair

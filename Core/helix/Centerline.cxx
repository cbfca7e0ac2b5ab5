#include "helix/Centerline.h"

#include "helix/HelixFunctions.h"

#include <algorithm>
#include <cmath>

namespace hair
{

void drawSuperHelix(const std::vector<double>& elementLengths, const double* q, const double* qdot,
                    const RootState& root, int perElement, StrandPoints& out)
{
  out.clear();
  perElement = std::max(1, perElement);
  const int n = static_cast<int>(elementLengths.size());
  Eigen::Matrix3d F = root.orientation;
  Eigen::Vector3d r = root.position, v = root.velocity, omega = root.angularVelocity;
  HelixEnd he;
  // The point at u on the element that starts at (r, F, v, ω) with curvature k, moving at k̇:
  // g, ∂g/∂k and the frame's rotation E(u) = I + uφ0 K + u²φ1 K² (K = [k]×) from one set of
  // helix coefficients, as helixPoint and helixEnd form them (of E only the two columns
  // drawn).
  auto add = [&](const Eigen::Vector3d& k, const Eigen::Vector3d& kd, double u)
  {
    const HelixCoefficients c = helixCoefficients(k.norm() * u);
    double f[7], e[3], g[3];
    helixFunctionValues(u, c, f);
    helixFrameCoefficients(u, c, e, g);
    Eigen::Vector3d gu;
    Eigen::Matrix3d dg;
    helixGValues(k, u, f[1], f[2], gu);
    helixJacobianValues(k, f[1], f[2], f[3], f[4], dg);
    const Eigen::Vector3d kx0 = k.cross(Eigen::Vector3d::UnitX());
    const Eigen::Vector3d kx1 = k.cross(Eigen::Vector3d::UnitY());
    const Eigen::Vector3d n0 = Eigen::Vector3d::UnitX() + e[1] * kx0 + e[2] * k.cross(kx0);
    const Eigen::Vector3d n1 = Eigen::Vector3d::UnitY() + e[1] * kx1 + e[2] * k.cross(kx1);
    const Eigen::Vector3d Fg = F * gu;
    out.positions.push_back(r + Fg);
    out.velocities.push_back(v + omega.cross(Fg) + F * (dg * kd));
    out.tangents.push_back(F * n0);
    out.directors.push_back(F * n1);
    out.curvature.push_back(std::hypot(k.y(), k.z()));
    out.twist.push_back(k.x());
  };
  for (int e = 0; e < n; ++e)
  {
    const Eigen::Vector3d k(q[3 * e], q[3 * e + 1], q[3 * e + 2]);
    const Eigen::Vector3d kd(qdot[3 * e], qdot[3 * e + 1], qdot[3 * e + 2]);
    const double l = elementLengths[e];
    for (int j = 0; j < perElement; ++j)
    {
      add(k, kd, l * j / perElement);
    }
    // The element's end starts the next one: the frame turned by E, the angular velocity
    // increased by F G k̇ (SuperHelix::kinematics does the same from its samples).
    helixEnd(k, kd, l, he);
    const Eigen::Vector3d Fg = F * he.g;
    v += omega.cross(Fg) + F * (he.dg * kd);
    omega += F * (he.G * kd);
    r += Fg;
    F = F * he.E;
    if (e + 1 == n)
    {
      // The tip: the end of the last element (u = l on it).
      out.positions.push_back(r);
      out.velocities.push_back(v);
      out.tangents.push_back(F.col(0));
      out.directors.push_back(F.col(1));
      out.curvature.push_back(std::hypot(k.y(), k.z()));
      out.twist.push_back(k.x());
    }
  }
}

} // namespace hair

#include "projective/ProjectiveStrands.h"

#include "common/Parallel.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

namespace hair
{

namespace
{
constexpr double Pi = 3.14159265358979323846;

bool finite(double x)
{
  return std::isfinite(x);
}
} // namespace

Eigen::Vector3d segmentDirection(double theta, double phi)
{
  const double st = std::sin(theta), ct = std::cos(theta);
  return Eigen::Vector3d(ct, st * std::sin(phi), st * std::cos(phi));
}

Eigen::Matrix3d segmentRotation(double theta, double phi)
{
  const double st = std::sin(theta), ct = std::cos(theta), sp = std::sin(phi), cp = std::cos(phi);
  Eigen::Matrix3d a;
  a << st, 0, ct, -sp * ct, cp, sp * st, -cp * ct, -sp, cp * st;
  return a;
}

Status strandFromPolyline(const std::vector<Eigen::Vector3d>& points,
                          const Eigen::Vector3d& rootSide, ProjectiveStrand& strand)
{
  if (points.size() < 2)
  {
    return Status::Error("strand polyline: it needs at least two points (one segment)");
  }
  for (const auto& p : points)
  {
    if (!p.allFinite())
    {
      return Status::Error("strand polyline: a point holds NaN or infinite coordinates");
    }
  }
  const std::size_t k = points.size() - 1;
  double dmin = 1e300, dmax = 0, sum = 0;
  for (std::size_t i = 0; i < k; ++i)
  {
    const double d = (points[i + 1] - points[i]).norm();
    dmin = std::min(dmin, d);
    dmax = std::max(dmax, d);
    sum += d;
  }
  const double d = sum / k;
  if (!(dmin > 0) || (dmax - dmin) > 1e-6 * d)
  {
    return Status::Error("strand polyline: segments must have equal, non-zero lengths "
                         "(resample the polyline first)");
  }
  const Eigen::Vector3d e3 = (points[1] - points[0]).normalized();
  Eigen::Vector3d e1 = rootSide - rootSide.dot(e3) * e3;
  if (!(e1.norm() > 1e-9 * std::max(1.0, rootSide.norm())))
  {
    return Status::Error("strand polyline: the root side vector is parallel to the first "
                         "segment; give one across it");
  }
  e1.normalize();
  Eigen::Matrix3d r;
  r.col(0) = e1;
  r.col(1) = e3.cross(e1);
  r.col(2) = e3;
  strand.root = points[0];
  strand.rootFrame = r;
  strand.segmentLength = d;
  strand.restAngles.resize(k);
  Eigen::Matrix3d parent = r;
  for (std::size_t i = 0; i < k; ++i)
  {
    const Eigen::Vector3d u = (points[i + 1] - points[i]).normalized();
    const Eigen::Vector3d l = parent.transpose() * u;
    const double theta = std::acos(std::clamp(l.x(), -1.0, 1.0));
    const double phi = std::atan2(l.y(), l.z());
    strand.restAngles[i] = Eigen::Vector2d(theta, phi);
    parent = parent * segmentRotation(theta, phi);
  }
  return Status::Ok();
}

Status ProjectiveParameters::validate() const
{
  if (!finite(linearDensity) || !finite(bendingStiffness) || !finite(dampingRate) ||
      !finite(dragDiameter))
  {
    return Status::Error("strand parameters: NaN or infinite values");
  }
  if (!(linearDensity > 0))
  {
    return Status::Error("strand parameters: the linear density must be > 0 kg/m");
  }
  if (bendingStiffness < 0 || dampingRate < 0 || dragDiameter < 0 || !finite(stiffnessDamping) ||
      stiffnessDamping < 0)
  {
    return Status::Error(
        "strand parameters: bending stiffness, damping rate and drag diameter must be ≥ 0");
  }
  return Status::Ok();
}

Status ProjectiveOptions::validate() const
{
  if (!finite(timeStep) || !(timeStep > 0))
  {
    return Status::Error("options: the time step must be a number > 0 s");
  }
  if (!gravity.allFinite())
  {
    return Status::Error("options: gravity holds NaN or infinite entries");
  }
  if (!finite(contact.stiffness) || contact.stiffness < 0 || !finite(contact.damping))
  {
    return Status::Error("options: the contact stiffness must be a number ≥ 0");
  }
  if (!finite(contactMargin) || contactMargin < 0)
  {
    return Status::Error("options: the contact margin must be a number ≥ 0 m");
  }
  if (threads < 1)
  {
    return Status::Error("options: the number of threads must be ≥ 1");
  }
  return parameters.validate();
}

/// Everything a step needs that does not depend on the strand.
struct ProjectiveStrands::StepFrame
{
  double t0 = 0, h = 0;
  Eigen::Vector3d gravity;
  // Parts at t0 and t0 + h; velocity twist at t0.
  std::vector<Eigen::Isometry3d> part0, part1, part0Inv, part1Inv;
  std::vector<Eigen::Vector3d> partV, partW;
  // Roots: poses at t0 − h, t0, t0 + h and the twist at t0.
  Eigen::Isometry3d rootM, root0, root1;
  Eigen::Vector3d rootV, rootW;
  bool useParts1 = false; ///< deepest() uses the poses at t0 + h
};

void ProjectiveStrands::forward(Strand& s, const Eigen::Vector3d& root,
                                const Eigen::Matrix3d& frame) const
{
  s.P[0] = root;
  s.R[0] = frame;
  const std::size_t k = s.q.size();
  for (std::size_t i = 1; i <= k; ++i)
  {
    s.R[i] = s.R[i - 1] * segmentRotation(s.q[i - 1].x(), s.q[i - 1].y());
    s.P[i] = s.P[i - 1] + s.d * s.R[i].col(2);
  }
}

bool ProjectiveStrands::deepest(const StepFrame& f, const Eigen::Vector3d& p, Contact& c) const
{
  c = Contact();
  c.depth = -1e300;
  bool any = false;
  for (std::size_t k = 0; k < Scene.parts.size(); ++k)
  {
    const BodyPart& part = Scene.parts[k];
    const Eigen::Vector3d pr = (f.useParts1 ? f.part1Inv[k] : f.part0Inv[k]) * p;
    // Cull with the ball or slab that holds the table before the look-up.
    const TableSpec& spec = part.table.spec();
    const Eigen::Vector3d rel = pr - spec.frame.origin;
    const double reach = PartReach[k];
    if (spec.projection == Projection::Spherical)
    {
      if (rel.squaredNorm() > reach)
      {
        continue;
      }
    }
    else
    {
      const Eigen::Vector3d& a = PartAxis[k];
      const double h = rel.dot(a);
      if (h < spec.heightMin || h > spec.heightMax || (rel - h * a).squaredNorm() > reach)
      {
        continue;
      }
    }
    const TableQuery q = part.table.query(pr);
    if (!q.covered)
    {
      continue;
    }
    // The table's inside test is authoritative; the depth along N follows it in sign.
    double depth = q.depth;
    if (q.inside)
    {
      depth = std::max(depth, 1e-9);
    }
    else
    {
      depth = std::min(depth, 0.0);
    }
    if (depth > c.depth)
    {
      c.depth = depth;
      c.part = static_cast<int>(k);
      const Eigen::Isometry3d& pose = f.useParts1 ? f.part1[k] : f.part0[k];
      c.normal = pose.linear() * q.normal;
      c.surface = pose * q.surfacePoint;
      any = true;
    }
  }
  if (!any)
  {
    c = Contact();
  }
  return any;
}

void ProjectiveStrands::forces(Strand& s, const StepFrame& f, ProjectiveStepStats& stats) const
{
  const std::size_t k = s.q.size();
  const double m = s.mass, d = s.d, h = f.h;
  const ProjectiveParameters& par = Options.parameters;

  // Root-to-tip: angular and linear velocities (world). The angle θ_i turns segment i about
  // −e2 of the segment itself, φ_i about −e1 of its parent (from A = Rx(−φ) Ry(π/2 − θ)).
  Eigen::Vector3d omega = f.rootW;
  s.v[0] = f.rootV + f.rootW.cross(s.P[0]);
  for (std::size_t i = 1; i <= k; ++i)
  {
    omega -= s.R[i].col(1) * s.qd[i - 1].x() + s.R[i - 1].col(0) * s.qd[i - 1].y();
    s.v[i] = s.v[i - 1] + omega.cross(s.P[i] - s.P[i - 1]);
  }

  // The root's acceleration: the inertial force −m a in the roots' frame.
  Eigen::Vector3d accel = Eigen::Vector3d::Zero();
  if (Options.inertialForce)
  {
    accel =
        (f.root1 * s.rootRest - 2.0 * (f.root0 * s.rootRest) + f.rootM * s.rootRest) / (f.h * f.h);
  }

  // Air drag at each segment's centre. A gust reaches a strand all at once: its phase is
  // taken at the root (the gust wavelength U·T is longer than a strand).
  const GustyWind& wind = Scene.wind;
  const Eigen::Vector3d air = wind.velocity(s.P[0], f.t0);
  const double dragCoefficient =
      0.5 * wind.airDensity * wind.dragCoefficient * par.dragDiameter * d;
  auto drag = [&](std::size_t i) -> Eigen::Vector3d
  {
    const Eigen::Vector3d t = s.R[i].col(2);
    Eigen::Vector3d w = air - 0.5 * (s.v[i - 1] + s.v[i]);
    w -= w.dot(t) * t;
    return (dragCoefficient * w.norm()) * w;
  };

  // Tip-to-root: sums of the forces on all that joint i carries and their moments about
  // P_{i−1}, then the update of joint i (each joint's update only needs its own forces).
  const Eigen::Vector3d p0 = s.P[0];
  double massSum = 0;
  Eigen::Vector3d massMoment = Eigen::Vector3d::Zero();
  Eigen::Vector3d sw = Eigen::Vector3d::Zero(), mw = Eigen::Vector3d::Zero();
  Eigen::Vector3d sc = Eigen::Vector3d::Zero(), mc = Eigen::Vector3d::Zero();
  const Eigen::Vector3d fieldPerMass = f.gravity - accel;
  Eigen::Vector3d windNext = Eigen::Vector3d::Zero(); // drag on segment i + 1
  bool anyContact = false;
  for (std::size_t i = k; i >= 1; --i)
  {
    const Eigen::Vector3d c = 0.5 * (s.P[i - 1] + s.P[i]) - p0;
    const Eigen::Vector3d fw = dragCoefficient > 0 ? drag(i) : Eigen::Vector3d::Zero();
    massSum += m;
    massMoment += m * c;
    sw += fw;
    mw += c.cross(fw);

    // The reaction constraint at node i (the end of segment i).
    const Contact& ct = s.contact[i];
    if (ct.part >= 0 && ct.depth > -Options.contactMargin)
    {
      ++stats.contacts;
      anyContact = true;
      const double mn = i < k ? m : 0.5 * m;
      const Eigen::Vector3d windNode = 0.5 * (fw + windNext);
      const Eigen::Vector3d fin = fieldPerMass + windNode / mn;
      const Eigen::Vector3d vs = f.partV[ct.part] + f.partW[ct.part].cross(s.P[i]);
      const Eigen::Vector3d target = s.P[i] + (ct.depth + Options.contactMargin) * ct.normal;
      // The explicit step holds the constraint only while h²k A < 1 and h c A < 1, A the
      // node's mobility: stiffness and damping are capped there (half of it).
      ReactionConstraintOptions opt = Options.contact;
      const double a = std::max(s.mobility[i], 1e-12);
      opt.stiffness = std::min(opt.stiffness, 0.5 / (h * h * a));
      opt.damping = std::min(Options.contact.criticalDamping(), 0.5 / (h * a));
      const Eigen::Vector3d fout =
          reactionConstraint(fin, s.v[i] - vs, s.P[i], target, ct.normal, opt);
      const Eigen::Vector3d g = mn * (fout - fin);
      sc += g;
      mc += (s.P[i] - p0).cross(g);
    }
    windNext = fw;

    const Eigen::Vector3d pivot = s.P[i - 1] - p0;
    const Eigen::Vector3d lever = massMoment - massSum * pivot; // Σ m (c − P_{i−1})
    const Eigen::Vector3d wt = -s.R[i].col(1), wp = -s.R[i - 1].col(0);
    const Eigen::Vector3d tg = lever.cross(f.gravity);
    const Eigen::Vector3d tb = lever.cross(-accel);
    const Eigen::Vector3d tw = mw - pivot.cross(sw);
    const Eigen::Vector2d qg(wt.dot(tg), wp.dot(tg));
    const Eigen::Vector2d qb(wt.dot(tb), wp.dot(tb));
    const Eigen::Vector2d qw(wt.dot(tw), wp.dot(tw));
    Eigen::Vector2d qc = Eigen::Vector2d::Zero();
    if (anyContact)
    {
      const Eigen::Vector3d tc = mc - pivot.cross(sc);
      qc = Eigen::Vector2d(wt.dot(tc), wp.dot(tc));
    }

    // Symplectic Euler, damping implicit: I (q̇⁺ − q̇)/h = Q − γ q̇⁺ ; q⁺ = q + h q̇⁺.
    const std::size_t j = i - 1;
    const Eigen::Vector2d total = qg - s.kappa * (s.q[j] - s.q0[j]) + qb + qw + qc;
    const Eigen::Vector2d qd = (s.qd[j] + s.gain[j] * total) * s.damper[j];
    s.dissipated += h * s.damping[j] * qd.squaredNorm();
    s.bodyWork += h * qb.dot(qd);
    s.windWork += h * qw.dot(qd);
    s.contactWork += h * qc.dot(qd);
    s.qd[j] = qd;
    s.q[j] += h * qd;
  }

  // Gravitational work of carrying the strand from the roots' pose at t0 to that at t0 + h
  // with its angles held: part of the body's work.
  const Eigen::Matrix3d turn = f.root1.linear() * f.root0.linear().transpose();
  const Eigen::Vector3d r1 = f.root1 * s.rootRest;
  s.bodyWork -=
      f.gravity.dot(massSum * (r1 - p0) + (turn - Eigen::Matrix3d::Identity()) * massMoment);
}

double ProjectiveStrands::gravitational(const Strand& s) const
{
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t i = 1; i < s.P.size(); ++i)
  {
    sum += 0.5 * (s.P[i - 1] + s.P[i]);
  }
  return -s.mass * Options.gravity.dot(sum);
}

double ProjectiveStrands::strandEnergy(const Strand& s) const
{
  double e = gravitational(s);
  for (std::size_t i = 0; i < s.q.size(); ++i)
  {
    e += 0.5 * s.inertia[i] * s.qd[i].squaredNorm() +
         0.5 * s.kappa * (s.q[i] - s.q0[i]).squaredNorm();
  }
  return e;
}

double ProjectiveStrands::unprojectedEnergy(const Strand& s, const Eigen::Vector3d& root,
                                            const Eigen::Matrix3d& rootFrame) const
{
  Eigen::Matrix3d r = rootFrame;
  Eigen::Vector3d p = root, sum = Eigen::Vector3d::Zero();
  double e = 0;
  for (std::size_t i = 0; i < s.q.size(); ++i)
  {
    r = r * segmentRotation(s.q[i].x(), s.q[i].y());
    const Eigen::Vector3d next = p + s.d * r.col(2);
    sum += 0.5 * (p + next);
    p = next;
    e += 0.5 * s.inertia[i] * s.qd[i].squaredNorm() +
         0.5 * s.kappa * (s.q[i] - s.q0[i]).squaredNorm();
  }
  return e - s.mass * Options.gravity.dot(sum);
}

void ProjectiveStrands::stepStrand(Strand& s, const StepFrame& f, ProjectiveStepStats& stats) const
{
  const std::size_t k = s.q.size();

  forces(s, f, stats);

  // Root to tip: place each segment; turn it back outside if its end node entered a part.
  const Eigen::Vector3d root = f.root1 * s.rootRest;
  const Eigen::Matrix3d rootFrame = f.root1.linear() * s.frameRest;
  if (Scene.parts.empty())
  {
    forward(s, root, rootFrame);
    return;
  }
  double before = 0;
  bool projected = false;
  s.P[0] = root;
  s.R[0] = rootFrame;
  const double margin = Options.contactMargin;
  // When a segment is turned, the part of the strand it carries is translated, not turned
  // with it: its children keep their absolute directions and rates (as far as two angles
  // can), so that a correction of a millimetre at one node does not swing the whole tip.
  bool parentTurned = false;
  Eigen::Matrix3d parentBefore;
  Eigen::Vector3d parentSpin = Eigen::Vector3d::Zero();
  auto angleAxes = [&](std::size_t i, Eigen::Vector3d& wt, Eigen::Vector3d& wp)
  {
    wp = -s.R[i - 1].col(0);
    wt = -s.R[i].col(1);
  };
  auto setDirection = [&](std::size_t i, const Eigen::Vector3d& u)
  {
    const Eigen::Vector3d l = s.R[i - 1].transpose() * u;
    const double theta = std::acos(std::clamp(l.x(), -1.0, 1.0));
    double phi = std::atan2(l.y(), l.z());
    phi += 2 * Pi * std::round((s.q[i - 1].y() - phi) / (2 * Pi));
    s.q[i - 1] = Eigen::Vector2d(theta, phi);
    s.R[i] = s.R[i - 1] * segmentRotation(theta, phi);
    s.P[i] = s.P[i - 1] + s.d * s.R[i].col(2);
  };
  for (std::size_t i = 1; i <= k; ++i)
  {
    if (parentTurned)
    {
      const Eigen::Vector3d keep =
          parentBefore * segmentRotation(s.q[i - 1].x(), s.q[i - 1].y()).col(2);
      setDirection(i, keep);
      // Cancel the parent's change of spin across this segment: least squares on the two
      // angle rates, (ω_parent change + w_θ δθ̇ + w_φ δφ̇) × u = 0.
      Eigen::Vector3d wt, wp;
      angleAxes(i, wt, wp);
      const Eigen::Vector3d u = s.R[i].col(2);
      Eigen::Matrix<double, 3, 2> m;
      m.col(0) = wt.cross(u);
      m.col(1) = wp.cross(u);
      const Eigen::Matrix2d mtm = m.transpose() * m;
      if (std::abs(mtm.determinant()) > 1e-12)
      {
        s.qd[i - 1] += mtm.inverse() * (m.transpose() * (-parentSpin.cross(u)));
      }
    }
    else
    {
      s.R[i] = s.R[i - 1] * segmentRotation(s.q[i - 1].x(), s.q[i - 1].y());
      s.P[i] = s.P[i - 1] + s.d * s.R[i].col(2);
    }
    parentTurned = false;
    Contact c;
    deepest(f, s.P[i], c);
    if (c.part >= 0)
    {
      stats.maxDepthBefore = std::max(stats.maxDepthBefore, c.depth);
    }
    if (Options.projectOutside && c.part >= 0 && c.depth > 0)
    {
      if (!projected)
      {
        // Energy of the state before any projection, for the contact work.
        before = unprojectedEnergy(s, root, rootFrame);
        projected = true;
      }
      ++stats.projections;
      const Contact c0 = c;
      parentBefore = s.R[i];
      Eigen::Vector3d u = s.R[i].col(2);
      for (int iter = 0; iter < 6 && c.part >= 0 && c.depth > 0; ++iter)
      {
        // Along the normal first; where the table's normal does not lead out (a surface
        // the projection describes poorly, under the chin say), along the table's ray.
        Eigen::Vector3d target = s.P[i] + (c.depth + margin) * c.normal;
        if (iter >= 2)
        {
          const Eigen::Vector3d ray = c.surface - s.P[i];
          const double len = ray.norm();
          target = len > 0 ? Eigen::Vector3d(c.surface + margin * ray / len) : target;
        }
        u = (target - s.P[i - 1]).normalized();
        s.P[i] = s.P[i - 1] + s.d * u;
        deepest(f, s.P[i], c);
      }
      setDirection(i, u);
      // Inelastic: the segment's own rate loses the part that drives its end node into the
      // surface (the position correction itself does not become a velocity). Cancelling
      // the whole inward velocity, ancestors' share included, through this segment's rates
      // alone is unstable (tried: the rates blow up where J is small).
      Eigen::Vector3d wt, wp;
      angleAxes(i, wt, wp);
      const Eigen::Vector3d arm = s.d * s.R[i].col(2);
      const Eigen::Vector2d jac(c0.normal.dot(wt.cross(arm)), c0.normal.dot(wp.cross(arm)));
      const double vn = jac.dot(s.qd[i - 1]);
      parentSpin.setZero();
      if (vn < 0 && jac.squaredNorm() > 0)
      {
        const Eigen::Vector2d change = -(vn / jac.squaredNorm()) * jac;
        s.qd[i - 1] += change;
        parentSpin = wt * change.x() + wp * change.y();
      }
      parentTurned = true;
    }
    if (c.part >= 0 && c.depth > stats.maxDepthAfter)
    {
      stats.maxDepthAfter = c.depth;
      stats.deepestPoint = s.P[i];
      stats.deepestPart = c.part;
    }
    s.contact[i] = c;
  }
  if (projected)
  {
    const double work = strandEnergy(s) - before;
    s.contactWork += work;
    s.projectionWork += work;
  }
}

Status ProjectiveStrands::initialize(std::vector<ProjectiveStrand> strands, ProjectiveScene scene,
                                     const ProjectiveOptions& options)
{
  if (strands.empty())
  {
    return Status::Error("projective strands: no strands; give at least one guide strand");
  }
  if (Status st = options.validate(); !st)
  {
    return Status::Error("projective strands: " + st.message());
  }
  for (std::size_t s = 0; s < strands.size(); ++s)
  {
    const ProjectiveStrand& st = strands[s];
    const std::string name = "projective strands: strand " + std::to_string(s);
    if (st.restAngles.empty())
    {
      return Status::Error(name + " has zero segments; give at least one rest angle pair");
    }
    if (!finite(st.segmentLength) || !(st.segmentLength > 0))
    {
      return Status::Error(name + ": the segment length must be a number > 0 m");
    }
    if (!st.root.allFinite() || !st.rootFrame.allFinite())
    {
      return Status::Error(name + ": the root or its frame holds NaN or infinite entries");
    }
    if (!(st.rootFrame.transpose() * st.rootFrame).isIdentity(1e-9) ||
        st.rootFrame.determinant() < 0)
    {
      return Status::Error(name + ": the root frame is not a rotation (orthonormal, "
                                  "right-handed)");
    }
    for (const auto& a : st.restAngles)
    {
      if (!a.allFinite())
      {
        return Status::Error(name + ": a rest angle is NaN or infinite");
      }
    }
  }
  if (!scene.motions.empty() && scene.motions.size() != scene.parts.size())
  {
    return Status::Error("projective strands: " + std::to_string(scene.motions.size()) +
                         " motions for " + std::to_string(scene.parts.size()) +
                         " body parts; give one motion per part, or none");
  }
  for (std::size_t k = 0; k < scene.parts.size(); ++k)
  {
    const BodyPart& part = scene.parts[k];
    const std::string name = "projective strands: body part '" + part.name + "'";
    if (part.table.empty() || part.table.numberOfHits() == 0)
    {
      return Status::Error(name + " has an empty collision table; build it from the part's "
                                  "mesh first");
    }
    if (!part.pose.matrix().allFinite())
    {
      return Status::Error(name + ": its pose holds NaN or infinite entries");
    }
  }
  for (std::size_t k = 0; k < scene.motions.size(); ++k)
  {
    if (Status st = scene.motions[k].validate("motion of body part '" + scene.parts[k].name + "'");
        !st)
    {
      return Status::Error("projective strands: " + st.message());
    }
  }
  if (Status st = scene.rootMotion.validate("root motion"); !st)
  {
    return Status::Error("projective strands: " + st.message());
  }
  if (Status st = scene.wind.validate(); !st)
  {
    return Status::Error("projective strands: " + st.message());
  }
  if (scene.motions.empty())
  {
    scene.motions.assign(scene.parts.size(), BodyMotion::still());
  }

  Scene = std::move(scene);
  Options = options;
  PartReach.clear();
  PartAxis.clear();
  for (const BodyPart& part : Scene.parts)
  {
    double rmax = 0;
    const auto& hit = part.table.hit();
    const auto& outer = part.table.outerRadius();
    for (std::size_t i = 0; i < hit.size(); ++i)
    {
      if (hit[i])
      {
        rmax = std::max(rmax, outer[i]);
      }
    }
    const double reach = rmax + 2 * Options.contactMargin + 1e-6;
    PartReach.push_back(reach * reach);
    PartAxis.push_back(part.table.spec().frame.axis.normalized());
  }

  const ProjectiveParameters& par = Options.parameters;
  Strands.clear();
  Strands.resize(strands.size());
  for (std::size_t n = 0; n < strands.size(); ++n)
  {
    Strand& s = Strands[n];
    const ProjectiveStrand& in = strands[n];
    const std::size_t k = in.restAngles.size();
    s.d = in.segmentLength;
    s.mass = par.linearDensity * s.d;
    s.kappa = par.bendingStiffness / s.d;
    s.rootRest = in.root;
    s.frameRest = in.rootFrame;
    s.q0 = in.restAngles;
    s.q = in.restAngles;
    s.qd.assign(k, Eigen::Vector2d::Zero());
    s.inertia.resize(k);
    s.damping.resize(k);
    s.gain.resize(k);
    s.damper.resize(k);
    for (std::size_t i = 0; i < k; ++i)
    {
      const double carried = static_cast<double>(k - i) * s.d;
      s.inertia[i] = par.linearDensity * carried * carried * carried / 3.0;
      s.damping[i] = par.dampingRate * s.inertia[i] + par.stiffnessDamping * s.kappa;
      s.gain[i] = Options.timeStep / s.inertia[i];
      s.damper[i] = 1.0 / (1.0 + s.gain[i] * s.damping[i]);
    }
    s.mobility.assign(k + 1, 0);
    for (std::size_t j = 1; j <= k; ++j)
    {
      double sum = 0;
      for (std::size_t i = 1; i <= j; ++i)
      {
        const double r = static_cast<double>(j - i + 1) * s.d;
        sum += r * r / s.inertia[i - 1];
      }
      s.mobility[j] = (j < k ? s.mass : 0.5 * s.mass) * sum;
    }
    s.P.resize(k + 1);
    s.R.resize(k + 1);
    s.contact.assign(k + 1, Contact());
    s.v.resize(k + 1);
  }
  Time = 0;
  Steps = 0;
  StepSeconds = 0;
  StepFrame f;
  f.useParts1 = false;
  for (std::size_t k = 0; k < Scene.parts.size(); ++k)
  {
    Scene.parts[k].pose = Scene.motions[k].pose(0);
    f.part0.push_back(Scene.parts[k].pose);
    f.part0Inv.push_back(Scene.parts[k].pose.inverse());
  }
  const Eigen::Isometry3d root0 = Scene.rootMotion.pose(0);
  for (Strand& s : Strands)
  {
    forward(s, root0 * s.rootRest, root0.linear() * s.frameRest);
    for (std::size_t i = 1; i < s.P.size(); ++i)
    {
      deepest(f, s.P[i], s.contact[i]);
    }
  }
  InitialEnergy = 0;
  InitialEnergy = energy().total();
  return Status::Ok();
}

Status ProjectiveStrands::setState(int s, const std::vector<Eigen::Vector2d>& angles,
                                   const std::vector<Eigen::Vector2d>& rates)
{
  if (s < 0 || s >= numberOfStrands())
  {
    return Status::Error("projective strands: no strand " + std::to_string(s));
  }
  Strand& st = Strands[s];
  if (angles.size() != st.q.size() || rates.size() != st.q.size())
  {
    return Status::Error("projective strands: strand " + std::to_string(s) + " has " +
                         std::to_string(st.q.size()) + " segments; give as many angles and rates");
  }
  for (std::size_t i = 0; i < angles.size(); ++i)
  {
    if (!angles[i].allFinite() || !rates[i].allFinite())
    {
      return Status::Error("projective strands: NaN or infinite angle or rate");
    }
  }
  st.q = angles;
  st.qd = rates;
  const Eigen::Isometry3d root = Scene.rootMotion.pose(Time);
  forward(st, root * st.rootRest, root.linear() * st.frameRest);
  StepFrame f;
  for (const BodyPart& part : Scene.parts)
  {
    f.part0.push_back(part.pose);
    f.part0Inv.push_back(part.pose.inverse());
  }
  for (std::size_t i = 1; i < st.P.size(); ++i)
  {
    deepest(f, st.P[i], st.contact[i]);
  }
  st.dissipated = st.bodyWork = st.windWork = st.contactWork = 0;
  for (Strand& other : Strands)
  {
    other.dissipated = other.bodyWork = other.windWork = other.contactWork = other.projectionWork =
        0;
  }
  InitialEnergy = 0;
  InitialEnergy = energy().total();
  return Status::Ok();
}

Status ProjectiveStrands::step(ProjectiveStepStats* statsOut)
{
  if (Strands.empty())
  {
    return Status::Error("projective strands: not initialized");
  }
  const auto start = std::chrono::steady_clock::now();
  const double h = Options.timeStep;
  StepFrame f;
  f.t0 = Time;
  f.h = h;
  f.gravity = Options.gravity;
  for (std::size_t k = 0; k < Scene.parts.size(); ++k)
  {
    const BodyMotion& m = Scene.motions[k];
    f.part0.push_back(m.pose(Time));
    f.part1.push_back(m.pose(Time + h));
    f.part0Inv.push_back(f.part0.back().inverse());
    f.part1Inv.push_back(f.part1.back().inverse());
    Eigen::Vector3d v, w;
    motionVelocity(m, Time, 0.5 * h, v, w);
    f.partV.push_back(v);
    f.partW.push_back(w);
  }
  f.rootM = Scene.rootMotion.pose(Time - h);
  f.root0 = Scene.rootMotion.pose(Time);
  f.root1 = Scene.rootMotion.pose(Time + h);
  motionVelocity(Scene.rootMotion, Time, 0.5 * h, f.rootV, f.rootW);
  // The force pass uses the contacts found at the end of the previous step (parts at t0);
  // the placement pass looks up the parts at t0 + h.
  f.useParts1 = true;

  // Strands in contact cost more than free ones: blocks of 16 strands go to whichever
  // thread is free. Each strand's result does not depend on which thread steps it, and the
  // statistics are merged in block order.
  const std::int64_t block = 16;
  std::vector<ProjectiveStepStats> stats(
      std::max<std::int64_t>(1, blockCount(numberOfStrands(), block)));
  parallelBlocks(numberOfStrands(), block, Options.threads,
                 [&](std::int64_t begin, std::int64_t end)
                 {
                   for (std::int64_t s = begin; s < end; ++s)
                   {
                     stepStrand(Strands[s], f, stats[begin / block]);
                   }
                 });
  const int nthreads = std::max(1, std::min(Options.threads, numberOfStrands()));
  Time += h;
  ++Steps;
  for (std::size_t k = 0; k < Scene.parts.size(); ++k)
  {
    Scene.parts[k].pose = f.part1[k];
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  StepSeconds += seconds;
  if (statsOut)
  {
    ProjectiveStepStats total;
    for (const auto& st : stats)
    {
      total.contacts += st.contacts;
      total.projections += st.projections;
      total.maxDepthBefore = std::max(total.maxDepthBefore, st.maxDepthBefore);
      if (st.maxDepthAfter > total.maxDepthAfter)
      {
        total.maxDepthAfter = st.maxDepthAfter;
        total.deepestPoint = st.deepestPoint;
        total.deepestPart = st.deepestPart;
      }
    }
    total.seconds = seconds;
    total.threads = nthreads;
    *statsOut = total;
  }
  // A NaN angle anywhere reaches the tip node, so the tips tell.
  for (const Strand& s : Strands)
  {
    if (!s.P.back().allFinite())
    {
      return Status::Error(
          "projective strands: the angles became NaN at t = " + std::to_string(Time) +
          " s; reduce the time step or the contact stiffness");
    }
  }
  return Status::Ok();
}

Status ProjectiveStrands::advance(double duration, const Progress& progress)
{
  const long n = std::lround(duration / Options.timeStep);
  for (long i = 0; i < n; ++i)
  {
    if (Status st = step(); !st)
    {
      return st;
    }
    if (progress && !progress(double(i + 1) / double(n)))
    {
      return Status::Error("projective strands: aborted at t = " + std::to_string(Time) + " s");
    }
  }
  return Status::Ok();
}

ProjectiveEnergy ProjectiveStrands::energy() const
{
  ProjectiveEnergy e;
  e.time = Time;
  const double h = Options.timeStep;
  for (const Strand& s : Strands)
  {
    const std::size_t k = s.q.size();
    e.gravitational += gravitational(s);
    double massSum = 0;
    Eigen::Vector3d massMoment = Eigen::Vector3d::Zero();
    for (std::size_t i = k; i >= 1; --i)
    {
      e.kinetic += 0.5 * s.inertia[i - 1] * s.qd[i - 1].squaredNorm();
      e.elastic += 0.5 * s.kappa * (s.q[i - 1] - s.q0[i - 1]).squaredNorm();
      // Shadow term: (h/2) q̇·Q_cons with Q_cons from gravity and springs.
      massSum += s.mass;
      massMoment += s.mass * (0.5 * (s.P[i - 1] + s.P[i]) - s.P[0]);
      const Eigen::Vector3d lever = massMoment - massSum * (s.P[i - 1] - s.P[0]);
      const Eigen::Vector3d tg = lever.cross(Options.gravity);
      const Eigen::Vector3d wp = -s.R[i - 1].col(0);
      const Eigen::Vector3d wt = -s.R[i].col(1);
      const Eigen::Vector2d q =
          Eigen::Vector2d(wt.dot(tg), wp.dot(tg)) - s.kappa * (s.q[i - 1] - s.q0[i - 1]);
      e.shadow += 0.5 * h * s.qd[i - 1].dot(q);
    }
    e.dissipated += s.dissipated;
    e.bodyWork += s.bodyWork;
    e.windWork += s.windWork;
    e.contactWork += s.contactWork;
    e.projectionWork += s.projectionWork;
  }
  e.residual = e.total() - InitialEnergy - (e.bodyWork + e.windWork + e.contactWork - e.dissipated);
  return e;
}

std::string ProjectiveStrands::summary() const
{
  long segments = 0;
  for (const Strand& s : Strands)
  {
    segments += static_cast<long>(s.q.size());
  }
  char line[256];
  std::snprintf(
      line, sizeof line,
      "projective strands: %d strands, %ld segments, %zu body parts, %ld steps, %.3f ms/step, "
      "%d threads",
      numberOfStrands(), segments, Scene.parts.size(), Steps,
      Steps ? 1e3 * StepSeconds / Steps : 0.0, Options.threads);
  return line;
}

} // namespace hair

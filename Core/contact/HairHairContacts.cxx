#include "contact/HairHairContacts.h"

#include "common/Parallel.h"

#include <Eigen/Geometry>
#include <Eigen/LU>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <tuple>

namespace hair
{

namespace
{
std::string number(double x)
{
  std::ostringstream s;
  s << x;
  return s.str();
}

Status checkNonNegative(const char* name, double value, const char* unit, const char* hint)
{
  if (!std::isfinite(value) || value < 0)
    return Status::Error(std::string("HairHairParameters: ") + name + " = " + number(value) + " " +
                         unit + " is invalid; it must be finite and >= 0. " + hint);
  return Status::Ok();
}
} // namespace

Status HairHairParameters::validate() const
{
  if (!std::isfinite(thickness) || thickness < 0)
    return Status::Error("HairHairParameters: thickness = " + number(thickness) +
                         " m is invalid; give the radius of the clump a guide stands for, finite "
                         "and > 0, or 0 for the automatic one.");
  if (thickness > 0.1)
    return Status::Error("HairHairParameters: thickness = " + number(thickness) +
                         " m is more than 0.1 m; a clump radius is millimetres (0: automatic). "
                         "Check the units.");
  if (!std::isfinite(stiffness) || stiffness <= 0)
    return Status::Error("HairHairParameters: stiffness = " + number(stiffness) +
                         " N/m is invalid; the penalty must be finite and > 0 (default 1 N/m).");
  if (Status s = checkNonNegative("damping", damping, "N·s/m", "(default 2e-4 N·s/m)"); !s)
    return s;
  if (!std::isfinite(friction) || friction < 0 || friction > 10)
    return Status::Error("HairHairParameters: friction = " + number(friction) +
                         " is invalid; give the Coulomb coefficient between guides, in [0, 10] "
                         "(dimensionless, default 0.3; 0: frictionless).");
  if (!std::isfinite(margin) || margin < 0 || margin > 4)
    return Status::Error("HairHairParameters: margin = " + number(margin) +
                         " is invalid; give the detection margin as a fraction of the contact "
                         "distance, in [0, 4] (default 0.25).");
  if (Status s = checkNonNegative("cellSize", cellSize, "m", "0 chooses it automatically."); !s)
    return s;
  if (iterations < 1 || iterations > 1000)
    return Status::Error("HairHairParameters: iterations = " + std::to_string(iterations) +
                         " is invalid; give 1 to 1000 Gauss-Seidel sweeps per solve (default 10).");
  if (!(tolerance > 0 && tolerance < 1))
    return Status::Error("HairHairParameters: tolerance = " + number(tolerance) +
                         " is invalid; give the move of a pair, as a fraction of the contact "
                         "distance, that ends the sweeps, in (0, 1) (default 0.01).");
  if (threads < 1 || threads > 256)
    return Status::Error("HairHairParameters: threads = " + std::to_string(threads) +
                         " is invalid; give 1 to 256 threads for the search (default 1).");
  if (!std::isfinite(referenceLength) || referenceLength <= 0)
    return Status::Error("HairHairParameters: referenceLength = " + number(referenceLength) +
                         " m is invalid; give the length of contact that gets the per-point "
                         "force, finite and > 0 (default 0.01 m).");
  return Status::Ok();
}

double HairHairParameters::automaticThickness(double fibreRadius, int guides)
{
  return fibreRadius * std::sqrt(HeadFibres / (std::max(1, guides) * ClumpPacking));
}

Status HairHairContacts::setParameters(const HairHairParameters& parameters)
{
  Status st = parameters.validate();
  if (!st)
    return st;
  if (!(parameters.thickness > 0))
    return Status::Error("HairHairContacts: thickness = 0 (automatic) must be resolved before "
                         "use; give HairHairParameters::automaticThickness() of the guides.");
  Params = parameters;
  Last.clear();
  Found.clear();
  return Status::Ok();
}

Status HairHairContacts::detect(const std::vector<std::vector<StrandSample>>& samples,
                                const std::vector<int>& ids, double h)
{
  if (Status st = Params.validate(); !st)
    return st;
  if (!(std::isfinite(h) && h > 0))
    return Status::Error("HairHairContacts::detect: the step h = " + number(h) +
                         " s is invalid; give the coming step's size, finite and > 0.");
  const int n = static_cast<int>(samples.size());
  if (!ids.empty() && ids.size() != samples.size())
    return Status::Error("HairHairContacts::detect: " + std::to_string(ids.size()) + " ids for " +
                         std::to_string(samples.size()) +
                         " strands; give one id per strand (or none).");
  std::vector<int> sortedIds(n);
  for (int i = 0; i < n; ++i)
  {
    const int id = ids.empty() ? i : ids[i];
    sortedIds[i] = id;
    const std::vector<StrandSample>& s = samples[i];
    for (size_t k = 0; k < s.size(); ++k)
    {
      if (!s[k].position.allFinite() || !s[k].velocity.allFinite() || !std::isfinite(s[k].s) ||
          !(s[k].weight > 0))
        return Status::Error("HairHairContacts::detect: strand id " + std::to_string(id) +
                             ", sample " + std::to_string(k) +
                             " has a non-finite position, velocity or arc length, or a weight "
                             "<= 0; the strand's state is broken.");
      if (k > 0 && !(s[k].s > s[k - 1].s))
        return Status::Error("HairHairContacts::detect: strand id " + std::to_string(id) +
                             ", sample " + std::to_string(k) +
                             ": arc lengths must increase along the strand.");
    }
  }
  std::sort(sortedIds.begin(), sortedIds.end());
  if (const auto dup = std::adjacent_find(sortedIds.begin(), sortedIds.end());
      dup != sortedIds.end())
    return Status::Error("HairHairContacts::detect: two strands have the same id " +
                         std::to_string(*dup) + "; give every strand its own StrandSpec::id.");
  Samples = samples;
  Ids.resize(n);
  for (int i = 0; i < n; ++i)
    Ids[i] = ids.empty() ? i : ids[i];
  StepSize = h;
  // The forces of the previous step's pairs, for the warm start.
  Last.clear();
  for (const Contact& c : Found)
    if (c.solved && c.r.dot(c.n) > 0)
      Last.push_back({c.keyA, c.keyB, c.r});
  std::sort(Last.begin(), Last.end(),
            [](const Previous& p, const Previous& q)
            { return std::tie(p.keyA, p.keyB) < std::tie(q.keyA, q.keyB); });
  const auto start = std::chrono::steady_clock::now();
  Stats = HairHairStats{};
  Stats.strands = n;
  Stats.rounds = 1;
  buildPieces(h);
  broadPhase();
  Stats.candidatePairs = static_cast<long>(Candidates.size());
  Found = narrowPhase(h);
  assignSlots();
  Stats.contacts = static_cast<long>(Found.size());
  Stats.searchSeconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return Status::Ok();
}

Status HairHairContacts::extend(const std::vector<std::vector<StrandSample>>& samples, bool& grew)
{
  grew = false;
  if (samples.size() != Samples.size())
    return Status::Error("HairHairContacts::extend: " + std::to_string(samples.size()) +
                         " strands for the " + std::to_string(Samples.size()) +
                         " of detect(); give the same strands.");
  for (size_t i = 0; i < samples.size(); ++i)
  {
    if (samples[i].size() != Samples[i].size())
      return Status::Error("HairHairContacts::extend: strand id " + std::to_string(Ids[i]) +
                           " has another number of samples than at detect().");
    for (const StrandSample& q : samples[i])
      if (!q.velocity.allFinite())
        return Status::Error("HairHairContacts::extend: strand id " + std::to_string(Ids[i]) +
                             " has a non-finite velocity.");
  }
  const auto start = std::chrono::steady_clock::now();
  ++Stats.rounds;
  // The same positions (so the same geometry for a pair found again), other velocities.
  for (size_t i = 0; i < samples.size(); ++i)
    for (size_t k = 0; k < samples[i].size(); ++k)
      Samples[i][k].velocity = samples[i][k].velocity;
  buildPieces(StepSize);
  broadPhase();
  std::vector<Contact> more = narrowPhase(StepSize);
  std::vector<std::pair<std::int64_t, std::int64_t>> known;
  known.reserve(Found.size());
  for (const Contact& c : Found)
    known.emplace_back(c.keyA, c.keyB);
  std::sort(known.begin(), known.end());
  for (Contact& c : more)
    if (!std::binary_search(known.begin(), known.end(), std::make_pair(c.keyA, c.keyB)))
    {
      Found.push_back(c);
      grew = true;
    }
  if (grew)
  {
    assignSlots();
    Stats.contacts = static_cast<long>(Found.size());
    Stats.candidatePairs = std::max(Stats.candidatePairs, static_cast<long>(Candidates.size()));
  }
  Stats.searchSeconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return Status::Ok();
}

void HairHairContacts::buildPieces(double h)
{
  const int n = static_cast<int>(Samples.size());
  Pieces.clear();
  // Swept boxes: each piece at the start and as predicted at the end of the step (x + h v),
  // grown by thickness (1 + margin), so that two boxes are apart only if the pieces are
  // farther than R (1 + margin) at the start and at the predicted end (the box of
  // the four points holds the piece throughout the predicted motion: linear in time).
  const double grow = Params.thickness * (1 + Params.margin);
  for (int i = 0; i < n; ++i)
  {
    const std::vector<StrandSample>& s = Samples[i];
    for (int k = 0; k + 1 < static_cast<int>(s.size()); ++k)
    {
      const Eigen::Vector3d e0 = s[k].position + h * s[k].velocity;
      const Eigen::Vector3d e1 = s[k + 1].position + h * s[k + 1].velocity;
      Piece p;
      p.strand = i;
      p.index = k;
      p.lo = s[k].position.cwiseMin(s[k + 1].position).cwiseMin(e0).cwiseMin(e1).array() - grow;
      p.hi = s[k].position.cwiseMax(s[k + 1].position).cwiseMax(e0).cwiseMax(e1).array() + grow;
      Pieces.push_back(p);
    }
  }
  Stats.pieces = static_cast<long>(Pieces.size());
}

void HairHairContacts::broadPhase()
{
  Candidates.clear();
  const int np = static_cast<int>(Pieces.size());
  if (np == 0)
    return;
  // The pieces' boxes in the uniform grid (geometry/UniformGrid), grouped by strand: its
  // overlapping pairs, sorted, are the candidates. Automatic cells: per axis, twice the
  // median extent of the boxes along it (hanging hair has long thin boxes; cubic cells as
  // large as the pieces would hold many strands each). A box longer than its cell spans a
  // few more cells; if that ever gives more than 27 entries per piece on average, the
  // cells are doubled. A requested cellSize is isotropic, honoured down to a quarter of the
  // largest box.
  double largest = 0;
  for (const Piece& p : Pieces)
    largest = std::max(largest, (p.hi - p.lo).maxCoeff());
  Eigen::Array3d cell;
  if (Params.cellSize > 0)
    cell.setConstant(std::max(Params.cellSize, 0.25 * largest));
  else
  {
    std::vector<double> e(static_cast<size_t>(np));
    for (int a = 0; a < 3; ++a)
    {
      for (int k = 0; k < np; ++k)
        e[k] = Pieces[k].hi[a] - Pieces[k].lo[a];
      std::nth_element(e.begin(), e.begin() + np / 2, e.end());
      cell[a] = 2 * e[np / 2];
    }
    for (;;)
    {
      double entries = 0;
      for (const Piece& p : Pieces)
        entries += ((p.hi - p.lo).array() / cell + 1.0).prod();
      if (entries <= 27.0 * np)
        break;
      cell *= 2;
    }
  }
  Boxes.resize(static_cast<size_t>(np));
  StrandOf.resize(static_cast<size_t>(np));
  for (int k = 0; k < np; ++k)
  {
    Boxes[k] = {Pieces[k].lo, Pieces[k].hi};
    StrandOf[k] = Pieces[k].strand;
  }
  Grid.build(Boxes, StrandOf, cell);
  Grid.overlappingPairs(Candidates, Params.threads);
}

std::vector<HairHairContacts::Contact> HairHairContacts::narrowPhase(double h)
{
  const double R = 2 * Params.thickness, reach = R * (1 + Params.margin);
  // Where on its strand a closest point lies: at a sample (the end of a piece, shared with the
  // neighbouring piece) or inside a piece. Two pieces meeting at their shared samples are
  // found by up to four pairs of pieces, which are one contact: they are merged below.
  auto feature = [](int strand, int piece, double u)
  {
    const std::int64_t index = u <= 0 ? 2 * piece : (u >= 1 ? 2 * (piece + 1) : 2 * piece + 1);
    return (static_cast<std::int64_t>(strand) << 32) | index;
  };
  // What one thread finds in a block of candidates; merged in block order, so the result
  // does not depend on the number of threads.
  auto process = [&](size_t first, size_t last, std::vector<Contact>& out)
  {
    for (size_t c = first; c < last; ++c)
    {
      const Piece &pa = Pieces[Candidates[c].first], &pb = Pieces[Candidates[c].second];
      const std::vector<StrandSample>& sa = Samples[pa.strand];
      const std::vector<StrandSample>& sb = Samples[pb.strand];
      const StrandSample &a0 = sa[pa.index], &a1 = sa[pa.index + 1];
      const StrandSample &b0 = sb[pb.index], &b1 = sb[pb.index + 1];
      double u, v;
      const double d2 =
          closestPointsOfSegments(a0.position, a1.position, b0.position, b1.position, u, v);
      // The pieces where the step without these contacts takes them.
      const Eigen::Vector3d ea0 = a0.position + h * a0.velocity,
                            ea1 = a1.position + h * a1.velocity;
      const Eigen::Vector3d eb0 = b0.position + h * b0.velocity,
                            eb1 = b1.position + h * b1.velocity;
      double ue, ve;
      const double e2 = closestPointsOfSegments(ea0, ea1, eb0, eb1, ue, ve);
      if (!(std::min(d2, e2) < reach * reach))
      {
        // Apart at both ends of the step, but maybe not between (a pair crossing faster than
        // a contact distance per step): the closest approach of the points closest at the
        // start, and of those closest at the end, moving linearly over the step.
        auto approach = [&](double x, double y)
        {
          const Eigen::Vector3d r0 = a0.position + x * (a1.position - a0.position) - b0.position -
                                     y * (b1.position - b0.position);
          const Eigen::Vector3d r1 = ea0 + x * (ea1 - ea0) - eb0 - y * (eb1 - eb0);
          const Eigen::Vector3d dr = r1 - r0;
          const double t =
              dr.squaredNorm() > 0 ? std::clamp(-r0.dot(dr) / dr.squaredNorm(), 0.0, 1.0) : 0.0;
          return (r0 + t * dr).squaredNorm();
        };
        if (!(std::min(approach(u, v), approach(ue, ve)) < reach * reach))
          continue;
      }
      const Eigen::Vector3d xa = a0.position + u * (a1.position - a0.position);
      const Eigen::Vector3d xb = b0.position + v * (b1.position - b0.position);
      double w;
      if (Params.perLength)
        w = 0.5 *
            std::max(lengthInCylinder(a0.position, a1.position, b0.position, b1.position, R) +
                         lengthInCylinder(b0.position, b1.position, a0.position, a1.position, R),
                     lengthInCylinder(ea0, ea1, eb0, eb1, R) +
                         lengthInCylinder(eb0, eb1, ea0, ea1, R)) /
            Params.referenceLength;
      else
        w = 1;
      if (!(w > 0))
        continue;
      Contact k;
      k.a = {pa.strand, pa.index, u, {-1, -1}, {1 - u, u}};
      k.b = {pb.strand, pb.index, v, {-1, -1}, {1 - v, v}};
      k.d0 = std::sqrt(d2);
      k.n = xa - xb;
      if (k.d0 > 1e-12 * R)
        k.n /= k.d0;
      else
      {
        // Touching centrelines: the common normal of the pieces, or any direction across.
        k.n = (a1.position - a0.position).cross(b1.position - b0.position);
        if (!(k.n.norm() > 0))
          k.n = (a1.position - a0.position).unitOrthogonal();
        k.n.normalize();
      }
      k.share = w;
      k.pa = xa;
      k.pb = xb;
      k.keyA = pieceKey(pa.strand, pa.index);
      k.keyB = pieceKey(pb.strand, pb.index);
      k.featureA = feature(pa.strand, pa.index, u);
      k.featureB = feature(pb.strand, pb.index, v);
      k.W.setZero();
      k.r.setZero();
      k.wFree.setZero();
      k.solved = false;
      out.push_back(k);
    }
  };
  const std::int64_t count = static_cast<std::int64_t>(Candidates.size()), grain = 4096;
  std::vector<std::vector<Contact>> found(
      static_cast<size_t>(std::max<std::int64_t>(1, blockCount(count, grain))));
  parallelBlocks(
      count, grain, Params.threads,
      [&](std::int64_t first, std::int64_t last)
      { process(static_cast<size_t>(first), static_cast<size_t>(last), found[first / grain]); });
  std::vector<Contact> out;
  for (const std::vector<Contact>& f : found)
    out.insert(out.end(), f.begin(), f.end());
  if (!Params.perLength)
  {
    // One contact per pair of closest features (the pair of pieces with the lowest keys
    // among those that found it): a closest point at a shared sample is not counted twice,
    // nor dropped. (Per length, the lengths in contact of the pairs of pieces partition
    // the length along the strands; nothing is merged.)
    std::sort(out.begin(), out.end(),
              [](const Contact& x, const Contact& y)
              {
                return std::tie(x.featureA, x.featureB, x.keyA, x.keyB) <
                       std::tie(y.featureA, y.featureB, y.keyA, y.keyB);
              });
    out.erase(std::unique(out.begin(), out.end(),
                          [](const Contact& x, const Contact& y)
                          { return x.featureA == y.featureA && x.featureB == y.featureB; }),
              out.end());
  }
  // In the order of the strands and their pieces (the merge above sorted by features).
  std::sort(out.begin(), out.end(),
            [](const Contact& x, const Contact& y)
            { return std::tie(x.keyA, x.keyB) < std::tie(y.keyA, y.keyB); });
  for (const Contact& c : out)
    Stats.maxPenetration = std::max(Stats.maxPenetration, R - c.d0);
  return out;
}

void HairHairContacts::assignSlots()
{
  const int n = static_cast<int>(Samples.size());
  Coupling.assign(n, {});
  for (const Contact& c : Found)
    for (const Side* s : {&c.a, &c.b})
      for (int e = 0; e < 2; ++e)
        if (s->phi[e] > 0)
          Coupling[s->strand].push_back(s->piece + e);
  for (std::vector<int>& v : Coupling)
  {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
  }
  for (Contact& c : Found)
    for (Side* s : {&c.a, &c.b})
      for (int e = 0; e < 2; ++e)
        if (s->phi[e] > 0)
        {
          const std::vector<int>& v = Coupling[s->strand];
          s->slot[e] =
              static_cast<int>(std::lower_bound(v.begin(), v.end(), s->piece + e) - v.begin());
        }
}

Eigen::Vector3d HairHairContacts::relativeVelocity(const Contact& c) const
{
  Eigen::Vector3d w = c.wFree;
  for (int side = 0; side < 2; ++side)
  {
    const Side& sd = side == 0 ? c.a : c.b;
    const StrandCompliance& k = (*Compliance)[sd.strand];
    const double* d = Response[sd.strand].data();
    const int m = static_cast<int>(k.Jt.rows());
    for (int e = 0; e < 2; ++e)
    {
      if (sd.slot[e] < 0)
        continue;
      const int cols = k.columns[sd.slot[e]];
      const double* j = k.Jt.data() + static_cast<std::ptrdiff_t>(3 * sd.slot[e]) * m;
      double w0 = 0, w1 = 0, w2 = 0;
      for (int i = 0; i < cols; ++i)
      {
        w0 += j[i] * d[i];
        w1 += j[m + i] * d[i];
        w2 += j[2 * m + i] * d[i];
      }
      const double f = side == 0 ? sd.phi[e] : -sd.phi[e];
      w += f * Eigen::Vector3d(w0, w1, w2);
    }
  }
  return w;
}

void HairHairContacts::apply(const Contact& c, const Eigen::Vector3d& dr)
{
  for (int side = 0; side < 2; ++side)
  {
    const Side& sd = side == 0 ? c.a : c.b;
    const StrandCompliance& k = (*Compliance)[sd.strand];
    double* d = Response[sd.strand].data();
    const int m = static_cast<int>(k.Y.rows());
    for (int e = 0; e < 2; ++e)
    {
      if (sd.slot[e] < 0)
        continue;
      const double f = side == 0 ? sd.phi[e] : -sd.phi[e];
      const double r0 = f * dr.x(), r1 = f * dr.y(), r2 = f * dr.z();
      const double* y = k.Y.data() + static_cast<std::ptrdiff_t>(3 * sd.slot[e]) * m;
      for (int i = 0; i < m; ++i)
        d[i] += y[i] * r0 + y[m + i] * r1 + y[2 * m + i] * r2;
    }
  }
}

void HairHairContacts::localSolve(Contact& c, const Eigen::Vector3d& w) const
{
  // The pair's law at the end of the step (docs/hair-hair-contacts.md): with the relative
  // velocity w = w_rest + W r of the end of the step and the gap predicted there,
  // d = d0 + h n·w, the normal force λ = max(0, k (R − d) − c_n n·w) and the tangential
  // force t in the Coulomb disc |t| ≤ μ λ, sticking (w_t = 0) when it can.
  const double R = 2 * Params.thickness, h = StepSize;
  const double k = c.share * Params.stiffness, cn = c.share * Params.damping;
  const double a = k * h + cn, b0 = k * (R - c.d0), mu = Params.friction;
  const Eigen::Vector3d& n = c.n;
  const Eigen::Vector3d rest = w - c.W * c.r;
  const double wnn = n.dot(c.W * n);
  Eigen::Vector3d t = c.r - n.dot(c.r) * n; // the current tangential force
  double lambda = 0;
  auto normal = [&]() { return std::max(0.0, (b0 - a * n.dot(rest + c.W * t)) / (1 + a * wnn)); };
  lambda = normal();
  if (mu > 0 && lambda > 0)
  {
    Eigen::Matrix<double, 3, 2> P;
    P.col(0) = n.unitOrthogonal();
    P.col(1) = n.cross(P.col(0));
    const Eigen::Matrix2d Wt = P.transpose() * c.W * P;
    const double det = Wt.determinant();
    for (int pass = 0; pass < 2; ++pass)
    {
      Eigen::Vector2d tau = Eigen::Vector2d::Zero();
      if (det > 0)
      {
        // Stick: the tangential force that zeroes the tangential relative velocity.
        const Eigen::Vector2d target = -P.transpose() * (rest + lambda * (c.W * n));
        tau = Wt.inverse() * target;
      }
      const double cap = mu * lambda, norm = tau.norm();
      if (norm > cap)
        tau *= cap / norm; // slide: on the Coulomb circle
      t = P * tau;
      lambda = normal();
    }
  }
  else
    t.setZero();
  if (lambda == 0)
  {
    t.setZero();
    lambda = normal();
  }
  c.r = lambda * n + t;
}

Status HairHairContacts::solve(const std::vector<StrandCompliance>& compliance)
{
  const int n = static_cast<int>(Samples.size());
  if (static_cast<int>(compliance.size()) != n)
    return Status::Error("HairHairContacts::solve: " + std::to_string(compliance.size()) +
                         " compliances for the " + std::to_string(n) +
                         " strands of detect(); give one per strand.");
  for (int i = 0; i < n; ++i)
  {
    const StrandCompliance& k = compliance[i];
    if (Coupling[i].empty())
      continue;
    const int cs = static_cast<int>(Coupling[i].size());
    if (k.samples != Coupling[i] || static_cast<int>(k.freeVelocity.size()) != cs ||
        k.Jt.cols() != 3 * cs || k.Y.cols() != 3 * cs || k.Jt.rows() != k.Y.rows() ||
        static_cast<int>(k.columns.size()) != cs)
      return Status::Error("HairHairContacts::solve: the compliance of strand id " +
                           std::to_string(Ids[i]) +
                           " does not describe its coupling samples; build it with "
                           "couplingSamples() of the same detect().");
  }
  const auto start = std::chrono::steady_clock::now();
  Forces.assign(n, {});
  Response.assign(n, Eigen::VectorXd());
  for (int i = 0; i < n; ++i)
  {
    Forces[i].assign(Coupling[i].size(), Eigen::Vector3d::Zero());
    Response[i] = Eigen::VectorXd::Zero(compliance[i].Y.rows());
  }
  // Each pair's own compliance W = Σ over its two sides of Σ φ_k φ_l J_k Y_l (how its
  // relative velocity answers its own force) and its relative velocity without contact
  // forces.
  Compliance = &compliance;
  for (Contact& c : Found)
  {
    c.W.setZero();
    c.wFree.setZero();
    for (int side = 0; side < 2; ++side)
    {
      const Side& sd = side == 0 ? c.a : c.b;
      const StrandCompliance& k = compliance[sd.strand];
      const int m = static_cast<int>(k.Y.rows());
      Eigen::Matrix<double, Eigen::Dynamic, 3> y = Eigen::MatrixXd::Zero(m, 3);
      for (int e = 0; e < 2; ++e)
        if (sd.slot[e] >= 0)
        {
          y += sd.phi[e] * k.Y.middleCols<3>(3 * sd.slot[e]);
          c.wFree += (side == 0 ? sd.phi[e] : -sd.phi[e]) * k.freeVelocity[sd.slot[e]];
        }
      for (int e = 0; e < 2; ++e)
        if (sd.slot[e] >= 0)
        {
          const int cols = k.columns[sd.slot[e]];
          c.W.noalias() +=
              sd.phi[e] * k.Jt.block(0, 3 * sd.slot[e], cols, 3).transpose() * y.topRows(cols);
        }
    }
  }
  // Solved from the stiffest pairs (smallest compliance along the normal, near the roots) to
  // the most compliant (near the tips): a force near a root moves the whole strand beyond
  // it, a force near a tip hardly moves the root, so this order settles the upstream pairs
  // first (measured on the demo: fewer pairs through each other at the same sweeps).
  std::stable_sort(Found.begin(), Found.end(),
                   [](const Contact& x, const Contact& y)
                   { return x.n.dot(x.W * x.n) < y.n.dot(y.W * y.n); });
  for (Contact& c : Found)
  {
    if (!c.solved)
    {
      c.r.setZero();
      const auto it = std::lower_bound(Last.begin(), Last.end(), c,
                                       [](const Previous& p, const Contact& x) {
                                         return std::tie(p.keyA, p.keyB) < std::tie(x.keyA, x.keyB);
                                       });
      if (it != Last.end() && it->keyA == c.keyA && it->keyB == c.keyB)
      {
        const double lambda = std::max(0.0, it->r.dot(c.n));
        Eigen::Vector3d t = it->r - it->r.dot(c.n) * c.n;
        if (t.norm() > Params.friction * lambda)
          t *= Params.friction * lambda / t.norm();
        c.r = lambda * c.n + t;
      }
    }
    if (!c.r.isZero(0))
      apply(c, c.r);
  }
  // Projected Gauss–Seidel: each pair in turn solves its law against the others' current
  // forces, exactly for its own (its relative velocity is affine in its force through W).
  const double R = 2 * Params.thickness, h = StepSize;
  for (int sweep = 0; sweep < Params.iterations && !Found.empty(); ++sweep)
  {
    double moved = 0;
    for (Contact& c : Found)
    {
      const Eigen::Vector3d old = c.r;
      localSolve(c, relativeVelocity(c));
      const Eigen::Vector3d dr = c.r - old;
      if (!dr.isZero(0))
      {
        apply(c, dr);
        moved = std::max(moved, h * (c.W * dr).norm());
      }
    }
    ++Stats.sweeps;
    Stats.change = moved / R;
    if (moved <= Params.tolerance * R)
      break;
  }
  // The guard: pairs that the sweeps leave predicted to end deeper than half the contact
  // distance with less force than their law asks for (so that they are still closing) are
  // swept again on their own, a few times, until none is left (at most GuardRounds rounds).
  std::vector<Contact*> bad;
  for (int round = 0; round < GuardRounds; ++round)
  {
    bad.clear();
    for (Contact& c : Found)
    {
      const Eigen::Vector3d w = relativeVelocity(c);
      const double wn = w.dot(c.n), end = c.d0 + h * wn;
      if (end >= 0.5 * R)
        continue;
      const double k = c.share * Params.stiffness, cn = c.share * Params.damping;
      if (k * (R - end) - cn * wn > c.r.dot(c.n) * (1 + 1e-6))
        bad.push_back(&c);
    }
    if (bad.empty())
      break;
    Stats.guarded += static_cast<long>(bad.size());
    for (int inner = 0; inner < GuardSweeps; ++inner)
      for (Contact* c : bad)
      {
        const Eigen::Vector3d old = c->r;
        localSolve(*c, relativeVelocity(*c));
        const Eigen::Vector3d dr = c->r - old;
        if (!dr.isZero(0))
          apply(*c, dr);
      }
  }
  // Forces at the coupling samples, the energy of the step and the report.
  Report.clear();
  Stats.work = Stats.dissipated = Stats.potentialEnergy = Stats.maxEndPenetration = 0;
  Stats.active = Stats.sticking = 0;
  for (Contact& c : Found)
  {
    c.solved = true;
    for (const Side* sd : {&c.a, &c.b})
    {
      const double sign = sd == &c.a ? 1.0 : -1.0;
      for (int e = 0; e < 2; ++e)
        if (sd->slot[e] >= 0)
          Forces[sd->strand][sd->slot[e]] += (sign * sd->phi[e]) * c.r;
    }
    const Eigen::Vector3d w = relativeVelocity(c);
    const double lambda = c.r.dot(c.n), wn = w.dot(c.n);
    const Eigen::Vector3d t = c.r - lambda * c.n, wt = w - wn * c.n;
    Stats.work += h * c.r.dot(w);
    if (lambda > 0)
    {
      ++Stats.active;
      Stats.sticking += t.norm() < Params.friction * lambda * (1 - 1e-9);
      const double k = c.share * Params.stiffness, cn = c.share * Params.damping;
      const double end = std::max(0.0, R - (c.d0 + h * wn));
      Stats.maxEndPenetration = std::max(Stats.maxEndPenetration, end);
      Stats.potentialEnergy += 0.5 * k * end * end;
      Stats.dissipated += h * (cn * wn * wn - t.dot(wt));
    }
    HairHairContact r;
    r.strandA = c.a.strand;
    r.strandB = c.b.strand;
    r.sA = Samples[c.a.strand][c.a.piece].s +
           c.a.u * (Samples[c.a.strand][c.a.piece + 1].s - Samples[c.a.strand][c.a.piece].s);
    r.sB = Samples[c.b.strand][c.b.piece].s +
           c.b.u * (Samples[c.b.strand][c.b.piece + 1].s - Samples[c.b.strand][c.b.piece].s);
    r.pointA = c.pa;
    r.pointB = c.pb;
    r.distance = c.d0;
    r.normal = c.n;
    r.forceOnA = c.r;
    r.relativeVelocity = w;
    Report.push_back(r);
  }
  Compliance = nullptr;
  Stats.solveSeconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return Status::Ok();
}

std::vector<std::pair<std::int64_t, std::int64_t>> HairHairContacts::candidatePairs() const
{
  std::vector<std::pair<std::int64_t, std::int64_t>> out;
  out.reserve(Candidates.size());
  for (const auto& [a, b] : Candidates)
  {
    std::int64_t ka = pieceKey(Pieces[a].strand, Pieces[a].index);
    std::int64_t kb = pieceKey(Pieces[b].strand, Pieces[b].index);
    if (kb < ka)
      std::swap(ka, kb);
    out.emplace_back(ka, kb);
  }
  std::sort(out.begin(), out.end());
  return out;
}

} // namespace hair

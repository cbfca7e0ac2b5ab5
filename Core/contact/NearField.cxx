#include "contact/NearField.h"

#include "common/Parallel.h"
#include "contact/SegmentGeometry.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <tuple>

namespace hair
{

namespace
{
std::int64_t key(int id, int piece)
{
  return (static_cast<std::int64_t>(id) << 32) | static_cast<std::uint32_t>(piece);
}
// Where a closest point lies on its strand: at a sample (shared by two pieces) or inside a
// piece; two pairs of pieces with the same features on both strands are one contact.
std::int64_t feature(int strand, int piece, double u)
{
  const std::int64_t at = u <= 0 ? 2 * piece : (u >= 1 ? 2 * (piece + 1) : 2 * piece + 1);
  return (static_cast<std::int64_t>(strand) << 32) | at;
}
// The smallest |r0 + t (r1 − r0)| over t in [0, 1].
double closestApproach(const Eigen::Vector3d& r0, const Eigen::Vector3d& r1)
{
  const Eigen::Vector3d d = r1 - r0;
  const double dd = d.squaredNorm();
  const double t = dd > 0 ? std::clamp(-r0.dot(d) / dd, 0.0, 1.0) : 0.0;
  return (r0 + t * d).norm();
}
} // namespace

Status NearFieldParameters::validate() const
{
  std::ostringstream s;
  if (!(std::isfinite(thickness) && thickness > 0 && thickness <= 0.1))
    s << "the contact thickness " << thickness
      << " m is not in (0, 0.1]: give the radius of the clump of fibres a guide stands for "
         "(e.g. 1e-3), or 0 for automatic where the model offers it.";
  else if (!(margin >= 0 && margin <= 4))
    s << "the margin " << margin << " is not in [0, 4] (a fraction of the contact distance).";
  else if (!(pieceLength >= 1e-4 && pieceLength <= 0.1))
    s << "the piece length " << pieceLength << " m is not in [1e-4, 0.1].";
  else if (sweeps < 1 || sweeps > 1000)
    s << "the sweeps " << sweeps << " are not in [1, 1000].";
  else if (threads < 1 || threads > 256)
    s << "the threads " << threads << " are not in [1, 256].";
  else
    return Status::Ok();
  return Status::Error("near field: " + s.str());
}

Status NearFieldContacts::setParameters(const NearFieldParameters& parameters)
{
  if (Status s = parameters.validate(); !s)
    return s;
  Params = parameters;
  return Status::Ok();
}

std::vector<double> NearFieldContacts::nodeArcLengths(double length) const
{
  const int pieces = std::max(1, static_cast<int>(std::ceil(length / Params.pieceLength - 1e-9)));
  std::vector<double> s(pieces + 1);
  for (int j = 0; j <= pieces; ++j)
    s[j] = length * j / pieces;
  return s;
}

Eigen::Vector3d NearFieldContacts::pointOf(const Side& s, bool velocity) const
{
  const std::vector<StrandSample>& q = Samples[s.strand];
  return velocity
             ? Eigen::Vector3d((1 - s.u) * q[s.piece].velocity + s.u * q[s.piece + 1].velocity)
             : Eigen::Vector3d((1 - s.u) * q[s.piece].position + s.u * q[s.piece + 1].position);
}

Status NearFieldContacts::detect(const std::vector<std::vector<StrandSample>>& samples,
                                 const std::vector<int>& ids, double h,
                                 const Eigen::Isometry3d& carry,
                                 const std::vector<std::vector<Eigen::Vector3d>>* startVelocities)
{
  const auto start = std::chrono::steady_clock::now();
  const int n = static_cast<int>(samples.size());
  if (!(std::isfinite(h) && h > 0))
    return Status::Error("near field: the step " + std::to_string(h) + " s is not > 0.");
  if ((!ids.empty() && static_cast<int>(ids.size()) != n) ||
      (startVelocities && static_cast<int>(startVelocities->size()) != n))
    return Status::Error("near field: " + std::to_string(n) + " strands with " +
                         std::to_string(ids.size()) + " ids; give one per strand.");
  for (int i = 0; i < n; ++i)
  {
    const std::string name = "near field: strand " + std::to_string(ids.empty() ? i : ids[i]);
    if (samples[i].size() < 2)
      return Status::Error(name + " has fewer than two nodes.");
    if (startVelocities && (*startVelocities)[i].size() != samples[i].size())
      return Status::Error(name + " has another number of start velocities than of nodes.");
    for (std::size_t k = 0; k < samples[i].size(); ++k)
    {
      const StrandSample& q = samples[i][k];
      if (!q.position.allFinite() || !q.velocity.allFinite())
        return Status::Error(name + " has a node that is not finite.");
    }
  }
  StepSize = h;
  Samples = samples;
  Ids = ids;
  if (Ids.empty())
    for (int i = 0; i < n; ++i)
      Ids.push_back(i);
  Stats = NearFieldStats();
  Stats.strands = n;
  const double R = 2 * Params.thickness, reach = R * (1 + Params.margin);
  // A node whose velocity changes by Δv over the step departs from x + h v by up to ½ h |Δv|
  // (at most `reach` more: a node whose velocity jumps is pushed by a contact, whose own
  // motion the step resolves).
  std::vector<std::vector<double>> slack(n);
  for (int i = 0; i < n; ++i)
  {
    slack[i].assign(samples[i].size(), 0.0);
    if (startVelocities)
      for (std::size_t k = 0; k < samples[i].size(); ++k)
        slack[i][k] =
            std::min(reach, 0.5 * h * (samples[i][k].velocity - (*startVelocities)[i][k]).norm());
  }

  // The pieces' swept boxes, the end of the step carried back by the roots' motion and each
  // grown by the slack of its nodes: two boxes are apart only if the pieces stay farther
  // than `reach` from each other.
  std::vector<Box3> boxes;
  std::vector<int> groups, pieceStrand, pieceIndex;
  std::vector<int> firstNode(n + 1, 0);
  std::vector<Eigen::Vector3d> at, ends; // every node at the start and (carried) at the end
  for (int i = 0; i < n; ++i)
  {
    firstNode[i + 1] = firstNode[i] + static_cast<int>(samples[i].size());
    for (const StrandSample& q : samples[i])
    {
      at.push_back(q.position);
      ends.push_back(carry * (q.position + h * q.velocity));
    }
  }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j + 1 < static_cast<int>(samples[i].size()); ++j)
    {
      const int f = firstNode[i] + j;
      const double grow = 0.5 * reach + std::max(slack[i][j], slack[i][j + 1]);
      Box3 b;
      b.lo = at[f].cwiseMin(at[f + 1]).cwiseMin(ends[f]).cwiseMin(ends[f + 1]).array() - grow;
      b.hi = at[f].cwiseMax(at[f + 1]).cwiseMax(ends[f]).cwiseMax(ends[f + 1]).array() + grow;
      boxes.push_back(b);
      groups.push_back(i);
      pieceStrand.push_back(i);
      pieceIndex.push_back(j);
    }
  const int np = static_cast<int>(boxes.size());
  Stats.pieces = np;
  std::vector<std::pair<int, int>> candidates;
  if (np > 1)
  {
    // Cells per axis twice the median extent of the boxes (hanging hair has long thin
    // boxes), doubled while the boxes would span more than 27 cells each on average
    // (counted before binning: a strand flung far would span more cells than memory holds).
    Eigen::Array3d cell;
    std::vector<double> e(static_cast<std::size_t>(np));
    for (int a = 0; a < 3; ++a)
    {
      for (int k = 0; k < np; ++k)
        e[k] = boxes[k].hi[a] - boxes[k].lo[a];
      std::nth_element(e.begin(), e.begin() + np / 2, e.end());
      cell[a] = std::max(2 * e[np / 2], 1e-9);
    }
    for (;;)
    {
      double entries = 0;
      for (const Box3& b : boxes)
        entries += ((b.hi.array() / cell).floor() - (b.lo.array() / cell).floor() + 1).prod();
      if (entries <= 27.0 * np)
        break;
      cell *= 2;
    }
    Grid.build(boxes, groups, cell);
    Grid.overlappingPairs(candidates, Params.threads);
  }
  Stats.candidates = static_cast<long>(candidates.size());

  // Narrow phase on blocks of candidates (merged in block order: the same on any threads).
  struct Found
  {
    int pa, pb; // pieces
    double u, v;
    bool interior;
    std::int64_t fa, fb;
  };
  const std::int64_t grain = 4096;
  std::vector<std::vector<Found>> blocks(
      static_cast<std::size_t>(blockCount(static_cast<std::int64_t>(candidates.size()), grain)));
  parallelBlocks(
      static_cast<std::int64_t>(candidates.size()), grain, Params.threads,
      [&](std::int64_t first, std::int64_t last)
      {
        std::vector<Found>& out = blocks[first / grain];
        for (std::int64_t c = first; c < last; ++c)
        {
          int pa = candidates[c].first, pb = candidates[c].second;
          if (pieceStrand[pa] > pieceStrand[pb])
            std::swap(pa, pb);
          const int ia = pieceStrand[pa], ja = pieceIndex[pa];
          const int ib = pieceStrand[pb], jb = pieceIndex[pb];
          const int fa = firstNode[ia] + ja, fb = firstNode[ib] + jb;
          const double limit = reach + std::max(slack[ia][ja], slack[ia][ja + 1]) +
                               std::max(slack[ib][jb], slack[ib][jb + 1]);
          double u = 0, v = 0, u1 = 0, v1 = 0;
          const double d0 =
              std::sqrt(closestPointsOfSegments(at[fa], at[fa + 1], at[fb], at[fb + 1], u, v));
          const double d1 = std::sqrt(
              closestPointsOfSegments(ends[fa], ends[fa + 1], ends[fb], ends[fb + 1], u1, v1));
          double dmin = std::min(d0, d1);
          if (dmin > limit)
          {
            // In between: either pair of material points moving linearly over the step.
            auto lerp = [](const Eigen::Vector3d& p, const Eigen::Vector3d& q, double t)
            { return Eigen::Vector3d(p + t * (q - p)); };
            dmin = std::min(
                closestApproach(lerp(at[fa], at[fa + 1], u) - lerp(at[fb], at[fb + 1], v),
                                lerp(ends[fa], ends[fa + 1], u) - lerp(ends[fb], ends[fb + 1], v)),
                closestApproach(lerp(at[fa], at[fa + 1], u1) - lerp(at[fb], at[fb + 1], v1),
                                lerp(ends[fa], ends[fa + 1], u1) -
                                    lerp(ends[fb], ends[fb + 1], v1)));
          }
          if (dmin > limit)
            continue;
          const bool interior = u > 0 && u < 1 && v > 0 && v < 1;
          out.push_back({pa, pb, u, v, interior, feature(ia, ja, u), feature(ib, jb, v)});
        }
      });
  std::vector<Found> found;
  for (auto& b : blocks)
    found.insert(found.end(), b.begin(), b.end());
  // One contact per pair of closest features (a closest point at a node is found by the
  // pieces on both sides of it): the first in candidate order is kept.
  {
    std::vector<std::size_t> order(found.size());
    for (std::size_t k = 0; k < order.size(); ++k)
      order[k] = k;
    std::stable_sort(
        order.begin(), order.end(),
        [&](std::size_t x, std::size_t y)
        { return std::tie(found[x].fa, found[x].fb) < std::tie(found[y].fa, found[y].fb); });
    std::vector<char> keep(found.size(), 0);
    for (std::size_t k = 0; k < order.size(); ++k)
      keep[order[k]] = k == 0 || found[order[k]].fa != found[order[k - 1]].fa ||
                       found[order[k]].fb != found[order[k - 1]].fb;
    std::vector<Found> merged;
    for (std::size_t k = 0; k < found.size(); ++k)
      if (keep[k])
        merged.push_back(found[k]);
    found.swap(merged);
  }

  // Each pair's side: followed from the previous step (its own memory, or that of a pair of
  // neighbouring pieces when the contact has moved along), else its direction now.
  auto recall = [&](std::int64_t ka, std::int64_t kb) -> const Memory_*
  {
    const auto it =
        std::lower_bound(Memory.begin(), Memory.end(), std::make_pair(ka, kb),
                         [](const Memory_& m, const std::pair<std::int64_t, std::int64_t>& k)
                         { return std::make_pair(m.keyA, m.keyB) < k; });
    return it != Memory.end() && it->keyA == ka && it->keyB == kb ? &*it : nullptr;
  };
  Pairs.clear();
  Pairs.reserve(found.size());
  for (const Found& f : found)
  {
    Pair p;
    int sa = pieceStrand[f.pa], sb = pieceStrand[f.pb];
    int ja = pieceIndex[f.pa], jb = pieceIndex[f.pb];
    double ua = f.u, ub = f.v;
    if (Ids[sa] > Ids[sb]) // memory keys in id order, whatever the strands' order here
    {
      std::swap(sa, sb);
      std::swap(ja, jb);
      std::swap(ua, ub);
    }
    p.a.strand = sa;
    p.a.piece = ja;
    p.a.u = ua;
    p.b.strand = sb;
    p.b.piece = jb;
    p.b.u = ub;
    p.keyA = key(Ids[sa], ja);
    p.keyB = key(Ids[sb], jb);
    p.interior = f.interior;
    const Eigen::Vector3d d = pointOf(p.a, false) - pointOf(p.b, false);
    const double dist = d.norm();
    Eigen::Vector3d now;
    if (dist > 1e-12)
      now = d / dist;
    else
    {
      // Touching centrelines: the pieces' common normal.
      const int fa = firstNode[sa] + ja, fb = firstNode[sb] + jb;
      now = (at[fa + 1] - at[fa]).cross(at[fb + 1] - at[fb]);
      if (now.norm() < 1e-12)
        now = (at[fa + 1] - at[fa]).unitOrthogonal();
      now.normalize();
    }
    const Memory_* m = recall(p.keyA, p.keyB);
    for (int da = -1; da <= 1 && !m; ++da)
      for (int db = -1; db <= 1 && !m; ++db)
        if (da != 0 || db != 0)
          m = recall(p.keyA + da, p.keyB + db);
    // A pair first found already within R has no side to keep: two guides grown through
    // each other may come apart either way. It gets one once it is R apart.
    p.trusted = m ? m->trusted || dist >= R : dist >= R;
    p.side = now;
    if (m && m->trusted)
    {
      if (m->keyA == p.keyA && m->keyB == p.keyB)
        p.lambda = m->lambda;
      // Crossed: the direction between the closest points reversed, with the closest points
      // inside both pieces then and now (at an end it can turn without any crossing).
      p.flipped = now.dot(m->side) < 0 && p.interior && m->interior;
      if (p.flipped)
        p.side = m->side;
    }
    p.gap = p.side.dot(d);
    p.wFree = p.side.dot(pointOf(p.a, true) - pointOf(p.b, true));
    p.active = p.trusted && (p.flipped || p.gap + h * p.wFree < R);
    Pairs.push_back(p);
  }
  Stats.tracked = static_cast<long>(Pairs.size());
  for (const Pair& p : Pairs)
    Stats.untrusted += p.trusted ? 0 : 1;

  // The loads: each acting pair pushes each of its strands at its point, along its side (A)
  // or against it (B); per strand in pair order.
  Loads.assign(n, {});
  for (int c = 0; c < static_cast<int>(Pairs.size()); ++c)
  {
    Pair& p = Pairs[c];
    if (!p.active)
      continue;
    ++Stats.active;
    Stats.flipped += p.flipped ? 1 : 0;
    for (int side = 0; side < 2; ++side)
    {
      Side& sd = side == 0 ? p.a : p.b;
      const std::vector<StrandSample>& q = Samples[sd.strand];
      NearFieldLoad l;
      l.node = sd.piece;
      l.s[0] = q[sd.piece].s;
      l.s[1] = q[sd.piece + 1].s;
      l.weight[0] = sd.weight(0);
      l.weight[1] = sd.weight(1);
      l.direction = side == 0 ? p.side : Eigen::Vector3d(-p.side);
      sd.load = static_cast<int>(Loads[sd.strand].size());
      Loads[sd.strand].push_back(l);
    }
  }
  for (const std::vector<NearFieldLoad>& l : Loads)
    Stats.coupled += l.empty() ? 0 : 1;
  Stats.searchSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return Status::Ok();
}

Status NearFieldContacts::solve(const std::vector<Eigen::MatrixXd>& delassus)
{
  const auto start = std::chrono::steady_clock::now();
  const int n = static_cast<int>(Samples.size());
  if (static_cast<int>(delassus.size()) != n)
    return Status::Error("near field: " + std::to_string(delassus.size()) +
                         " load compliances for " + std::to_string(n) + " strands.");
  for (int i = 0; i < n; ++i)
  {
    const Eigen::Index p = static_cast<Eigen::Index>(Loads[i].size());
    if (p > 0 && (delassus[i].rows() != p || delassus[i].cols() != p || !delassus[i].allFinite()))
      return Status::Error("near field: strand " + std::to_string(Ids[i]) +
                           "'s load compliance is " + std::to_string(delassus[i].rows()) + " × " +
                           std::to_string(delassus[i].cols()) + " for its " + std::to_string(p) +
                           " loads, or not finite.");
  }
  const double h = StepSize, R = 2 * Params.thickness;
  // The loads' velocities along their directions from the pairs' forces: u_i = D_i λ_i per
  // strand (D_i[k][l] = d_kᵀ J_k h A⁻¹ J_lᵀ d_l from the strand's step), so that a pair's
  // relative normal velocity at the end of the step is wFree + u_A[kA] + u_B[kB].
  std::vector<int> acting;
  for (int c = 0; c < static_cast<int>(Pairs.size()); ++c)
    if (Pairs[c].active)
      acting.push_back(c);
  std::vector<std::vector<double>> lambda(n), u(n);
  for (int i = 0; i < n; ++i)
  {
    lambda[i].assign(Loads[i].size(), 0.0);
    u[i].assign(Loads[i].size(), 0.0);
  }
  for (int c : acting)
  {
    Pair& p = Pairs[c];
    p.compliance = std::max(delassus[p.a.strand](p.a.load, p.a.load) +
                                delassus[p.b.strand](p.b.load, p.b.load),
                            1e-300);
  }
  auto apply = [&](const Pair& p, double dl)
  {
    for (const Side* sd : {&p.a, &p.b})
    {
      lambda[sd->strand][sd->load] += dl;
      const Eigen::MatrixXd& D = delassus[sd->strand];
      std::vector<double>& v = u[sd->strand];
      for (std::size_t k = 0; k < v.size(); ++k)
        v[k] += D(static_cast<Eigen::Index>(k), sd->load) * dl;
    }
  };
  for (int c : acting) // the warm start
    if (Pairs[c].lambda > 0)
      apply(Pairs[c], Pairs[c].lambda);
  auto relative = [&](const Pair& p)
  { return p.wFree + u[p.a.strand][p.a.load] + u[p.b.strand][p.b.load]; };
  // Projected Gauss–Seidel over the acting pairs: each solves for its own force with the
  // others held, in a fixed order (the stiffest first: a force near a root moves all the
  // strand beyond it), so that the result depends on nothing but the pairs.
  std::sort(acting.begin(), acting.end(),
            [&](int x, int y)
            {
              const Pair &p = Pairs[x], &q = Pairs[y];
              return std::tie(p.compliance, p.keyA, p.keyB) <
                     std::tie(q.compliance, q.keyA, q.keyB);
            });
  int sweeps = 0;
  const double tolerance = 1e-3 * R; // a change of the predicted gap below this is converged
  for (; sweeps < Params.sweeps && !acting.empty(); ++sweeps)
  {
    double change = 0;
    for (int c : acting)
    {
      Pair& p = Pairs[c];
      const double wanted = (R - p.gap) / h; // the relative normal velocity that ends at R
      const double next = std::max(0.0, p.lambda + (wanted - relative(p)) / p.compliance);
      const double dl = next - p.lambda;
      if (dl != 0)
      {
        apply(p, dl);
        p.lambda = next;
      }
      change = std::max(change, std::abs(dl) * p.compliance * h);
    }
    if (change < tolerance)
    {
      ++sweeps;
      break;
    }
  }
  Stats.sweeps = sweeps;
  Stats.deficit = acting.empty() ? 0 : -R;
  Stats.work = 0;
  for (int c : acting)
  {
    const Pair& p = Pairs[c];
    const double w = relative(p);
    Stats.deficit = std::max(Stats.deficit, R - (p.gap + h * w));
    Stats.work += h * p.lambda * w;
  }
  LoadForces = std::move(lambda);
  // What the next step remembers: every tracked pair's side, and its force.
  Memory.clear();
  Memory.reserve(Pairs.size());
  for (const Pair& p : Pairs)
    Memory.push_back({p.keyA, p.keyB, p.side, p.interior, p.trusted, p.active ? p.lambda : 0.0});
  std::sort(Memory.begin(), Memory.end(),
            [](const Memory_& x, const Memory_& y)
            { return std::tie(x.keyA, x.keyB) < std::tie(y.keyA, y.keyB); });
  Stats.solveSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return Status::Ok();
}

std::vector<NearFieldPair> NearFieldContacts::pairs() const
{
  std::vector<NearFieldPair> out;
  for (const Pair& p : Pairs)
  {
    NearFieldPair q;
    q.strandA = p.a.strand;
    q.strandB = p.b.strand;
    const std::vector<StrandSample>&qa = Samples[p.a.strand], &qb = Samples[p.b.strand];
    q.sA = (1 - p.a.u) * qa[p.a.piece].s + p.a.u * qa[p.a.piece + 1].s;
    q.sB = (1 - p.b.u) * qb[p.b.piece].s + p.b.u * qb[p.b.piece + 1].s;
    q.side = p.side;
    q.gap = p.gap;
    q.active = p.active;
    q.flipped = p.flipped;
    q.trusted = p.trusted;
    q.force = p.active ? p.lambda : 0;
    out.push_back(q);
  }
  return out;
}

} // namespace hair

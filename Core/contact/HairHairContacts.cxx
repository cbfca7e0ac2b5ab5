#include "contact/HairHairContacts.h"

#include "common/Parallel.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <sstream>

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

double clamp01(double x)
{
  return x < 0 ? 0 : (x > 1 ? 1 : x);
}
} // namespace

Status HairHairParameters::validate() const
{
  if (!std::isfinite(thickness) || thickness <= 0)
    return Status::Error("HairHairParameters: thickness = " + number(thickness) +
                         " m is invalid; give the radius of the clump a guide stands for, finite "
                         "and > 0 (default 2.5e-3 m).");
  if (thickness > 0.1)
    return Status::Error("HairHairParameters: thickness = " + number(thickness) +
                         " m is more than 0.1 m; a clump radius is millimetres (default "
                         "2.5e-3 m). Check the units.");
  if (!std::isfinite(stiffness) || stiffness <= 0)
    return Status::Error("HairHairParameters: stiffness = " + number(stiffness) +
                         " N/m is invalid; the penalty must be finite and > 0 (default 0.1 N/m).");
  if (Status s = checkNonNegative("damping", damping, "N·s/m", "(default 2e-4 N·s/m)"); !s)
    return s;
  if (Status s = checkNonNegative("friction", friction, "N·s/m", "(default 1e-5 N·s/m)"); !s)
    return s;
  if (!std::isfinite(maxForce) || maxForce <= 0)
    return Status::Error("HairHairParameters: maxForce = " + number(maxForce) +
                         " N is invalid; the cap of a contact's normal force must be finite and "
                         "> 0 (default 1e-4 N).");
  if (Status s = checkNonNegative("margin", margin, "m",
                                  "0 disables temporal coherence (default 2.5e-3 m).");
      !s)
    return s;
  if (Status s = checkNonNegative("cellSize", cellSize, "m", "0 chooses it automatically."); !s)
    return s;
  if (!(allowedDepth > 0 && allowedDepth < 1))
    return Status::Error("HairHairParameters: allowedDepth = " + number(allowedDepth) +
                         " is invalid; give the fraction of the contact distance a pair may "
                         "reach within a step, in (0, 1) (default 0.3).");
  if (threads < 1 || threads > 256)
    return Status::Error("HairHairParameters: threads = " + std::to_string(threads) +
                         " is invalid; give 1 to 256 threads for the narrow phase (default 1).");
  if (!std::isfinite(referenceLength) || referenceLength <= 0)
    return Status::Error("HairHairParameters: referenceLength = " + number(referenceLength) +
                         " m is invalid; give the length of contact that gets the per-point "
                         "force, finite and > 0 (default 0.01 m).");
  if (margin > 1)
    return Status::Error("HairHairParameters: margin = " + number(margin) +
                         " m is more than 1 m; it is a distance of the order of the thickness "
                         "(default 2.5e-3 m). Check the units.");
  return Status::Ok();
}

Status HairHairContacts::setParameters(const HairHairParameters& parameters)
{
  Status st = parameters.validate();
  if (!st)
    return st;
  Params = parameters;
  HaveBuild = false;
  ContactKeys.clear();
  return Status::Ok();
}

Status HairHairContacts::update(const std::vector<std::vector<StrandSample>>& samples,
                                const std::vector<int>& ids)
{
  if (Status st = Params.validate(); !st)
    return st;
  const int n = static_cast<int>(samples.size());
  if (!ids.empty() && ids.size() != samples.size())
    return Status::Error("HairHairContacts::update: " + std::to_string(ids.size()) + " ids for " +
                         std::to_string(samples.size()) +
                         " strands; give one id per strand (or none).");
  std::unordered_map<int, int> index;
  for (int i = 0; i < n; ++i)
  {
    const int id = ids.empty() ? i : ids[i];
    if (!index.emplace(id, i).second)
      return Status::Error("HairHairContacts::update: strands " + std::to_string(index[id]) +
                           " and " + std::to_string(i) + " have the same id " + std::to_string(id) +
                           "; give every strand its own StrandSpec::id.");
    const std::vector<StrandSample>& s = samples[i];
    for (size_t k = 0; k < s.size(); ++k)
    {
      if (!s[k].position.allFinite() || !s[k].velocity.allFinite() || !std::isfinite(s[k].s) ||
          !(s[k].weight > 0))
        return Status::Error("HairHairContacts::update: strand id " + std::to_string(id) +
                             ", sample " + std::to_string(k) +
                             " has a non-finite position, velocity or arc length, or a weight "
                             "<= 0; the strand's state is broken.");
      if (k > 0 && !(s[k].s > s[k - 1].s))
        return Status::Error("HairHairContacts::update: strand id " + std::to_string(id) +
                             ", sample " + std::to_string(k) +
                             ": arc lengths must increase along the strand.");
    }
  }
  const bool layoutSame = HaveBuild && static_cast<int>(Samples.size()) == n &&
                          [&]()
  {
    for (int i = 0; i < n; ++i)
    {
      if (Samples[i].size() != samples[i].size())
        return false;
      for (size_t k = 0; k < samples[i].size(); ++k)
        if (Samples[i][k].s != samples[i][k].s)
          return false;
    }
    return true;
  }();
  Samples = samples;
  Ids.resize(n);
  for (int i = 0; i < n; ++i)
    Ids[i] = ids.empty() ? i : ids[i];
  IndexOfId = std::move(index);

  Stats = HairHairStats{};
  Stats.strands = n;
  buildPieces();
  if (!(layoutSame && canReuse()))
  {
    broadPhase();
    BuildPositions.assign(n, {});
    for (int i = 0; i < n; ++i)
      for (const StrandSample& s : Samples[i])
        BuildPositions[i].push_back(s.position);
    HaveBuild = Params.margin > 0;
    Stats.rebuilt = true;
  }
  Stats.candidatePairs = static_cast<long>(Candidates.size());
  narrowPhase();
  return Status::Ok();
}

void HairHairContacts::buildPieces()
{
  const int n = static_cast<int>(Samples.size());
  PieceStart.assign(n + 1, 0);
  Pieces.clear();
  // Boxes grown by thickness + margin / 2: two boxes are apart only if the pieces are
  // farther than 2 × thickness + margin.
  const double grow = Params.thickness + 0.5 * Params.margin;
  for (int i = 0; i < n; ++i)
  {
    PieceStart[i] = static_cast<int>(Pieces.size());
    const std::vector<StrandSample>& s = Samples[i];
    for (int k = 0; k + 1 < static_cast<int>(s.size()); ++k)
    {
      Piece p;
      p.strand = i;
      p.index = k;
      p.lo = s[k].position.cwiseMin(s[k + 1].position).array() - grow;
      p.hi = s[k].position.cwiseMax(s[k + 1].position).array() + grow;
      Pieces.push_back(p);
    }
  }
  PieceStart[n] = static_cast<int>(Pieces.size());
  Stats.pieces = static_cast<long>(Pieces.size());
}

bool HairHairContacts::canReuse() const
{
  // Pairs left out had pieces farther than 2 × thickness + margin apart. A point of a piece
  // moves no more than the farther of its two samples, so while every sample has moved less
  // than margin / 2 since then, none of them can have come within 2 × thickness.
  if (!HaveBuild || !(Params.margin > 0) || BuildPositions.size() != Samples.size())
    return false;
  const double limit2 = 0.25 * Params.margin * Params.margin;
  for (size_t i = 0; i < Samples.size(); ++i)
  {
    if (BuildPositions[i].size() != Samples[i].size())
      return false;
    for (size_t k = 0; k < Samples[i].size(); ++k)
      if ((Samples[i][k].position - BuildPositions[i][k]).squaredNorm() >= limit2)
        return false;
  }
  return true;
}

void HairHairContacts::broadPhase()
{
  Candidates.clear();
  const int np = static_cast<int>(Pieces.size());
  if (np == 0)
    return;
  // Uniform grid, hashed. Automatic cells: per axis, twice the median extent of the boxes
  // along it (about 3.4 cells per box; the median itself gave 8 and more cache misses in the
  // counting sort: 158 against 104 ms for 5000 guides). Hanging hair has long thin boxes (a
  // piece is longer than the strands are apart), and cubic cells as large as the pieces held
  // many strands each, which made the pair loop grow with density (measured: 30 ms for 1000
  // guides, 257 ms for 5000, no pair found). A box
  // longer than its cell spans a few more cells; if that ever gives more than 27 entries per
  // piece on average, the cells are doubled. A requested cellSize is isotropic, honoured down
  // to a quarter of the largest box (at most 5³ cells per box).
  Eigen::Vector3d origin = Pieces[0].lo;
  double largest = 0;
  for (const Piece& p : Pieces)
  {
    origin = origin.cwiseMin(p.lo);
    largest = std::max(largest, (p.hi - p.lo).maxCoeff());
  }
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
  const Eigen::Array3d inv = cell.inverse();
  auto cellOf = [&](const Eigen::Vector3d& x)
  { return ((x - origin).array() * inv).floor().cast<int>().eval(); };
  Entries.clear();
  for (int k = 0; k < np; ++k)
  {
    const Piece& p = Pieces[k];
    const Eigen::Array3i lo = cellOf(p.lo);
    const Eigen::Array3i hi = cellOf(p.hi);
    for (int x = lo.x(); x <= hi.x(); ++x)
      for (int y = lo.y(); y <= hi.y(); ++y)
        for (int z = lo.z(); z <= hi.z(); ++z)
          Entries.push_back({k, p.strand, x, y, z});
  }
  // Counting sort of the entries by hashed cell: O(entries).
  std::uint32_t buckets = 1;
  while (2 * buckets < Entries.size())
    buckets <<= 1;
  const std::uint32_t mask = buckets - 1;
  auto hash = [mask](const Entry& e)
  {
    return (static_cast<std::uint32_t>(e.ix) * 73856093u ^
            static_cast<std::uint32_t>(e.iy) * 19349663u ^
            static_cast<std::uint32_t>(e.iz) * 83492791u) &
           mask;
  };
  BucketStart.assign(buckets + 1, 0);
  CellKey.resize(Entries.size());
  for (size_t e = 0; e < Entries.size(); ++e)
  {
    CellKey[e] = hash(Entries[e]);
    ++BucketStart[CellKey[e] + 1];
  }
  for (std::uint32_t b = 0; b < buckets; ++b)
    BucketStart[b + 1] += BucketStart[b];
  Sorted.resize(Entries.size());
  {
    std::vector<std::uint32_t> fill(BucketStart.begin(), BucketStart.end() - 1);
    for (size_t e = 0; e < Entries.size(); ++e)
      Sorted[fill[CellKey[e]]++] = Entries[e];
  }
  // Pairs in each cell; a pair whose boxes share several cells is kept only in the cell
  // holding the low corner of the boxes' intersection.
  for (std::uint32_t b = 0; b < buckets; ++b)
  {
    const std::uint32_t first = BucketStart[b], last = BucketStart[b + 1];
    for (std::uint32_t i = first; i + 1 < last; ++i)
    {
      const Entry& ei = Sorted[i];
      const Piece& pi = Pieces[ei.piece];
      for (std::uint32_t j = i + 1; j < last; ++j)
      {
        const Entry& ej = Sorted[j];
        if (ei.strand == ej.strand || ei.ix != ej.ix || ei.iy != ej.iy || ei.iz != ej.iz)
          continue; // the same strand, or another cell with the same hash
        const Piece& pj = Pieces[ej.piece];
        if ((pi.lo.array() > pj.hi.array()).any() || (pj.lo.array() > pi.hi.array()).any())
          continue;
        const Eigen::Array3i corner = cellOf(pi.lo.cwiseMax(pj.lo));
        if (corner.x() != ei.ix || corner.y() != ei.iy || corner.z() != ei.iz)
          continue;
        Candidates.emplace_back(std::min(ei.piece, ej.piece), std::max(ei.piece, ej.piece));
      }
    }
  }
}

void HairHairContacts::narrowPhase()
{
  const int n = static_cast<int>(Samples.size());
  const double R = 2 * Params.thickness;
  const double k = Params.stiffness, cn = Params.damping, ct = Params.friction;
  // The share of a contact whose closest point is an interior vertex V of a strand (shared
  // by two pieces): 0 when the other point lies beyond V towards the neighbouring piece
  // (that piece holds the true closest point), ½ otherwise (both pieces report V).
  auto share =
      [](const std::vector<StrandSample>& s, int piece, double u, const Eigen::Vector3d& other)
  {
    const int last = static_cast<int>(s.size()) - 2;
    int vertex = -1, neighbour = -1;
    if (u <= 0 && piece > 0)
    {
      vertex = piece;
      neighbour = piece - 1;
    }
    else if (u >= 1 && piece < last)
    {
      vertex = piece + 1;
      neighbour = piece + 2;
    }
    if (vertex < 0)
      return 1.0;
    const Eigen::Vector3d t = s[neighbour].position - s[vertex].position;
    const Eigen::Vector3d w = other - s[vertex].position;
    return w.dot(t) > 1e-9 * t.norm() * w.norm() ? 0.0 : 0.5;
  };
  // What one thread finds in a range of candidates; merged in range order, so the result
  // does not depend on the number of threads.
  struct Found
  {
    std::vector<HairHairContact> contacts;
    std::vector<Side> sideA, sideB;
    std::vector<double> arrival; // ½ k w δ² per contact
    std::vector<std::pair<std::int64_t, std::int64_t>> keys;
    double potential = 0, dissipation = 0, deepest = 0, rate = 0;
  };
  auto process = [&](size_t first, size_t last, Found& out)
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
      const Eigen::Vector3d xa = a0.position + u * (a1.position - a0.position);
      if (d2 >= R * R)
      {
        // Not in contact: how fast it closes on the contact distance, against its gap plus
        // the allowed depth (the rate of updates it asks for; see updatesPerStep).
        const Eigen::Vector3d xb = b0.position + v * (b1.position - b0.position);
        const Eigen::Vector3d va = a0.velocity + u * (a1.velocity - a0.velocity);
        const Eigen::Vector3d vb = b0.velocity + v * (b1.velocity - b0.velocity);
        const double d = std::sqrt(d2);
        const double closing = -(va - vb).dot(xa - xb) / d;
        if (closing > 0)
          out.rate = std::max(out.rate, closing / (d - R + Params.allowedDepth * R));
        continue;
      }
      const Eigen::Vector3d xb = b0.position + v * (b1.position - b0.position);
      // Per point: the vertex shares. Per length: the length in contact, which already
      // counts a piece's own part only (no vertex is counted twice).
      const double w =
          Params.perLength
              ? 0.5 *
                    (lengthInCylinder(a0.position, a1.position, b0.position, b1.position, R) +
                     lengthInCylinder(b0.position, b1.position, a0.position, a1.position, R)) /
                    Params.referenceLength
              : share(sa, pa.index, u, xb) * share(sb, pb.index, v, xa);
      if (w == 0)
        continue;
      const Eigen::Vector3d va = a0.velocity + u * (a1.velocity - a0.velocity);
      const Eigen::Vector3d vb = b0.velocity + v * (b1.velocity - b0.velocity);
      const double sA = a0.s + u * (a1.s - a0.s), sB = b0.s + v * (b1.s - b0.s);
      out.sideA.push_back({sA, xa - xb, va - vb, xa, va, w});
      out.sideB.push_back({sB, xb - xa, vb - va, xb, vb, w});
      // The force at the update's configuration (what addResponses gives with these samples).
      const double d = std::sqrt(d2);
      Eigen::Vector3d nrm = xa - xb;
      if (d > 0)
        nrm /= d;
      else
      {
        nrm = (a1.position - a0.position).cross(b1.position - b0.position);
        if (nrm.norm() == 0)
          nrm = (a1.position - a0.position).unitOrthogonal();
        nrm.normalize();
      }
      const double delta = R - d;
      const Eigen::Vector3d vrel = va - vb;
      const double vn = vrel.dot(nrm);
      const double lambda = std::min(k * delta - cn * vn, Params.maxForce);
      Eigen::Vector3d force = Eigen::Vector3d::Zero();
      if (lambda > 0)
      {
        const Eigen::Vector3d vt = vrel - vn * nrm;
        force = w * (lambda * nrm - ct * vt);
        out.dissipation += w * (cn * vn * vn + ct * vt.squaredNorm());
      }
      out.potential += w * 0.5 * k * delta * delta;
      out.arrival.push_back(w * 0.5 * k * delta * delta);
      out.keys.emplace_back(pieceKey(pa.strand, pa.index), pieceKey(pb.strand, pb.index));
      out.deepest = std::max(out.deepest, delta);
      if (-vn > 0) // still closing: what is left of the allowed depth (5 % if past it)
        out.rate = std::max(out.rate, -vn / std::max(Params.allowedDepth * R - delta, 0.05 * R));
      HairHairContact hc;
      hc.strandA = pa.strand;
      hc.strandB = pb.strand;
      hc.sA = sA;
      hc.sB = sB;
      hc.pointA = xa;
      hc.pointB = xb;
      hc.distance = d;
      hc.forceOnA = force;
      out.contacts.push_back(hc);
    }
  };
  // Blocks of 4096 candidates on the narrow phase's threads, merged in block order: the
  // blocks depend on the number of candidates only, so the result does not depend on the
  // number of threads.
  const std::int64_t count = static_cast<std::int64_t>(Candidates.size()), grain = 4096;
  std::vector<Found> found(
      static_cast<size_t>(std::max<std::int64_t>(1, blockCount(count, grain))));
  parallelBlocks(
      count, grain, Params.threads,
      [&](std::int64_t first, std::int64_t last)
      { process(static_cast<size_t>(first), static_cast<size_t>(last), found[first / grain]); });
  Sides.assign(n, {});
  Contacts.clear();
  std::swap(PreviousKeys, ContactKeys);
  ContactKeys.clear();
  for (const Found& f : found)
  {
    for (size_t c = 0; c < f.contacts.size(); ++c)
    {
      const HairHairContact& hc = f.contacts[c];
      Sides[hc.strandA].push_back(f.sideA[c]);
      Sides[hc.strandB].push_back(f.sideB[c]);
      ContactKeys.push_back(f.keys[c]);
      if (!std::binary_search(PreviousKeys.begin(), PreviousKeys.end(), f.keys[c]))
        Stats.arrivalEnergy += f.arrival[c];
      Contacts.push_back(hc);
    }
    Stats.potentialEnergy += f.potential;
    Stats.dissipationRate += f.dissipation;
    Stats.maxPenetration = std::max(Stats.maxPenetration, f.deepest);
    Stats.closingRate = std::max(Stats.closingRate, f.rate);
  }
  Stats.contacts = static_cast<long>(Contacts.size());
  std::sort(ContactKeys.begin(), ContactKeys.end());
}

void HairHairContacts::addResponses(int strandId, const std::vector<StrandSample>& samples,
                                    std::vector<ContactResponse>& response) const
{
  const auto it = IndexOfId.find(strandId);
  if (it == IndexOfId.end() || samples.size() < 2 || response.size() != samples.size())
    return;
  const std::vector<Side>& sides = Sides[it->second];
  const double R = 2 * Params.thickness;
  const double k = Params.stiffness, cn = Params.damping, ct = Params.friction;
  const int last = static_cast<int>(samples.size()) - 2;
  for (const Side& side : sides)
  {
    // The material point s on the strand's current samples (the layout may differ from the
    // update's when the step is split into sub-steps).
    auto pos = std::upper_bound(samples.begin(), samples.end(), side.s,
                                [](double s, const StrandSample& x) { return s < x.s; });
    const int j = std::clamp(static_cast<int>(pos - samples.begin()) - 1, 0, last);
    const StrandSample &s0 = samples[j], &s1 = samples[j + 1];
    const double u = clamp01((side.s - s0.s) / (s1.s - s0.s));
    const Eigen::Vector3d x = s0.position + u * (s1.position - s0.position);
    const Eigen::Vector3d v = s0.velocity + u * (s1.velocity - s0.velocity);
    // The partner is stepped at the same time against this strand, which does not see it
    // move. Held fixed, each strand would remove the whole penetration in a stiff step and
    // the pair would overshoot by as much (a period-2 chatter, measured). Each strand assumes
    // instead that its partner moves equally and oppositely from the update on: the relative
    // position is gap + 2 (x − x₀), the relative velocity w₀ + 2 (v − v₀). That is the exact
    // implicit step of a pair of equal masses; against a heavier partner it under-relaxes
    // (never overshoots), against a lighter one it over-relaxes by less than 2. At the update
    // configuration (one sub-step) it is the pair force itself, equal and opposite.
    Eigen::Vector3d nrm = side.gap + 2 * (x - side.ownPoint);
    const double d = nrm.norm();
    if (!(d < R))
      continue;
    if (d > 0)
      nrm /= d;
    else
      nrm = (s1.position - s0.position).unitOrthogonal();
    const Eigen::Vector3d vrel = side.relativeVelocity + 2 * (v - side.ownVelocity);
    const double vn = vrel.dot(nrm);
    double lambda = k * (R - d) - cn * vn;
    if (!(lambda > 0))
      continue;
    // Capped at maxForce. The stiffness and damping stay those of the uncapped penalty: the
    // step then pushes a deep overlap apart with at most maxForce and still damps it
    // implicitly (measured: dropping them when capped made the capped contacts explicit,
    // and the pair and the clump gained energy and flew apart).
    lambda = std::min(lambda, Params.maxForce);
    const Eigen::Matrix3d nn = nrm * nrm.transpose();
    const Eigen::Vector3d force = side.share * (lambda * nrm - ct * (vrel - vn * nrm));
    // −∂F/∂x and −∂F/∂v of that model (the factor 2 of the relative coordinate). Only the
    // normal part of the stiffness is kept: the transverse geometric term −(kδ/d)(I − n nᵀ)
    // is indefinite.
    const Eigen::Matrix3d K = (2 * side.share * k) * nn;
    const Eigen::Matrix3d D =
        (2 * side.share) * (cn * nn + ct * (Eigen::Matrix3d::Identity() - nn));
    // The point force F at x = (1 − u) x_j + u x_{j+1} goes to the two samples in those
    // proportions, per unit length (÷ weight); the Jacobians are lumped by rows (each
    // sample's block is its share of ∂F/∂x, exact when the two samples move together).
    const double share[2] = {1 - u, u};
    for (int e = 0; e < 2; ++e)
    {
      if (share[e] == 0)
        continue;
      const double f = share[e] / samples[j + e].weight;
      ContactResponse& r = response[j + e];
      r.force += f * force;
      r.stiffness += f * K;
      r.damping += f * D;
    }
  }
}

int HairHairContacts::updatesPerStep(double dt, int maxUpdates) const
{
  if (!(dt > 0) || maxUpdates < 1)
    return 1;
  const double n = std::ceil(dt * Stats.closingRate);
  return n < 1 ? 1 : (n > maxUpdates ? maxUpdates : static_cast<int>(n));
}

ContactForces HairHairContacts::hook() const
{
  return [this](int id, double, const std::vector<StrandSample>& samples,
                std::vector<ContactResponse>& response) { addResponses(id, samples, response); };
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

#include "contact/HairGrid.h"

#include "common/Parallel.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

namespace hair
{

Status HairGridParameters::validate() const
{
  auto bad = [](const char* name, double value, const char* what)
  {
    std::ostringstream s;
    s << "hair grid: " << name << " = " << value << " " << what;
    return Status::Error(s.str());
  };
  if (!(volumeFraction > 0 && volumeFraction <= 0.9))
    return bad("the rest volume fraction", volumeFraction,
               "is not in (0, 0.9]: give the share of space the fibres fill where hair rests, "
               "e.g. 0.05.");
  if (!(volume >= 0 && volume <= 1))
    return bad("the volume", volume,
               "is not in [0, 1]: give the share of the packing above the rest fraction undone "
               "in a step, 1 to keep the hair at its rest fraction, 0 for no volume.");
  if (iterations < 1 || iterations > 1000)
    return bad("the pressure iterations", iterations, "are not in [1, 1000]: e.g. 30.");
  if (!(std::isfinite(friction) && friction >= 0))
    return bad("the friction", friction,
               "1/s is not a rate >= 0: give how fast a strand's velocity relative to the hair "
               "around it decays, e.g. 10 per second, or 0 for none.");
  if (!(std::isfinite(cellSize) && cellSize >= 0 && cellSize <= 1))
    return bad("the cell size", cellSize, "m is not in [0, 1]: give 0 for automatic.");
  return Status::Ok();
}

Status HairGrid::setParameters(const HairGridParameters& parameters)
{
  if (Status s = parameters.validate(); !s)
    return s;
  Params = parameters;
  return Status::Ok();
}

void HairGrid::begin(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double automaticCell,
                     double h)
{
  Step = h > 0 ? h : Step;
  const auto start = std::chrono::steady_clock::now();
  const Eigen::Vector3d extent = (hi - lo).cwiseMax(0.0);
  double cell = Params.cellSize > 0 ? Params.cellSize : automaticCell;
  // At most MaxCellsPerAxis nodes along an axis, one cell of margin below the box and two
  // above it: a node holding hair (its trilinear corners) is never on the grid's border, so
  // its six neighbours are in the grid.
  cell = std::max({cell, extent.maxCoeff() / (HairGridParameters::MaxCellsPerAxis - 4), 1e-6});
  Cell = cell;
  Origin = lo - Eigen::Vector3d::Constant(cell);
  for (int a = 0; a < 3; ++a)
    Dims[a] = static_cast<int>(std::ceil(extent[a] / cell)) + 4;
  const std::size_t total = static_cast<std::size_t>(Dims.cast<std::int64_t>().prod());
  if (Nodes.size() < total)
  {
    Nodes.assign(total, Node()); // stamps 0: stale for any step
    Stamp = 0;
  }
  // A new stamp marks every node stale at once (no clearing pass); on wrap-around, clear.
  if (++Stamp == 0)
  {
    for (Node& n : Nodes)
      n.stamp = 0;
    Stamp = 1;
  }
  Touched.clear();
  Stats = HairGridStats();
  Stats.cellSize = Cell;
  Stats.nodes = Dims.matrix();
  Stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

namespace
{
// x (already in quanta, finite and far inside int64) to the nearest integer, halves away
// from zero: the same on every machine and thread.
inline std::int64_t nearest(double x)
{
  return static_cast<std::int64_t>(x >= 0 ? x + 0.5 : x - 0.5);
}
} // namespace

HairGrid::Node& HairGrid::touch(std::int64_t n, std::vector<std::int64_t>& touched)
{
  Node& nd = Nodes[n];
  if (nd.stamp != Stamp)
  {
    nd.stamp = Stamp;
    nd.q[0] = nd.q[1] = nd.q[2] = nd.q[3] = 0;
    nd.pressure = 0;
    touched.push_back(n);
  }
  return nd;
}

bool HairGrid::locate(const Eigen::Vector3d& x, Eigen::Array3i& base, Eigen::Array3d& f) const
{
  const Eigen::Array3d g = (x - Origin).array() / Cell;
  // In the grid (floor(g) + 1 < Dims), checked before the cast: a point far outside or not
  // finite would not fit an int.
  if (!g.allFinite() || (g < 0).any() || (g >= (Dims - 1).cast<double>()).any())
    return false;
  const Eigen::Array3d fl = g.floor();
  base = fl.cast<int>();
  f = g - fl;
  return true;
}

void HairGrid::add(const std::vector<Strand>& strands, int threads)
{
  const auto start = std::chrono::steady_clock::now();
  // Per strand: the fibres' cross-section per unit length of its polyline [m²].
  std::vector<double> perLength(strands.size(), 0.0);
  for (std::size_t k = 0; k < strands.size(); ++k)
  {
    const Strand& st = strands[k];
    if (st.count < 2 || !(st.area > 0))
      continue;
    double chords = 0;
    for (int j = 0; j + 1 < st.count; ++j)
      chords += (st.x[j + 1] - st.x[j]).norm();
    if (chords > 0 && std::isfinite(chords))
      perLength[k] = st.area * (st.length > 0 ? st.length / chords : 1.0);
  }
  const double inv = 1.0 / (Cell * Cell * Cell);
  const int slabs = std::max(1, std::min(threads, static_cast<int>(Dims[2])));
  std::vector<std::vector<std::int64_t>> touched(slabs);
  parallelBlocks(slabs, 1, slabs,
                 [&](std::int64_t b0, std::int64_t b1)
                 {
                   for (std::int64_t b = b0; b < b1; ++b)
                   {
                     const int k0 = static_cast<int>(Dims[2] * b / slabs);
                     const int k1 = static_cast<int>(Dims[2] * (b + 1) / slabs);
                     for (std::size_t k = 0; k < strands.size(); ++k)
                       if (perLength[k] > 0)
                         splat(strands[k], perLength[k] * inv, k0, k1, touched[b]);
                   }
                 });
  for (const std::vector<std::int64_t>& t : touched)
    Touched.insert(Touched.end(), t.begin(), t.end());
  Stats.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void HairGrid::splat(const Strand& st, double perLength, int k0, int k1,
                     std::vector<std::int64_t>& touched)
{
  for (int j = 0; j + 1 < st.count; ++j)
  {
    const Eigen::Vector3d& a = st.x[j];
    const Eigen::Vector3d& e = st.x[j + 1];
    // The layers the segment's splat can reach: skip it when none is this slab's.
    const double z0 = (std::min(a.z(), e.z()) - Origin.z()) / Cell;
    const double z1 = (std::max(a.z(), e.z()) - Origin.z()) / Cell;
    if (!(z1 + 1 >= k0 && z0 < k1))
      continue;
    const Eigen::Vector3d d = e - a;
    const double len = d.norm();
    const int pieces = std::max(1, static_cast<int>(std::ceil(len / Cell)));
    // In the nodes' fixed point: a volume fraction × cell³ / cell³, in quanta.
    const double volume = perLength * len / pieces / Quantum;
    for (int m = 0; m < pieces; ++m)
    {
      const double t = (m + 0.5) / pieces;
      const Eigen::Vector3d p = a + t * d;
      Eigen::Array3i b;
      Eigen::Array3d f;
      if (!locate(p, b, f) || b[2] + 1 < k0 || b[2] >= k1)
        continue;
      Eigen::Vector3d u = (1 - t) * st.v[j] + t * st.v[j + 1];
      // φ v in quanta stays far inside int64 (|v| ≤ 1e4 m/s; a faster sample is a blown-up
      // strand, which its step refuses).
      if (!(u.allFinite() && u.cwiseAbs().maxCoeff() <= 1e4))
        u = u.allFinite() ? Eigen::Vector3d(u.cwiseMax(-1e4).cwiseMin(1e4))
                          : Eigen::Vector3d::Zero();
      const double wx[2] = {1 - f[0], f[0]}, wy[2] = {1 - f[1], f[1]}, wz[2] = {1 - f[2], f[2]};
      const bool whole = b[2] >= k0 && b[2] + 1 < k1; // both layers this slab's
      for (int c = 0; c < 8; ++c)
      {
        const int di = c & 1, dj = (c >> 1) & 1, dk = (c >> 2) & 1;
        if (!whole && (b[2] + dk < k0 || b[2] + dk >= k1))
          continue;
        const double share = wx[di] * wy[dj] * wz[dk] * volume;
        Node& nd = touch(index(b[0] + di, b[1] + dj, b[2] + dk), touched);
        nd.q[0] += nearest(share);
        nd.q[1] += nearest(share * u[0]);
        nd.q[2] += nearest(share * u[1]);
        nd.q[3] += nearest(share * u[2]);
      }
    }
  }
}

void HairGrid::finish(const Ranks& ranks, int threads)
{
  const auto start = std::chrono::steady_clock::now();
  if (ranks.parallel())
  {
    // The nodes each rank touched as rows (index, then the node's four sums), gathered on
    // every rank and added: integers, so in any order the same on every rank.
    std::vector<std::int64_t> rows;
    rows.reserve(5 * Touched.size());
    for (std::int64_t n : Touched)
    {
      rows.push_back(n);
      rows.insert(rows.end(), Nodes[n].q, Nodes[n].q + 4);
    }
    const std::vector<std::int64_t> all = ranks.gather(rows);
    for (std::int64_t n : Touched)
      Nodes[n].q[0] = Nodes[n].q[1] = Nodes[n].q[2] = Nodes[n].q[3] = 0;
    const std::int64_t total = Dims.cast<std::int64_t>().prod();
    for (std::size_t r = 0; r + 4 < all.size(); r += 5)
    {
      const std::int64_t n = all[r];
      if (n < 0 || n >= total)
        continue; // not this grid's: a rank with another box (never, by begin()'s contract)
      Node& nd = touch(n, Touched);
      for (int c = 0; c < 4; ++c)
        nd.q[c] += all[r + 1 + c];
    }
  }
  Stats.touched = static_cast<long>(Touched.size());
  std::int64_t volume = 0;
  for (std::int64_t n : Touched)
  {
    const double phi = Nodes[n].phi();
    Stats.maxFraction = std::max(Stats.maxFraction, phi);
    Stats.compressed += phi > Params.volumeFraction ? 1 : 0;
    volume += Nodes[n].q[0];
  }
  Stats.volume = Quantum * static_cast<double>(volume) * Cell * Cell * Cell;
  const auto solve = std::chrono::steady_clock::now();
  solveVolume(threads);
  Stats.solveSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - solve).count();
  Stats.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void HairGrid::solveVolume(int threads)
{
  if (!(Params.volume > 0) || Touched.empty())
    return;
  // The touched nodes in compact arrays (their order in Touched): each one's six
  // neighbours (−1: outside the hair, where Q = 0) and its colour for the red–black sweeps.
  const std::int64_t stride[3] = {1, Dims[0], static_cast<std::int64_t>(Dims[0]) * Dims[1]};
  const std::size_t n = Touched.size();
  for (std::size_t t = 0; t < n; ++t)
    Nodes[Touched[t]].slot = static_cast<std::int32_t>(t);
  Around.resize(6 * n);
  Excess.resize(n);
  Potential.assign(n, 0.0);
  Colour[0].clear();
  Colour[1].clear();
  for (std::size_t t = 0; t < n; ++t)
  {
    const std::int64_t m = Touched[t];
    const Node& nd = Nodes[m];
    const std::int64_t i = m % Dims[0], j = (m / Dims[0]) % Dims[1], k = m / stride[2];
    const std::int64_t at[3] = {i, j, k};
    // The packing above φ0 the step would reach without the pressure: φ* − φ0 with
    // φ* = φ − h ∇·(φ ū) (central differences of the momentum density), times `volume`.
    double divergence = 0;
    for (int a = 0; a < 3; ++a)
    {
      const Node* up = at[a] + 1 < Dims[a] ? node(m + stride[a]) : nullptr;
      const Node* down = at[a] > 0 ? node(m - stride[a]) : nullptr;
      Around[6 * t + 2 * a] = up ? up->slot : -1;
      Around[6 * t + 2 * a + 1] = down ? down->slot : -1;
      const double hi = up ? Quantum * static_cast<double>(up->q[1 + a]) : 0.0;
      const double lo = down ? Quantum * static_cast<double>(down->q[1 + a]) : 0.0;
      divergence += (hi - lo) / (2 * Cell);
    }
    Excess[t] = Params.volume * (nd.phi() - Step * divergence - Params.volumeFraction);
    Colour[(i + j + k) & 1].push_back(static_cast<std::int32_t>(t));
  }
  // −∇²Q ≥ φ* − φ0, Q ≥ 0, complementary: projected red–black Gauss–Seidel, each node set
  // from its neighbours, Q = max(0, (cell² (φ* − φ0) + Σ Q_neighbour) / 6). A colour's nodes
  // depend on the other colour's only: the same result on any number of threads.
  const double cell2 = Cell * Cell;
  // (A parallel region per colour and sweep pays only above some thousands of nodes.)
  const int workers = n > 20000 ? threads : 1;
  auto sweep = [&](const std::vector<std::int32_t>& nodes)
  {
    parallelBlocks(static_cast<std::int64_t>(nodes.size()), 4096, workers,
                   [&](std::int64_t b0, std::int64_t b1)
                   {
                     for (std::int64_t p = b0; p < b1; ++p)
                     {
                       const std::int32_t t = nodes[p];
                       const std::int32_t* nb = &Around[6 * static_cast<std::size_t>(t)];
                       double around = 0;
                       for (int d = 0; d < 6; ++d)
                         around += nb[d] >= 0 ? Potential[nb[d]] : 0.0;
                       Potential[t] = std::max(0.0, (cell2 * Excess[t] + around) / 6);
                     }
                   });
  };
  for (int iteration = 0; iteration < Params.iterations; ++iteration)
  {
    sweep(Colour[0]);
    sweep(Colour[1]);
  }
  for (std::size_t t = 0; t < n; ++t)
  {
    double around = 0;
    for (int d = 0; d < 6; ++d)
      around += Around[6 * t + d] >= 0 ? Potential[Around[6 * t + d]] : 0.0;
    Nodes[Touched[t]].pressure = Potential[t];
    const double left = Excess[t] - (6 * Potential[t] - around) / cell2;
    Stats.pressed += Potential[t] > 0 ? 1 : 0;
    Stats.residual = std::max(Stats.residual, left);
  }
}

double HairGrid::fraction(const Eigen::Vector3d& x, Eigen::Vector3d* velocity) const
{
  Eigen::Array3i b;
  Eigen::Array3d f;
  double phi = 0;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  if (locate(x, b, f))
    for (int c = 0; c < 8; ++c)
    {
      const int di = c & 1, dj = (c >> 1) & 1, dk = (c >> 2) & 1;
      const Node* nd = node(index(b[0] + di, b[1] + dj, b[2] + dk));
      if (!nd)
        continue;
      const double w = (di ? f[0] : 1 - f[0]) * (dj ? f[1] : 1 - f[1]) * (dk ? f[2] : 1 - f[2]);
      phi += w * nd->phi();
      p += w * nd->momentum();
    }
  if (velocity)
    *velocity = phi > 0 ? Eigen::Vector3d(p / phi) : Eigen::Vector3d::Zero();
  return phi;
}

void HairGrid::respond(const Eigen::Vector3d& x, double rhoS, double area,
                       ContactResponse& out) const
{
  // The most a strand adds to a node by itself: its cross-section over a cell's face (a
  // straight strand through the node, the trilinear weights summing to one along it).
  const double own = area / (Cell * Cell);
  Eigen::Array3i b;
  Eigen::Array3d f;
  if (!locate(x, b, f))
    return;
  double phi = 0;
  Eigen::Vector3d momentum = Eigen::Vector3d::Zero(), gradient = Eigen::Vector3d::Zero();
  for (int c = 0; c < 8; ++c)
  {
    const int di = c & 1, dj = (c >> 1) & 1, dk = (c >> 2) & 1;
    const Node* nd = node(index(b[0] + di, b[1] + dj, b[2] + dk));
    if (!nd)
      continue;
    const double wx = di ? f[0] : 1 - f[0], wy = dj ? f[1] : 1 - f[1], wz = dk ? f[2] : 1 - f[2];
    const double w = wx * wy * wz;
    phi += w * nd->phi();
    momentum += w * nd->momentum();
    if (nd->pressure > 0)
    {
      // ∂w/∂x of the trilinear weights (per cell; divided by the cell below).
      const double sx = di ? 1 : -1, sy = dj ? 1 : -1, sz = dk ? 1 : -1;
      gradient += nd->pressure * Eigen::Vector3d(sx * wy * wz, sy * wx * wz, sz * wx * wy);
    }
  }
  if (!(phi > 0))
    return;
  const double phi0 = Params.volumeFraction;
  // Friction: c (ū − v), c = ρS β (φ − φ_own)/φ0, ū = momentum / φ.
  const double c = rhoS * Params.friction * std::max(0.0, phi - own) / phi0;
  const double drag0 = out.drag;
  if (c > 0)
  {
    const Eigen::Vector3d medium = momentum / phi;
    const double total = out.drag + c;
    out.medium = (out.drag * out.medium + c * medium) / total;
    out.drag = total;
  }
  // Volume: −(a/φ) ∇P = −(ρS / (φ h²)) ∇Q per unit length (ρS = ρ a), the velocity the
  // continuum's pressure gives in a step; limited, where the solve is unconverged or the
  // hair thin, so that it alone moves a sample held by the drag at most a cell in a step:
  // h² |push| / (ρS + h c) ≤ cell.
  if (!gradient.isZero(0))
  {
    Eigen::Vector3d push = -(rhoS / (std::max(phi, phi0) * Step * Step)) * (gradient / Cell);
    const double limit = (rhoS + Step * (drag0 + c)) * Cell / (Step * Step);
    const double norm = push.norm();
    if (norm > limit)
      push *= limit / norm;
    out.push += push;
  }
}

void HairGrid::build(const std::vector<Strand>& strands, double h, const Ranks& ranks, int threads)
{
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  double clump = 0;
  for (const Strand& st : strands)
  {
    for (int j = 0; j < st.count; ++j)
    {
      lo = lo.cwiseMin(st.x[j]);
      hi = hi.cwiseMax(st.x[j]);
    }
    clump = std::max(clump, st.area);
  }
  ranks.min(lo.data(), 3);
  ranks.max(hi.data(), 3);
  clump = ranks.max(clump);
  begin(lo, hi, automaticCell(clump), h);
  add(strands, std::max(1, threads));
  finish(ranks, std::max(1, threads));
}

} // namespace hair

#pragma once
// The far field of hair–hair interaction: the hair as a continuum on a grid, for volume and
// friction at a cost linear in the strands (after Petrovic, Henne, Anderson 2005, "Volumetric
// methods for simulation and rendering of hair", and McAdams, Selle, Ward, Sifakis, Teran
// 2009, "Detail preserving continuum simulation of straight hair"; written here). Once per
// step every strand's polyline is splatted, segment by segment, to a grid fitted to the
// hair's bounds: the volume fraction φ of hair (the fibres a guide stands for × their
// cross-section) and its momentum density. Each sample of a strand then gets
//   friction: a drag towards the local mean velocity of the hair, c (ū − v) with
//             c = ρS β (φ − φ_own)/φ0, ū = (Σ φ_j v_j)/φ (implicit, so stable at any step),
//             φ_own = a_g / cell² the most a strand of cross-section a_g can add to a node by
//             itself: a strand alone feels none of it;
//   volume:   the hair may not pack above the rest fraction φ0: the pressure P ≥ 0 that
//             undoes, within the step, the packing above φ0 the step would reach (φ − h ∇·(φ ū),
//             continuity) is solved on the grid, implicitly, as a complementarity problem
//             (P > 0 only where the hair would be packed; after Narain, Golas, Lin 2010,
//             "Free-flowing granular materials with two-way solid coupling", who keep sand
//             below its packing density so), and each fibre is pushed down its gradient with
//             −(a/φ) ∇P per unit length (a the fibre's cross-section: the continuum's −∇P
//             shared among the fibres that fill φ of the space). Solved implicitly, it is
//             stable at any step, with no stiffness to choose.
// The equations, the parameters and their defaults: docs/hair-hair-interaction.md.
#include "common/Ranks.h"
#include "common/Status.h"
#include "contact/ContactResponse.h"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace hair
{

struct HairGridParameters
{
  /// φ0: the share of space the fibres fill where hair rests unpressed (dimensionless, in
  /// (0, 0.9]). Below it the grid only carries friction; above it the hair pushes back.
  double volumeFraction = 0.05;
  /// The share of the packing above φ0 the pressure undoes in a step (dimensionless, in
  /// [0, 1]): 1 keeps the hair at its rest fraction, 0 lets it pack (no volume).
  double volume = 1;
  /// Red–black Gauss–Seidel sweeps of the pressure solve per step.
  int iterations = 30;
  /// β [1/s]: how fast a strand's velocity relative to the hair around it decays where the
  /// hair is at its rest fraction (the drag grows with φ/φ0). 0: no friction.
  double friction = 10;
  /// Cell size [m]; 0: automatic (HairGrid::automaticCell, at least the hair's extent /
  /// MaxCellsPerAxis).
  double cellSize = 0;
  /// The grid has at most this many nodes along an axis: larger cells for a larger extent.
  static constexpr int MaxCellsPerAxis = 128;
  /// Names the first bad parameter, what is wrong and what to do.
  Status validate() const;
};

/// What the last step's grid held.
struct HairGridStats
{
  double cellSize = 0; ///< [m]
  Eigen::Vector3i nodes{0, 0, 0};
  long touched = 0;        ///< nodes holding hair
  long compressed = 0;     ///< of them, above the rest fraction
  double maxFraction = 0;  ///< the largest volume fraction at a node
  double volume = 0;       ///< the hair's volume on the grid, Σ φ cell³ [m³]
  long pressed = 0;        ///< nodes where the pressure acts (P > 0)
  double residual = 0;     ///< the largest packing above φ0 the solve left at a node
  double seconds = 0;      ///< wall time of the splat, the sum over ranks and the solve
  double solveSeconds = 0; ///< of it, the pressure solve's
};

class HairGrid
{
public:
  /// Validates and keeps the parameters.
  Status setParameters(const HairGridParameters& parameters);
  const HairGridParameters& parameters() const { return Params; }

  /// The automatic cell for guides standing for fibres of cross-section `area` [m²]: the
  /// diameter of their clump at the rest fraction, 2 √(area / (π φ0)) (15 mm for 200 guides
  /// of the wavy preset), doubled, so that a strand alone adds at most a fifth of the rest
  /// fraction to a node; and at least MinAutomaticCell, a few cells across a head's hair
  /// layer, so that more guides refine the strands, not the continuum
  /// (docs/hair-hair-interaction.md).
  double automaticCell(double area) const
  {
    return std::max(MinAutomaticCell,
                    4 * std::sqrt(area / (3.14159265358979 * Params.volumeFraction)));
  }
  static constexpr double MinAutomaticCell = 0.008; ///< [m]
  /// Starts a step of h [s]: the grid over the box [lo, hi] holding every point to be added,
  /// with the automatic cell `automaticCell` [m] when the parameters ask for one.
  void begin(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double automaticCell, double h);
  /// One strand to splat: its polyline from the root (points x[0..count), velocities v),
  /// the cross-section of the fibres it stands for, `area` [m²] (a guide standing for n
  /// fibres of radius r: n π r²), and its length [m].
  struct Strand
  {
    const Eigen::Vector3d* x = nullptr;
    const Eigen::Vector3d* v = nullptr;
    int count = 0;
    double area = 0;
    double length = 0;
  };
  /// Splats the strands on up to `threads` threads: every segment at points at most a cell
  /// apart (so that no cell it crosses is skipped), the volumes scaled so that a strand adds
  /// up to area × length (its polyline may cut corners or stop short of the tip). Each
  /// thread owns a slab of the grid's layers; the nodes add in fixed point (2⁻⁴⁰), so the
  /// grid is the same on any number of threads and ranks.
  void add(const std::vector<Strand>& strands, int threads = 1);
  /// Ends the splat (collective over `ranks`): every rank's strands summed, so that each rank
  /// holds the whole run's grid (every rank having called begin() with the same box).
  /// The pressure is solved on up to `threads` threads.
  void finish(const Ranks& ranks = Ranks(), int threads = 1);

  /// A step's grid in one call (collective over `ranks`): begin() over the bounds of every
  /// rank's strands with the automatic cell of the largest clump among them, add() and
  /// finish(), on up to `threads` threads. The same grid on any number of ranks.
  void build(const std::vector<Strand>& strands, double h, const Ranks& ranks, int threads);

  /// The response at a point x of a strand of linear density rhoS [kg/m] (one fibre's) which
  /// stands for fibres of cross-section `area` [m²] (add()'s), added to `out` (drag, medium, push;
  /// ContactResponse). Thread-safe (reads only).
  void respond(const Eigen::Vector3d& x, double rhoS, double area, ContactResponse& out) const;
  /// The volume fraction and the hair's mean velocity at x (0 and 0 outside the hair).
  double fraction(const Eigen::Vector3d& x, Eigen::Vector3d* velocity = nullptr) const;

  double cellSize() const { return Cell; }
  const HairGridStats& stats() const { return Stats; }

private:
  // A node holds φ and the momentum density in fixed point (units of Quantum): integer sums
  // do not depend on their order, so the grid is the same, bit for bit, whichever threads
  // or ranks added which strands.
  static constexpr double Quantum = 1.0 / (1ll << 40);
  struct Node
  {
    std::uint32_t stamp = 0;
    std::int32_t slot = 0;            ///< its place in Touched (the pressure solve's)
    std::int64_t q[4] = {0, 0, 0, 0}; ///< φ, then φ v
    /// The pressure's potential Q = h² P / ρ [m²] (ρ the fibres' density), solved in finish().
    double pressure = 0;
    double phi() const { return Quantum * static_cast<double>(q[0]); }
    Eigen::Vector3d momentum() const
    {
      return Quantum * Eigen::Vector3d(static_cast<double>(q[1]), static_cast<double>(q[2]),
                                       static_cast<double>(q[3]));
    }
  };
  // Node (i, j, k) and its trilinear weights for x; false outside the grid.
  bool locate(const Eigen::Vector3d& x, Eigen::Array3i& base, Eigen::Array3d& f) const;
  std::int64_t index(int i, int j, int k) const
  {
    return (static_cast<std::int64_t>(k) * Dims[1] + j) * Dims[0] + i;
  }
  const Node* node(std::int64_t n) const
  {
    const Node& nd = Nodes[n];
    return nd.stamp == Stamp ? &nd : nullptr;
  }
  Node& touch(std::int64_t n, std::vector<std::int64_t>& touched);
  // Adds strand `st` (perLength: its cross-section per unit length over a cell³) to the
  // nodes of layers [k0, k1).
  void splat(const Strand& st, double perLength, int k0, int k1,
             std::vector<std::int64_t>& touched);
  /// The pressure's potential at the touched nodes (finish()).
  void solveVolume(int threads);
  // The pressure solve's compact arrays, per touched node: its six neighbours' places (−1:
  // none), the packing to undo, the potential; the nodes of each colour.
  std::vector<std::int32_t> Around;
  std::vector<double> Excess, Potential;
  std::vector<std::int32_t> Colour[2];

  HairGridParameters Params;
  double Cell = 1;
  double Step = 1.0 / 30;
  Eigen::Vector3d Origin = Eigen::Vector3d::Zero();
  Eigen::Array3i Dims = Eigen::Array3i::Zero();
  std::vector<Node> Nodes;
  std::vector<std::int64_t> Touched;
  std::uint32_t Stamp = 0;
  HairGridStats Stats;
};

} // namespace hair

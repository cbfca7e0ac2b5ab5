#pragma once
// The near field of hair–hair interaction: against crossing only. Volume and friction are the
// grid's (contact/HairGrid); what a grid cannot do is keep two guides from passing through
// each other, and that is all this does. Each strand is cut into material pieces of fixed
// arc length (the same material pieces at every step, whatever the quadrature samples its
// model has; their nodes are given by the model, exact on its curve), and pairs of pieces of
// different strands found close are tracked over the steps (temporal coherence, as Bertails et al.
// 2006 §4.1 cite after Raghupathi et al. 2003): each pair remembers its side (the direction from B
// to A, followed while it does not reverse) and its last force (warm start). A pair acts only when
// it would end the step within the contact distance R = 2 × thickness along its side, or when its
// side has flipped (it crossed): then it pushes A and B apart along the remembered side until the
// gap the step predicts is R again. The forces are unknowns of the step, solved by
// projected Gauss–Seidel over the acting pairs with each strand's compliance
// (StrandCompliance, from the factors of its step) in a fixed order, so that the result
// depends on nothing but the pairs. The equations, the defaults and what was measured:
// docs/hair-hair-interaction.md.
//
// Use, once per step of h (superhelix/StepStrands.cxx, stepStrandsWithNearField):
//   per strand i: beginStep(h)                     (its step without these forces)
//   near.detect(every strand's nodes (materialPoints at nodeArcLengths), ids, h, carry);
//   per strand i with loads(i): D_i, its loads' compliance (SuperHelix::loadCompliance);
//   near.solve(D);
//   per strand i: the loads' forces loadForces(i) into its step (endStep).
#include "common/Status.h"
#include "contact/ContactResponse.h"
#include "geometry/UniformGrid.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <vector>

namespace hair
{

struct NearFieldParameters
{
  /// The radius of the clump of fibres a guide stands for [m]: two guides are in contact
  /// within R = 2 × thickness of each other (> 0; the models resolve an automatic one).
  double thickness = 1e-3;
  /// Pairs within R (1 + margin) of each other at the start or at the predicted end of the
  /// step, or in between, are tracked (their side remembered); only those predicted to end
  /// within R, or crossed, act. In [0, 4].
  double margin = 0.5;
  /// The length of the material pieces the strands are cut into [m] (in [1e-4, 0.1]).
  double pieceLength = 5e-3;
  /// Gauss–Seidel sweeps over the acting pairs per step (1 to 1000).
  int sweeps = 8;
  /// Threads of the search (1 to 256; the result does not depend on it).
  int threads = 1;
  Status validate() const;
};

/// A force a pair puts on one of its strands: along `direction` (unit) at the point
/// weight[0] × node `node` + weight[1] × node `node + 1`, of arc lengths s[0], s[1].
struct NearFieldLoad
{
  int node = 0;
  double s[2] = {0, 0};
  double weight[2] = {1, 0};
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();
};

struct NearFieldStats
{
  int strands = 0;
  long pieces = 0;
  long candidates = 0; ///< pairs of pieces whose swept boxes overlap
  long tracked = 0;    ///< pairs kept (within reach over the step)
  long untrusted = 0;  ///< of them, without a side yet (found within R, not R apart since)
  long active = 0;     ///< of them, acting this step (predicted within R, or crossed)
  long flipped = 0;    ///< of them, found on the wrong side of their remembered side
  long coupled = 0;    ///< strands carrying a force
  int sweeps = 0;
  /// The largest gap still missing after the sweeps, R − the predicted end gap [m] (≤ 0:
  /// every acting pair ends at R or beyond).
  double deficit = 0;
  double work = 0; ///< work of the pair forces on the strands over the step [J]
  double searchSeconds = 0, solveSeconds = 0;
};

/// One tracked pair (tests and studies).
struct NearFieldPair
{
  int strandA = 0, strandB = 0; ///< indices in detect()'s order
  double sA = 0, sB = 0;        ///< arc lengths of the closest points [m]
  Eigen::Vector3d side;         ///< remembered direction from B to A (unit)
  double gap = 0;               ///< side · (A − B) at the start of the step [m]
  bool active = false, flipped = false;
  bool trusted = false; ///< side known: found apart, or R apart since (not grown through)
  double force = 0;     ///< along `side` on A (−side on B) [N]
};

class NearFieldContacts
{
public:
  Status setParameters(const NearFieldParameters& parameters);
  const NearFieldParameters& parameters() const { return Params; }
  /// Forgets every pair (their sides and forces): a new run.
  void reset() { Memory.clear(); }

  /// The arc lengths of the nodes of a strand of length L [m]: from the root (0) to the tip
  /// (L), pieces of at most pieceLength.
  std::vector<double> nodeArcLengths(double length) const;
  /// Finds the pairs of pieces of different strands within reach over a step of h [s] from
  /// every strand's nodes (at nodeArcLengths: positions at the start, velocities the step
  /// gives them without these forces, each point moving to x + h v), follows their sides from
  /// the previous step, and picks those that act. `ids` name the strands across steps
  /// (distinct; empty: 0, 1, …). `carry`: the rigid motion the strands' frame makes over the
  /// step, end to start (the roots' motion), so that pieces moving with the head are not
  /// boxed by its sweep. `startVelocities` (optional, per strand per node): the nodes'
  /// velocities at the start of the step; a node whose velocity changes by Δv departs from
  /// the predicted line by up to ½ h |Δv|, and the search reaches that much farther.
  Status detect(const std::vector<std::vector<StrandSample>>& nodes, const std::vector<int>& ids,
                double h, const Eigen::Isometry3d& carry = Eigen::Isometry3d::Identity(),
                const std::vector<std::vector<Eigen::Vector3d>>* startVelocities = nullptr);
  /// The loads the acting pairs put on strand i (empty: none), in a fixed order.
  const std::vector<NearFieldLoad>& loads(int strand) const { return Loads[strand]; }
  /// Solves the acting pairs given, per strand, the compliance of its loads: D[k][l] =
  /// d_kᵀ J_k h A⁻¹ J_lᵀ d_l, how load k's point moves along its direction at the end of the
  /// step per newton of load l (p × p for p loads; empty for a strand without loads).
  Status solve(const std::vector<Eigen::MatrixXd>& delassus);
  /// After solve(): each load's force along its direction [N] (≥ 0), per strand.
  const std::vector<double>& loadForces(int strand) const { return LoadForces[strand]; }

  const NearFieldStats& stats() const { return Stats; }
  std::vector<NearFieldPair> pairs() const;

private:
  // One side of a contact: its strand, piece (nodes piece and piece + 1), parameter on the
  // piece, and the coupling slots of its two nodes (−1: weight 0).
  struct Side
  {
    int strand = 0, piece = 0;
    double u = 0;
    int load = -1; // its place in the strand's loads (when the pair acts)
    double weight(int e) const { return e == 0 ? 1 - u : u; }
  };
  struct Pair
  {
    Side a, b;
    std::int64_t keyA = 0, keyB = 0; // (id << 32 | piece) of each side: the pair's memory
    Eigen::Vector3d side = Eigen::Vector3d::UnitX(); // from B to A (unit)
    double gap = 0;                                  // side · (pA − pB) at the start
    bool interior = false;                           // the closest points inside both pieces
    bool trusted = false; // its side is known (found apart, or R apart since)
    bool active = false, flipped = false;
    double wFree = 0;      // side · (vA − vB) at the end of the free step
    double compliance = 0; // side · W side: its own
    double lambda = 0;     // force along side on A [N]
  };
  struct Memory_
  {
    std::int64_t keyA, keyB;
    Eigen::Vector3d side;
    bool interior, trusted;
    double lambda;
  };
  Eigen::Vector3d pointOf(const Side& s, bool velocity) const;

  NearFieldParameters Params;
  double StepSize = 0;
  std::vector<std::vector<StrandSample>> Samples; // the nodes, per strand
  std::vector<int> Ids;
  UniformGrid Grid;
  std::vector<Pair> Pairs;
  std::vector<Memory_> Memory; // sorted by keys
  std::vector<std::vector<NearFieldLoad>> Loads;
  std::vector<std::vector<double>> LoadForces;
  NearFieldStats Stats;
};

} // namespace hair

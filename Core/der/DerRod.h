#pragma once
// One hair strand as a Discrete Elastic Rod (Bergou, Wardetzky, Robinson, Audoly, Grinspun,
// "Discrete Elastic Rods", SIGGRAPH 2008) with the time-parallel reference frame and viscous
// strain-rate friction of Bergou, Audoly, Vouga, Wardetzky, Grinspun, "Discrete Viscous
// Threads", SIGGRAPH 2010: N edges between N + 1 nodes and a twist angle per edge, clamped at
// a moving root, advanced by backward Euler solved with Newton's method on the incremental
// potential. The equations are in docs/discrete-elastic-rods.md. No VTK, no printing, no
// exceptions across the API.
#include "common/Status.h"
#include "contact/ContactResponse.h"
#include "der/DerStencil.h"
#include "scene/AirField.h"
#include "scene/RigidMotion.h"
#include "strands/HairParameters.h"

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace hair
{

/// How each step's Newton iteration stops.
struct DerSolverOptions
{
  /// Converged when a full Newton step moves no node by more than this fraction of the
  /// shortest rest edge and no twist angle by more than this many radians.
  double stepTolerance = 1e-10;
  /// … or when the gradient of the incremental potential (free unknowns, max norm) has
  /// fallen to this fraction of its value at the step's start.
  double gradientTolerance = 1e-10;
  int maxIterations = 150;
};

/// Everything that defines a strand before it moves.
struct DerSpec
{
  /// The largest rest curvature per node κ̄ l̄ (= 2 tan(φ/2)) validate() accepts: a natural
  /// turning angle φ of 90° per node.
  static constexpr double MaxRestTurn = 2.0;

  std::string name = "strand";
  int id = 0;
  std::vector<double> edgeLengths; ///< rest lengths |ē_j| [m], N = size() >= 2, each > 0
  HairParameters hair;
  std::uint32_t seed = 1; ///< for the natural-curvature variation
  /// The rest twist and curvatures per unit length (τ, κ1, κ2) [1/m] at the interior nodes
  /// 1 … N−1 (3(N−1) values), when they are not the hair type's helix (a sag-free rest shape).
  /// Empty: HairParameters::naturalCurvature() times (1 + v ξ), ξ seeded uniform in [−1, 1]
  /// per value, v = curvatureVariation (the Super-Helix's draw, node by node).
  std::vector<double> restStrains;
  /// The initial node positions (N + 1; the first two must be the clamp's, x_0 = root
  /// position and x_1 = x_0 + |ē_0| root tangent, to 1e-9 of |ē_0|). Empty: straight along
  /// the root tangent. Either way the strand starts at rest relative to its root and its
  /// material frame is the root's, parallel-transported along the strand.
  std::vector<Eigen::Vector3d> initialNodes;
  /// With initialNodes: each edge's material angle from the root's material frame carried
  /// along the initial nodes by parallel transport (N values, the first 0; the twist at node j
  /// is the difference of edges j and j − 1). Empty: 0, the carried frame itself.
  std::vector<double> initialTwists;
  Eigen::Vector3d gravity = Eigen::Vector3d(0, -9.81, 0);
  Eigen::Vector3d wind = Eigen::Vector3d::Zero(); ///< uniform air velocity, unless windField
  AirVelocityField windField;                     ///< optional, overrides `wind`
  /// The clamp: x_0 = p(t), x_1 = p(t) + |ē_0| R(t) e_x, m1_0 = R(t) e_y, R the orientation
  /// (columns tangent, n1, n2). Empty: fixed at RootState{} (the origin, tangent +x).
  RootMotion root;
  /// A dead load on the last node [N]; its work is DerEnergyTerms::loadWork.
  Eigen::Vector3d tipForce = Eigen::Vector3d::Zero();
  DerSolverOptions solver;
  /// Clamp the tip too: the last edge held where the initial shape puts it, its material
  /// frame turned by `tipTwist` [rad] about its tangent from the frame carried from the root
  /// (without initialTwists the edges' angles start linear from 0 to tipTwist: a straight rod
  /// in uniform twist). A rod clamped at both ends, as Greenhill's twisted shaft; N >= 4.
  bool clampTip = false;
  double tipTwist = 0;

  /// A strand of `edges` equal edges of total length `length` [m].
  static DerSpec uniform(double length, int edges, const HairParameters& hair);
  Status validate() const;
};

/// Works and dissipations [J], over the last step and accumulated. The budget, which closes
/// by construction of `residual`:
///   Δ(kinetic + elastic + gravitational) = rootWork + windWork + contactWork + loadWork
///                                          − frictionDissipated − airDissipated + residual
/// (the Super-Helix's EnergyTerms; docs/discrete-elastic-rods.md, "Energy budget").
struct DerEnergyTerms
{
  double frictionDissipated = 0; ///< internal (viscous) friction, γ Σ |Δstrains|²/(h l̄) ≥ 0
  double airDissipated = 0;      ///< h Σ ν w |v − v_air|² ≥ 0
  double rootWork = 0;           ///< the clamp's reaction times the clamped unknowns' motion
  double windWork = 0;           ///< h Σ ν w (v_air − v)·v_air
  double contactWork = 0;        ///< of the contact hook's forces, the far field included
  double loadWork = 0;           ///< of DerSpec::tipForce
  double residual = 0;           ///< what backward Euler itself adds (< 0: dissipation)
  double fieldWork = 0;          ///< of contactWork, the far field's (drag, push, spring)
  double fieldDissipated = 0;    ///< what the far field's drag dissipated, ≥ 0
};

struct DerEnergyReport
{
  double time = 0;
  double kinetic = 0; ///< ½ Σ m_k |v_k|² + ½ Σ I_j θ̇_j²
  double elastic = 0; ///< stretching + bending + twisting
  double stretching = 0, bending = 0, twisting = 0;
  double gravitational = 0; ///< −Σ m_k g·x_k
  DerEnergyTerms lastStep;
  DerEnergyTerms total;
  double mechanical() const { return kinetic + elastic + gravitational; }
};

class DerRod
{
public:
  DerRod();
  DerRod(const DerRod& other);
  DerRod& operator=(const DerRod& other);
  ~DerRod();

  /// Validates the spec, draws the rest strains, puts the strand at `time` in its initial
  /// shape, at rest relative to its root. On error the strand is left as it was.
  Status initialize(const DerSpec& spec, double time = 0);
  /// One backward Euler step of h [s]. On error (bad h, a root or hook giving non-finite
  /// values, Newton not converging) the state is unchanged and the message names the strand
  /// and the time.
  Status step(double h);
  /// Called once per step with the nodes (element: the edge the node starts, the last node
  /// the last edge; s: rest arc length; weight: Voronoi rest length; position and velocity at
  /// the step's start). Its responses act implicitly (ContactResponse).
  void setContactForces(ContactForces hook) { Contacts = std::move(hook); }

  /// Everything the next steps read beyond the spec, as numbers (appended to `out`): time,
  /// unknowns and their rates, reference directors and tangents, reference twists, energy.
  void saveState(std::vector<double>& out) const;
  /// Puts back what saveState gave into a strand initialized from the same spec.
  Status restoreState(const std::vector<double>& values);

  const DerSpec& spec() const { return Spec; }
  int edgeCount() const { return static_cast<int>(Spec.edgeLengths.size()); }
  double time() const { return Time; }
  /// The unknowns (x_0, θ_0, x_1, θ_1, …, x_N) [m, rad] and their rates [m/s, rad/s].
  const Eigen::VectorXd& coordinates() const { return Q; }
  const Eigen::VectorXd& rates() const { return V; }
  Eigen::Vector3d position(int node) const { return Q.segment<3>(4 * node); }
  Eigen::Vector3d velocity(int node) const { return V.segment<3>(4 * node); }
  double twistAngle(int edge) const { return Q[4 * edge + 3]; }
  double twistRate(int edge) const { return V[4 * edge + 3]; }
  Eigen::Vector3d tangent(int edge) const { return Tangents.col(edge); }
  Eigen::Vector3d referenceDirector(int edge) const { return Directors.col(edge); }
  Eigen::Vector3d materialDirector1(int edge) const;
  Eigen::Vector3d materialDirector2(int edge) const;
  /// The shape the strand takes with no load from its clamp at time 0: nodes 0 … N and each
  /// edge's material angle, for DerSpec::initialNodes and initialTwists (each node turns the
  /// material frame by half its rest twist, its rest curvature — the turning angle φ with
  /// 2 tan(φ/2) = |κ̄| — and the other half of its twist). For a strand initialized
  /// straight, to be initialized again in its natural shape.
  void naturalShape(std::vector<Eigen::Vector3d>& nodes, std::vector<double>& twists) const;
  /// (m_i, κ_i1, κ_i2) [rad] at interior node i (1 … N−1), and their rest values.
  Eigen::Vector3d strains(int node) const;
  Eigen::Vector3d restStrains(int node) const { return Rest.col(node); }
  /// Newton iterations of the last step.
  int lastIterations() const { return LastIterations; }
  const DerEnergyReport& energy() const { return Energy; }
  RootState rootState(double time) const { return Spec.root ? Spec.root(time) : RootState{}; }

  /// The Hessian of the elastic energy (stretching, bending, twisting; the dead loads add
  /// none) with respect to the free unknowns (all but x_0, θ_0, x_1) at the current state:
  /// its smallest eigenvalue is the stability of a static equilibrium.
  Eigen::MatrixXd elasticHessian() const;

private:
  struct Step; // a step's data: inertial target, loads, contact responses
  struct Solver;
  double potential(const Eigen::VectorXd& q, const Step& s, Eigen::VectorXd* gradient,
                   std::vector<Eigen::Triplet<double>>* hessian) const;
  StencilData stencil(int node) const;
  Status solveStep(double h, Eigen::VectorXd& q, Step& s, int& iterations) const;
  /// The second-order correction of a Newton trial q + α p (nodes 2 … N, root outwards):
  /// each edge keeps the trial's direction and takes the length the linearized step gives it,
  /// |e| + α t·(p_k − p_{k−1}), instead of the longer chord a rotation's linear step gives.
  void correctStretch(const Eigen::VectorXd& q, const Eigen::VectorXd& p, double alpha,
                      Eigen::VectorXd& trial) const;
  void updateStateEnergies(DerEnergyReport& e) const;
  std::string where(double t0, double t1) const;

  DerSpec Spec;
  bool Initialized = false;
  double Time = 0;
  Eigen::VectorXd Q, V;
  Eigen::VectorXd Mass;                 // per unknown: m_k (3×) and I_j
  Eigen::VectorXd Voronoi;              // per node [m]
  Eigen::Matrix3Xd Tangents, Directors; // per edge, at the current state
  Eigen::VectorXd RefTwist;             // per node (0 and N unused)
  Eigen::Matrix3Xd Rest;                // per node: (m̄, κ̄1, κ̄2); columns 0 and N unused
  Eigen::Vector3d Stiffness = Eigen::Vector3d::Zero(); // (GJ, EI1, EI2)
  double StretchStiffness = 0;                         // EA
  double MinEdge = 0;
  std::vector<int> Free; // per unknown: its index among the free ones, or −1
  int FreeCount = 0;
  DerEnergyReport Energy;
  int LastIterations = 0;
  ContactForces Contacts;
  std::unique_ptr<Solver> Factor; // the free Hessian's pattern, analyzed once
};

} // namespace hair

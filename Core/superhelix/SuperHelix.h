#pragma once
// One hair strand as a Super-Helix (Bertails, Audoly, Cani, Querleux, Leroy, Lévêque,
// "Super-Helices for predicting the dynamics of natural hair", ACM TOG 25(3), 2006):
// N helical elements with constant twist and curvatures q = (τ, κ1, κ2) per element,
// clamped at a moving root, advanced by the paper's semi-implicit step. The equations are
// in docs/super-helix.md. No VTK, no printing, no exceptions across the API.
#include "common/Status.h"
#include "contact/ContactResponse.h"
#include "contact/HairHairContacts.h"
#include "contact/NearField.h"
#include "helix/HelixFunctions.h"
#include "helix/Quadrature.h"
#include "scene/AirField.h"
#include "scene/RigidMotion.h"
#include "strands/HairParameters.h"

#include <Eigen/Core>
#include <Eigen/LU>

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace hair
{

/// The time step of a strand (docs/super-helix.md, "The time step"). Both take one linear
/// solve per step with the same M, C = ∂f/∂q̇, K_T and contact terms.
enum class Integrator
{
  /// [B06] §3.4: linearly implicit, first order; backward Euler in the elastic, friction,
  /// drag, tension and contact terms, the velocity terms half implicit. Dissipates energy
  /// at O(dt).
  SemiImplicit = 0,
  /// The implicit midpoint rule linearized once about the predicted midpoint
  /// (q + dt/2 q̇, t + dt/2): second order; energy-neutral for the linear parts. A strand
  /// touching anything takes the semi-implicit step (a stiff contact would ring).
  Midpoint = 1,
  /// The two-step backward differentiation formula (BDF2, variable step) linearized once
  /// about an extrapolated prediction of the step's end: second order and L-stable, so the
  /// contacts' stiffness, damping and friction and the hair around are inside the step
  /// (docs/super-helix.md, "BDF2"). Its embedded error estimate is the prediction's
  /// distance from the result; the first step (after initialize or setState) is semi-implicit.
  Bdf2 = 2
};
/// "semi-implicit", "midpoint", "bdf2" (state files, messages).
const char* toString(Integrator integrator);
/// Whether `integrator` is one of Integrator's values; the message says which are.
Status checkIntegrator(Integrator integrator);

/// Everything that defines a strand before it moves.
struct StrandSpec
{
  std::string name = "strand";
  int id = 0;
  std::vector<double> elementLengths; ///< ℓ_Q [m], N = size(), each > 0
  HairParameters hair;
  std::uint32_t seed = 1; ///< for the natural-curvature variation
  /// The natural (rest) curvatures and twist, (τ, κ1, κ2) per element (3N values), when they
  /// are not the hair type's helix: a sag-free rest shape (groom/SagFree.h). Empty: the
  /// helix of `hair` with its seeded variation.
  std::vector<double> restCurvature;
  Eigen::Vector3d gravity = Eigen::Vector3d(0, -9.81, 0);
  Eigen::Vector3d wind = Eigen::Vector3d::Zero(); ///< uniform air velocity, unless windField
  AirVelocityField windField;                     ///< optional, overrides `wind`
  RootMotion root; ///< empty: fixed at RootState{} (root at the origin, tangent +x)
  /// A dead load at the free end [N] (constant direction; e.g. the axial load of a
  /// buckling study). Its work is EnergyTerms::loadWork.
  Eigen::Vector3d tipForce = Eigen::Vector3d::Zero();
  /// A priori bound on the relative error of each element's Gauss quadrature (of M, the
  /// forces and C); the rule is chosen per element from its turning Ω ℓ (Quadrature.h).
  /// The default is the bound of 4 points per π/2 of turning; smaller is more accurate and
  /// dearer.
  double quadratureTolerance = QuadratureChooser::defaultTolerance();
  /// 0: the rule size is chosen per element (default). n in [3, MaxGaussPoints]: n points
  /// per interval, intervals from the tolerance; 4 with the default tolerance is the fixed
  /// rule of 4 points per π/2 of turning on every element.
  int quadraturePoints = 0;
  /// A tuning knob, not a model setting (the results agree to round-off either way):
  /// elements with at least this many quadrature samples sum the velocity Jacobian's
  /// moments from a Gram matrix of the helix functions, the others sample by sample (the
  /// same sums in another order: cheaper per sample, dearer per element; see FunctionGram in
  /// VelocityJacobian.cxx). With D²g[k̇, ·] taken from per-element coefficients
  /// (helixBilinearBasis) on the per-sample path, the break-even is ~11–12 samples:
  /// instructions per step at N = 10 (callgrind), per sample against Gram, curly (7.6
  /// samples per element) 108.0 M against 111.9 M, fuzzy (15.4) 156.4 M against 153.0 M over
  /// 330 steps; BM_GramSideBySide, C alone, 8.4 against 9.4 µs (wavy), 9.1 against 9.7
  /// (curly), 11.5 against 10.6 (fuzzy). The tests set it to 1 (every element from the Gram
  /// matrix) and to a large value (none) to compare both ways.
  int gramMinSamples = 12;
  /// The time step (Integrator): the paper's semi-implicit step by default.
  Integrator integrator = Integrator::SemiImplicit;

  /// A strand of `elements` equal elements of total length `length`.
  static StrandSpec uniform(double length, int elements, const HairParameters& hair);
  Status validate() const;
};

/// Energies [J]. State energies are at `time`; the work terms are over the last step and
/// accumulated since initialize(). The budget, which closes by construction of `residual`:
///   Δ(kinetic + elastic + gravitational) = rootWork + windWork + contactWork + loadWork
///                                          − frictionDissipated − airDissipated + residual
/// residual is what the time integrator itself adds (< 0: numerical dissipation).
struct EnergyTerms
{
  double frictionDissipated = 0;
  double airDissipated = 0;
  double rootWork = 0;
  double windWork = 0;
  double contactWork = 0;
  double loadWork = 0; ///< work of StrandSpec::tipForce
  double residual = 0;
  /// Of contactWork, the work of the contact responses' far-field part (ContactResponse's
  /// drag, push and spring: the hair around, contact/HairGrid), and what its drag dissipated,
  /// h Σ w drag |v − medium|² (≥ 0; the rest of its work is what the hair around gave).
  double fieldWork = 0;
  double fieldDissipated = 0;
};

struct EnergyReport
{
  double time = 0;
  double kinetic = 0;
  double elastic = 0;
  double gravitational = 0; ///< −∫ ρS g·r ds (zero at the origin)
  EnergyTerms lastStep;
  EnergyTerms total;
  double mechanical() const { return kinetic + elastic + gravitational; }
};

class SuperHelix
{
public:
  /// Validates the spec, draws the natural curvature, puts the strand at rest in its
  /// natural shape at `time`. On error the strand is left as it was.
  Status initialize(const StrandSpec& spec, double time = 0);

  /// One step of size dt [s] of StrandSpec::integrator, without sub-steps (linearly
  /// implicit in the elastic, friction, drag and tension forces and in the
  /// velocity-dependent forces; see docs/super-helix.md; dt = 1/30 s is stable). On error
  /// (bad dt, a root or force callback returning non-finite values, a step that blows up)
  /// the state is unchanged and the message names the strand and the time.
  Status step(double dt);

  /// Advances by dt. With tolerance > 0 [m], in sub-steps whose sizes are controlled by the
  /// step's embedded error estimate (lastErrorEstimate()): each sub-step h is accepted when
  /// its estimate is at most tolerance · h / dt, so that the estimates of the sub-steps
  /// taken add up to at most `tolerance` over dt; a rejected sub-step is taken again
  /// smaller. At most MaxSubsteps sub-steps: the last ones are then accepted whatever
  /// their estimate (lastErrorEstimate() shows it). With tolerance <= 0 it is step(dt).
  Status advance(double dt, double tolerance);

  /// One step of dt split around a solve that couples this strand to others (hair–hair
  /// contacts, docs/hair-hair-contacts.md). beginStep does what step(dt) does up to the new
  /// velocities, without the coupling forces, and keeps the step's factorized matrix;
  /// freeSamples() are then the samples at the start of the step with the velocities they
  /// have at its end without the coupling forces (x + dt v predicts where they end);
  /// compliance() describes how the velocities of some of them (indices into samples(),
  /// increasing) respond to point forces there (StrandCompliance); endStep commits the step
  /// with forces[k] [N] at those samples and the coordinate velocities changed by `response`
  /// (Σ Y_k forces[k]), as step(dt) with those forces added by the contact hook would (to
  /// round-off). Between beginStep and endStep the strand must not be stepped or changed;
  /// on error the state is unchanged.
  Status beginStep(double dt);
  const std::vector<StrandSample>& freeSamples() const { return Pending.free; }
  Status compliance(const std::vector<int>& samples, StrandCompliance& out) const;
  /// Points of the strand at arc lengths `s` [m] (increasing, in [0, L]) of the current state,
  /// exact on the helices: positions, arc lengths and velocities; with `free`, the
  /// velocities at the end of the step begun by beginStep without the coupling forces (as
  /// freeSamples()'), else the current ones. Weights are 0.
  void materialPoints(const std::vector<double>& s, bool free,
                      std::vector<StrandSample>& out) const;
  /// How point loads along given directions move the strand within the step begun by
  /// beginStep: load l acts at Σ_e weight[l][e] r(s[l][e]) (two material points, arc lengths
  /// in [0, L]) along the unit direction d_l. Y's column l is h A⁻¹ j_l, j_l = Σ_e
  /// weight_e J(s_e)ᵀ d_l, the coordinate velocities one newton of load l adds; D = [j_k ·
  /// Y_l], how load k's point moves along d_k per newton of load l (the loads' Delassus
  /// matrix). A force λ_l on each load then changes q̇ by Y λ.
  Status loadCompliance(const std::vector<std::array<double, 2>>& s,
                        const std::vector<std::array<double, 2>>& weight,
                        const std::vector<Eigen::Vector3d>& direction, Eigen::MatrixXd& D,
                        Eigen::MatrixXd& Y) const;
  /// Like freeSamples(), with the coordinate velocities changed by `response` (a coupled
  /// solve's Σ Y_k F_k; empty: freeSamples()).
  void predictedSamples(const Eigen::VectorXd& response, std::vector<StrandSample>& out) const;
  Status endStep(const std::vector<int>& samples, const std::vector<Eigen::Vector3d>& forces,
                 const Eigen::VectorXd& response);

  /// Replaces q and q̇ (sizes 3N, finite). Energies are recomputed; totals are kept.
  Status setState(const Eigen::VectorXd& q, const Eigen::VectorXd& qdot);
  void setContactForces(ContactForces hook) { Contacts = std::move(hook); }
  /// Everything its next steps depend on beyond its spec, as numbers (appended to `out`):
  /// the time, q, q̇, the energy report, the step controller's and BDF2's history.
  void saveContinuation(std::vector<double>& out) const;
  /// Puts back what saveContinuation gave into a strand initialized from the same spec;
  /// `used` is how many of `values` it took. Refuses numbers of another strand's layout.
  Status restoreContinuation(const double* values, std::size_t count, std::size_t& used);
  /// How many numbers saveContinuation gives for a strand of `elements` elements.
  static std::size_t continuationSize(int elements);

  const StrandSpec& spec() const { return Spec; }
  int elementCount() const { return static_cast<int>(Spec.elementLengths.size()); }
  double length() const { return Length; }
  double time() const { return Time; }
  const Eigen::VectorXd& q() const { return Q; }
  const Eigen::VectorXd& qdot() const { return Qdot; }
  const Eigen::VectorXd& restCurvature() const { return Qrest; }
  /// Diagonals of 𝕂 = diag(EI_i ℓ_Q) and Γ = diag(γ ℓ_Q).
  const Eigen::VectorXd& stiffnessDiagonal() const { return Kdiag; }
  const Eigen::VectorXd& frictionDiagonal() const { return Gdiag; }
  const EnergyReport& energy() const { return Energy; }
  RootState rootState(double time) const;

  /// Reconstruction at arc length s ∈ [0, L] (clamped) for the current state.
  Eigen::Vector3d position(double s) const;
  Eigen::Matrix3d frame(double s) const; ///< columns n0 (tangent), n1, n2
  Eigen::Vector3d velocity(double s) const;
  /// position(s) and velocity(s) from one evaluation of the helix (the same values).
  void positionAndVelocity(double s, Eigen::Vector3d& position, Eigen::Vector3d& velocity) const;
  /// ∂r(s)/∂q: 3 × 3N, exact (closed form).
  Eigen::Matrix3Xd jacobian(double s) const;
  /// Acceleration of the point s when q̈ = 0 (root motion, centrifugal, Coriolis).
  Eigen::Vector3d accelerationAtRest(double s) const;
  /// Element ends r(s_0 = 0), …, r(s_N), plus `perElement − 1` points inside each element.
  void polyline(int perElement, std::vector<Eigen::Vector3d>& points) const;
  /// Quadrature samples for the current state.
  const std::vector<StrandSample>& samples() const;

  /// The pieces of one step, exposed for tests and for the benchmark's breakdown.
  /// solve() uses the M, f, C and K_T assembled last for the current state. M, C and K_T
  /// are per-thread buffers: their accessors return the last ones assembled on the calling
  /// thread (for any strand), so read them before assembling another strand.
  void reconstruct();              ///< kinematics and the air's velocity at every sample (time())
  void assemble();                 ///< M and the explicit generalized force f
  void assembleVelocityJacobian(); ///< C = ∂f/∂q̇ (after assemble)
  void assembleTensionStiffness(double h); ///< K_T for a step h (after assemble)
  /// The linear system of the step (outside a step the semi-implicit one; while the
  /// second-order step is taken, its own at the predicted midpoint).
  Status solve(double dt, Eigen::VectorXd& qdotNext);
  const Eigen::MatrixXd& massMatrix() const;
  const Eigen::VectorXd& generalizedForce() const { return F; }
  const Eigen::MatrixXd& velocityJacobian() const;
  /// K_T, the tension part of the loads' stiffness −∂f/∂q, for a step of h (after
  /// assembleTensionStiffness(h)): symmetric, positive semi-definite.
  const Eigen::MatrixXd& tensionStiffness() const;
  /// Sub-steps the last step or advance took: 1 for step(), more only when advance() was
  /// asked for accuracy.
  int lastSubsteps() const { return LastSubsteps; }
  /// Sub-steps the last advance() computed and rejected (their cost is in no state).
  int lastRejected() const { return LastRejected; }
  /// Of lastSubsteps(), those taken by the first-order semi-implicit step: all of them with
  /// Integrator::SemiImplicit; with Integrator::Midpoint, those where the second-order step
  /// was declined (it would have created energy, blew up, or the strand touched a contact;
  /// docs/super-helix.md, "The second-order step").
  int lastFirstOrder() const { return LastFirstOrder; }
  /// The last step's (or advance's, summed over its sub-steps) estimate of its error [m]:
  /// the largest distance, over the element ends, between the positions of the step's
  /// first-order update q + h q̇ⁿ⁺¹ and its midpoint update q + h (q̇ⁿ + q̇ⁿ⁺¹)/2,
  /// h |J (q̇ⁿ⁺¹ − q̇ⁿ)| / 2 with the Jacobian where the step was evaluated. It is the
  /// leading local error of the semi-implicit step, and a bound far above that of the
  /// midpoint step (docs/super-helix.md, "Accuracy on request").
  double lastErrorEstimate() const { return LastError; }
  /// The order p of lastErrorEstimate() in the step, e ∝ hᵖ: 3 after a BDF2 step (its own
  /// local error), 2 otherwise (superhelix/SubstepControl.h sizes sub-steps with it).
  int lastErrorPower() const { return LastErrorPower; }

  /// Asks the CPU to start loading this strand's samples into cache (no effect on results);
  /// stepStrands calls it for the next strand while it steps one.
  void prefetch() const;
  /// Upper bound on the sub-steps of advance().
  static constexpr int MaxSubsteps = 256;

private:
  // One quadrature sample of the step, streamed through several times per step. Aligned to
  // cache lines, 256 bytes, four lines, so that no sample straddles a line (unaligned
  // samples make a step at N = 10 1.5–2.6 % slower on every preset). What only some strands
  // have stays out of it: the wind of a wind field (Winds), the contact response and the
  // load per unit length (the step workspace's ContactBuffer and Loads, same index;
  // SuperHelixInternal.h).
  struct alignas(64) Node
  {
    int element;
    // The contact's force, −∂f/∂x, −∂f/∂v, its far-field part (drag, push, spring) are
    // non-zero (set by evaluateForces in a step).
    bool hasF = false, hasK = false, hasD = false, hasField = false;
    double u, w;
    Eigen::Vector3d r, v, v0, a0;
    Eigen::Matrix3d J;
    HelixCoefficients coefficients;
  };
  static_assert(sizeof(Node) == 256, "a sample is four cache lines");
  struct Element
  {
    Eigen::Matrix3d F0; // frame at the start
    Eigen::Vector3d r0, omega0, v0, alpha0, acc0;
    Eigen::Matrix3d A, W; // tail Jacobian: J_iQ(s) = A_i × r(s) + W_i past the element
    Eigen::Matrix3d jEnd; // F0 ∂g/∂k at the end
    Eigen::Vector3d jkdEnd, fgEnd, akd;
    HelixCoefficients endCoefficients; // helixCoefficients(Ω ℓ), for C's end terms
    int first, count;
  };
  struct Kinematics
  {
    RootState root;
    double time = 0;
    std::vector<Element> elements;
    std::vector<Node> nodes;
    Element tip; // frame and point at s = L
    double kinetic = 0, gravitational = 0;
    double carried = 0; // ∫ ρS ṙ · v₀ ds, v₀ the root-carried velocity (the midpoint's root work)
  };

  void kinematics(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const RootState& root,
                  double time, Kinematics& out) const;
  int locate(double s, double& u) const;
  Status evaluateForces(Kinematics& k, double time);
  // One step of h: Integrator::Midpoint's guarded second-order step or the semi-implicit
  // one. With acceptLimit finite, a step whose error estimate exceeds it is not committed:
  // `rejected` is set and the state is unchanged (the estimate in LastError).
  Status singleStep(double h, double acceptLimit, bool& rejected);
  Status singleStep(double h)
  {
    bool rejected = false;
    return singleStep(h, std::numeric_limits<double>::infinity(), rejected);
  }
  // The scheme one attempt takes (Integrator's, or the semi-implicit fallback).
  enum class Scheme
  {
    SemiImplicit,
    Midpoint,
    Bdf2
  };
  // Why a step attempt was not committed.
  enum class Outcome
  {
    Committed,
    Rejected, // its error estimate is above acceptLimit (advance() takes a smaller one)
    Declined  // the midpoint step would create energy, blew up or met a contact
  };
  // `coupled`: the step's velocities already solved (endStep: beginStep's with the coupling
  // forces' response); only the semi-implicit step is coupled.
  Status attemptStep(double h, Scheme scheme, double acceptLimit, Outcome& outcome,
                     const Eigen::VectorXd* coupled = nullptr);
  // Forces, assembly and solve of the step evaluated at the current state (the midpoint's or
  // BDF2's prediction once attemptStep has moved it there); `declined`: a midpoint step
  // meeting a contact.
  Status prepareStep(double h, double t0, Scheme scheme, Eigen::VectorXd& qdotNext, bool& declined,
                     bool& solveFailed);
  void endVelocities(const Eigen::VectorXd& qdot, std::vector<StrandSample>& out) const;
  Status checkStep(double dt) const;
  double elasticEnergy(const Eigen::VectorXd& q) const;
  std::string where(double t0, double t1) const;

  StrandSpec Spec;
  double Length = 0;
  double Time = 0;
  double RhoS = 0;
  Eigen::Vector3d RotI = Eigen::Vector3d::Zero(); // ρ (I_p, I1, I2) per unit length
  QuadratureChooser Rules;
  Eigen::VectorXd Q, Qdot, Qrest, Kdiag, Gdiag, Starts;
  EnergyReport Energy;
  ContactForces Contacts;
  bool Initialized = false;
  int LastSubsteps = 1;
  int LastRejected = 0;
  int LastFirstOrder = 0;
  double LastError = 0;
  // Integrator::Midpoint: after a declined midpoint step the next MidpointSkip steps are
  // taken semi-implicit without trying (MidpointBackoff doubles, up to 8, while attempts
  // keep being declined, and is reset by an accepted one).
  int MidpointSkip = 0, MidpointBackoff = 0;
  // advance(): the sub-step the controller would take next (0: none yet; dt at most).
  double NextSubstep = 0;
  // The committed step before the current state (BDF2's history): q, q̇ at its start and its
  // size; HasPrevious is false after initialize() and setState().
  Eigen::VectorXd PreviousQ, PreviousQdot;
  double PreviousStep = 0;
  bool HasPrevious = false;
  // A BDF2 step being taken: its weight β = h (1 + ω)/(1 + 2ω) (ω: the step ratio) and the
  // history's velocity q̇̂ = q̇ⁿ + ω²/(1 + 2ω) (q̇ⁿ − q̇ⁿ⁻¹), the mass matrix's vector of its
  // right-hand side (solve(), assemble()).
  double BdfWeight = 0;
  Eigen::VectorXd BdfHat;
  // While a BDF2 step evaluates its forces: the contact hook is asked at the step's start
  // (these samples, the prediction's material points where the strand is at tⁿ, and
  // HookTime = tⁿ), whose response its own linearization carries to the prediction
  // (evaluateForces). Null otherwise.
  const std::vector<StrandSample>* HookSamples = nullptr;
  double HookTime = 0;
  // BDF2 is zero-stable for step ratios below 1 + √2; advance() grows its sub-steps at most
  // by this factor, and a larger ratio takes the semi-implicit step.
  static constexpr double MaxBdfRatio = 2;
  // The power of h in LastError's leading term: 2 for the first-order difference, 3 for
  // BDF2's local error (advance() sizes the next sub-step from it).
  int LastErrorPower = 2;

  Kinematics Cur;
  bool CurValid = false;
  // The wind field at Cur's samples (only with StrandSpec::windField; filled by a step's
  // evaluateForces, by reconstruct() and, when stale, by assemble()).
  std::vector<Eigen::Vector3d> Winds;
  bool WindsValid = false;
  void fillWinds(double time);
  // The step workspace's ContactBuffer holds this strand's contact response at Cur: true
  // from a step's evaluateForces to the end of that step.
  bool ContactsSet = false;

  // A step begun by beginStep and not yet ended: its size, the velocities without the
  // coupling forces, the coupling samples and the contact hook's response (the step
  // workspace's ContactBuffer, which other strands reuse in between).
  struct PendingStep
  {
    bool active = false;
    double h = 0;
    Eigen::VectorXd qdot;
    std::vector<StrandSample> free;
    bool contactsSet = false;
    std::vector<ContactResponse> contacts;
    Eigen::MatrixXd lu; // the step's matrix factorized (luSolveInPlace), or
    std::vector<int> pivots;
    Eigen::PartialPivLU<Eigen::MatrixXd> largeLu; // Eigen's, past UnblockedLuMax
  } Pending;
  // Y ← A⁻¹ Y with the pending step's kept factors, all columns at once.
  void solvePending(Eigen::MatrixXd& Y) const;

  mutable std::vector<StrandSample> Samples;
  Eigen::VectorXd F;
  // Which reconstruction Cur is: a process-wide counter, renewed whenever Cur changes, so
  // that the per-thread step workspace can tell whose loads it holds (SuperHelixInternal.h).
  std::uint64_t CurId = 0;
  void newCurId();
  // Implicit contact terms into the step's Lhs and Rhs, for a step of weight h (BDF2: β);
  // `aboutPrediction`: the samples are BDF2's prediction of the step's end (the contact is
  // linearized about it), else the step's start.
  void addContactJacobians(double h, bool aboutPrediction);
  // The system solve() forms: the midpoint's or BDF2's while one is being taken, else the
  // semi-implicit step's.
  Scheme StepScheme = Scheme::SemiImplicit;
  // The step size h (BDF2: β) while a step assembles M: the contact responses' drag c and
  // spring k (multiples of the identity) are folded into M's translational weights,
  // ρS + (h c + h² k) / (1 + h ν/ρS), and their right-hand side into f (assemble()). 0
  // outside a step.
  double FoldStep = 0;
  // J x at every sample of Cur (x: 3N coordinate velocities), from the tail Jacobians; with
  // `carried`, v0 + J x (the samples' velocities for coordinate velocities x).
  void sampleVelocities(const Eigen::VectorXd& x, bool carried,
                        std::vector<Eigen::Vector3d>& out) const;
};

/// Steps every strand by dt on `threads` threads (common/Parallel.h; 1: the calling thread
/// only). Returns the first error in strand order; strands that failed keep their state,
/// the others are advanced.
Status stepStrands(std::vector<SuperHelix>& strands, double dt, int threads, double tolerance = 0);

/// Steps every strand by dt on `threads` threads with the contacts between strands solved
/// together with their steps (docs/hair-hair-contacts.md): the pairs that may touch within
/// the step are found from the strands' samples (each named by its StrandSpec::id; ids must
/// be distinct), every strand's step is solved without them (strands with none are stepped
/// outright), the contacts are solved with the strands' compliances, and the strands that
/// carry one commit their step with its forces. Returns the first error in strand order.
Status stepStrandsWithContacts(std::vector<SuperHelix>& strands, HairHairContacts& contacts,
                               double dt, int threads);

/// Steps every strand by dt on `threads` threads with the near field of hair–hair interaction
/// (contact/NearField.h: the pairs that would cross or end within the contact distance push
/// apart): every strand's step is solved without the pairs' forces, the acting pairs are
/// found from where it takes the samples and solved with the compliances of the strands they
/// load, and every strand commits its step with its forces. `carry`: the roots' rigid motion
/// over the step, end to start (NearFieldContacts::detect). Returns the first error in
/// strand order.
Status stepStrandsWithNearField(std::vector<SuperHelix>& strands, NearFieldContacts& near,
                                double dt, int threads,
                                const Eigen::Isometry3d& carry = Eigen::Isometry3d::Identity());

} // namespace hair

#pragma once
// The Super-Helix model behind the StrandModel seam: one SuperHelix per guide, their
// contacts with the body (penalty with anisotropic friction) and with each other, stepped
// together on the run's threads.
#include "contact/BodyContacts.h"
#include "contact/HairHairContacts.h"
#include "model/GroomReport.h"
#include "model/StrandModel.h"
#include "superhelix/Quadrature.h"
#include "superhelix/SuperHelix.h"

#include <vector>

namespace hair
{

struct SuperHelixOptions
{
  /// Points per element in the frames (drawn exactly on the helices, drawSuperHelix): what
  /// the state file stores and the penetration measure counts. Hair Simulation sets it from
  /// its Points Per Element (default 16); Core's callers keep 4, at which the studies' and
  /// golden tests' figures are recorded.
  int pointsPerElement = 4;
  /// A priori bound on each element's quadrature error (StrandSpec::quadratureTolerance, in
  /// [1e-15, 1e-2]). The default keeps the quadrature error far below the 1/30 s step's own;
  /// 1e-2 makes curled hair 5–10 % faster (docs/benchmarks.md).
  double quadratureTolerance = QuadratureChooser::defaultTolerance();
  /// The time step of every strand (StrandSpec::integrator).
  Integrator integrator = Integrator::SemiImplicit;
  /// Accuracy on request [m per second of simulated time]: with tolerance > 0 every strand
  /// advances in sub-steps whose error estimates (SuperHelix::lastErrorEstimate, at every
  /// element end) add up to at most `tolerance` over each second (SuperHelix::advance with
  /// tolerance · dt for a step dt); 0: fixed steps of the run's time step. Measured on a
  /// released strand, the tip's error after 1 s stayed below the tolerance with both
  /// integrators (docs/super-helix.md, "Accuracy on request"). With hair–hair contacts the
  /// sub-steps are common to all strands, each sized from the previous one's largest
  /// estimate and none taken again (docs/hair-hair-contacts.md).
  double tolerance = 0;
  /// Hair–body contacts against the scene's parts (docs/superhelix-contacts.md).
  /// `lookAhead` is set to the time step by the model.
  BodyContactParameters contacts;
  /// Hair–hair contacts between the guides (docs/hair-hair-contacts.md), solved together
  /// with every step (stepStrandsWithContacts): the pairs that may touch within the step
  /// are found before it, and their forces are unknowns of the step.
  bool hairHairEnabled = false;
  HairHairParameters hairHair;
  /// How sag-free rest shapes are found (guides whose restShape is SagFree); a run sets it
  /// from SimulationOptions::sagFree.
  SagFreeOptions sagFree;
  /// The seam for other contact responses: a hook called for every strand at every
  /// (sub-)step right after the body's and the other strands' response, with the same
  /// samples and response buffer, to which it ADDS its own force, stiffness and damping
  /// (never overwrites). It runs on the thread that steps the strand, several at once for
  /// different strands. Empty: none.
  ContactForces additionalContacts;
  /// Names the first bad option, what is wrong and what to do.
  Status validate() const;
};

class SuperHelixModel final : public StrandModel
{
public:
  explicit SuperHelixModel(const SuperHelixOptions& options = {});
  SuperHelixModel(const SuperHelixModel&) = delete;
  SuperHelixModel& operator=(const SuperHelixModel&) = delete;

  const char* name() const override { return "super-helix"; }
  Status initialize(const std::vector<GuideStrand>& guides, const Scene& scene,
                    const RunSettings& run) override;
  Status advanceTo(double t) override;
  double time() const override;
  void describe(StateHeader& header) const override;
  void writeFrame(StateFrame& frame) const override;
  EnergyBudget energy() const override;
  void groomed(std::vector<GuideStrand>& guides, std::vector<GroomReport>& reports) const override;
  void restCoordinates(std::vector<double>& values) const override;
  /// µs of a step on the benchmark machine: per element and per quadrature sample of the
  /// guide's natural curl (docs/benchmarks.md).
  double stepCost(const GuideStrand& guide) const override;
  /// Over the steps since the previous frame (advanceTo): "substeps", the (sub-)steps each
  /// strand took, mean over the strands (1 per step with fixed steps); "rejected_substeps",
  /// the sub-steps the accuracy control computed and took again smaller, mean over the
  /// strands; "first_order_share", the share of the steps taken by the first-order
  /// semi-implicit step (1 with Integrator::SemiImplicit); "error_estimate" [m], the largest
  /// over the strands of the sum of their steps' error estimates
  /// (SuperHelix::lastErrorEstimate).
  std::map<std::string, double> stepStatistics() const override;

  const std::vector<SuperHelix>& strands() const { return Helices; }
  /// The hair–hair contacts of the last step (when enabled).
  const HairHairContacts& hairHair() const { return HairHair; }

private:
  /// Strand k from guide g: fitted to its groom, made sag-free when asked.
  Status buildStrand(int k, const GuideStrand& g, bool uniformAir,
                     const Eigen::Vector3d& uniformWind, const ContactForces& restContacts);
  /// The contacts of Helices[strand], whose id (number in the run) is `id`.
  void respond(std::size_t strand, int id, double t, const std::vector<StrandSample>& samples,
               std::vector<ContactResponse>& response) const;

  SuperHelixOptions Options;
  RunSettings Run;
  Scene World;
  std::vector<SuperHelix> Helices;
  std::vector<GuideStrand> Built;   ///< the guides as built (groomed: the fit's length, tangent)
  std::vector<GroomReport> Reports; ///< per strand: the fit and the rest shape
  BodyContacts Body;
  HairHairContacts HairHair;
  // Hair–hair contacts since t = 0: the work of their forces on the strands (included in
  // the strands' contact work) and what their damping and friction dissipated [J].
  double HairHairWork = 0, HairHairDissipated = 0;
  double HairHairThickness = 0; // as used: the automatic one when the option is 0
  // stepStatistics() of the steps since the last frame, added up after every stepStrands.
  void tally();
  double Substeps = 0, Rejected = 0, FirstOrder = 0;
  double NextCoupledStep = 0;     // with hair–hair contacts and a tolerance: the next sub-step
  std::vector<double> FrameError; // per strand
  /// The run's time: every strand is stepped by the same dt from it. Not a strand's own
  /// time, which sub-steps (a tolerance) leave off by round-off that differs from strand to
  /// strand, so that which strand came first (under MPI: on which rank) changed every dt.
  double Time = 0;
};

} // namespace hair

#pragma once
// The Super-Helix model behind the StrandModel seam: one SuperHelix per guide, their
// contacts with the body (penalty with anisotropic friction) and with each other, stepped
// together on the run's threads.
#include "contact/BodyContacts.h"
#include "contact/HairGrid.h"
#include "contact/HairHairContacts.h"
#include "contact/HairHairOptions.h"
#include "contact/NearField.h"
#include "helix/Quadrature.h"
#include "model/GroomReport.h"
#include "model/GuideDrawing.h"
#include "model/StrandModel.h"
#include "superhelix/SuperHelix.h"

#include <vector>

namespace hair
{

struct SuperHelixOptions
{
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
  /// Hair–body contacts against the scene's parts (docs/superhelix-contacts.md); a run sets
  /// it from SimulationOptions::contacts. `lookAhead` is set to the time step by the model.
  BodyContactParameters contacts;
  /// Hair–hair interaction between the guides (docs/hair-hair-interaction.md): the grid's
  /// volume and friction (the default), with the near field's pairs against crossing, or
  /// every close pair solved with the step (docs/hair-hair-contacts.md); a run sets it from
  /// SimulationOptions::hairHair.
  HairHairOptions hairHair;
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
  std::vector<StepStatisticRule> stepStatisticRules() const override;
  double bytesPerElement() const override;
  std::string continuationRefusal() const override;
  std::size_t continuationCapacity(std::size_t k) const override;
  void saveContinuation(StateContinuation& out) const override;
  Status restoreContinuation(const StateContinuation& in) override;

  const std::vector<SuperHelix>& strands() const { return Helices; }
  /// The hair–hair contacts of the last step (when enabled, Coupled).
  const HairHairContacts& hairHair() const { return HairHair; }
  /// The far and near field of the last step (when enabled: Grid, GridAndNearField).
  const HairGrid& hairGrid() const { return Grid; }
  const NearFieldContacts& nearField() const { return Near; }
  /// The contact thickness as used (the automatic one when the option is 0) [m].
  double hairThickness() const { return HairHairThickness; }

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
  /// Static friction's anchors, per strand (samples × parts): updated by respond(), which a
  /// strand's own step calls (one thread per strand at a time).
  mutable std::vector<std::vector<BodyAnchor>> Anchors;
  HairHairContacts HairHair;
  HairGrid Grid;
  NearFieldContacts Near;
  // Per strand: the cross-section of the fibres it stands for (the grid's volume) [m²].
  std::vector<double> ClumpArea;
  /// Per strand: the polyline buildGrid splats (root, then the samples) and its velocities.
  std::vector<std::vector<Eigen::Vector3d>> GridPoints, GridVelocities;
  /// The far field's grid for a step of h from every strand's samples now, summed over
  /// the ranks (collective).
  void buildGrid(double h);
  bool usesGrid() const { return Options.hairHair.usesGrid(); }
  /// One step of h from t0 of every strand with the pairs asked for: the coupled solve, or
  /// the grid and the near field (the grid alone is stepped by advanceTo).
  Status coupledStep(double t0, double h);
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

/// The model's drawer (simulation/ModelRegistry.cxx, model/GuideDrawing.h): the strands drawn
/// again from q, q̇ and the root at `pointsPerElement` points per element (0: as stored),
/// curvature and twist those of the element a point starts, the other per-point scalars
/// interpolated linearly in arc length between the stored points.
Status drawSuperHelixFrame(const StateHeader& header, const StateFrame& frame, int pointsPerElement,
                           int threads, GuideDrawing& out);

} // namespace hair

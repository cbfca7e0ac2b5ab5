#pragma once
// What a model made of each guide's groom and rest shape: the error of its fit to the guide
// curve and what became of a sag-free rest shape. Both models report it; the state file
// keeps it under /groom and the filters show it per strand (names in GroomReport.cxx).
#include <string>
#include <vector>

namespace hair
{

/// What became of a strand's rest shape (the state file's /groom/rest_status).
enum class RestOutcome
{
  AsGrown = 0,  ///< the model's own natural shape (no sag-free asked)
  Held = 1,     ///< sag-free: the shape is a stable equilibrium (resting on the body if pressed in)
  Unstable = 2, ///< no natural shape makes the shape stable: the closest stable one is used
  BeyondBending = 3 ///< holding the shape strains the fibre past its elastic range: closest one
};
const char* toString(RestOutcome outcome);

struct GroomReport
{
  /// Largest distance of the guide curve's points from the strand the model built from it
  /// [m]; 0 for a guide without a curve.
  double fitError = 0;
  RestOutcome outcome = RestOutcome::AsGrown;
  /// Largest distance between the shape asked for (the fit, or the grown shape) and the shape
  /// the strand starts in [m]: 0 unless the closest stable shape replaced it.
  double deviation = 0;
  /// The smallest eigenvalue of the potential's Hessian at the shape asked for over the
  /// largest stiffness (> 0: stable), for a sag-free strand; 0 otherwise.
  double stability = 0;
  /// For Unstable and BeyondBending: why, in words.
  std::string reason;
  /// A grown strand whose shape at t = 0 entered the body starts draped over it
  /// (collision/PosedPart.h, drapeOutside): the largest distance a point of it was moved
  /// [m]; 0 for a strand that started outside (or a groom: its curve is the shape asked for).
  double drape = 0;
};

/// How sag-free rest shapes are found (groom/SagFree.h, projective/ProjectiveGroom.h).
struct SagFreeOptions
{
  /// Stable when the smallest eigenvalue of the potential's Hessian H exceeds this fraction
  /// of the largest stiffness: a margin well above the round-off of H's finite differences
  /// (~1e-9 of it).
  double stabilityMargin = 1e-6;
  /// The settling of a shape that cannot be held: steps of `relaxStep` (the Super-Helix's;
  /// the projective model keeps its own) with a damping rate raised to `relaxDamping` (1/s;
  /// it changes no equilibrium), for at most `relaxTime`, until no element or segment turns
  /// faster than `settledRate` (rad/s).
  /// The largest strain at the fibre's surface a rest shape's prestress may reach (the
  /// bending and twist it holds, |q − q_rest| times the fibre's radius): hair is elastic to
  /// about 2 % (the Hookean region of its stress–strain curve; C. R. Robbins, Chemical and
  /// Physical Behavior of Human Hair, 5th ed., Springer 2012, ch. 9), beyond that it yields.
  double elasticStrain = 0.02;
  double relaxStep = 1.0 / 30;
  double relaxTime = 10;
  double relaxDamping = 10;
  double settledRate = 1e-6;
};

/// The per-strand values of the reports as the state file (/groom/<file>) and the
/// filters' cell arrays (<array>) name them.
struct GroomReportValue
{
  const char* array;
  const char* file;
  const char* unit;
  double (*get)(const GroomReport&);
};
const std::vector<GroomReportValue>& groomReportValues();

} // namespace hair

#pragma once
// A sag-free rest shape for a Super-Helix (inverse statics; after Derouet-Jourdan,
// Bertails-Descoubes and Thollot, "Stable inverse dynamic curves", ACM TOG 29(6), 2010, and
// with contact Derouet-Jourdan, Bertails-Descoubes, Daviet and Thollot, "Inverse dynamic hair
// modeling with frictional contact", ACM TOG 32(6), 2013): the natural curvatures and twist
// q_rest chosen so that a given shape q is a static equilibrium under gravity and the body's
// contacts,
//     𝕂 (q − q_rest) = f(q)      ⇒      q_rest = q − 𝕂⁻¹ f(q),
// with f the generalized force of gravity and of the contacts at q (at rest, the body
// still). Where the strand lies on the body the body carries its weight: of the contacts'
// forces the balance takes what leaves the least prestress (at most the penalty's force at
// the shape: a shape pressed deeper into the body than its load needs settles onto it,
// reported). Whether the equilibrium is stable does not depend on q_rest at all: the Hessian
// of the potential, H = 𝕂 − ∂f/∂q, has no q_rest in it. So a shape that is unstable (H not
// positive definite, e.g. a long strand held out sideways, which lowers its weight by
// twisting over) can be held by no natural shape; nor can one whose q_rest curls tighter
// than the fibre allows. Those get the closest stable shape instead: the equilibrium the
// strand settles into from the given shape, its rest shape made exactly balanced there.
// docs/super-helix.md, "Sag-free rest shape".
#include "common/Status.h"
#include "contact/ContactResponse.h"
#include "model/GroomReport.h"
#include "superhelix/SuperHelix.h"

#include <Eigen/Core>

#include <string>

namespace hair
{

struct SagFreeResult
{
  Eigen::VectorXd rest;  ///< q_rest, 3N values
  Eigen::VectorXd start; ///< the shape to start from: the given one, or the closest stable one
  RestOutcome outcome = RestOutcome::Held;
  /// Largest distance between the given shape and `start`, at 8 points per element [m].
  double deviation = 0;
  /// Smallest eigenvalue of H at the shape asked for over the largest entry of 𝕂 (> margin:
  /// stable); the shape used instead is stable unless the reason says otherwise.
  double stability = 0;
  /// |𝕂 (start − rest) − f(start)| / |f(start)|: round-off when the balance is exact.
  double imbalance = 0;
  std::string reason; ///< for Unstable and BeyondBending: what cannot be held, in words
};

/// The sag-free rest shape of the strand `spec` (its hair, element lengths, gravity, tip
/// force and root pose at t = 0, held still; its wind is not part of the balance) in the
/// shape `shape` (3N values), against `contacts` (the body's response with the body at rest,
/// called with the strand's id and t = 0; empty: none).
Status sagFree(const StrandSpec& spec, const Eigen::VectorXd& shape, const ContactForces& contacts,
               const SagFreeOptions& options, SagFreeResult& result);

/// H = 𝕂 − ∂f/∂q (central differences of the generalized force at rest, contacts included)
/// of `spec` held still in `shape`, and f(shape): what sagFree balances and tests (exposed for
/// the tests).
Status restHessian(const StrandSpec& spec, const Eigen::VectorXd& shape,
                   const ContactForces& contacts, Eigen::MatrixXd& hessian, Eigen::VectorXd& force);

} // namespace hair

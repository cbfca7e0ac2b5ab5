#pragma once
// A Super-Helix fitted to a guide curve (a polyline, root first): the N elements' constant
// twist and curvatures q = (τ, κ1, κ2) per element, the root tangent and the strand's
// length, such that the reconstructed centreline passes as close as possible to every point
// of the curve (least squares on positions: the orthogonal distance of each point to the
// strand). A curve that is itself a Super-Helix of N elements is recovered to round-off; a
// smooth curve's error falls as N⁻³ (docs/super-helix.md, "Fitting a guide curve").
#include "common/Status.h"

#include <Eigen/Core>

#include <vector>

namespace hair
{

struct SuperHelixFit
{
  /// (τ, κ1, κ2) of each element in its material frame, chained from `rootFrame` (3N values).
  Eigen::VectorXd q;
  /// The root's material frame: n0 the fitted tangent at the root, n1 the scalp normal made
  /// perpendicular to it (orthonormalFrame(n0, normal)), n2 = n0 × n1.
  Eigen::Matrix3d rootFrame = Eigen::Matrix3d::Identity();
  /// The fitted strand's length [m] (elements of length / N each); the polyline's own
  /// length is a lower bound of it (chords are shorter than arcs).
  double length = 0;
  /// Largest and root-mean-square distance of the curve's points to the fitted strand [m].
  double maxError = 0, rmsError = 0;
  int iterations = 0; ///< of the global Gauss–Newton (Levenberg–Marquardt) refinement
};

/// Fits N = `elements` equal Super-Helix elements to `curve` (at least two points, finite, no
/// two consecutive points closer than 1e-12 of its length: GuideCurves checks them first).
/// The root is curve[0] exactly; `normal` orients the root's material frame (any vector not
/// parallel to the root tangent; the scalp normal). Curves with fewer than four points per
/// element are first refined by points on their chords (so that the fit is determined).
/// `twistWeight` [m⁴] > 0 adds twistWeight Σ (τ_e − twistPrior)² to the sum of squares: on a
/// nearly straight element the positions do not determine the twist, and a fit left free
/// there can return twists of 1e3–1e7 1/m that no step can take (measured on grooms of
/// straight hair settled on the body: the first step blew up).
Status fitSuperHelix(const std::vector<Eigen::Vector3d>& curve, const Eigen::Vector3d& normal,
                     int elements, SuperHelixFit& fit, double twistWeight = 0,
                     double twistPrior = 0);

/// The centreline of the Super-Helix (q, rootFrame, root, equal elements of `length` / N) at
/// arc lengths `s` (each clamped to [0, length]): the fit's own forward map, for tests and
/// reports (drawSuperHelix, helix/Centerline.h, draws the same curve at equal steps).
void superHelixPoints(const Eigen::VectorXd& q, const Eigen::Matrix3d& rootFrame,
                      const Eigen::Vector3d& root, double length, const std::vector<double>& s,
                      std::vector<Eigen::Vector3d>& points);

} // namespace hair

#pragma once
// Private to Core/superhelix/: what the SuperHelix translation units share and the public
// header does not show. The per-thread step workspace (the matrices and buffers that every
// step rebuilds and only that step reads) and the small 3 × 3 helper that several phases of
// the step use. Other layers include SuperHelix.h only.
#include "contact/ContactResponse.h"

#include <Eigen/Core>
#include <Eigen/LU>

#include <cstdint>
#include <vector>

namespace hair::detail
{

// Rebuilt by every step and used only inside it: one copy per thread, not per strand. With
// a thousand strands stepped in turn, a strand's own data comes from memory on each step;
// the four (3N)² matrices would be most of it (29 KB at N = 10) and stay in cache instead.
// SuperHelix::massMatrix(), velocityJacobian() and tensionStiffness() return the last ones
// built on the calling thread.
struct StepWorkspace
{
  Eigen::MatrixXd M, C, Kt;                // mass matrix, velocity Jacobian, tension stiffness
  Eigen::MatrixXd Lhs;                     // the step's matrix, then its LU factors
  Eigen::VectorXd Rhs;                     // the step's right-hand side, then q̇ⁿ⁺¹
  std::vector<int> Pivots;                 // row interchanges of the unblocked LU (small N)
  Eigen::PartialPivLU<Eigen::MatrixXd> Lu; // large N
  // The contact hook's response at the current samples of the strand being stepped (same
  // index as the samples): valid while SuperHelix::ContactsSet is true.
  std::vector<ContactResponse> ContactBuffer;
  // The explicit load per unit length at each sample, set by assemble() for
  // assembleTensionStiffness (same index as the samples).
  std::vector<Eigen::Vector3d> Loads;
  // Which reconstruction Loads belong to (SuperHelix::CurId): assembleTensionStiffness
  // re-assembles when they are another strand's or another state's.
  std::uint64_t LoadsId = 0;
};

// Up to this size (3N) the step's matrix is factorized by luSolveInPlace (DenseLu.h), in
// place in StepWorkspace::Lhs with its Pivots, larger ones by Eigen's blocked PartialPivLU
// (StepWorkspace::Lu). In whole steps of the wavy strand (alternated processes) ours is
// faster up to 3N = 360 (N = 120: 1.9–3.1 ms a step against 4.0–4.2 ms); at 3N = 480 the
// two are within the noise.
constexpr int UnblockedLuMax = 360;

/// The calling thread's workspace.
StepWorkspace& stepWorkspace();

// [v]× m, column by column (cheaper than a 3 × 3 product with skew(v)).
EIGEN_STRONG_INLINE Eigen::Matrix3d crossCols(const Eigen::Vector3d& v, const Eigen::Matrix3d& m)
{
  Eigen::Matrix3d r;
  r.col(0) = v.cross(m.col(0));
  r.col(1) = v.cross(m.col(1));
  r.col(2) = v.cross(m.col(2));
  return r;
}

} // namespace hair::detail

// The implicit contact terms of the step (SuperHelix::addContactJacobians): the contact hook's
// linearized response adds Σ w Jᵀ (h² K + h D) J to the step's matrix (h: the step, or BDF2's
// weight β) and the matching terms to its right-hand side, from per-element moments of the samples
// in contact and tail sums, O(N²) per strand plus O(1) per sample in contact.
#include "superhelix/SuperHelix.h"

#include "superhelix/StepKernels.h"
#include "superhelix/SuperHelixInternal.h"

#include <algorithm>
#include <vector>

namespace hair
{

using detail::crossCols;
using detail::stackedProductAdd;

void SuperHelix::addContactJacobians(double h, bool aboutPrediction)
{
  // Backward Euler on the linearized contact force f − K h (v0 + J q̇ⁿ⁺¹) − D J (q̇ⁿ⁺¹ − q̇ⁿ):
  //   Lhs += Σ w Jᵀ S J,  S = h² K + h D,  Rhs += Σ w Jᵀ b,  b = h D J q̇ⁿ − h² K v0.
  // BDF2, about its prediction (x*, v* = v0 + J q̇*) of the step's end, where the step moves
  // the sample by x − x* = β J (q̇ⁿ⁺¹ − q̇*): the force f − (β K + D) J (q̇ⁿ⁺¹ − q̇*), so
  //   S = β² K + β D,  b = S J q̇* (h = β).
  // A sample of element e has J_p = −[r]× A_p + W_p = H(r) Z_p for p < e, with
  // H(r) = [−[r]×  I] (3 × 6) and Z_p = [A_p; W_p] (6 × 3), its own block J_e, and 0 past e.
  // So only per-element moments of the samples in contact are summed,
  //   Φ_e = Σ w Hᵀ S H (6 × 6), Ψ_e = Σ w Hᵀ S J_e, Ψ'_e = Σ w J_eᵀ S H, Ω_e = Σ w J_eᵀ S J_e,
  //   β_e = Σ w Hᵀ b, γ_e = Σ w J_eᵀ b,
  // and with the tail T_q = Σ_{e > q} Φ_e (and β's), for p < q:
  //   block(p, q) = Z_pᵀ (T_q Z_q + Ψ_q),  block(q, p) = (Z_qᵀ T_q + Ψ'_q) Z_p,
  //   block(q, q) = Z_qᵀ T_q Z_q + Ω_q,   Rhs_q = Z_qᵀ Σ_{e > q} β_e + γ_q:
  // O(N²) per strand plus O(1) per sample in contact, like the mass matrix. (Forming
  // Σ w Jᵀ S J sample by sample costs O(e²) per sample: a 40-element strand lying on the
  // scalp takes 3 × the step without contacts.) S need not be symmetric (friction).
  using Mat6 = Eigen::Matrix<double, 6, 6>;
  using Mat63 = Eigen::Matrix<double, 6, 3>;
  using Mat36 = Eigen::Matrix<double, 3, 6>;
  using Vec6 = Eigen::Matrix<double, 6, 1>;
  struct Moments
  {
    Mat6 phi;
    Mat63 psi;
    Mat36 psiT;
    Eigen::Matrix3d omega;
    Vec6 beta;
    Eigen::Vector3d gamma;
  };
  const int n = elementCount();
  detail::StepWorkspace& ws = detail::stepWorkspace();
  const std::vector<ContactResponse>& responses = ws.ContactBuffer;
  Eigen::MatrixXd& Lhs = ws.Lhs;
  Eigen::VectorXd& Rhs = ws.Rhs;
  thread_local std::vector<Moments> mom;
  thread_local std::vector<char> touched;
  mom.resize(n);
  touched.assign(n, 0);
  int last = -1;
  for (size_t j = 0; j < Cur.nodes.size(); ++j)
  {
    const Node& nd = Cur.nodes[j];
    if (!nd.hasK && !nd.hasD)
      continue;
    // K and D stay in the hook's buffer (hasK/hasD are set only from it, this step).
    const Eigen::Matrix3d& contactK = responses[j].stiffness;
    const Eigen::Matrix3d& contactD = responses[j].damping;
    Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    if (nd.hasK)
    {
      S += (nd.w * h * h) * contactK;
      b -= (nd.w * h * h) * (contactK * (aboutPrediction ? nd.v0 - nd.v : nd.v0));
    }
    if (nd.hasD)
    {
      S += (nd.w * h) * contactD;
      b += (nd.w * h) * (contactD * (nd.v - nd.v0)); // J q̇ⁿ = v − v0
    }
    const int e = nd.element;
    Moments& m = mom[e];
    if (!touched[e])
    {
      m.phi.setZero();
      m.psi.setZero();
      m.psiT.setZero();
      m.omega.setZero();
      m.beta.setZero();
      m.gamma.setZero();
      touched[e] = 1;
    }
    last = std::max(last, e);
    // S H = [−S [r]×  S] and Hᵀ X = [[r]× X; X] ((−[r]×)ᵀ = [r]×); −X [r]× = ([r]× Xᵀ)ᵀ.
    const Eigen::Matrix3d SR = crossCols(nd.r, S.transpose()).transpose(); // −S [r]×
    const Eigen::Matrix3d SJ = S * nd.J, JtS = nd.J.transpose() * S;
    m.phi.block<3, 3>(0, 0) += crossCols(nd.r, SR);
    m.phi.block<3, 3>(0, 3) += crossCols(nd.r, S);
    m.phi.block<3, 3>(3, 0) += SR;
    m.phi.block<3, 3>(3, 3) += S;
    m.psi.topRows<3>() += crossCols(nd.r, SJ);
    m.psi.bottomRows<3>() += SJ;
    m.psiT.leftCols<3>() += crossCols(nd.r, JtS.transpose()).transpose(); // −Jᵀ S [r]×
    m.psiT.rightCols<3>() += JtS;
    m.omega.noalias() += JtS * nd.J;
    m.beta.head<3>() += nd.r.cross(b);
    m.beta.tail<3>() += b;
    m.gamma.noalias() += nd.J.transpose() * b;
  }
  if (last < 0)
    return;
  // The stack of the rows Z_pᵀ = [A_pᵀ W_pᵀ], as for M and C.
  thread_local Eigen::Matrix<double, Eigen::Dynamic, 6> B;
  if (B.rows() < 3 * n)
    B.resize(3 * n, 6);
  for (int p = 0; p <= last; ++p)
  {
    B.block<3, 3>(3 * p, 0) = Cur.elements[p].A.transpose();
    B.block<3, 3>(3 * p, 3) = Cur.elements[p].W.transpose();
  }
  const Eigen::Index ld = Lhs.rows(), lds = B.rows();
  Mat6 T = Mat6::Zero();
  Vec6 tailBeta = Vec6::Zero();
  for (int q = last; q >= 0; --q)
  {
    const Mat63 Z = B.block<3, 6>(3 * q, 0).transpose(); // [A_q; W_q]
    Mat63 upper = T * Z;                                 // T_q Z_q (+ Ψ_q below)
    Mat36 lower = Z.transpose() * T;                     // Z_qᵀ T_q (+ Ψ'_q below)
    Eigen::Matrix3d diag = Z.transpose() * upper;
    Eigen::Vector3d rhs = Z.transpose() * tailBeta;
    if (touched[q])
    {
      const Moments& m = mom[q];
      upper += m.psi;
      lower += m.psiT;
      diag += m.omega;
      rhs += m.gamma;
      T += m.phi;
      tailBeta += m.beta;
    }
    Lhs.block<3, 3>(3 * q, 3 * q) += diag;
    Rhs.segment<3>(3 * q) += rhs;
    // Rows p < q of column block q, and columns p < q of row block q (transposed: the
    // same stacked product with lowerᵀ, written to the mirrored places).
    const Eigen::Matrix<double, 6, 3> lowerT = lower.transpose();
    stackedProductAdd<6>(Lhs.data() + 3 * q * ld, 1, ld, B.data(), lds, upper.data(), 3 * q);
    stackedProductAdd<6>(Lhs.data() + 3 * q, ld, 1, B.data(), lds, lowerT.data(), 3 * q);
  }
}

} // namespace hair

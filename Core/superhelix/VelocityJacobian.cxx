// The velocity Jacobian C = ∂f/∂q̇ (SuperHelix::assembleVelocityJacobian): per-element
// moments of the samples, summed sample by sample (SampleMoments) or contracted from a Gram
// matrix of the helix functions (FunctionGram, for elements with at least
// StrandSpec::gramMinSamples samples), then each column block in O(N) by propagating the
// change of the frame's motion along the strand.
#include "superhelix/SuperHelix.h"

#include "common/Multiversioning.h"
#include "helix/HelixFunctions.h"
#include "superhelix/StepKernels.h"
#include "superhelix/SuperHelixInternal.h"

#include <vector>

namespace hair
{

using detail::crossCols;
using detail::lowerAndPropagate;
using detail::stackedProduct;

namespace
{
// The per-sample moments behind the velocity Jacobian's element maps (see
// assembleVelocityJacobian), summed in plain arrays (column-major 3 × 3 blocks): the same
// sums written with Eigen's 3 × 3 expressions take 9 % more of C's instructions on fuzzy
// hair (4 % on smooth).
//   PJ = Σ w J,  N_a = Σ w J_a Fgᵀ,  X = Σ w (J_0 × J_1, J_0 × J_2, J_1 × J_2),
//   S2 = Σ w Fg Fgᵀ,  with Y = w F0 D (D = D²g[k̇, ·]):  Qm = Σ Jᵀ Y,  SD = Σ Y,  R = Σ [Fg]× Y.
struct SampleMoments
{
  double sc = 0, sF[3] = {}, PJ[9] = {}, N[27] = {}, X[9] = {}, S2[9] = {}, Qm[9] = {}, SD[9] = {},
         R[9] = {};

  HAIR_AVX2_CLONES
  void add(double w, const double* __restrict J, const Eigen::Vector3d& fgv,
           const double* __restrict y)
  {
    const double f[3] = {fgv[0], fgv[1], fgv[2]};
    double wj[9];
    for (int i = 0; i < 9; ++i)
      wj[i] = w * J[i];
    sc += w;
    for (int i = 0; i < 3; ++i)
      sF[i] += w * f[i];
    for (int i = 0; i < 9; ++i)
      PJ[i] += wj[i];
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 3; ++c)
        for (int b = 0; b < 3; ++b)
          N[9 * a + 3 * c + b] += wj[3 * a + b] * f[c];
    const double* const j1 = J + 3;
    const double* const j2 = J + 6;
    const double* const v0 = wj;
    const double* const v1 = wj + 3;
    X[0] += v0[1] * j1[2] - v0[2] * j1[1];
    X[1] += v0[2] * j1[0] - v0[0] * j1[2];
    X[2] += v0[0] * j1[1] - v0[1] * j1[0];
    X[3] += v0[1] * j2[2] - v0[2] * j2[1];
    X[4] += v0[2] * j2[0] - v0[0] * j2[2];
    X[5] += v0[0] * j2[1] - v0[1] * j2[0];
    X[6] += v1[1] * j2[2] - v1[2] * j2[1];
    X[7] += v1[2] * j2[0] - v1[0] * j2[2];
    X[8] += v1[0] * j2[1] - v1[1] * j2[0];
    for (int c = 0; c < 3; ++c)
      for (int b = 0; b < 3; ++b)
        S2[3 * c + b] += w * f[b] * f[c];
    for (int c = 0; c < 3; ++c)
      for (int a = 0; a < 3; ++a)
        Qm[3 * c + a] +=
            J[3 * a] * y[3 * c] + J[3 * a + 1] * y[3 * c + 1] + J[3 * a + 2] * y[3 * c + 2];
    for (int i = 0; i < 9; ++i)
      SD[i] += y[i];
    for (int c = 0; c < 3; ++c)
    {
      const double* const yc = y + 3 * c;
      R[3 * c] += f[1] * yc[2] - f[2] * yc[1];
      R[3 * c + 1] += f[2] * yc[0] - f[0] * yc[2];
      R[3 * c + 2] += f[0] * yc[1] - f[1] * yc[0];
    }
  }
};

// The same moments from a Gram matrix of scalar functions, for elements with many samples.
// Every per-sample quantity above is linear in seven functions of u with coefficients that
// are constant on the element (helixPoint, helixBilinear), in the element's start frame:
//   f = (u, a = u²φ1, b = u³φ2, c1 = u⁴ψ1, c2 = u⁵ψ2, e6 = u⁶χ1, e7 = u⁷χ2)  (φ, ψ, χ of Ω u),
//   g = u e0 + a k×e0 + b k×(k×e0)                       (f0, f1, f2),
//   ∂g/∂k = a [e_i × e0]_i + b (k0 I − 2 e0 kᵀ + k e0ᵀ) + c1 (k×e0) kᵀ + c2 k×(k×e0) kᵀ
//                                                        (f1 … f4),
//   D = D²g[k̇, ·] = helixBilinearValues(k, k̇, f2, f3, f4, f5, f6)  (f2 … f6),
// and J = F0 ∂g/∂k, Fg = F0 g, Y = w F0 D. So each moment is a contraction of the Gram
// matrix Σ w f_i f_j (28 numbers) and the sums Σ w f_i with those coefficients, e.g.
// Σ w J_a Fgᵀ = F0 (Σ_ij G_ij ∂g_i/∂k_a g_jᵀ) F0ᵀ, Σ Jᵀ Y = Σ_ij G_ij (∂g_i/∂k)ᵀ D_j and
// Σ w J_a × J_b = F0 Σ_ij G_ij ∂g_i/∂k_a × ∂g_j/∂k_b (F0 a proper rotation). Per sample
// that is 35 products instead of SampleMoments::add and helixBilinear; the contraction is a
// fixed cost per element, which pays from StrandSpec::gramMinSamples samples on.
struct FunctionGram
{
  double sw = 0, m[7] = {}, G[7][7] = {}; // G: upper triangle while summing

  void add(double w, double u, const HelixCoefficients& c)
  {
    double f[7];
    helixFunctionValues(u, c, f);
    sw += w;
    for (int i = 0; i < 7; ++i)
    {
      const double wf = w * f[i];
      m[i] += wf;
      for (int j = i; j < 7; ++j)
        G[i][j] += wf * f[j];
    }
  }

  // The moments of SampleMoments from the sums, for curvature k, rate kd and start frame F0.
  // The helix kernels are linear in the functions' values, so a row of G passed as values
  // gives Σ_h G_fh (coefficient of h) without forming the coefficient matrices.
  void moments(const Eigen::Vector3d& k, const Eigen::Vector3d& kd, const Eigen::Matrix3d& F0,
               SampleMoments& out)
  {
    for (int i = 0; i < 7; ++i)
      for (int j = 0; j < i; ++j)
        G[i][j] = G[j][i];
    using M3 = Eigen::Matrix3d;
    using V3 = Eigen::Vector3d;
    // Coefficients of g (functions 0 … 2: e0, k×e0, k×(k×e0)) and of ∂g/∂k (1 … 4).
    V3 g[3];
    for (int f = 0; f < 3; ++f)
      helixGValues(k, f == 0, f == 1, f == 2, g[f]);
    M3 dg[5];
    for (int f = 1; f < 5; ++f)
      helixJacobianValues(k, f == 1, f == 2, f == 3, f == 4, dg[f]);
    // Rows of G contracted: T_f = Σ_h G_fh g_h, U_f = Σ_h G_fh ∂g_h, V_f = Σ_h G_fh D_h.
    V3 T[5];
    M3 U[5], V[5];
    for (int f = 0; f < 5; ++f)
    {
      const double* r = G[f];
      helixGValues(k, r[0], r[1], r[2], T[f]);
      helixJacobianValues(k, r[1], r[2], r[3], r[4], U[f]);
      helixBilinearValues(k, kd, r[2], r[3], r[4], r[5], r[6], V[f]);
    }
    V3 sF;
    M3 PJ, SD;
    helixGValues(k, m[0], m[1], m[2], sF);
    helixJacobianValues(k, m[1], m[2], m[3], m[4], PJ);
    helixBilinearValues(k, kd, m[2], m[3], m[4], m[5], m[6], SD);
    // Σ w ∂g_a gᵀ = Σ_h U_h(:, a) g_hᵀ, Σ w g gᵀ = Σ_f g_f T_fᵀ, Σ w [g]× D = Σ_f [g_f]× V_f,
    // Σ w ∂g_a × ∂g_b = Σ_f ∂g_f(:, a) × U_f(:, b), Σ w ∂gᵀ D = Σ_f ∂g_fᵀ V_f.
    M3 Nl[3], S2 = M3::Zero(), R = M3::Zero(), Qm = M3::Zero();
    for (int a = 0; a < 3; ++a)
      Nl[a].noalias() = U[0].col(a) * g[0].transpose() + U[1].col(a) * g[1].transpose() +
                        U[2].col(a) * g[2].transpose();
    for (int f = 0; f < 3; ++f)
    {
      S2.noalias() += g[f] * T[f].transpose();
      R += crossCols(g[f], V[f]);
    }
    V3 X[3] = {V3::Zero(), V3::Zero(), V3::Zero()};
    for (int f = 1; f < 5; ++f)
    {
      X[0] += dg[f].col(0).cross(U[f].col(1));
      X[1] += dg[f].col(0).cross(U[f].col(2));
      X[2] += dg[f].col(1).cross(U[f].col(2));
      Qm.noalias() += dg[f].transpose() * V[f];
    }
    out.sc = sw;
    Eigen::Map<V3>(out.sF) = F0 * sF;
    Eigen::Map<M3>(out.PJ) = F0 * PJ;
    for (int a = 0; a < 3; ++a)
    {
      Eigen::Map<M3>(out.N + 9 * a) = F0 * Nl[a] * F0.transpose();
      Eigen::Map<V3>(out.X + 3 * a) = F0 * X[a];
    }
    Eigen::Map<M3>(out.S2) = F0 * S2 * F0.transpose();
    Eigen::Map<M3>(out.Qm) = Qm;
    Eigen::Map<M3>(out.SD) = F0 * SD;
    Eigen::Map<M3>(out.R) = F0 * R;
  }
};

} // namespace

void SuperHelix::assembleVelocityJacobian()
{
  // C = ∂f/∂q̇ with f ∋ −ρS a0: a0 is quadratic in q̇ (plus root-coupled linear terms).
  // A change δq̇ of element Q changes, at the start of each later element, the frame's
  // angular velocity δω, its q̈ = 0 angular acceleration δα and the point's acceleration
  // δa; inside an element the change at a sample is linear in those three:
  //   δa0 = δa − [Fg]× δα + Φ δω,  Φ = −[ω × Fg]× − [ω]× [Fg]× − 2 [J k̇]×,
  // so per-element moments of these maps give each column block in O(N).
  const int n = elementCount();
  Eigen::MatrixXd& C = detail::stepWorkspace().C;
  C.resize(3 * n, 3 * n); // per-thread buffer
  const Kinematics& k = Cur;
  struct Maps
  {
    // Moments over the element's samples of the maps (δa, δα, δω) ↦ δa0 (P: weighted by
    // Jᵀ, S: plain, T: by [r]×), and what is handed on to the next element.
    Eigen::Matrix3d Pc, Pl, Po, So, Tl, To, PhiEnd;
    Eigen::Vector3d sumFg, sumR, fgEnd, akd;
    double Sc;
    // The element's own k̇-dependence: moments of δa0 (own samples), and (δα, δa) at its end.
    Eigen::Matrix3d ownR, ownF, ownM, Dal0, Dac0;
  };
  thread_local std::vector<Maps> maps;
  maps.resize(n);
  // Φ = −[ω × Fg]× − [ω]× [Fg]× − 2 [J k̇]× = −2 Fg ωᵀ + ω Fgᵀ + (ω·Fg) I − 2 [J k̇]×
  // ([a × b]× = b aᵀ − a bᵀ, [a]× [b]× = b aᵀ − (a·b) I); linear in (Fg, J k̇).
  auto phi = [](const Eigen::Vector3d& om, const Eigen::Vector3d& fg, const Eigen::Vector3d& jkd)
  {
    Eigen::Matrix3d m = om * fg.transpose() - 2 * fg * om.transpose() - 2 * skew(jkd);
    m.diagonal().array() += om.dot(fg);
    return m;
  };
  Eigen::Matrix3d D2W, DGW;
  for (int e = 0; e < n; ++e)
  {
    const Element& el = k.elements[e];
    const Eigen::Vector3d kq = Q.segment<3>(3 * e), kd = Qdot.segment<3>(3 * e);
    const Eigen::Vector3d& om = el.omega0;
    Maps& m = maps[e];
    // Every moment above is linear in a few per-sample moments (ω and k̇ are the element's),
    // so only those (SampleMoments) are summed over the samples, and contracted here once
    // per element.
    SampleMoments sm;
    if (el.count >= Spec.gramMinSamples)
    {
      FunctionGram fg;
      for (int j = el.first; j < el.first + el.count; ++j)
        fg.add(k.nodes[j].w, k.nodes[j].u, k.nodes[j].coefficients);
      fg.moments(kq, kd, el.F0, sm);
    }
    else
    {
      // Y = w F0 D²g[k̇, ·] = w Σ_i f_i FB_i (helixBilinearBasis, once per element).
      Eigen::Matrix3d FB[5];
      helixBilinearBasis(kq, kd, el.F0, FB);
      for (int j = el.first; j < el.first + el.count; ++j)
      {
        const Node& nd = k.nodes[j];
        double f[7], y[9];
        helixFunctionValues(nd.u, nd.coefficients, f);
        for (int c = 0; c < 9; ++c)
          y[c] = nd.w * (f[2] * FB[0].data()[c] + f[3] * FB[1].data()[c] + f[4] * FB[2].data()[c] +
                         f[5] * FB[3].data()[c] + f[6] * FB[4].data()[c]);
        sm.add(nd.w, nd.J.data(), nd.r - el.r0, y);
      }
    }
    using M3 = Eigen::Map<const Eigen::Matrix3d>;
    using V3 = Eigen::Map<const Eigen::Vector3d>;
    const M3 PJ(sm.PJ), S2(sm.S2), Qm(sm.Qm), SD(sm.SD), R(sm.R);
    const M3 N[3] = {M3(sm.N), M3(sm.N + 9), M3(sm.N + 18)};
    const V3 X01(sm.X), X02(sm.X + 3), X12(sm.X + 6), sF(sm.sF);
    const double sc = sm.sc;
    // Σ_a k̇_a N_a = Σ w (J k̇) Fgᵀ, and J_a·Fg, J_a·ω, (Fg·ω) J_a, J_a × J k̇ summed.
    const Eigen::Matrix3d JkdF = kd[0] * N[0] + kd[1] * N[1] + kd[2] * N[2];
    const Eigen::Vector3d Xa[3] = {kd[1] * X01 + kd[2] * X02, kd[2] * X12 - kd[0] * X01,
                                   -kd[0] * X02 - kd[1] * X12}; // Σ w J_a × J k̇
    m.Sc = sc;
    m.sumFg = sF;
    m.sumR = sc * el.r0 + sF;
    m.Pc = PJ.transpose();
    Eigen::Vector3d trN, nOm[3];
    for (int a = 0; a < 3; ++a)
    {
      const M3& Na = N[a];
      trN[a] = Na.trace();        // Σ w J_a·Fg
      nOm[a].noalias() = Na * om; // Σ w (Fg·ω) J_a
      // −Jᵀ [Fg]× = ([Fg]× J)ᵀ: row a is Σ w Fg × J_a.
      m.Pl.row(a) << Na(2, 1) - Na(1, 2), Na(0, 2) - Na(2, 0), Na(1, 0) - Na(0, 1);
      // Jᵀ Φ, row a: (J_a·ω) Fgᵀ − 2 (J_a·Fg) ωᵀ + (ω·Fg) J_aᵀ − 2 (J_a × J k̇)ᵀ.
      m.Po.row(a) = (Na.transpose() * om + nOm[a] - 2 * trN[a] * om - 2 * Xa[a]).transpose();
    }
    // −[r]× [Fg]× = (r·Fg) I − Fg rᵀ with r = r0 + Fg.
    m.Tl = -S2 - sF * el.r0.transpose();
    m.Tl.diagonal().array() += el.r0.dot(sF) + S2.trace();
    const Eigen::Vector3d sumJkd = PJ * kd;
    m.So = phi(om, sF, sumJkd); // Σ w Φ
    // Σ w [r]× Φ = [r0]× Σ w Φ + Σ w [Fg]× Φ, and [Fg]× Φ = −[ω]× Fg Fgᵀ + (ω·Fg) [Fg]×
    // − 2 (J k̇ Fgᵀ − (Fg·J k̇) I).
    m.To = crossCols(el.r0, m.So) - crossCols(om, S2) + skew(S2 * om) - 2 * JkdF;
    m.To.diagonal().array() += 2 * JkdF.trace();
    // Own element: δa0 = 2 ([ω]× J + F0 D²g[k̇, ·]) δk̇ at a sample. Jᵀ [ω]× J has the
    // entries J_a·(ω × J_b) = −ω·(J_a × J_b).
    const double o01 = om.dot(X01), o02 = om.dot(X02), o12 = om.dot(X12);
    m.ownR << 0, -o01, -o02, o01, 0, -o12, o02, o12, 0;
    m.ownR = 2 * (m.ownR + Qm);
    m.ownF = 2 * (crossCols(om, PJ) + SD);
    // Σ w [Fg]× [ω]× J: column a is ω (J_a·Fg) − N_a ω.
    m.ownM = crossCols(el.r0, m.ownF);
    for (int a = 0; a < 3; ++a)
      m.ownM.col(a) += 2 * (trN[a] * om - nOm[a] + R.col(a));
    m.PhiEnd = phi(om, el.fgEnd, el.jkdEnd);
    m.fgEnd = el.fgEnd;
    m.akd = el.akd;
    helixBilinear(kq, kd, Spec.elementLengths[e], D2W, &DGW, &el.endCoefficients);
    m.Dal0 = crossCols(om, el.A) + 2 * el.F0 * DGW;
    m.Dac0 = 2 * (crossCols(om, el.jEnd) + el.F0 * D2W);
  }
  // For a column block qe, the state S_p = [δa; δα; δω] (9 × 3) at the start of each later
  // element p evolves linearly, S_{p+1} = Prop_p S_p with
  //   Prop_p = [I, −[Fg_end]×, Φ_end; 0, I, −[A k̇]×; 0, 0, I],
  // starting from S_{qe+1} = [Dac0; Dal0; A]_qe, and element p contributes R_p = P_p S_p to
  // its own row, [M_p; F_p] = Mm_p S_p to the tail torque and force felt by the rows before
  // it (row p sees A_pᵀ tailM + W_pᵀ tailF).
  // Backward, once: Λ_p = Mm_p + Λ_{p+1} Prop_p gives Σ_{p' >= p} [M_p'; F_p'] = Λ_p S_p, so
  // row p > qe is C_p,qe = G_p S_p with G_p = −ρS (P_p + [A_pᵀ W_pᵀ] Λ_{p+1} Prop_p),
  // independent of qe. Carried backward as well, the stack Γ_m (rows p >= m: the 3 × 9 maps
  // G_p Prop_{p−1} ⋯ Prop_m) gives the whole column block qe below the diagonal as ONE
  // product Γ_{qe+1} S_{qe+1} over long columns, and Γ_m = [G_m; Γ_{m+1} Prop_m] is a
  // product on long columns too (3 × 3 products block by block vectorize poorly).
  // Above the diagonal the whole tail from qe acts rigidly, C_p,qe = A_pᵀ TM + W_pᵀ TF: one
  // product B_{p<qe} [TM; TF] with B the 3N × 6 stack of the rows [A_pᵀ W_pᵀ].
  // The buffers only grow: nothing is allocated per step.
  thread_local Eigen::Matrix<double, Eigen::Dynamic, 6> B;
  thread_local Eigen::Matrix<double, Eigen::Dynamic, 9> Gam; // rows 3p..3p+2: the row p of Γ_m
  if (B.rows() < 3 * n)
  {
    B.resize(3 * n, 6);
    Gam.resize(3 * n, 9);
  }
  for (int p = 0; p < n; ++p)
  {
    B.block<3, 3>(3 * p, 0) = k.elements[p].A.transpose();
    B.block<3, 3>(3 * p, 3) = k.elements[p].W.transpose();
  }
  const Eigen::Index ldc = C.rows(), ldg = Gam.rows();
  // Λ_{qe+1} as one 6 × 9 matrix: rows 0–2 the tail torque, 3–5 the tail force; columns
  // (δa, δα, δω). Six-row products vectorize in three packets, where eighteen 3 × 3
  // products of the same sums would leave a row over in each.
  Eigen::Matrix<double, 6, 9> L = Eigen::Matrix<double, 6, 9>::Zero();
  for (int qe = n - 1; qe >= 0; --qe)
  {
    const Maps& mq = maps[qe];
    const Element& eq = k.elements[qe];
    // Column block qe. State at the start of element qe + 1, S = [Dac; Dal; Dw].
    Eigen::Matrix<double, 9, 3> S;
    S.topRows<3>() = mq.Dac0;
    S.middleRows<3>(3) = mq.Dal0;
    S.bottomRows<3>() = eq.A;
    // Tail torque and force from the elements past qe, [HM; HF] = Λ S.
    Eigen::Matrix<double, 6, 3> H;
    H.noalias() = L * S;
    const Eigen::Matrix<double, 3, 6> Bq = B.block<3, 6>(3 * qe, 0); // [A_qeᵀ W_qeᵀ]
    Eigen::Matrix3d b = mq.ownR;
    b.noalias() += Bq * H;
    C.block<3, 3>(3 * qe, 3 * qe) = -RhoS * b;
    // Rows p < qe: [TM; TF], the rigid tail's torque and force.
    Eigen::Matrix<double, 6, 3> T;
    T.topRows<3>() = -RhoS * (mq.ownM + H.topRows<3>());
    T.bottomRows<3>() = -RhoS * (mq.ownF + H.bottomRows<3>());
    double* const col = C.data() + 3 * qe * ldc;
    stackedProduct<6, false>(col, nullptr, ldc, B.data(), B.rows(), T.data(), 3 * qe);
    // Rows p > qe: Γ_{qe+1} S; then Γ_{qe+1} Prop_qe (the rows of Γ_qe past qe).
    lowerAndPropagate(col + 3 * qe + 3, ldc, Gam.data() + 3 * qe + 3, ldg, S.data(),
                      mq.PhiEnd.data(), mq.akd.data(), mq.fgEnd.data(), 3 * (n - qe - 1));
    // Λ_{qe+1} Prop_qe, block columns (δa, δα, δω): w += a Φ_end − l [A k̇]×, l −= a [Fg_end]×
    // (w first: it uses the old l).
    L.middleCols<3>(6).noalias() += L.leftCols<3>() * mq.PhiEnd;
    L.middleCols<3>(6).noalias() -= L.middleCols<3>(3) * skew(mq.akd);
    L.middleCols<3>(3).noalias() -= L.leftCols<3>() * skew(mq.fgEnd);
    // G_qe = −ρS (P_qe + [A_qeᵀ W_qeᵀ] Λ_{qe+1} Prop_qe): row qe of Γ_qe.
    Eigen::Matrix<double, 3, 9> G;
    G.leftCols<3>() = mq.Pc;
    G.middleCols<3>(3) = mq.Pl;
    G.rightCols<3>() = mq.Po;
    G.noalias() += Bq * L;
    Gam.block<3, 9>(3 * qe, 0) = -RhoS * G;
    // Λ_qe = Mm_qe + Λ_{qe+1} Prop_qe: tail torque [[Σ w r]×, Tl, To], force [Σ w I, −[Σ w Fg]×,
    // So].
    L.block<3, 3>(0, 0) += skew(mq.sumR);
    L.block<3, 3>(0, 3) += mq.Tl;
    L.block<3, 3>(0, 6) += mq.To;
    L.block<3, 3>(3, 0).diagonal().array() += mq.Sc;
    L.block<3, 3>(3, 3) -= skew(mq.sumFg);
    L.block<3, 3>(3, 6) += mq.So;
  }
}

} // namespace hair

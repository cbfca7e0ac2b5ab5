// The explicit side of the step: evaluateForces (the wind field and the contact hook at the
// current samples, checked), assemble() (the mass matrix M and the generalized force f,
// with the explicit load per unit length kept for K_T) and assembleTensionStiffness (K_T,
// the tension part of the loads' stiffness). Both matrices from tail sums over the
// elements: O(N²) with O(1) work per sample.
#include "superhelix/SuperHelix.h"

#include "helix/HelixFunctions.h"
#include "superhelix/StepKernels.h"
#include "superhelix/SuperHelixInternal.h"

#include <cmath>
#include <string>
#include <vector>

namespace hair
{

using detail::crossCols;
using detail::stackedProduct;

namespace
{
// The tension an explicit step carries, T_ex = ρS ℓ² / (64 h²): a string of tension T with
// nodes ℓ apart has its highest mode at ω = 2 √(T/ρS) / ℓ, so T_ex keeps h ω <= 1/4, an
// eighth of the explicit (symplectic Euler) limit h ω < 2. With 1/16 (h ω <= 1/2) the smooth
// N = 1 strand on the shaking head gains 0.011 J in 300 s (4.5 × the stability test's
// bound); with 1/64 and 1/256 every preset and N = 1…40 runs 60 s (N = 1, 2, 3: 600 s) with
// an energy gain below 6e-5 J; with no explicit share (K_T from T = 0 up) the
// falling-strand residual at dt = 1/8000 s is 4.5 × the explicit step's (docs/super-helix.md).
constexpr double ExplicitTensionDivisor = 64;
} // namespace

Status SuperHelix::evaluateForces(Kinematics& k, double time)
{
  ContactsSet = false;
  if (Spec.windField)
  {
    if (!WindsValid) // reconstruct() has evaluated it at these samples and this time
      fillWinds(time);
    for (size_t j = 0; j < k.nodes.size(); ++j)
      if (!Winds[j].allFinite())
        return Status::Error(
            "the wind at s = " + std::to_string(Starts[k.nodes[j].element] + k.nodes[j].u) +
            " m is not finite; check the wind field.");
  }
  if (Contacts)
  {
    // BDF2: the hook answers for the step's start (HookSamples, HookTime), as it does for
    // the semi-implicit step, and its linearization carries the response to the prediction
    // of the step's end, where the step is evaluated: f − K (x* − xⁿ) − D (v* − vⁿ), the push
    // less spring (x* − xⁿ). (The look-ahead and the surface's motion over the step in the
    // body's response are the semi-implicit step's; asked at the prediction they would be
    // counted twice.)
    const std::vector<StrandSample>& smp = HookSamples ? *HookSamples : samples();
    std::vector<ContactResponse>& buffer = detail::stepWorkspace().ContactBuffer;
    buffer.assign(k.nodes.size(), ContactResponse());
    Contacts(Spec.id, HookSamples ? HookTime : time, smp, buffer);
    if (buffer.size() != k.nodes.size())
      return Status::Error("the contact hook changed the size of the response buffer (" +
                           std::to_string(buffer.size()) + " instead of " +
                           std::to_string(k.nodes.size()) + "); write one response per sample.");
    if (HookSamples)
      for (size_t i = 0; i < k.nodes.size(); ++i)
      {
        ContactResponse& c = buffer[i];
        const Eigen::Vector3d dx = k.nodes[i].r - smp[i].position;
        const Eigen::Vector3d dv = k.nodes[i].v - smp[i].velocity;
        c.force -= c.stiffness * dx + c.damping * dv;
        if (c.spring != 0)
          c.push -= c.spring * dx;
      }
    for (size_t i = 0; i < k.nodes.size(); ++i)
    {
      Node& nd = k.nodes[i];
      const ContactResponse& c = buffer[i];
      nd.hasF = !c.force.isZero(0);
      nd.hasK = !c.stiffness.isZero(0);
      nd.hasD = !c.damping.isZero(0);
      nd.hasField = c.hasField();
      if (!c.force.allFinite())
        return Status::Error(
            "the contact force at s = " + std::to_string(Starts[nd.element] + nd.u) +
            " m is not finite; check the contact hook.");
      if (!c.stiffness.allFinite() || !c.damping.allFinite())
        return Status::Error(
            "the contact stiffness or damping at s = " + std::to_string(Starts[nd.element] + nd.u) +
            " m is not finite; check the contact hook.");
      if (nd.hasField && !(std::isfinite(c.drag) && c.drag >= 0 && std::isfinite(c.spring) &&
                           c.spring >= 0 && c.medium.allFinite() && c.push.allFinite()))
        return Status::Error(
            "the far-field response (drag, spring, medium velocity, push) at s = " +
            std::to_string(Starts[nd.element] + nd.u) +
            " m is not finite or negative; check the contact hook.");
    }
    ContactsSet = true;
  }
  if (!Spec.tipForce.allFinite())
    return Status::Error("the tip force is not finite.");
  return Status::Ok();
}

void SuperHelix::assemble()
{
  const int n = elementCount();
  detail::StepWorkspace& ws = detail::stepWorkspace();
  Eigen::MatrixXd& M = ws.M;
  M.resize(3 * n, 3 * n); // per-thread buffer (no-op when the size is kept)
  Kinematics& k = Cur;
  if (Spec.windField && !WindsValid)
    fillWinds(Time);
  // The explicit force per unit length at each sample: gravity, drag on the rigid
  // (root-carried) velocity against the wind, the inertia of the root motion and the
  // velocity-dependent terms, contacts (the q̇-part of drag is implicit). Kept in Loads for
  // assembleTensionStiffness. Thread-local buffers are reached once, not per sample.
  ws.Loads.resize(k.nodes.size());
  ws.LoadsId = CurId;
  Eigen::Vector3d* const loads = ws.Loads.data();
  const Eigen::Vector3d* const winds = Spec.windField ? Winds.data() : nullptr;
  const ContactResponse* const contacts = ContactsSet ? ws.ContactBuffer.data() : nullptr;
  const Eigen::Vector3d gravity = RhoS * Spec.gravity;
  const double nu = Spec.hair.airFriction;
  // The contact responses' far field (drag c towards `medium`, push with spring k), implicit
  // at no cost: backward Euler adds Σ w (h c + h² k) Jᵀ J to the step's matrix, which is M's
  // translational sum with ρS raised by (h c + h² k) / airScale at the sample (airScale: the
  // factor solve() gives M for the air's drag), and the right-hand side terms that M q̇ⁿ
  // then counts too are taken out of the sample's load in f:
  //   f += c (medium − v) + push + (c − s/h) (v − v0) − h k v0,  s = (h c + h² k)/airScale,
  // which makes the step's force c (medium − v⁽ⁿ⁺¹⁾) + push − k h v⁽ⁿ⁺¹⁾ (ContactResponse).
  // Loads (the tension's) keep the physical force c (medium − v) + push.
  // BDF2 (StepScheme; the samples are its prediction x*, v* of the step's end, M's vector q̇̂):
  // the step's force c (medium − v⁽ⁿ⁺¹⁾) + push − k β (v⁽ⁿ⁺¹⁾ − v*) with M u = M q̇̂ counting
  // s J q̇̂ too: f += c (medium − v) + push + (c + β k) (v − v0) − (s/β) J q̇̂.
  const double fold = FoldStep;
  const double airScale = 1 + fold * nu / RhoS;
  const bool bdf = fold > 0 && StepScheme == Scheme::Bdf2;
  thread_local std::vector<Eigen::Vector3d> hatVelocity;
  if (bdf && contacts)
    sampleVelocities(BdfHat, false, hatVelocity);
  // Tail sums, from the tip: force, torque, mass, first and second moments. The tip load
  // acts beyond every element: J(L)ᵀP = A_eᵀ (r(L) × P) + W_eᵀ P for every e.
  Eigen::Vector3d tailF = Spec.tipForce, tailT = k.tip.r0.cross(Spec.tipForce);
  Eigen::Vector3d tailC = Eigen::Vector3d::Zero();
  Eigen::Matrix3d tailTheta = Eigen::Matrix3d::Zero();
  double tailM = 0;
  // Per element P: Z_P = [U_P; V_P] such that block(Q < P) = A_Qᵀ U_P + W_Qᵀ V_P, and the
  // stack B (rows 3Q..3Q+2 = [A_Qᵀ W_Qᵀ]) so that the whole column block P above the diagonal
  // is one product B_{Q<P} Z_P over long columns (3 × 3 products block by block vectorize
  // poorly). The buffers only grow: nothing is allocated per step.
  thread_local std::vector<Eigen::Matrix<double, 6, 3>> Z;
  thread_local Eigen::Matrix<double, Eigen::Dynamic, 6> B;
  Z.resize(n);
  if (B.rows() < 3 * n)
    B.resize(3 * n, 6);
  for (int e = n - 1; e >= 0; --e)
  {
    const Element& el = k.elements[e];
    Eigen::Matrix3d Mloc = Eigen::Matrix3d::Zero(), X = Eigen::Matrix3d::Zero(),
                    Y = Eigen::Matrix3d::Zero();
    const Eigen::Matrix3d K = skew(Q.segment<3>(3 * e)), K2 = K * K;
    Eigen::Vector3d floc = Eigen::Vector3d::Zero(), eF = Eigen::Vector3d::Zero(),
                    eT = Eigen::Vector3d::Zero(), eC = Eigen::Vector3d::Zero();
    Eigen::Matrix3d eTheta, eRR = Eigen::Matrix3d::Zero();
    double eM = 0, eR2 = 0;
    double sBB[3][3] = {}, sEB[3][3] = {}, sEE[3][3] = {};
    for (int j = el.first; j < el.first + el.count; ++j)
    {
      Node& nd = k.nodes[j];
      double wm = nd.w * RhoS;
      Eigen::Vector3d f = gravity - nu * (nd.v0 - (winds ? winds[j] : Spec.wind)) - RhoS * nd.a0;
      if (contacts && nd.hasF)
        f += contacts[j].force;
      Eigen::Vector3d fg = f; // the load in the generalized force
      if (contacts && nd.hasField)
      {
        const ContactResponse& c = contacts[j];
        f += c.drag * (c.medium - nd.v) + c.push;
        fg = f;
        if (fold > 0)
        {
          const double s = (fold * c.drag + fold * fold * c.spring) / airScale;
          wm += nd.w * s;
          if (bdf)
            fg += (c.drag + fold * c.spring) * (nd.v - nd.v0) - (s / fold) * hatVelocity[j];
          else
            fg += (c.drag - s / fold) * (nd.v - nd.v0) - (fold * c.spring) * nd.v0;
        }
      }
      loads[j] = f;
      floc.noalias() += nd.w * (nd.J.transpose() * fg);
      eF += nd.w * fg;
      eT += nd.w * nd.r.cross(fg);
      // JᵀJ and r rᵀ are symmetric: their upper triangles here, mirrored after the loop.
      for (int b = 0; b < 3; ++b)
        for (int a = 0; a <= b; ++a)
        {
          Mloc(a, b) += wm * nd.J.col(a).dot(nd.J.col(b));
          eRR(a, b) += (wm * nd.r[a]) * nd.r[b];
        }
      {
        // X += [wm r]× J, written out: GCC does not inline crossCols here (the call would be
        // 3 % of a curly step's time), and forcing it inline everywhere makes every preset
        // 3–5 % slower.
        const double r0 = wm * nd.r[0], r1 = wm * nd.r[1], r2 = wm * nd.r[2];
        for (int c = 0; c < 3; ++c)
        {
          const double j0 = nd.J(0, c), j1 = nd.J(1, c), j2 = nd.J(2, c);
          X(0, c) += r1 * j2 - r2 * j1;
          X(1, c) += r2 * j0 - r0 * j2;
          X(2, c) += r0 * j1 - r1 * j0;
        }
      }
      Y += wm * nd.J;
      eM += wm;
      eC += wm * nd.r;
      eR2 += wm * nd.r.squaredNorm(); // Θ = Σ wm (|r|² I − r rᵀ), completed below
      // Rotary inertia of the cross-section, I(s) = F diag(ρI_p, ρI1, ρI2) Fᵀ, about the
      // frame's angular velocity, whose Jacobian is A_P (P < e) and F0 G(u) (own element):
      // the same tail-sum structure as the translational second moment Θ.
      // In the sample's own frame: Fᵀ F0 G(u) = E(u)ᵀ G(u) = G(u) with −k (E and G commute),
      // so with B = G(−k, u) and D = w diag(ρI_p, ρI1, ρI2):
      // (F0G)ᵀ I F0G = Bᵀ D B, I F0G = F D B, I = F D Fᵀ.
      // E and B are polynomials in K = [k]× with per-sample coefficients,
      //   E = I + u φ0 K + u² φ1 K²,  B = u I − u² φ1 K + u³ φ2 K²,
      // so only the weighted products of the coefficients are summed per sample; the
      // matrices K^i D K^j are formed once per element, below.
      {
        double Ec[3], Bc[3]; // B = G(u) with −k: the middle coefficient changes sign
        helixFrameCoefficients(nd.u, nd.coefficients, Ec, Bc);
        Bc[1] = -Bc[1];
        for (int i = 0; i < 3; ++i)
        {
          const double wE = nd.w * Ec[i], wB = nd.w * Bc[i];
          for (int jj = 0; jj < 3; ++jj)
          {
            sBB[i][jj] += wB * Bc[jj];
            sEB[i][jj] += wE * Bc[jj];
            sEE[i][jj] += wE * Ec[jj];
          }
        }
      }
    }
    Mloc.triangularView<Eigen::StrictlyLower>() = Mloc.transpose();
    eRR.triangularView<Eigen::StrictlyLower>() = eRR.transpose();
    {
      // P_ij = K^i D K^j (D = diag(ρI_p, ρI1, ρI2)); (K^i)ᵀ = (−1)^i K^i:
      //   Σ Bᵀ D B = Σ_ij sBB_ij (−1)^i P_ij,  Σ F D B = F0 Σ_ij sEB_ij P_ij,
      //   Σ F D Fᵀ = F0 (Σ_ij sEE_ij (−1)^j P_ij) F0ᵀ.
      // The six P_ij with i <= j are formed once per element (K X by column cross products);
      // the others are P_ji = (−1)^(i+j) P_ijᵀ (K D = −(D K)ᵀ, K² D = (D K²)ᵀ,
      // K² D K = −(K D K²)ᵀ). As Horner forms in K the three sums would cost 150 flops
      // each and, in a lambda GCC does not inline, 5.6 % of a curly step's time (perf
      // cpu-clock samples).
      const Eigen::Vector3d k = Q.segment<3>(3 * e);
      Eigen::Matrix3d P01, P02;
      P01.noalias() = RotI.asDiagonal() * K;
      P02.noalias() = RotI.asDiagonal() * K2;
      const Eigen::Matrix3d P11 = crossCols(k, P01), P12 = crossCols(k, P02),
                            P22 = crossCols(k, P12);
      auto sum = [&](const double(&c)[3][3]) __attribute__((always_inline))
      {
        Eigen::Matrix3d S = c[1][1] * P11 + c[2][2] * P22 + c[0][1] * P01 + c[0][2] * P02 +
                            c[1][2] * P12 - c[1][0] * P01.transpose() + c[2][0] * P02.transpose() -
                            c[2][1] * P12.transpose();
        S.diagonal() += c[0][0] * RotI;
        return S;
      };
      double cM[3][3], cT[3][3];
      for (int i = 0; i < 3; ++i)
        for (int jj = 0; jj < 3; ++jj)
        {
          cM[i][jj] = (i == 1 ? -1.0 : 1.0) * sBB[i][jj];
          cT[i][jj] = (jj == 1 ? -1.0 : 1.0) * sEE[i][jj];
        }
      const Eigen::Matrix3d Ms = sum(cM), Xs = sum(sEB), Ts = sum(cT);
      Mloc += Ms;
      X.noalias() += el.F0 * Xs;
      eTheta = -eRR;
      eTheta.diagonal().array() += eR2;
      eTheta.noalias() += el.F0 * Ts * el.F0.transpose();
    }
    // Generalized force of element e: own samples plus the rigid tail beyond it.
    F.segment<3>(3 * e) = floc + el.A.transpose() * tailT + el.W.transpose() * tailF;
    const Eigen::Matrix3d C = skew(tailC);
    const Eigen::Matrix3d ThA = tailTheta * el.A;
    // The tail's parts of U and V, shared with the diagonal block (fixed-size temporaries:
    // Eigen evaluates the nested product expression coefficient by coefficient).
    Eigen::Matrix3d TU = ThA, TV = tailM * el.W;
    TU.noalias() += C * el.W;
    TV.noalias() -= C * el.A;
    Eigen::Matrix3d d = Mloc;
    d.noalias() += el.A.transpose() * TU;
    d.noalias() += el.W.transpose() * TV;
    // Symmetric up to round-off: symmetrized exactly.
    M.block<3, 3>(3 * e, 3 * e) = 0.5 * (d + d.transpose());
    Z[e].topRows<3>() = X + TU;
    Z[e].bottomRows<3>() = Y + TV;
    B.block<3, 3>(3 * e, 0) = el.A.transpose();
    B.block<3, 3>(3 * e, 3) = el.W.transpose();
    tailF += eF;
    tailT += eT;
    tailM += eM;
    tailC += eC;
    tailTheta += eTheta;
  }
  // Column block P above the diagonal, B_{Q<P} Z_P, and its transpose below.
  const Eigen::Index ld = M.rows();
  for (int p = 1; p < n; ++p)
    stackedProduct<6, true>(M.data() + 3 * p * ld, M.data() + 3 * p, ld, B.data(), B.rows(),
                            Z[p].data(), 3 * p);
}

void SuperHelix::assembleTensionStiffness(double h)
{
  // K_T = ∫ T⁺(s) J_ω(s)ᵀ (I − n0 n0ᵀ) J_ω(s) ds (docs/super-helix.md, "Tension
  // stiffness"): the part of the loads' geometric stiffness −∂f/∂q carried by the tension
  // T(s) = n0(s) · ∫_s^L f (+ the tip force), which is what makes a hanging strand a chain
  // of pendulums. J_ω is the Jacobian of the frame's rotation: A_P for P before the
  // sample's element, F0 G(u) for its own element. Only the tension beyond what an explicit
  // step carries is used, T⁺ = max(0, T − ρS ℓ² / (64 h²)), so that small steps keep the
  // explicit (energy-neutral) treatment. Tail sums as for the mass matrix: O(N²).
  const int n = elementCount();
  detail::StepWorkspace& ws = detail::stepWorkspace();
  Eigen::MatrixXd& Kt = ws.Kt;
  Kt.resize(3 * n, 3 * n); // per-thread buffer
  Kinematics& k = Cur;
  // Per element P: Y_P such that block(Q < P) = A_Qᵀ Y_P, and the stack At (rows
  // 3Q..3Q+2 = A_Qᵀ) so that column block P above the diagonal is one product At_{Q<P} Y_P.
  thread_local std::vector<Eigen::Matrix3d> Y;
  thread_local Eigen::Matrix<double, Eigen::Dynamic, 3> At;
  Y.resize(n);
  if (At.rows() < 3 * n)
    At.resize(3 * n, 3);
  if (ws.LoadsId != CurId) // assemble() ran for another strand or state on this thread since
    assemble();
  const Eigen::Vector3d* const loads = ws.Loads.data(); // set by assemble()
  Eigen::Vector3d tailF = Spec.tipForce;
  Eigen::Matrix3d tailP = Eigen::Matrix3d::Zero(); // ∫ T⁺ (I − n0 n0ᵀ) beyond the element
  for (int e = n - 1; e >= 0; --e)
  {
    const Element& el = k.elements[e];
    const double l = Spec.elementLengths[e];
    const double explicitTension = RhoS * l * l / (ExplicitTensionDivisor * h * h);
    // The own element's terms from per-sample coefficients. With K = [k]×, V_i = K^i e0 (the
    // columns of Vm), n0 = F0 E(u) e0 = F0 Vm c and F0ᵀ FG = G(u) = Σ_j d_j K^j, where
    // c = (1, uφ0, u²φ1) and d = (u, u²φ1, u³φ2), and since G(u)ᵀ E(u) = G(u) (both are
    // functions of K; Gᵀ E = ∫0^u exp((u − s) K) ds), G(u)ᵀ F0ᵀ n0 = G(u) e0 = g = Vm d. So
    // with P = wT (I − n0 n0ᵀ) at a sample of weight w and tension T:
    //   P FG = wT F0 (G − Vm c dᵀ Vmᵀ),  FGᵀ P FG = wT (GᵀG − Vm d dᵀ Vmᵀ),
    //   P = F0 (wT I − Vm c cᵀ Vmᵀ wT) F0ᵀ,
    // and GᵀG = Σ_ij (−1)^i d_i d_j K^(i+j) = d0² I + (2 d0 d2 − d1² − Ω² d2²) K² (odd powers
    // cancel, K⁴ = −Ω² K²). Per sample only the weighted products of c and d are summed.
    const Eigen::Vector3d kq = Q.segment<3>(3 * e);
    const double k0 = kq[0], k1 = kq[1], k2 = kq[2], w0 = -(k1 * k1 + k2 * k2);
    Eigen::Matrix3d Vm; // K e0 = (0, k2, −k1), K² e0 = k k0 − Ω² e0
    Vm << 1, 0, w0, 0, k2, k0 * k1, 0, -k1, k0 * k2;
    Eigen::Matrix3d W; // F0 Vm, n0 = W c
    W.col(0) = el.F0.col(0);
    W.col(1) = k2 * el.F0.col(1) - k1 * el.F0.col(2);
    W.col(2) = w0 * el.F0.col(0) + (k0 * k1) * el.F0.col(1) + (k0 * k2) * el.F0.col(2);
    double sw = 0, sd[3] = {0, 0, 0};
    Eigen::Matrix3d sdd = Eigen::Matrix3d::Zero(), scd = Eigen::Matrix3d::Zero(),
                    scc = Eigen::Matrix3d::Zero();
    double beyond = 0; // Σ w of the element's samples beyond the current one
    for (int j = el.first + el.count - 1; j >= el.first; --j)
    {
      const Node& nd = k.nodes[j];
      const Eigen::Vector3d& load = loads[j];
      const Eigen::Vector3d wf = nd.w * load;
      // Tail force at the sample: the samples beyond it, and its own load over the rest of
      // the length to the element's end (exact for a uniform load).
      const Eigen::Vector3d atSample = tailF + (l - nd.u - beyond) * load;
      tailF += wf;
      beyond += nd.w;
      const HelixCoefficients& hc = nd.coefficients;
      double ce[3], dg[3];
      helixFrameCoefficients(nd.u, hc, ce, dg);
      const Eigen::Vector3d c(ce[0], ce[1], ce[2]), d(dg[0], dg[1], dg[2]);
      // T⁺ without a branch: the sign of T changes along a moving strand, and a mispredicted
      // branch costs more than the products of a sample in compression (which add zeros).
      // A NaN tension counts as none (T > 0 is false); F's check stops such a step.
      const double T = (W * c).dot(atSample) - explicitTension;
      const double wT = nd.w * (T > 0 ? T : 0.0);
      const Eigen::Vector3d wd = wT * d;
      sw += wT;
      for (int i = 0; i < 3; ++i)
        sd[i] += wd[i];
      sdd.noalias() += wd * d.transpose();
      scd.noalias() += (wT * c) * d.transpose();
      scc.noalias() += (wT * c) * c.transpose();
    }
    Eigen::Matrix3d Yown = Eigen::Matrix3d::Zero(), Down = Eigen::Matrix3d::Zero(),
                    eP = Eigen::Matrix3d::Zero();
    if (sw > 0) // some sample in tension
    {
      const Eigen::Matrix3d K = skew(kq), K2 = K * K;
      Eigen::Matrix3d Gsum = sd[1] * K + sd[2] * K2;
      Gsum.diagonal().array() += sd[0];
      Yown.noalias() = el.F0 * (Gsum - Vm * scd * Vm.transpose());
      Down = (2 * sdd(0, 2) - sdd(1, 1) - kq.squaredNorm() * sdd(2, 2)) * K2 -
             Vm * sdd * Vm.transpose();
      Down.diagonal().array() += sdd(0, 0);
      eP = -(W * scc * W.transpose());
      eP.diagonal().array() += sw;
    }
    Y[e] = Yown + tailP * el.A;
    At.block<3, 3>(3 * e, 0) = el.A.transpose();
    const Eigen::Matrix3d d = Down + el.A.transpose() * (tailP * el.A);
    Kt.block<3, 3>(3 * e, 3 * e) = 0.5 * (d + d.transpose());
    tailP += eP;
  }
  // Column block P above the diagonal, At_{Q<P} Y_P, and its transpose below.
  const Eigen::Index ld = Kt.rows();
  for (int p = 1; p < n; ++p)
    stackedProduct<3, true>(Kt.data() + 3 * p * ld, Kt.data() + 3 * p, ld, At.data(), At.rows(),
                            Y[p].data(), 3 * p);
}

} // namespace hair

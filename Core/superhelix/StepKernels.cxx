// The definitions of the step's array kernels declared in StepKernels.h, each compiled for
// AVX2 and for baseline x86-64 (HAIR_AVX2_CLONES), and the instantiations the phases use.
// The comments on what each computes are in the header. A translation unit of its own, not
// in the step's unity build (Core/CMakeLists.txt): GCC does not multiversion a template
// instantiated in a unit before its definition.
#include "superhelix/StepKernels.h"

#include "common/Multiversioning.h"

namespace hair::detail
{

HAIR_AVX2_CLONES
bool formStepSystem(double* __restrict lhs, double* __restrict rhs, const double* __restrict M,
                    const double* __restrict C, const double* __restrict Kt,
                    const double* __restrict qd, int m, double a, double b, double c,
                    const double* __restrict u, double cr)
{
  double check = 0;
  if (!u) // the semi-implicit step: rhs += (M − b C) q̇
  {
    for (int j = 0; j < m; ++j)
    {
      const double q = qd[j];
      const Eigen::Index o = static_cast<Eigen::Index>(j) * m;
      double colCheck = 0;
      for (int i = 0; i < m; ++i)
      {
        const double mij = M[o + i], cij = C[o + i];
        const double l = a * mij - b * cij + c * Kt[o + i];
        lhs[o + i] = l;
        rhs[i] += (mij - b * cij) * q;
        colCheck += l - l;
      }
      check += colCheck;
    }
    return check == 0;
  }
  for (int j = 0; j < m; ++j)
  {
    const double q = qd[j], uj = u[j];
    const Eigen::Index o = static_cast<Eigen::Index>(j) * m;
    double colCheck = 0;
    for (int i = 0; i < m; ++i)
    {
      const double mij = M[o + i], cij = C[o + i], kij = Kt[o + i];
      const double l = a * mij - b * cij + c * kij;
      lhs[o + i] = l;
      rhs[i] += mij * uj + (cr * kij - b * cij) * q;
      colCheck += l - l;
    }
    check += colCheck;
  }
  return check == 0;
}

template <int K, bool Mirror>
HAIR_AVX2_CLONES void stackedProduct(double* __restrict dst, double* __restrict mirror,
                                     Eigen::Index ldd, const double* __restrict src,
                                     Eigen::Index lds, const double* __restrict z, int rows)
{
  for (int r = 0; r < rows; ++r)
  {
    double s0 = 0, s1 = 0, s2 = 0;
    for (int j = 0; j < K; ++j)
    {
      const double x = src[j * lds + r];
      s0 += x * z[j];
      s1 += x * z[K + j];
      s2 += x * z[2 * K + j];
    }
    dst[r] = s0;
    dst[ldd + r] = s1;
    dst[2 * ldd + r] = s2;
    if (Mirror)
    {
      mirror[r * ldd] = s0;
      mirror[r * ldd + 1] = s1;
      mirror[r * ldd + 2] = s2;
    }
  }
}

template <int K>
HAIR_AVX2_CLONES void stackedProductAdd(double* __restrict dst, Eigen::Index rowStride,
                                        Eigen::Index colStride, const double* __restrict src,
                                        Eigen::Index lds, const double* __restrict z, int rows)
{
  for (int r = 0; r < rows; ++r)
  {
    double s0 = 0, s1 = 0, s2 = 0;
    for (int j = 0; j < K; ++j)
    {
      const double x = src[j * lds + r];
      s0 += x * z[j];
      s1 += x * z[K + j];
      s2 += x * z[2 * K + j];
    }
    double* const d = dst + r * rowStride;
    d[0] += s0;
    d[colStride] += s1;
    d[2 * colStride] += s2;
  }
}

HAIR_AVX2_CLONES
void lowerAndPropagate(double* __restrict dst, Eigen::Index ldc, double* __restrict g,
                       Eigen::Index ldg, const double* __restrict S, const double* __restrict phi,
                       const double* __restrict akd, const double* __restrict fg, int rows)
{
  const double v0 = akd[0], v1 = akd[1], v2 = akd[2], f0 = fg[0], f1 = fg[1], f2 = fg[2];
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC ivdep // each pass reads and writes row r of Γ only
#endif
  for (int r = 0; r < rows; ++r)
  {
    const double a0 = g[r], a1 = g[ldg + r], a2 = g[2 * ldg + r];
    const double l0 = g[3 * ldg + r], l1 = g[4 * ldg + r], l2 = g[5 * ldg + r];
    const double w0 = g[6 * ldg + r], w1 = g[7 * ldg + r], w2 = g[8 * ldg + r];
    for (int c = 0; c < 3; ++c)
    {
      const double* const s = S + 9 * c;
      dst[c * ldc + r] = a0 * s[0] + a1 * s[1] + a2 * s[2] + l0 * s[3] + l1 * s[4] + l2 * s[5] +
                         w0 * s[6] + w1 * s[7] + w2 * s[8];
    }
    g[6 * ldg + r] = w0 + (a0 * phi[0] + a1 * phi[1] + a2 * phi[2]) - (l1 * v2 - l2 * v1);
    g[7 * ldg + r] = w1 + (a0 * phi[3] + a1 * phi[4] + a2 * phi[5]) - (l2 * v0 - l0 * v2);
    g[8 * ldg + r] = w2 + (a0 * phi[6] + a1 * phi[7] + a2 * phi[8]) - (l0 * v1 - l1 * v0);
    g[3 * ldg + r] = l0 - (a1 * f2 - a2 * f1);
    g[4 * ldg + r] = l1 - (a2 * f0 - a0 * f2);
    g[5 * ldg + r] = l2 - (a0 * f1 - a1 * f0);
  }
}

template void stackedProduct<6, true>(double* __restrict, double* __restrict, Eigen::Index,
                                      const double* __restrict, Eigen::Index,
                                      const double* __restrict, int);
template void stackedProduct<3, true>(double* __restrict, double* __restrict, Eigen::Index,
                                      const double* __restrict, Eigen::Index,
                                      const double* __restrict, int);
template void stackedProduct<6, false>(double* __restrict, double* __restrict, Eigen::Index,
                                       const double* __restrict, Eigen::Index,
                                       const double* __restrict, int);
template void stackedProductAdd<6>(double* __restrict, Eigen::Index, Eigen::Index,
                                   const double* __restrict, Eigen::Index, const double* __restrict,
                                   int);

} // namespace hair::detail

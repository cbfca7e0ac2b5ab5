#pragma once
// The step's loops over long arrays, shared by the phases that assemble and solve the step's
// system: forming a M − b C + c K_T with its right-hand side (formStepSystem), the stacked
// products that fill the off-diagonal blocks of M, K_T, C and the contact Jacobians
// (stackedProduct, stackedProductAdd) and the row pass of C below the diagonal
// (lowerAndPropagate). Their definitions (StepKernels.cxx) are compiled for AVX2 and for
// baseline x86-64 (HAIR_AVX2_CLONES, common/Multiversioning.h), with the same results.
// Private to Core/superhelix/.
#include <Eigen/Core>

namespace hair::detail
{

// The step's matrix a M − b C + c K_T and its right-hand side, column by column (m × m,
// column-major): one pass over the three matrices instead of three. With u null (the
// semi-implicit step) rhs += (M − b C) q̇, else rhs += M u + (c_r K_T − b C) q̇ (the
// generalized-α step: u carries the mass matrix's own vector). Returns whether every entry of
// the matrix is finite (x − x is 0 for finite x and NaN otherwise; a, b, c > 0, so a
// non-finite entry of M, C or K_T leaves one in the matrix).
bool formStepSystem(double* __restrict lhs, double* __restrict rhs, const double* __restrict M,
                    const double* __restrict C, const double* __restrict Kt,
                    const double* __restrict qd, int m, double a, double b, double c,
                    const double* __restrict u, double cr);

// dst(r, c) = Σ_{j < K} src(r, j) z(j, c) for r < rows and c < 3, column-major (src with
// leading dimension lds, z K × 3 contiguous, dst with leading dimension ldd); with Mirror,
// each row's three values also go to the transposed place, mirror[r ldd + c]. The three
// columns in one pass, vectorized over r: the off-diagonal blocks of M, K_T and C as one
// product over a long stack of rows (3 × 3 products block by block vectorize poorly, and
// Eigen's lazy product on these dynamic blocks is slower than those). Instantiated for
// <6, true> (M), <3, true> (K_T) and <6, false> (C).
template <int K, bool Mirror>
void stackedProduct(double* __restrict dst, double* __restrict mirror, Eigen::Index ldd,
                    const double* __restrict src, Eigen::Index lds, const double* __restrict z,
                    int rows);

// dst[r · rowStride + c · colStride] += Σ_{j < K} src(r, j) z(j, c) for r < rows, c < 3 (src
// column-major with leading dimension lds, z K × 3 contiguous): a stacked product added to
// a block column (rowStride 1) or, transposed, to a block row (colStride 1). The loop is
// stackedProduct's, written again: one kernel taking the store as a lambda costs +1.2 %
// instructions per step (the restrict-qualified stores do not vectorize). Instantiated for
// K = 6 (the contact Jacobians).
template <int K>
void stackedProductAdd(double* __restrict dst, Eigen::Index rowStride, Eigen::Index colStride,
                       const double* __restrict src, Eigen::Index lds, const double* __restrict z,
                       int rows);

// One pass over the rows of Γ_{qe+1} (columns [a l w] with leading dimension ldg, rows
// r < rows): C's column block qe below the diagonal, dst(r, :) = Γ(r, :) S (leading dimension
// ldc), then Γ_{qe+1} Prop_qe in place,
//   w += a Φ_end − l [A k̇]×,  l −= a [Fg_end]×   (row vectors: x [v]× = x × v).
// O(N²) in all (~100 instructions per row with 2-wide vectors). See
// SuperHelix::assembleVelocityJacobian (VelocityJacobian.cxx) for Γ, S and Prop.
void lowerAndPropagate(double* __restrict dst, Eigen::Index ldc, double* __restrict g,
                       Eigen::Index ldg, const double* __restrict S, const double* __restrict phi,
                       const double* __restrict akd, const double* __restrict fg, int rows);

} // namespace hair::detail

#include "helix/DenseLu.h"

#include "common/Multiversioning.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <utility>

namespace hair
{

namespace
{
// Columns per panel; the U12 solve and trailingRows below are written out for four.
constexpr int LuPanel = 4;

// y −= f x over n entries (distinct arrays; vectorizable).
inline void subtractScaled(double* __restrict y, const double* __restrict x, double f, int n)
{
  for (int i = 0; i < n; ++i)
    y[i] -= f * x[i];
}

// The trailing update of LuPanel = 4 columns for the rows [i, i + 4V) of the columns
// [c1, m): y −= l_c0 u_c0, …, l_c0+3 u_c0+3 in that order, with the rows of L21 held in
// 4-wide vectors (GCC / Clang vector extensions: two SSE2 halves without AVX2). The short
// columns at 3N = 30 made a loop down each column spend most of its instructions on set-up
// and remainders.
using Vec4 = double __attribute__((vector_size(32), aligned(8), may_alias));
template <int V>
[[gnu::always_inline]] inline void trailingRows(double* a, int m, int c0, int c1, int i)
{
  Vec4 l[4][V];
  for (int c = 0; c < 4; ++c)
    for (int v = 0; v < V; ++v)
      l[c][v] =
          *reinterpret_cast<const Vec4*>(a + static_cast<std::ptrdiff_t>(c0 + c) * m + i + 4 * v);
  for (int j = c1; j < m; ++j)
  {
    double* cj = a + static_cast<std::ptrdiff_t>(j) * m;
    const double u0 = cj[c0], u1 = cj[c0 + 1], u2 = cj[c0 + 2], u3 = cj[c0 + 3];
    for (int v = 0; v < V; ++v)
    {
      Vec4 t = *reinterpret_cast<const Vec4*>(cj + i + 4 * v);
      t -= l[0][v] * u0;
      t -= l[1][v] * u1;
      t -= l[2][v] * u2;
      t -= l[3][v] * u3;
      *reinterpret_cast<Vec4*>(cj + i + 4 * v) = t;
    }
  }
}

// x ← A⁻¹ x from the factors of luSolveInPlace: P x, then the unit lower and the upper
// triangular solves, column by column.
[[gnu::always_inline]] inline void substitute(const double* a, const int* piv, double* x, int m)
{
  auto column = [a, m](int j) { return a + static_cast<std::ptrdiff_t>(j) * m; };
  for (int c = 0; c < m; ++c) // P b: the interchanges in order (L's rows are in final order)
    std::swap(x[c], x[piv[c]]);
  for (int c = 0; c < m; ++c)
    subtractScaled(x + c + 1, column(c) + c + 1, x[c], m - c - 1);
  for (int c = m - 1; c >= 0; --c)
  {
    const double* col = column(c);
    x[c] /= col[c];
    subtractScaled(x, col, x[c], c);
  }
}

} // namespace

HAIR_AVX2_CLONES
double luSolveInPlace(double* a, double* x, int m, int* piv)
{
  double pivot = std::numeric_limits<double>::infinity();
  auto column = [a, m](int j) { return a + static_cast<std::ptrdiff_t>(j) * m; };
  for (int c0 = 0; c0 < m; c0 += LuPanel)
  {
    const int c1 = std::min(c0 + LuPanel, m); // panel columns [c0, c1)
    for (int c = c0; c < c1; ++c)
    {
      double* col = column(c);
      int p = c;
      double best = std::abs(col[c]);
      for (int i = c + 1; i < m; ++i)
        if (std::abs(col[i]) > best)
        {
          best = std::abs(col[i]);
          p = i;
        }
      piv[c] = p;
      if (!(best > 0))
        return best; // singular (or NaN): refused by the caller
      pivot = std::min(pivot, best);
      if (p != c)
        for (int j = 0; j < m; ++j)
          std::swap(column(j)[c], column(j)[p]);
      const double inv = 1.0 / col[c];
      for (int i = c + 1; i < m; ++i)
        col[i] *= inv;
      for (int j = c + 1; j < c1; ++j) // the panel's later columns
      {
        double* cj = column(j);
        const double f = cj[c];
        if (f != 0)
          subtractScaled(cj + c + 1, col + c + 1, f, m - c - 1);
      }
    }
    if (c1 == m)
      break; // the last panel, the only one that may be narrower than four, has no right
    // Rows [c0, c1) of the columns right of the panel, U12 = L11⁻¹ A12, then the trailing
    // matrix, rows and columns from c1: A22 −= L21 U12, the panel's updates in order.
    const double* const p0 = column(c0);
    const double* const p1 = column(c0 + 1);
    const double* const p2 = column(c0 + 2);
    const double* const p3 = column(c0 + 3);
    const double l10 = p0[c0 + 1], l20 = p0[c0 + 2], l30 = p0[c0 + 3];
    const double l21 = p1[c0 + 2], l31 = p1[c0 + 3], l32 = p2[c0 + 3];
    for (int j = c1; j < m; ++j)
    {
      double* cj = column(j);
      const double u0 = cj[c0];
      double u1 = cj[c0 + 1], u2 = cj[c0 + 2], u3 = cj[c0 + 3];
      u1 -= l10 * u0;
      u2 -= l20 * u0;
      u3 -= l30 * u0;
      u2 -= l21 * u1;
      u3 -= l31 * u1;
      u3 -= l32 * u2;
      cj[c0 + 1] = u1;
      cj[c0 + 2] = u2;
      cj[c0 + 3] = u3;
    }
    // Blocks of rows: L21's rows in registers, one pass over the trailing columns each
    // (the columns are short at 3N = 30: a loop down each column spends most of its
    // instructions on its set-up and remainder).
    int i = c1;
    for (; i + 8 <= m; i += 8)
      trailingRows<2>(a, m, c0, c1, i);
    for (; i + 4 <= m; i += 4)
      trailingRows<1>(a, m, c0, c1, i);
    for (; i < m; ++i)
    {
      const double a0 = p0[i], a1 = p1[i], a2 = p2[i], a3 = p3[i];
      for (int j = c1; j < m; ++j)
      {
        double* cj = column(j);
        double t = cj[i];
        t -= a0 * cj[c0];
        t -= a1 * cj[c0 + 1];
        t -= a2 * cj[c0 + 2];
        t -= a3 * cj[c0 + 3];
        cj[i] = t;
      }
    }
  }
  substitute(a, piv, x, m);
  return pivot;
}

HAIR_AVX2_CLONES
void luSolveFactored(const double* lu, const int* piv, double* x, int m)
{
  substitute(lu, piv, x, m);
}

} // namespace hair

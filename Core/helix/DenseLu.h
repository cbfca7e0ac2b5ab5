#pragma once
// The small dense solve of the Super-Helix step (3N × 3N, N up to a few tens).

namespace hair
{

// Solves a x = b in place for the column-major m × m matrix a (overwritten by its LU
// factors, row interchanges in piv) and b (overwritten by x); returns the smallest pivot
// magnitude (0 or NaN: singular, x not computed).
//
// Partial pivoting by row interchanges, as LAPACK getrf / Eigen's PartialPivLU. Right-looking
// and blocked by panels of 4 columns: the panel is factorized column
// by column (pivot search, whole-row interchange, scaling, update of the panel's later
// columns), its rows of U to the right are solved with the panel's unit L, and the trailing
// matrix gets the panel's 4 rank-1 updates in one pass per column, from registers
// (one load and one store of each entry per panel instead of per column). Every entry
// receives the same updates in the same order as in the column-by-column algorithm
// (y −= l_c u_c for c = 0, 1, …, one rounding each), so the factors are the same bit for
// bit. Compiled for AVX2 and for baseline x86-64 (common/Multiversioning.h).
// Against Eigen's PartialPivLU: 2.25 against ~4 µs at m = 30, 52 against 115–169 µs at
// m = 120; SuperHelix uses it up to m = 360.
double luSolveInPlace(double* a, double* x, int m, int* piv);

// Solves a x = b once more with the factors (lu) and interchanges (piv) that luSolveInPlace
// left: x is b on entry, the solution on return (the same operations as its own solve).
void luSolveFactored(const double* lu, const int* piv, double* x, int m);

} // namespace hair

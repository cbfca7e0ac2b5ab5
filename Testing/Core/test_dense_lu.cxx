// The Super-Helix step's dense solve, luSolveInPlace (Core/helix/DenseLu.h).
#include "helix/DenseLu.h"

#include <Eigen/Core>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

using namespace hair;

namespace
{
Eigen::MatrixXd randomMatrix(int m, std::mt19937& g)
{
  std::uniform_real_distribution<double> d(-1, 1);
  Eigen::MatrixXd a(m, m);
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i)
      a(i, j) = d(g);
  return a;
}

// The textbook column-by-column LU with partial pivoting (Golub & Van Loan, Algorithm 3.4.1
// with the row interchanges of LAPACK getf2) and its two triangular solves.
Eigen::VectorXd referenceSolve(Eigen::MatrixXd a, Eigen::VectorXd x)
{
  const int m = static_cast<int>(a.rows());
  for (int c = 0; c < m; ++c)
  {
    int p = c;
    for (int i = c + 1; i < m; ++i)
      if (std::abs(a(i, c)) > std::abs(a(p, c)))
        p = i;
    a.row(c).swap(a.row(p));
    std::swap(x[c], x[p]);
    const double inv = 1.0 / a(c, c);
    for (int i = c + 1; i < m; ++i)
      a(i, c) *= inv;
    for (int j = c + 1; j < m; ++j)
      for (int i = c + 1; i < m; ++i)
        a(i, j) -= a(c, j) * a(i, c);
  }
  for (int c = 0; c < m; ++c)
    for (int i = c + 1; i < m; ++i)
      x[i] -= x[c] * a(i, c);
  for (int c = m - 1; c >= 0; --c)
  {
    x[c] /= a(c, c);
    for (int i = 0; i < c; ++i)
      x[i] -= x[c] * a(i, c);
  }
  return x;
}

// Sizes around the panel width (4) and the 8-row blocks, up to the step's largest (3N = 360).
const int Sizes[] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 11, 12, 13, 16, 17, 30, 31, 45, 60, 121, 360};

// A random system a x = b of size m and what luSolveInPlace makes of it.
struct Solved
{
  Eigen::MatrixXd a, lu;
  Eigen::VectorXd b, x;
  std::vector<int> piv;
  double pivot;
};

Solved solveRandom(int m, std::mt19937& g)
{
  Solved s;
  s.a = randomMatrix(m, g);
  s.b = randomMatrix(m, g).col(0);
  s.lu = s.a;
  s.x = s.b;
  s.piv.resize(static_cast<size_t>(m));
  s.pivot = luSolveInPlace(s.lu.data(), s.x.data(), m, s.piv.data());
  return s;
}
} // namespace

TEST(DenseLu, BackwardErrorWithinTheBoundOfGaussianEliminationWithPartialPivoting)
{
  // Higham, Accuracy and Stability of Numerical Algorithms (2nd ed.), Theorem 9.4: the
  // computed solution satisfies (A + ΔA) x̂ = b with |ΔA| ≤ γ_3m Pᵀ |L̂| |Û|, γ_k = k u/(1 − k u),
  // so every component of the residual b − A x̂ is at most γ_3m (|L̂| |Û| |x̂|) of its row. The
  // bound is rigorous for any correct implementation; a wrong interchange or update leaves an
  // O(1) residual. Random matrices in [−1, 1] pivot at almost every column.
  std::mt19937 g(7);
  for (const int m : Sizes)
  {
    const Solved s = solveRandom(m, g);
    const Eigen::MatrixXd &a = s.a, &lu = s.lu;
    const Eigen::VectorXd &b = s.b, &x = s.x;
    ASSERT_GT(s.pivot, 0) << "m = " << m;
    const Eigen::MatrixXd L = lu.triangularView<Eigen::UnitLower>();
    const Eigen::MatrixXd U = lu.triangularView<Eigen::Upper>();
    const Eigen::VectorXd bound = L.cwiseAbs() * (U.cwiseAbs() * x.cwiseAbs());
    const double u = std::numeric_limits<double>::epsilon() / 2;
    const double gamma = 3 * m * u / (1 - 3 * m * u);
    const double residual = (b - a * x).cwiseAbs().maxCoeff();
    EXPECT_LE(residual, gamma * bound.maxCoeff()) << "m = " << m;
    // P A = L U, with P the interchanges in order.
    Eigen::MatrixXd pa = a;
    for (int c = 0; c < m; ++c)
      pa.row(c).swap(pa.row(s.piv[static_cast<size_t>(c)]));
    const Eigen::MatrixXd lup = (L.cwiseAbs() * U.cwiseAbs()).eval();
    EXPECT_LE((pa - L * U).cwiseAbs().maxCoeff(), gamma * lup.maxCoeff()) << "m = " << m;
  }
}

TEST(DenseLu, SameResultsBitForBitAsTheColumnByColumnAlgorithm)
{
  // The panels only regroup the loops: each entry gets the same updates in the same order
  // (one rounding each, no fused multiply-add in ISO C++ mode), so x must be identical, not
  // merely close. This is what keeps results unchanged from the former column-by-column LU.
  std::mt19937 g(11);
  for (const int m : Sizes)
  {
    const Solved s = solveRandom(m, g);
    const Eigen::VectorXd& x = s.x;
    ASSERT_GT(s.pivot, 0) << "m = " << m;
    const Eigen::VectorXd ref = referenceSolve(s.a, s.b);
    int differing = 0;
    for (int i = 0; i < m; ++i)
      differing += x[i] != ref[i];
    EXPECT_EQ(differing, 0) << "m = " << m << ": max difference "
                            << (x - ref).cwiseAbs().maxCoeff();
  }
}

TEST(DenseLu, SingularOrNotFiniteMatricesAreReportedByTheSmallestPivot)
{
  // A zero column has no pivot: the smallest pivot is 0 and x is not computed; a NaN makes it
  // NaN. Either way the caller (SuperHelix::solve) refuses the step.
  for (const int m : {3, 9, 30})
  {
    std::mt19937 g(3);
    Eigen::MatrixXd a = randomMatrix(m, g);
    a.col(m / 2).setZero();
    Eigen::VectorXd x = Eigen::VectorXd::Ones(m);
    std::vector<int> piv(static_cast<size_t>(m));
    EXPECT_EQ(luSolveInPlace(a.data(), x.data(), m, piv.data()), 0) << "m = " << m;

    Eigen::MatrixXd n = randomMatrix(m, g);
    n(m - 1, 0) = std::numeric_limits<double>::quiet_NaN();
    Eigen::VectorXd y = Eigen::VectorXd::Ones(m);
    EXPECT_TRUE(std::isnan(luSolveInPlace(n.data(), y.data(), m, piv.data()))) << "m = " << m;
  }
}

// The interior-node energy of a Discrete Elastic Rod, written once as a template over the
// scalar: with double it gives the energy, with Jet (value, gradient and Hessian in the 11
// unknowns, propagated by the chain rule) its exact derivatives. A hand-written Jet rather
// than Eigen's nested AutoDiffScalar: the same forward-over-forward arithmetic, with the
// Hessian's outer products done once per operation instead of through 11 inner scalars.
#include "der/DerStencil.h"

#include <cmath>
#include <utility>

namespace hair
{

namespace
{

// A value with its gradient and Hessian in the stencil's 11 unknowns.
struct Jet
{
  double v = 0;
  Vector11d g = Vector11d::Zero();
  Matrix11d h = Matrix11d::Zero();
  Jet() = default;
  Jet(double value) : v(value) {} // NOLINT: constants convert implicitly
  static Jet variable(double value, int i)
  {
    Jet j(value);
    j.g[i] = 1;
    return j;
  }
};

double value(double x)
{
  return x;
}
double value(const Jet& x)
{
  return x.v;
}

Jet operator+(const Jet& a, const Jet& b)
{
  Jet r;
  r.v = a.v + b.v;
  r.g = a.g + b.g;
  r.h = a.h + b.h;
  return r;
}
Jet operator-(const Jet& a, const Jet& b)
{
  Jet r;
  r.v = a.v - b.v;
  r.g = a.g - b.g;
  r.h = a.h - b.h;
  return r;
}
Jet operator*(const Jet& a, const Jet& b)
{
  Jet r;
  r.v = a.v * b.v;
  r.g = a.v * b.g + b.v * a.g;
  r.h.noalias() = a.v * b.h + b.v * a.h;
  r.h.noalias() += a.g * b.g.transpose();
  r.h.noalias() += b.g * a.g.transpose();
  return r;
}
Jet operator+(Jet a, double b)
{
  a.v += b;
  return a;
}
Jet operator+(double a, Jet b)
{
  return std::move(b) + a;
}
Jet operator-(Jet a, double b)
{
  a.v -= b;
  return a;
}
Jet operator*(Jet a, double b)
{
  a.v *= b;
  a.g *= b;
  a.h *= b;
  return a;
}
Jet operator*(double a, Jet b)
{
  return std::move(b) * a;
}

// f(a) from f, f', f'' at a's value.
Jet chain(const Jet& a, double f0, double f1, double f2)
{
  Jet r;
  r.v = f0;
  r.g = f1 * a.g;
  r.h.noalias() = f1 * a.h;
  r.h.noalias() += f2 * a.g * a.g.transpose();
  return r;
}
Jet inverse(const Jet& a)
{
  const double i = 1 / a.v;
  return chain(a, i, -i * i, 2 * i * i * i);
}
Jet operator/(const Jet& a, const Jet& b)
{
  return a * inverse(b);
}
Jet sqrt(const Jet& a)
{
  const double s = std::sqrt(a.v);
  return chain(a, s, 0.5 / s, -0.25 / (s * a.v));
}
Jet sin(const Jet& a)
{
  return chain(a, std::sin(a.v), std::cos(a.v), -std::sin(a.v));
}
Jet cos(const Jet& a)
{
  return chain(a, std::cos(a.v), -std::sin(a.v), -std::cos(a.v));
}
// θ = atan2(y, x): θ_x = −y/r², θ_y = x/r², θ_xx = 2xy/r⁴ = −θ_yy, θ_xy = (y² − x²)/r⁴.
Jet atan2(const Jet& y, const Jet& x)
{
  const double r2 = x.v * x.v + y.v * y.v, r4 = r2 * r2;
  const double fx = -y.v / r2, fy = x.v / r2;
  const double fxx = 2 * x.v * y.v / r4, fxy = (y.v * y.v - x.v * x.v) / r4;
  Jet r;
  r.v = std::atan2(y.v, x.v);
  r.g = fx * x.g + fy * y.g;
  r.h.noalias() = fx * x.h + fy * y.h;
  r.h.noalias() += fxx * (x.g * x.g.transpose() - y.g * y.g.transpose());
  r.h.noalias() += fxy * (x.g * y.g.transpose() + y.g * x.g.transpose());
  return r;
}

// Three scalars; mixed Jet/double arithmetic takes the cheap overloads above.
template <class T>
struct V3
{
  T c[3];
  const T& operator[](int i) const { return c[i]; }
};
template <class A, class B>
using Product = decltype(std::declval<A>() * std::declval<B>());

V3<double> vec(const Eigen::Vector3d& v)
{
  return {{v[0], v[1], v[2]}};
}
template <class A, class B>
V3<Product<A, B>> operator+(const V3<A>& a, const V3<B>& b)
{
  return {{a[0] + b[0], a[1] + b[1], a[2] + b[2]}};
}
template <class A, class B>
V3<Product<A, B>> operator-(const V3<A>& a, const V3<B>& b)
{
  return {{a[0] - b[0], a[1] - b[1], a[2] - b[2]}};
}
template <class A, class S>
V3<Product<A, S>> operator*(const V3<A>& a, const S& s)
{
  return {{a[0] * s, a[1] * s, a[2] * s}};
}
template <class A, class B>
Product<A, B> dot(const V3<A>& a, const V3<B>& b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
template <class A, class B>
V3<Product<A, B>> cross(const V3<A>& a, const V3<B>& b)
{
  return {{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}};
}
// d transported by the rotation about w = a × b taking a to b, c = a·b (unit a, b).
template <class W, class C, class D>
auto transport(const V3<D>& d, const V3<W>& w, const C& c)
{
  const auto wd = cross(w, d);
  return d + wd + cross(w, wd) * (1.0 / (1.0 + c));
}

template <class T>
struct Strains
{
  T twist, k1, k2;
  double referenceTwist;
};

template <class T>
Strains<T> strains(const T* u, const StencilData& s)
{
  using std::atan2;
  using std::cos;
  using std::sin;
  using std::sqrt;
  const V3<T> xa{{u[0], u[1], u[2]}}, xb{{u[4], u[5], u[6]}}, xc{{u[8], u[9], u[10]}};
  const T &tha = u[3], &thb = u[7];
  const V3<T> ea = xb - xa, eb = xc - xb;
  const V3<T> ta = ea * (1.0 / sqrt(dot(ea, ea))), tb = eb * (1.0 / sqrt(dot(eb, eb)));
  // Time-parallel reference frames: the old directors carried to the current tangents.
  const V3<double> ta0 = vec(s.tangentA), tb0 = vec(s.tangentB);
  const V3<T> d1a = transport(vec(s.directorA), cross(ta0, ta), dot(ta0, ta));
  const V3<T> d1b = transport(vec(s.directorB), cross(tb0, tb), dot(tb0, tb));
  const V3<T> d2a = cross(ta, d1a), d2b = cross(tb, d1b);
  const T ca = cos(tha), sa = sin(tha), cb = cos(thb), sb = sin(thb);
  const V3<T> m1a = d1a * ca + d2a * sa, m2a = d2a * ca - d1a * sa;
  const V3<T> m1b = d1b * cb + d2b * sb, m2b = d2b * cb - d1b * sb;
  // Curvature binormal κb = 2 t_a × t_b / (1 + t_a·t_b) and the reference twist: the signed
  // angle about t_b from d1_a space-parallel transported onto t_b to d1_b.
  const V3<T> w = cross(ta, tb);
  const T c = dot(ta, tb);
  const V3<T> kb = w * (2.0 / (1.0 + c));
  const V3<T> carried = transport(d1a, w, c);
  const T angle = atan2(dot(cross(carried, d1b), tb), dot(carried, d1b));
  const double turns = std::round((s.referenceTwist - value(angle)) / (2 * M_PI));
  const T mref = angle + 2 * M_PI * turns;
  Strains<T> r{thb - tha + mref, 0.5 * (dot(kb, m1a) + dot(kb, m1b)),
               0.5 * (dot(kb, m2a) + dot(kb, m2b)), value(mref)};
  return r;
}

template <class T>
void energy(const T* u, const StencilData& s, T& bending, T& twisting, T& viscous)
{
  const Strains<T> q = strains(u, s);
  const double il = 1 / s.restLength;
  const T dm = q.twist - s.rest[0], d1 = q.k1 - s.rest[1], d2 = q.k2 - s.rest[2];
  bending = 0.5 * il * (s.stiffness[1] * (d1 * d1) + s.stiffness[2] * (d2 * d2));
  twisting = 0.5 * il * s.stiffness[0] * (dm * dm);
  if (s.viscosity > 0)
  {
    const T r0 = q.twist - s.previous[0], r1 = q.k1 - s.previous[1], r2 = q.k2 - s.previous[2];
    viscous = 0.5 * il * s.viscosity * (r0 * r0 + r1 * r1 + r2 * r2);
  }
  else
    viscous = T(0.0);
}

} // namespace

Eigen::Vector3d parallelTransport(const Eigen::Vector3d& d, const Eigen::Vector3d& a,
                                  const Eigen::Vector3d& b)
{
  const Eigen::Vector3d w = a.cross(b);
  return d + w.cross(d) + w.cross(w.cross(d)) / (1 + a.dot(b));
}

StencilStrains stencilStrains(const Vector11d& u, const StencilData& data)
{
  const Strains<double> q = strains(u.data(), data);
  StencilStrains r;
  r.strains = Eigen::Vector3d(q.twist, q.k1, q.k2);
  r.referenceTwist = q.referenceTwist;
  return r;
}

StencilEnergy stencilEnergy(const Vector11d& u, const StencilData& data)
{
  StencilEnergy e;
  energy(u.data(), data, e.bending, e.twisting, e.viscous);
  return e;
}

double stencilEnergy(const Vector11d& u, const StencilData& data, Vector11d& gradient,
                     Matrix11d& hessian)
{
  Jet x[11];
  for (int i = 0; i < 11; ++i)
    x[i] = Jet::variable(u[i], i);
  Jet b, t, v;
  energy(x, data, b, t, v);
  const Jet e = b + t + v;
  gradient = e.g;
  hessian = 0.5 * (e.h + e.h.transpose());
  return e.v;
}

} // namespace hair

// What is left of SuperHelix once the step's phases have their own files: initialize()
// (the natural curvature drawn from the seed, the stiffness and friction diagonals, the
// state at rest), the elastic energy, the root state, the per-thread step workspace and
// the accessors that read it, and the reconstruction counter. The other parts:
// StrandSpec.cxx, Kinematics.cxx, Assembly.cxx, VelocityJacobian.cxx,
// ContactJacobians.cxx, StepKernels.cxx, Step.cxx, StepStrands.cxx. All but StepKernels.cxx
// are compiled as one translation unit (Core/CMakeLists.txt), so names in their anonymous
// namespaces must differ from file to file.
#include "superhelix/SuperHelix.h"

#include "superhelix/SuperHelixInternal.h"

#include <atomic>
#include <cmath>
#include <random>
#include <sstream>
#include <string>

namespace hair
{

detail::StepWorkspace& detail::stepWorkspace()
{
  thread_local StepWorkspace workspace;
  return workspace;
}

const Eigen::MatrixXd& SuperHelix::massMatrix() const
{
  return detail::stepWorkspace().M;
}

const Eigen::MatrixXd& SuperHelix::velocityJacobian() const
{
  return detail::stepWorkspace().C;
}

const Eigen::MatrixXd& SuperHelix::tensionStiffness() const
{
  return detail::stepWorkspace().Kt;
}

void SuperHelix::newCurId()
{
  static std::atomic<std::uint64_t> counter{0};
  CurId = ++counter;
}

namespace
{
// Deterministic on every platform (std::uniform_real_distribution is not).
double uniformSigned(std::mt19937& g)
{
  return 2.0 * (static_cast<double>(g()) / 4294967296.0) - 1.0;
}
} // namespace

std::string SuperHelix::where(double t0, double t1) const
{
  std::ostringstream s;
  s << "strand '" << Spec.name << "' (id " << Spec.id << "), step from t = " << t0
    << " s to t = " << t1 << " s: ";
  return s.str();
}

RootState SuperHelix::rootState(double time) const
{
  return Spec.root ? Spec.root(time) : RootState{};
}

Status SuperHelix::initialize(const StrandSpec& spec, double time)
{
  Status st = spec.validate();
  if (!st)
    return st;
  if (!std::isfinite(time))
    return Status::Error("strand '" + spec.name + "': initial time is not finite.");
  const RootState root = spec.root ? spec.root(time) : RootState{};
  st = root.validate();
  if (!st)
    return Status::Error("strand '" + spec.name + "' at t = " + std::to_string(time) + ": " +
                         st.message());

  Spec = spec;
  const int n = elementCount();
  Length = 0;
  Starts.resize(n + 1);
  Starts[0] = 0;
  for (int i = 0; i < n; ++i)
  {
    Length += Spec.elementLengths[i];
    Starts[i + 1] = Length;
  }
  RhoS = Spec.hair.linearDensity();
  RotI = Spec.hair.rotaryInertia();
  Rules = Spec.quadraturePoints > 0
              ? QuadratureChooser(Spec.quadratureTolerance, Spec.quadraturePoints,
                                  Spec.quadraturePoints)
              : QuadratureChooser(Spec.quadratureTolerance);
  const Eigen::Vector3d k0 = Spec.hair.naturalCurvature();
  const Eigen::Vector3d stiff = Spec.hair.stiffness();
  std::mt19937 gen(Spec.seed);
  Qrest.resize(3 * n);
  Kdiag.resize(3 * n);
  Gdiag.resize(3 * n);
  for (int e = 0; e < n; ++e)
  {
    const double l = Spec.elementLengths[e];
    for (int i = 0; i < 3; ++i)
    {
      const double var = Spec.hair.curvatureVariation * uniformSigned(gen);
      Qrest[3 * e + i] =
          Spec.restCurvature.empty() ? k0[i] * (1 + var) : Spec.restCurvature[3 * e + i];
      Kdiag[3 * e + i] = stiff[i] * l;
      Gdiag[3 * e + i] = Spec.hair.internalFriction * l;
    }
  }
  Q = Qrest;
  Qdot = Eigen::VectorXd::Zero(3 * n);
  Time = time;
  Energy = EnergyReport{};
  F.resize(3 * n);
  Initialized = true;
  MidpointSkip = MidpointBackoff = 0;
  NextSubstep = 0;
  HasPrevious = false;
  kinematics(Q, Qdot, root, Time, Cur);
  newCurId();
  CurValid = true;
  WindsValid = ContactsSet = false;
  Energy.time = Time;
  Energy.kinetic = Cur.kinetic;
  Energy.gravitational = Cur.gravitational;
  Energy.elastic = elasticEnergy(Q);
  return Status::Ok();
}

double SuperHelix::elasticEnergy(const Eigen::VectorXd& q) const
{
  return 0.5 * (Kdiag.array() * (q - Qrest).array().square()).sum();
}

} // namespace hair

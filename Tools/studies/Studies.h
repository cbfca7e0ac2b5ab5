// The studies of hair_study (issue 6 and after), one per file in Tools/studies/, each with
// its table of keys (StudyArguments.h) and its run function; hair_study.cxx dispatches to
// them by name. What several studies share is here and in common.cxx.
//
// A study's run function returns the exit status: 0 done, 1 a failed computation, 2 bad
// input (a message on stderr naming the argument and what to do). Every study is described
// in docs/study-*.md.
#pragma once

#include "../StudyArguments.h"

#include "AnalyticBodies.h"
#include "ClumpScene.h"
#include "DemoScene.h"
#include "analysis/StrandAnalysis.h"
#include "contact/BodyContacts.h"
#include "contact/HairHairContacts.h"
#include "contact/PassThrough.h"
#include "io/StateFile.h"
#include "simulation/Simulation.h"
#include "strands/BundledBody.h"
#include "superhelix/SuperHelix.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace hair::tools
{

/// One study: its name on the command line, a line saying what it does, its keys and what
/// runs it.
struct Study
{
  std::string name;
  std::string summary;
  Keys keys;
  int (*run)(const Arguments& args);
};

// Each in its own file, Tools/studies/<name>.cxx, in the order of the usage text.
Study convergenceStudy();
Study bucklingStudy();
Study releaseStudy();
Study sceneStudy();
Study integratorStudy();
Study workprecisionStudy();
Study orderStudy();
Study accuracyStudy();
Study clumpStudy();
Study demoStudy();
Study oscillationStudy();
Study pendulumStudy();
Study hairhairStudy();

/// Every study, in the order above.
std::vector<Study> studies();

// ---------------------------------------------------------------------------------------
// Shared keys and helpers.

/// The output file every study takes (its `what`: "<csv>", "<h5>").
inline Key outKey(const std::string& what)
{
  return textKey("out", "", "the output file (required)").as(what);
}

/// integrator=, the time step of a study's strands (read with integratorByName).
inline Key integratorKey()
{
  return textKey("integrator", "semi-implicit",
                 "the time step: semi-implicit (the paper's), midpoint or bdf2");
}

/// The round, straight hair of the Euler–Bernoulli comparisons (smooth preset, no natural
/// curvature); friction and drag are off unless asked for.
HairParameters roundHair(bool dissipation);

/// Opens out=<path> for writing, 17 digits.
Status openOutput(const Arguments& args, std::ofstream& out);

/// A hair preset by its name (smooth, wavy, curly, fuzzy).
Status presetByName(const std::string& name, HairType& type);

/// One row of a strand's energy budget: time, the energies, the work terms, the residual.
void energyRow(std::ostream& out, const SuperHelix& h);

/// The time step the study's strands take, by its name (toString).
Status integratorByName(const std::string& name, Integrator& integrator);

/// The root frame of a hanging strand: tangent −y (gravity −y), n1 = +x.
Eigen::Matrix3d hangingFrame();

/// A strand hanging from a root at the origin carried by `motion`, in its natural shape.
StrandSpec hangingStrand(double length, int n, const HairParameters& hair,
                         const RigidMotion& motion = RigidMotion::still());

/// The static equilibrium of `spec`'s strand under gravity: the semi-implicit step's fixed
/// point, reached with steps of 1 s (much longer than the strand's periods, so the step is a
/// damped fixed-point iteration; as in the buckling study) until the tip moves by less than
/// 1e-12 m in a step. Returns q.
Status hangAtRest(const StrandSpec& spec, Eigen::VectorXd& q, int& steps);

/// The released strand of the integrator and workprecision studies.
struct IntegratorRun
{
  std::vector<Eigen::Vector3d> tips;
  double residualShare = 0, wall = 0;
  long steps = 0, rejected = 0, firstOrder = 0;
};

IntegratorRun releasedStrand(Integrator integrator, double air, double seconds, int perFrame,
                             double tolerance, Status& st, int elements = 10);

} // namespace hair::tools

// hair_study order: see Tools/studies/Studies.h and docs/study-*.md.
#include "Studies.h"

using namespace hair;
using namespace hair::tools;

namespace
{

// ---------------------------------------------------------------------------------------
// The order of the time step in contact (docs/study-accuracy.md): a smooth 25 cm strand rooted
// on the crown of the bundled head, growing sideways, falls onto the head table and slides
// over it (body contacts with friction `friction`, 0.3 by default); the tip's largest
// distance over [0, `seconds`] (sampled every 1/30 s) from a run at 1/(30·`reference`) s of
// the same integrator, for steps of 1/(30 k) s, k = 1, 2, 4, …, `finest`; the observed order
// between consecutive k.

Status contactStrandRun(const std::vector<PosedPart>& bodies, const Eigen::Vector3d& above,
                        Integrator integrator, int perFrame, double friction, double lookAhead,
                        double seconds, std::vector<Eigen::Vector3d>& tips, long& firstOrder)
{
  const TableQuery top = bodies[0].query(above);
  if (!top.covered)
    return Status::Error("the first table does not cover the top.");
  HairParameters hp = HairParameters::preset(HairType::Smooth);
  hp.curvatureVariation = 0;
  StrandSpec s = StrandSpec::uniform(0.25, 10, hp);
  s.integrator = integrator;
  const Eigen::Vector3d root = top.surfacePoint + 0.002 * top.normal;
  s.root = [root](double)
  {
    RootState r;
    r.position = root;
    r.orientation = Eigen::Matrix3d::Identity(); // tangent +x: sideways over the head
    return r;
  };
  SuperHelix h;
  if (Status st = h.initialize(s); !st)
    return st;
  BodyContactParameters prm;
  prm.friction = friction;
  prm.lookAhead = lookAhead;
  BodyContacts contacts;
  if (Status st = contacts.setParameters(prm); !st)
    return st;
  const double rhoS = hp.linearDensity();
  h.setContactForces(
      [&](int, double, const std::vector<StrandSample>& smp, std::vector<ContactResponse>& r)
      { contacts.respond(smp, rhoS, bodies.data(), static_cast<int>(bodies.size()), r); });
  tips.assign(1, h.position(h.length()));
  firstOrder = 0;
  const long frames = std::lround(seconds * 30);
  for (long f = 0; f < frames; ++f)
  {
    for (int k = 0; k < perFrame; ++k)
    {
      if (Status st = h.step(1.0 / (30 * perFrame)); !st)
        return st;
      firstOrder += h.lastFirstOrder();
    }
    tips.push_back(h.position(h.length()));
  }
  return Status::Ok();
}

int order(const Arguments& args)
{
  const int finest = args.integer("finest"), referenceSteps = args.integer("reference");
  const double seconds = args.number("seconds"), friction = args.number("friction"),
               lookAhead = args.number("lookahead");
  std::ofstream out;
  Status s;
  std::vector<Integrator> integrators;
  {
    std::stringstream list(args.text("integrators"));
    std::string item;
    Integrator in;
    while (s && std::getline(list, item, ','))
      if (s = integratorByName(item, in); s)
        integrators.push_back(in);
  }
  if (s)
    s = openOutput(args, out);
  if (!s)
  {
    std::cerr << "hair_study order: " << s.message() << "\n";
    return 2;
  }
  // The head and trunk tables of the bundled body, or a sphere of radius 0.1 m (its table
  // cast on the exact sphere).
  const std::string bodyName = args.text("body");
  std::vector<PosedPart> bodies;
  Eigen::Vector3d above;
  BundledBody b;
  CollisionTable sphereTable;
  if (bodyName == "head")
  {
    if (s = loadBundledBody(HAIR_DATA_DIR, b); s)
    {
      bodies = {PosedPart::still(b.parts[b.head].table), PosedPart::still(b.parts[b.trunk].table)};
      above = b.headCentre + Eigen::Vector3d(0, 0.2, 0);
    }
  }
  else if (bodyName == "sphere")
  {
    const hairtest::Ellipsoid sphere(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(0.1));
    TableSpec t;
    t.projection = Projection::Spherical;
    if (s = sphereTable.build(t, sphere); s)
    {
      bodies = {PosedPart::still(sphereTable)};
      above = Eigen::Vector3d(0, 0.2, 0);
    }
  }
  else
    s = Status::Error("body=" + bodyName + " is not one of head, sphere.");
  if (!s)
  {
    std::cerr << "hair_study order: " << s.message() << "\n";
    return 1;
  }
  out << "integrator,friction,steps_per_frame,dt_s,tip_error_m,order,first_order_steps\n";
  for (Integrator in : integrators)
  {
    std::vector<Eigen::Vector3d> ref, tips;
    long firstOrder = 0;
    if (s = contactStrandRun(bodies, above, in, referenceSteps, friction, lookAhead, seconds, ref,
                             firstOrder);
        !s)
      break;
    double previous = 0;
    for (int k = 1; k <= finest; k *= 2)
    {
      if (s = contactStrandRun(bodies, above, in, k, friction, lookAhead, seconds, tips,
                               firstOrder);
          !s)
        break;
      double e = 0;
      for (size_t i = 0; i < tips.size(); ++i)
        e = std::max(e, (tips[i] - ref[i]).norm());
      out << toString(in) << "," << friction << "," << k << "," << 1.0 / (30 * k) << "," << e
          << ",";
      if (previous > 0)
        out << std::log2(previous / e);
      out << "," << firstOrder << std::endl;
      previous = e;
    }
    if (!s)
      break;
  }
  if (!s)
  {
    std::cerr << "hair_study order: " << s.message() << "\n";
    return 1;
  }
  return 0;
}

} // namespace

namespace hair::tools
{
Study orderStudy()
{
  return {
      "order", "the order of the time step in contact: a strand falling onto the head",
      Keys{outKey("<csv>"),
           textKey("integrators", "semi-implicit,bdf2", "time steps, comma-separated"),
           numberKey("friction", "0.3", 0, 10, "the body contacts' friction"),
           numberKey("lookahead", "1/30", 0, 1, "s, the contacts' look-ahead"),
           numberKey("seconds", "1", 1.0 / 30, 100, "s"),
           choiceKey("body", "head", {"head", "sphere"}, "the bundled head and trunk, or a sphere"),
           integerKey("finest", "64", 1, 4096, "steps per frame of the finest run"),
           integerKey("reference", "2048", 2, 100000, "steps per frame of the reference")},
      order};
}
} // namespace hair::tools

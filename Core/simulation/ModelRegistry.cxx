#include "simulation/ModelRegistry.h"

#include "der/DerModel.h"
#include "projective/ProjectiveModel.h"
#include "simulation/Simulation.h"
#include "superhelixmodel/SuperHelixModel.h"

#include <algorithm>
#include <cctype>

namespace hair
{

namespace
{
std::unique_ptr<StrandModel> makeSuperHelix(const SimulationOptions& options)
{
  SuperHelixOptions superHelix = options.superHelix;
  superHelix.contacts = options.contacts;
  superHelix.hairHair = options.hairHair;
  superHelix.sagFree = options.sagFree;
  return std::make_unique<SuperHelixModel>(superHelix);
}

std::unique_ptr<StrandModel> makeProjective(const SimulationOptions& options)
{
  // The body's friction law (SimulationOptions::contacts): Coulomb's with static friction,
  // the only one the projective model has, on when μ_s > 0.
  ProjectiveOptions projective = options.projective;
  const BodyContactParameters& c = options.contacts;
  const bool on = c.staticFriction > 0;
  projective.friction = on ? c.friction : 0.0;
  projective.staticFriction = on ? c.staticFriction : 0.0;
  projective.anisotropy = c.anisotropy;
  return std::make_unique<ProjectiveModel>(projective, options.sagFree);
}

std::unique_ptr<StrandModel> makeDer(const SimulationOptions& options)
{
  return std::make_unique<DerModel>(options.contacts, options.hairHair);
}

// The Super-Helix's elements are exact helices whatever the curl: 10 (3 cm on the demo's
// 30 cm guides) resolve its motion (docs/super-helix.md); the projective model's rigid
// segments: 40, as its demo runs (docs/projective-strands.md).
int superHelixElements(const HairParameters&, double)
{
  return 10;
}
int projectiveElements(const HairParameters&, double)
{
  return 40;
}

std::string lower(std::string s)
{
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}
} // namespace

const std::vector<ModelEntry>& registeredModels()
{
  static const std::vector<ModelEntry> models = {
      {ModelType::SuperHelix, "super-helix", "Super-Helix", makeSuperHelix, drawSuperHelixFrame,
       superHelixElements,
       ReadsSuperHelixOptions | ReadsBodyContactLaw | ReadsHairGrid | ReadsHairHairPairs},
      // Its friction from the body's law; its normal response is its reaction constraint.
      {ModelType::Projective, "projective", "Projective", makeProjective, drawProjectiveFrame,
       projectiveElements, 0},
      {ModelType::DiscreteElasticRods, "discrete-elastic-rods", "Discrete Elastic Rods", makeDer,
       drawDerFrame, DerModel::edgesFor, ReadsBodyContactLaw | ReadsHairGrid},
  };
  return models;
}

const std::vector<ModelReadsName>& modelReadsNames()
{
  static const std::vector<ModelReadsName> names = {
      {ReadsSuperHelixOptions, "SuperHelixOptions"},
      {ReadsBodyContactLaw, "BodyContactLaw"},
      {ReadsHairGrid, "HairGrid"},
      {ReadsHairHairPairs, "HairHairPairs"},
  };
  return names;
}

const ModelEntry* findModel(ModelType type)
{
  for (const ModelEntry& e : registeredModels())
  {
    if (e.type == type)
    {
      return &e;
    }
  }
  return nullptr;
}

const ModelEntry* findModel(const std::string& name)
{
  for (const ModelEntry& e : registeredModels())
  {
    if (name == e.name)
    {
      return &e;
    }
  }
  return nullptr;
}

std::string modelNames()
{
  std::string names;
  for (const ModelEntry& e : registeredModels())
  {
    names += (names.empty() ? "" : ", ") + std::string(e.name);
  }
  return names;
}

Status parseModel(const std::string& name, const std::string& what, ModelType& type)
{
  for (const ModelEntry& e : registeredModels())
  {
    if (lower(name) == e.name || lower(name) == lower(e.label))
    {
      type = e.type;
      return Status::Ok();
    }
  }
  return Status::Error(what + name + " is not a registered model: use one of " + modelNames() +
                       ".");
}

Status makeModel(const SimulationOptions& options, std::unique_ptr<StrandModel>& model)
{
  const ModelEntry* entry = findModel(options.model);
  if (!entry)
  {
    std::string values;
    for (const ModelEntry& e : registeredModels())
    {
      values += (values.empty() ? "" : ", ") + std::to_string(int(e.type)) + " (" + e.name + ")";
    }
    return Status::Error("the model " + std::to_string(int(options.model)) +
                         " is not a registered model: use one of " + values + ".");
  }
  model = entry->make(options);
  return Status::Ok();
}

} // namespace hair

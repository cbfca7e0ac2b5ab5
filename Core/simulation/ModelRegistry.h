#pragma once
// The strand models a run can use: the one place that names them all. Each has one entry —
// its name (the state file's "model" attribute, the tools' model=), its value (Hair
// Simulation's Model property, SimulationOptions::model), the label the GUI shows, the
// factory that makes it from the run's options and the drawer that shows its frames. The
// simulation, the filters, the reader (through drawGuides) and the tools ask here; a model no
// one registered is refused with the list of those that are (docs/architecture.md,
// "Adding a model").
#include "common/Status.h"
#include "model/GuideDrawing.h"
#include "model/StrandModel.h"
#include "strands/HairParameters.h"

#include <memory>
#include <string>
#include <vector>

namespace hair
{

/// The registered models' values (SimulationOptions::model, Hair Simulation's Model).
enum class ModelType
{
  SuperHelix = 0, ///< Bertails, Audoly, Cani et al. 2006
  Projective = 1, ///< Kurihara, Anjyo and Thalmann 1993
  DiscreteElasticRods =
      2 ///< Bergou, Wardetzky, Robinson, Audoly, Grinspun 2008; Bergou et al. 2010
};

struct SimulationOptions;

/// The groups of Hair Simulation's properties a model reads (ModelEntry::reads): the GUI
/// shows a group's properties only when the chosen model reads it (Plugin/HairSimulation.xml
/// is generated from the registry, Plugin/GenerateSimulationXml.cxx). The names are the
/// template's (`<ModelDecorator reads="BodyContactLaw"/>`).
enum ModelReads : unsigned
{
  /// The Super-Helix's own options: Integrator, Tolerance, Quadrature Tolerance.
  ReadsSuperHelixOptions = 1u << 0,
  /// The body contact law's penalty: Contacts, Contact Stiffness, Damping, Thickness, Slip
  /// Velocity (the friction coefficients are read by every model).
  ReadsBodyContactLaw = 1u << 1,
  /// Hair–hair interaction's solver and grid: Hair Hair Contacts, Hair Volume Fraction …
  /// Hair Grid Cell Size.
  ReadsHairGrid = 1u << 2,
  /// Hair–hair pairs (the near field, the coupled solve): Hair Contact Thickness … Hair
  /// Contact Per Length.
  ReadsHairHairPairs = 1u << 3,
};
/// The groups by their template names, for the XML generator and its messages.
struct ModelReadsName
{
  ModelReads group;
  const char* name;
};
const std::vector<ModelReadsName>& modelReadsNames();

struct ModelEntry
{
  ModelType type;
  const char* name;  ///< "super-helix": the state file's model attribute, the tools' model=
  const char* label; ///< "Super-Helix": Hair Simulation's Model entry
  /// The model, made with its part of `options` (not yet initialized).
  std::unique_ptr<StrandModel> (*make)(const SimulationOptions& options);
  /// Draws its frames (drawGuides); null: its frames are shown as stored.
  DrawFrame draw;
  /// The number of elements the tools give a guide of `hair` and `length` [m] when they are
  /// asked for none (hair_study demo, hair_soak).
  int (*elementsFor)(const HairParameters& hair, double length);
  /// The property groups it reads (ModelReads, or-ed).
  unsigned reads;
};

/// Every registered model, in the order of their values.
const std::vector<ModelEntry>& registeredModels();
/// The entry of a model by value or by name; null when no model is registered as that.
const ModelEntry* findModel(ModelType type);
const ModelEntry* findModel(const std::string& name);
/// The registered models' names, "super-helix, projective" (for messages and usage).
std::string modelNames();
/// The model named `name` (its name or its label, any case) into `type`; an error naming
/// `what` (e.g. "model=") and the registered names when there is none.
Status parseModel(const std::string& name, const std::string& what, ModelType& type);

/// The model `options` names, made with its options; an error naming the registered models
/// when its value is not one of theirs.
Status makeModel(const SimulationOptions& options, std::unique_ptr<StrandModel>& model);

} // namespace hair

/**
 * @class vtkHairSimulation
 * @brief Advances guide strands over time (Super-Helix or projective model), answers any
 * requested time from its cache, and writes every frame to an HDF5 state file.
 *
 * hair::Simulation does the work; this filter turns Hair Strands' polylines and Cylindrical
 * Collision Map's tables into a scene, time requests into frames, and frames into
 * polylines. Port 0: the strands; port 1: any number of collision tables (optional).
 * Output 0: the strands at the requested time (point data Velocity, Speed, curvature,
 * twist, contact_depth, Tangent, Director1; cell data StrandId, the per-strand parameters and
 * vectors), drawn by hair::drawGuides. Output 1: one row per
 * computed frame of every energy term, the nodes inside a body part and the deepest of them,
 * and the model's step statistics (Super-Helix: sub-steps and their error estimate).
 */
#ifndef vtkHairSimulation_h
#define vtkHairSimulation_h

#include "HairDynamicsFiltersModule.h"

#include <vtkPolyDataAlgorithm.h>

#include <memory>
#include <string>

class HAIRDYNAMICSFILTERS_EXPORT vtkHairSimulation : public vtkPolyDataAlgorithm
{
public:
  static vtkHairSimulation* New();
  vtkTypeMacro(vtkHairSimulation, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The collision tables (Cylindrical Collision Map, output 0), any number.
  void AddColliderConnection(vtkAlgorithmOutput* output) { this->AddInputConnection(1, output); }
  void RemoveAllColliders() { this->SetInputConnection(1, nullptr); }

  enum MotionType
  {
    NONE = 0,
    SHAKE = 1,
    NOD = 2,
    VERTICAL = 3
  };

  /// A model's value in Core's model registry (simulation/ModelRegistry.h: 0 Super-Helix,
  /// 1 projective, 2 Discrete Elastic Rods); any other is refused, with the registered ones,
  /// when the filter runs.
  vtkSetMacro(Model, int);
  vtkGetMacro(Model, int);
  vtkSetMacro(TimeStep, double);
  vtkGetMacro(TimeStep, double);
  vtkSetMacro(Duration, double);
  vtkGetMacro(Duration, double);
  vtkSetMacro(FrameRate, double);
  vtkGetMacro(FrameRate, double);
  vtkSetVector3Macro(Gravity, double);
  vtkGetVector3Macro(Gravity, double);
  vtkSetVector3Macro(Wind, double);
  vtkGetVector3Macro(Wind, double);
  vtkSetClampMacro(BodyMotion, int, NONE, VERTICAL);
  vtkGetMacro(BodyMotion, int);
  vtkSetMacro(MotionAmplitude, double);
  vtkGetMacro(MotionAmplitude, double);
  vtkSetMacro(MotionFrequency, double);
  vtkGetMacro(MotionFrequency, double);
  /// Seconds over which the motion grows from rest (0: it starts at full amplitude).
  vtkSetMacro(MotionFadeIn, double);
  vtkGetMacro(MotionFadeIn, double);
  vtkSetVector3Macro(MotionAxis, double);
  vtkGetVector3Macro(MotionAxis, double);
  vtkSetVector3Macro(MotionPivot, double);
  vtkGetVector3Macro(MotionPivot, double);
  /// Super-Helix points per element drawn in output 0, exactly on the helices from the
  /// frame's state; the projective model's points are its segments' nodes whatever this
  /// says. Changing it draws the frame again: the run goes on.
  void SetPointsPerElement(int points);
  vtkGetMacro(PointsPerElement, int);
  vtkSetMacro(NumberOfThreads, int);
  vtkGetMacro(NumberOfThreads, int);
  /// Super-Helix: the time step, hair::Integrator (SEMI_IMPLICIT: the paper's, SECOND_ORDER:
  /// the guarded implicit midpoint rule, BDF2: the guarded two-step backward differentiation
  /// formula, second order in contact).
  enum IntegratorType
  {
    SEMI_IMPLICIT = 0,
    SECOND_ORDER = 1,
    BDF2 = 2
  };
  vtkSetClampMacro(Integrator, int, SEMI_IMPLICIT, BDF2);
  vtkGetMacro(Integrator, int);
  /// Super-Helix: accuracy on request, m per second of simulated time
  /// (hair::SuperHelixOptions::tolerance); 0: fixed steps. Checked against [0, 1].
  vtkSetMacro(Tolerance, double);
  vtkGetMacro(Tolerance, double);
  /// Super-Helix: hair::SimulationOptions::quadratureTolerance. Not clamped here:
  /// hair::SimulationOptions::validate refuses values outside [1e-15, 1e-2] with a message.
  vtkSetMacro(QuadratureTolerance, double);
  vtkGetMacro(QuadratureTolerance, double);
  /// Super-Helix hair–body contacts (docs/superhelix-contacts.md). Not clamped here:
  /// hair::BodyContactParameters::validate refuses bad values with a message.
  vtkSetMacro(Contacts, bool);
  vtkGetMacro(Contacts, bool);
  vtkBooleanMacro(Contacts, bool);
  vtkSetMacro(ContactStiffness, double);
  vtkGetMacro(ContactStiffness, double);
  vtkSetMacro(ContactDamping, double);
  vtkGetMacro(ContactDamping, double);
  vtkSetMacro(FrictionCoefficient, double);
  vtkGetMacro(FrictionCoefficient, double);
  vtkSetMacro(FrictionAnisotropy, double);
  vtkGetMacro(FrictionAnisotropy, double);
  vtkSetMacro(StaticFrictionCoefficient, double);
  vtkGetMacro(StaticFrictionCoefficient, double);
  vtkSetMacro(ContactThickness, double);
  vtkGetMacro(ContactThickness, double);
  /// Super-Helix: how the guides interact with each other (hair::HairHairSolver; its values,
  /// 0: off). GRID (the default): the far field of hair::HairGrid, volume and friction;
  /// GRID_AND_NEAR_FIELD: with hair::NearFieldContacts against crossing (one rank);
  /// COUPLED: every close pair solved with the step (hair::HairHairContacts; one rank).
  enum HairHairType
  {
    HAIR_HAIR_OFF = 0,
    HAIR_HAIR_COUPLED = 1,
    HAIR_HAIR_GRID = 2,
    HAIR_HAIR_GRID_AND_NEAR_FIELD = 3
  };
  vtkSetMacro(HairHairContacts, int);
  vtkGetMacro(HairHairContacts, int);
  /// The grid (hair::HairGridParameters): the rest volume fraction φ0, the share of the
  /// packing above it undone in a step, the friction rate β [1/s], the cell [m] (0: auto).
  vtkSetMacro(HairVolumeFraction, double);
  vtkGetMacro(HairVolumeFraction, double);
  vtkSetMacro(HairVolume, double);
  vtkGetMacro(HairVolume, double);
  vtkSetMacro(HairGridFriction, double);
  vtkGetMacro(HairGridFriction, double);
  vtkSetMacro(HairGridCellSize, double);
  vtkGetMacro(HairGridCellSize, double);
  vtkSetMacro(HairContactThickness, double);
  vtkGetMacro(HairContactThickness, double);
  vtkSetMacro(HairContactStiffness, double);
  vtkGetMacro(HairContactStiffness, double);
  vtkSetMacro(HairContactDamping, double);
  vtkGetMacro(HairContactDamping, double);
  /// Coulomb friction coefficient between guides (dimensionless).
  vtkSetMacro(HairFrictionCoefficient, double);
  vtkGetMacro(HairFrictionCoefficient, double);
  /// Most Gauss–Seidel sweeps of the hair–hair solve per detection round.
  vtkSetMacro(HairContactIterations, int);
  vtkGetMacro(HairContactIterations, int);
  /// Hair–hair penalty per length of contact (HairHairParameters::perLength, ℓ_ref = 1 cm).
  vtkSetMacro(HairContactPerLength, bool);
  vtkGetMacro(HairContactPerLength, bool);
  vtkSetMacro(SlipVelocity, double);
  vtkGetMacro(SlipVelocity, double);
  /// Where every frame is written (HDF5, docs/state-file.md); empty: not written.
  vtkSetStdStringFromCharMacro(StateFileName);
  vtkGetCharFromStdStringMacro(StateFileName);
  /// Replace a HairDynamics state file already at StateFileName (anything else there is
  /// never written over).
  vtkSetMacro(OverwriteStateFile, bool);
  vtkGetMacro(OverwriteStateFile, bool);
  vtkBooleanMacro(OverwriteStateFile, bool);
  /// Continue the run whose state file is at StateFileName from its last whole frame (a run
  /// that was killed or stopped), instead of starting it: the inputs and properties must be
  /// those it was written with (refused, naming what differs, otherwise).
  vtkSetMacro(Resume, bool);
  vtkGetMacro(Resume, bool);
  vtkBooleanMacro(Resume, bool);

  /// Memory the frames may take, in MiB; 0: half of this machine's memory. A run that needs
  /// more is refused, unless a state file is set: then only the newest frames that fit stay
  /// in memory and earlier ones are read back from the file.
  vtkSetMacro(MemoryBudget, double);
  vtkGetMacro(MemoryBudget, double);

  /// Drops every computed frame: the next request starts again from t = 0.
  void Reset();

protected:
  vtkHairSimulation();
  ~vtkHairSimulation() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Model = 0;
  double TimeStep = 1.0 / 30;
  double Duration = 5;
  double FrameRate = 30;
  double Gravity[3] = {0, -9.81, 0};
  double Wind[3] = {0, 0, 0};
  int BodyMotion = NONE;
  double MotionAmplitude = 0.5;
  double MotionFrequency = 1.0;
  double MotionFadeIn = 0;
  double MotionAxis[3] = {0, 1, 0};
  double MotionPivot[3]; ///< the bundled body's neck (hair::bundled::neckPivot), by the constructor
  int PointsPerElement = 16;
  int NumberOfThreads = 2;
  double QuadratureTolerance; ///< Core's default, set by the constructor
  int Integrator = SEMI_IMPLICIT;
  double Tolerance = 0; ///< m/s, 0: fixed steps
  bool Contacts = true;
  double ContactStiffness = 10;         ///< N/m²
  double ContactDamping = 1;            ///< fraction of critical
  double FrictionCoefficient = 0.3;     ///< μ
  double FrictionAnisotropy = 0.2;      ///< a: μ (1 ± a) against / with the scales
  double StaticFrictionCoefficient = 0; ///< μ_s; 0: no sticking
  double ContactThickness = 1e-3;       ///< m
  int HairHairContacts = HAIR_HAIR_GRID;
  double HairVolumeFraction = 0.05;     ///< φ0 (hair::HairGridParameters)
  double HairVolume = 1;                ///< share of the packing above φ0 undone per step
  double HairGridFriction = 10;         ///< 1/s
  double HairGridCellSize = 0;          ///< m; 0: automatic
  double HairContactThickness = 0;      ///< m, radius of the clump a guide stands for; 0: auto
  double HairContactStiffness = 1;      ///< N/m per contact
  double HairContactDamping = 2e-4;     ///< N·s/m
  double HairFrictionCoefficient = 0.3; ///< μ, Coulomb
  int HairContactIterations = 10;       ///< Gauss–Seidel sweeps per round
  bool HairContactPerLength = false;
  double SlipVelocity = 1e-3; ///< m/s
  std::string StateFileName;
  bool OverwriteStateFile = false;
  bool Resume = false;
  double MemoryBudget = 0; ///< MiB, 0: half of the machine's memory

private:
  /// Builds the run from the inputs and the properties; false (with the error reported)
  /// when they are refused.
  bool Build(vtkInformationVector** inputVector);
  /// Warns of the strands whose groom no natural shape can hold (each with its reason).
  void WarnGroom();
  /// The run's properties against the ranges of their XML domains (no setter clamps): an
  /// error naming the property, its value and its range, before any work.
  bool CheckProperties();
  vtkHairSimulation(const vtkHairSimulation&) = delete;
  void operator=(const vtkHairSimulation&) = delete;
  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif

#pragma once
// vtkPolyData / vtkImageData <-> HairCore types. The one place where the pipeline's data
// and Core's meet; filters call these and stay thin.
#include "collision/CollisionTable.h"
#include "common/Ranks.h"
#include "common/Status.h"
#include "geometry/TriangleMesh.h"
#include "io/StateFile.h"
#include "render/HairInterpolation.h"
#include "simulation/GuideDrawing.h"
#include "strands/GuideStrand.h"

#include <vtkCellArray.h>
#include <vtkSmartPointer.h>
#include <vtkType.h>

#include <map>
#include <string>
#include <vector>

class vtkImageData;
class vtkMultiProcessController;
class vtkPolyData;
class vtkTable;

namespace hair
{
namespace convert
{

/// Triangulates the polygons and strips of `input` (lines and vertices are ignored) into a
/// triangle soup. `what` names the input in messages.
Status toTriangleMesh(vtkPolyData* input, const std::string& what, TriangleMesh& mesh);

/// Field-data names of a table image: the frame and extent that turn it back into a table.
namespace names
{
constexpr const char* Radius = "Radius";
constexpr const char* InnerRadius = "InnerRadius";
constexpr const char* Normal = "Normal";
constexpr const char* InnerNormal = "InnerNormal";
constexpr const char* Hit = "Hit";
constexpr const char* Projection = "Projection";
constexpr const char* FrameOrigin = "FrameOrigin";
constexpr const char* FrameAxis = "FrameAxis";
constexpr const char* FrameReference = "FrameReference";
constexpr const char* HeightRange = "HeightRange";
constexpr const char* MaximumRadius = "MaximumRadius";
constexpr const char* BodyPartName = "BodyPartName";
constexpr const char* MovesWithHead = "MovesWithHead";
} // namespace names

/// Writes `table` into `image`: dimensions azimuth × second × 1, x = azimuth (radians),
/// y = height (cylindrical) or polar angle (spherical); point arrays Radius, InnerRadius,
/// Normal, InnerNormal, Hit; the frame and extent in field data.
void toImage(const CollisionTable& table, const std::string& bodyPart, bool movesWithHead,
             vtkImageData* image);

/// Reads a table written by toImage back. Refuses an image that is not a collision table.
Status fromImage(vtkImageData* image, CollisionTable& table, std::string* bodyPart = nullptr,
                 bool* movesWithHead = nullptr);

/// The surface the table represents (outer radii), as quads between neighbouring samples
/// that met the body, with the Radius and Normals arrays, in world coordinates.
void toSurface(const CollisionTable& table, vtkPolyData* surface);

/// Guide strands as polylines (each polyline's points as grown, root first), with the cell
/// arrays of every per-strand parameter (strands/StrandParameters.h), RootNormal and
/// GrowthDirection, and StrandId.
void fromGuides(const std::vector<GuideStrand>& guides,
                const std::vector<std::vector<Eigen::Vector3d>>& polylines, vtkPolyData* strands);

/// Hair Strands' polylines and cell arrays back into guide strands: refuses an input without
/// polylines, a missing cell array (but an optional one, strands/StrandParameters.h) or one
/// without a value per polyline, and an empty polyline, naming which. A polyline marked
/// Groomed (1) is its guide's curve (GuideStrand::curve).
Status toGuides(vtkPolyData* input, std::vector<GuideStrand>& guides);

/// Guide curves: the points of each polyline of `input`, root first, and the cell array
/// RootNormal when it has one (else `normals` is left empty). Refuses an input without
/// polylines.
Status toCurves(vtkPolyData* input, std::vector<std::vector<Eigen::Vector3d>>& curves,
                std::vector<Eigen::Vector3d>& normals);

/// Guides over time (Hair Simulation's or Hair State Reader's output, or Hair Strands' at
/// rest) for the interpolation: the guides as grown (`rest`: the cell array RestRoot, or the
/// first point when there is none, RootNormal, GrowthDirection and the per-strand
/// parameters) and their curves now (points; point arrays Tangent and Director1 when
/// present; Speed and curvature carried when present). Refuses what toGuides refuses.
Status toGuideCurves(vtkPolyData* input, std::vector<GuideStrand>& rest, GuideCurves& curves);

/// The output of rendered hair laid out for `strands` polylines of `n` points, its arrays
/// made and handed back as where HairInterpolation::evaluate writes (no copy): float points,
/// point data Tangent, ArcParameter and one per carried scalar (`scalarNames`, the guides'
/// order; "curvature" named Curvature), cell data StrandId and GuideId. `lines`, the
/// polylines' cells, is kept by the caller and made again only when the counts change.
RenderedHairArrays prepareRenderedHair(vtkPolyData* output, vtkIdType strands, int n,
                                       const std::vector<std::string>& scalarNames,
                                       vtkSmartPointer<vtkCellArray>& lines);

/// Field data PointsLookedUp, PointsPushedOut, DeepestBeforePushOut (m) and
/// PointsInsideAfterPushOut.
void addPushOutCounts(const PushOutCounts& counts, vtkPolyData* output);

/// One polyline per strand (points offsets[k] … offsets[k+1]−1), point data Velocity and
/// Speed, cell data StrandId and every per-strand parameter and vector (named as the
/// pipeline names them, strands/StrandParameters.h) and the groom's reports when the run has
/// them (FitError, RestShapeStatus, GroomDeviation, Stability: model/GroomReport.h); the
/// frame's time in field data ("Time").
void toStrands(const StateHeader& header, const StateFrame& frame, vtkPolyData* strands);

/// The drawn guides: toStrands of the drawing's header and frame, and the point arrays
/// Tangent and Director1 (3 components) when the drawing has material frames.
void toStrands(const GuideDrawing& drawing, vtkPolyData* strands);

/// The ranks of ParaView's MPI controller (pvbatch, pvserver under mpirun) as Core's Ranks
/// (a duplicate of its communicator; collective over the controller's processes): this
/// process alone without MPI or on one process.
Ranks toRanks(vtkMultiProcessController* controller);

/// Appends `ghosts` (strands of other MPI ranks, with the same arrays) to `strands`, and
/// marks them with VTK's ghost arrays (vtkGhostType: DUPLICATECELL on their cells,
/// DUPLICATEPOINT on their points; 0 on the strands' own), which renderers hide and
/// filters that count skip.
void appendGhosts(vtkPolyData* strands, vtkPolyData* ghosts);

/// One row per frame: Time, then one column per entry of `columns` (energy terms and, from a
/// simulation, the penetration and the model's step statistics). Which of them are energy
/// terms, `energyTerms`, goes with the table as its field data "EnergyTerms" (a string per
/// term), so that Hair Analysis takes those and no other column, whatever model made them.
void toEnergyTable(const std::vector<double>& times,
                   const std::map<std::string, std::vector<double>>& columns,
                   const std::vector<std::string>& energyTerms, vtkTable* table);

} // namespace convert
} // namespace hair

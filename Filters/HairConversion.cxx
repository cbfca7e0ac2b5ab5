#include "HairConversion.h"

#include "model/GroomReport.h"
#include "strands/StrandParameters.h"

#include <vtkAppendPolyData.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataSetAttributes.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkIdList.h>
#include <vtkIdTypeArray.h>
#include <vtkImageData.h>
#include <vtkIntArray.h>
#include <vtkMPI.h>
#include <vtkMPICommunicator.h>
#include <vtkMPIController.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkTable.h>
#include <vtkTriangleFilter.h>
#include <vtkUnsignedCharArray.h>

#include <cmath>
#include <utility>

namespace hair
{
namespace convert
{

Status toTriangleMesh(vtkPolyData* input, const std::string& what, TriangleMesh& mesh)
{
  if (input == nullptr || input->GetNumberOfPoints() == 0)
  {
    return Status::Error(what + " is empty: connect a surface mesh (e.g. Data/body.vtk).");
  }
  if (input->GetNumberOfPolys() + input->GetNumberOfStrips() == 0)
  {
    return Status::Error(
        what + " has " + std::to_string(input->GetNumberOfPoints()) +
        " points but no polygons: the table needs a closed surface (apply Extract Surface to a "
        "volume mesh first).");
  }
  vtkNew<vtkPolyData> surface;
  surface->SetPoints(input->GetPoints());
  surface->SetPolys(input->GetPolys());
  surface->SetStrips(input->GetStrips());
  vtkNew<vtkTriangleFilter> triangulate;
  triangulate->SetInputData(surface);
  triangulate->PassLinesOff();
  triangulate->PassVertsOff();
  triangulate->Update();
  vtkPolyData* tri = triangulate->GetOutput();

  TriangleMesh m;
  m.points.resize(tri->GetNumberOfPoints());
  for (vtkIdType i = 0; i < tri->GetNumberOfPoints(); ++i)
  {
    double p[3];
    tri->GetPoint(i, p);
    m.points[i] = Eigen::Vector3d(p[0], p[1], p[2]);
  }
  vtkCellArray* polys = tri->GetPolys();
  m.triangles.reserve(polys->GetNumberOfCells());
  vtkNew<vtkIdList> ids;
  for (polys->InitTraversal(); polys->GetNextCell(ids);)
  {
    if (ids->GetNumberOfIds() == 3)
    {
      m.triangles.push_back({static_cast<int>(ids->GetId(0)), static_cast<int>(ids->GetId(1)),
                             static_cast<int>(ids->GetId(2))});
    }
  }
  if (Status s = m.validate(what); !s)
  {
    return s;
  }
  mesh = std::move(m);
  return Status::Ok();
}

namespace
{
void addField(vtkFieldData* fd, const char* name, const Eigen::Vector3d& v)
{
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->SetNumberOfComponents(3);
  a->InsertNextTuple3(v.x(), v.y(), v.z());
  fd->AddArray(a);
}

void addField(vtkFieldData* fd, const char* name, std::initializer_list<double> values)
{
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  for (double v : values)
  {
    a->InsertNextValue(v);
  }
  fd->AddArray(a);
}

vtkDataArray* field(vtkFieldData* fd, const char* name, int components, vtkIdType minimumValues)
{
  vtkDataArray* a = fd ? vtkDataArray::SafeDownCast(fd->GetAbstractArray(name)) : nullptr;
  if (a == nullptr || a->GetNumberOfComponents() != components ||
      a->GetNumberOfValues() < minimumValues)
  {
    return nullptr;
  }
  return a;
}

vtkDoubleArray* pointArray(const char* name, int components, vtkIdType n)
{
  auto* a = vtkDoubleArray::New();
  a->SetName(name);
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(n);
  return a;
}
} // namespace

void toImage(const CollisionTable& table, const std::string& bodyPart, bool movesWithHead,
             vtkImageData* image)
{
  const TableSpec& spec = table.spec();
  const int na = spec.azimuthSamples, ns = spec.secondSamples;
  image->Initialize();
  image->SetDimensions(na, ns, 1);
  image->SetOrigin(0, table.second(0), 0);
  image->SetSpacing(2 * M_PI / na, (table.second(ns - 1) - table.second(0)) / (ns - 1), 1);
  const vtkIdType n = vtkIdType(na) * ns;
  vtkSmartPointer<vtkDoubleArray> outer =
      vtkSmartPointer<vtkDoubleArray>::Take(pointArray(names::Radius, 1, n));
  vtkSmartPointer<vtkDoubleArray> inner =
      vtkSmartPointer<vtkDoubleArray>::Take(pointArray(names::InnerRadius, 1, n));
  vtkSmartPointer<vtkDoubleArray> normal =
      vtkSmartPointer<vtkDoubleArray>::Take(pointArray(names::Normal, 3, n));
  vtkSmartPointer<vtkDoubleArray> innerNormal =
      vtkSmartPointer<vtkDoubleArray>::Take(pointArray(names::InnerNormal, 3, n));
  vtkNew<vtkUnsignedCharArray> hit;
  hit->SetName(names::Hit);
  hit->SetNumberOfTuples(n);
  for (vtkIdType s = 0; s < n; ++s)
  {
    outer->SetValue(s, table.outerRadius()[s]);
    inner->SetValue(s, table.innerRadius()[s]);
    normal->SetTuple(s, table.outerNormal()[s].data());
    innerNormal->SetTuple(s, table.innerNormal()[s].data());
    hit->SetValue(s, table.hit()[s]);
  }
  vtkPointData* pd = image->GetPointData();
  pd->AddArray(outer);
  pd->AddArray(inner);
  pd->AddArray(normal);
  pd->AddArray(innerNormal);
  pd->AddArray(hit);
  pd->SetActiveScalars(names::Radius);

  vtkFieldData* fd = image->GetFieldData();
  vtkNew<vtkIntArray> projection;
  projection->SetName(names::Projection);
  projection->InsertNextValue(static_cast<int>(spec.projection));
  fd->AddArray(projection);
  addField(fd, names::FrameOrigin, spec.frame.origin);
  addField(fd, names::FrameAxis, spec.frame.axis);
  addField(fd, names::FrameReference, spec.frame.reference);
  addField(fd, names::HeightRange, {spec.heightMin, spec.heightMax});
  addField(fd, names::MaximumRadius, {std::isfinite(spec.maxRadius) ? spec.maxRadius : 0.0});
  vtkNew<vtkStringArray> name;
  name->SetName(names::BodyPartName);
  name->InsertNextValue(bodyPart);
  fd->AddArray(name);
  vtkNew<vtkIntArray> moves;
  moves->SetName(names::MovesWithHead);
  moves->InsertNextValue(movesWithHead ? 1 : 0);
  fd->AddArray(moves);
}

Status fromImage(vtkImageData* image, CollisionTable& table, std::string* bodyPart,
                 bool* movesWithHead)
{
  const std::string notATable =
      "is not a collision table (make it with the Cylindrical Collision Map filter)";
  if (image == nullptr)
  {
    return Status::Error("the collision table input is missing.");
  }
  int dims[3];
  image->GetDimensions(dims);
  vtkFieldData* fd = image->GetFieldData();
  vtkDataArray* projection = field(fd, names::Projection, 1, 1);
  vtkDataArray* origin = field(fd, names::FrameOrigin, 3, 3);
  vtkDataArray* axis = field(fd, names::FrameAxis, 3, 3);
  vtkDataArray* reference = field(fd, names::FrameReference, 3, 3);
  vtkDataArray* heights = field(fd, names::HeightRange, 1, 2);
  vtkDataArray* maxRadius = field(fd, names::MaximumRadius, 1, 1);
  if (!projection || !origin || !axis || !reference || !heights || !maxRadius)
  {
    return Status::Error("the image " + notATable + ": its frame is missing from field data.");
  }
  vtkPointData* pd = image->GetPointData();
  const vtkIdType n = vtkIdType(dims[0]) * dims[1];
  auto pointArray = [&](const char* name, int components) -> vtkDataArray*
  {
    vtkDataArray* a = pd->GetArray(name);
    return a && a->GetNumberOfComponents() == components && a->GetNumberOfTuples() == n ? a
                                                                                        : nullptr;
  };
  vtkDataArray* outer = pointArray(names::Radius, 1);
  vtkDataArray* inner = pointArray(names::InnerRadius, 1);
  vtkDataArray* normal = pointArray(names::Normal, 3);
  vtkDataArray* innerNormal = pointArray(names::InnerNormal, 3);
  vtkDataArray* hit = pointArray(names::Hit, 1);
  if (dims[2] != 1 || !outer || !inner || !normal || !innerNormal || !hit)
  {
    return Status::Error("the image " + notATable +
                         ": its Radius, InnerRadius, Normal, "
                         "InnerNormal or Hit array is missing.");
  }
  TableSpec spec;
  const int p = static_cast<int>(projection->GetTuple1(0));
  if (p != 0 && p != 1)
  {
    return Status::Error("the image " + notATable + ": unknown projection " + std::to_string(p));
  }
  spec.projection = static_cast<Projection>(p);
  for (int k = 0; k < 3; ++k)
  {
    spec.frame.origin[k] = origin->GetComponent(0, k);
    spec.frame.axis[k] = axis->GetComponent(0, k);
    spec.frame.reference[k] = reference->GetComponent(0, k);
  }
  spec.azimuthSamples = dims[0];
  spec.secondSamples = dims[1];
  spec.heightMin = heights->GetComponent(0, 0);
  spec.heightMax = heights->GetComponent(1, 0);
  const double r = maxRadius->GetTuple1(0);
  spec.maxRadius = r > 0 ? r : std::numeric_limits<double>::infinity();
  std::vector<std::uint8_t> h(n);
  std::vector<double> ro(n), ri(n);
  std::vector<Eigen::Vector3d> no(n), ni(n);
  for (vtkIdType s = 0; s < n; ++s)
  {
    h[s] = hit->GetTuple1(s) != 0;
    ro[s] = outer->GetTuple1(s);
    ri[s] = inner->GetTuple1(s);
    normal->GetTuple(s, no[s].data());
    innerNormal->GetTuple(s, ni[s].data());
  }
  CollisionTable t;
  if (Status s =
          t.assign(spec, std::move(h), std::move(ro), std::move(ri), std::move(no), std::move(ni));
      !s)
  {
    return s;
  }
  if (bodyPart)
  {
    auto* names = vtkStringArray::SafeDownCast(fd->GetAbstractArray(names::BodyPartName));
    *bodyPart = names && names->GetNumberOfValues() > 0 ? names->GetValue(0) : std::string();
  }
  if (movesWithHead)
  {
    vtkDataArray* m = field(fd, names::MovesWithHead, 1, 1);
    *movesWithHead = m && m->GetTuple1(0) != 0;
  }
  table = std::move(t);
  return Status::Ok();
}

void toSurface(const CollisionTable& table, vtkPolyData* surface)
{
  const TableSpec& spec = table.spec();
  const int na = spec.azimuthSamples, ns = spec.secondSamples;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(vtkIdType(na) * ns);
  vtkSmartPointer<vtkDoubleArray> radius =
      vtkSmartPointer<vtkDoubleArray>::Take(pointArray(names::Radius, 1, vtkIdType(na) * ns));
  vtkSmartPointer<vtkDoubleArray> normals =
      vtkSmartPointer<vtkDoubleArray>::Take(pointArray("Normals", 3, vtkIdType(na) * ns));
  for (int j = 0; j < ns; ++j)
  {
    for (int i = 0; i < na; ++i)
    {
      const int s = table.index(i, j);
      const Eigen::Vector3d x =
          table.rayOrigin(i, j) + table.outerRadius()[s] * table.rayDirection(i, j);
      points->SetPoint(s, x.data());
      radius->SetValue(s, table.outerRadius()[s]);
      normals->SetTuple(s, table.outerNormal()[s].data());
    }
  }
  vtkNew<vtkCellArray> quads;
  for (int j = 0; j + 1 < ns; ++j)
  {
    for (int i = 0; i < na; ++i)
    {
      const int i1 = (i + 1) % na;
      // Counter-clockwise seen from outside: (+θ, +height) turns outwards on a cylinder,
      // (+θ, +polar angle) inwards on a sphere, so the spherical quads run the other way
      // (renderers take the winding as the front side for two-sided lighting).
      vtkIdType q[4] = {table.index(i, j), table.index(i1, j), table.index(i1, j + 1),
                        table.index(i, j + 1)};
      if (spec.projection == Projection::Spherical)
      {
        std::swap(q[1], q[3]);
      }
      if (table.hit()[q[0]] && table.hit()[q[1]] && table.hit()[q[2]] && table.hit()[q[3]])
      {
        quads->InsertNextCell(4, q);
      }
    }
  }
  surface->Initialize();
  surface->SetPoints(points);
  surface->SetPolys(quads);
  surface->GetPointData()->AddArray(radius);
  surface->GetPointData()->SetNormals(normals);
  surface->GetPointData()->SetActiveScalars(names::Radius);
}

void toStrands(const StateHeader& header, const StateFrame& frame, vtkPolyData* strands)
{
  const vtkIdType n = static_cast<vtkIdType>(frame.positions.size());
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(n);
  vtkSmartPointer<vtkDoubleArray> velocity =
      vtkSmartPointer<vtkDoubleArray>::Take(pointArray("Velocity", 3, n));
  vtkSmartPointer<vtkDoubleArray> speed =
      vtkSmartPointer<vtkDoubleArray>::Take(pointArray("Speed", 1, n));
  for (vtkIdType i = 0; i < n; ++i)
  {
    points->SetPoint(i, frame.positions[i].data());
    const Eigen::Vector3d v =
        i < vtkIdType(frame.velocities.size()) ? frame.velocities[i] : Eigen::Vector3d::Zero();
    velocity->SetTuple(i, v.data());
    speed->SetValue(i, v.norm());
  }
  vtkNew<vtkCellArray> lines;
  vtkNew<vtkIdTypeArray> ids;
  ids->SetName("StrandId");
  const std::size_t strandsCount = header.numberOfStrands();
  for (std::size_t k = 0; k < strandsCount; ++k)
  {
    const vtkIdType first = header.offsets[k], last = header.offsets[k + 1];
    lines->InsertNextCell(last - first);
    for (vtkIdType i = first; i < last; ++i)
    {
      lines->InsertCellPoint(i);
    }
    ids->InsertNextValue(static_cast<vtkIdType>(header.strandId(k)));
  }
  strands->Initialize();
  strands->SetPoints(points);
  strands->SetLines(lines);
  strands->GetPointData()->AddArray(velocity);
  strands->GetPointData()->AddArray(speed);
  for (const auto& [name, values] : frame.pointData)
  {
    vtkSmartPointer<vtkDoubleArray> a =
        vtkSmartPointer<vtkDoubleArray>::Take(pointArray(name.c_str(), 1, n));
    for (vtkIdType i = 0; i < n && i < vtkIdType(values.size()); ++i)
    {
      a->SetValue(i, values[i]);
    }
    strands->GetPointData()->AddArray(a);
  }
  strands->GetPointData()->SetActiveScalars("Speed");
  strands->GetCellData()->AddArray(ids);
  for (const auto& [name, values] : header.strandParameters)
  {
    // The pipeline's name of a parameter the table knows; a file's own name otherwise.
    std::string arrayName = name;
    for (const StrandParameter& p : strandParameters())
    {
      if (name == p.file)
      {
        arrayName = p.array;
      }
    }
    vtkNew<vtkDoubleArray> a;
    a->SetName(arrayName.c_str());
    a->SetNumberOfTuples(static_cast<vtkIdType>(values.size()));
    for (std::size_t k = 0; k < values.size(); ++k)
    {
      a->SetValue(static_cast<vtkIdType>(k), values[k]);
    }
    strands->GetCellData()->AddArray(a);
  }
  for (const auto& [name, values] : header.strandVectors)
  {
    std::string arrayName = name;
    for (const StrandVector& v : strandVectors())
    {
      if (name == v.file)
      {
        arrayName = v.array;
      }
    }
    vtkSmartPointer<vtkDoubleArray> a = vtkSmartPointer<vtkDoubleArray>::Take(
        pointArray(arrayName.c_str(), 3, static_cast<vtkIdType>(values.size())));
    for (std::size_t k = 0; k < values.size(); ++k)
    {
      a->SetTuple(static_cast<vtkIdType>(k), values[k].data());
    }
    strands->GetCellData()->AddArray(a);
  }
  for (const GroomReportValue& v : groomReportValues())
  {
    const auto it = header.groom.strandValues.find(v.file);
    if (it == header.groom.strandValues.end())
    {
      continue;
    }
    vtkNew<vtkDoubleArray> a;
    a->SetName(v.array);
    a->SetNumberOfTuples(static_cast<vtkIdType>(it->second.size()));
    for (std::size_t k = 0; k < it->second.size(); ++k)
    {
      a->SetValue(static_cast<vtkIdType>(k), it->second[k]);
    }
    strands->GetCellData()->AddArray(a);
  }
  addField(strands->GetFieldData(), "Time", {frame.time});
}

void toStrands(const GuideDrawing& drawing, vtkPolyData* strands)
{
  toStrands(drawing.header, drawing.frame, strands);
  const vtkIdType n = static_cast<vtkIdType>(drawing.frame.positions.size());
  if (drawing.tangents.size() != std::size_t(n) || drawing.directors.size() != std::size_t(n))
  {
    return;
  }
  vtkSmartPointer<vtkDoubleArray> tangent =
      vtkSmartPointer<vtkDoubleArray>::Take(pointArray("Tangent", 3, n));
  vtkSmartPointer<vtkDoubleArray> director =
      vtkSmartPointer<vtkDoubleArray>::Take(pointArray("Director1", 3, n));
  for (vtkIdType i = 0; i < n; ++i)
  {
    tangent->SetTuple(i, drawing.tangents[i].data());
    director->SetTuple(i, drawing.directors[i].data());
  }
  strands->GetPointData()->AddArray(tangent);
  strands->GetPointData()->AddArray(director);
}

void fromGuides(const std::vector<GuideStrand>& guides,
                const std::vector<std::vector<Eigen::Vector3d>>& polylines, vtkPolyData* strands)
{
  const vtkIdType n = static_cast<vtkIdType>(guides.size());
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkCellArray> lines;
  for (const std::vector<Eigen::Vector3d>& line : polylines)
  {
    lines->InsertNextCell(static_cast<vtkIdType>(line.size()));
    for (const Eigen::Vector3d& x : line)
    {
      lines->InsertCellPoint(points->InsertNextPoint(x.data()));
    }
  }
  strands->Initialize();
  strands->SetPoints(points);
  strands->SetLines(lines);
  vtkCellData* cd = strands->GetCellData();
  vtkNew<vtkIdTypeArray> ids;
  ids->SetName("StrandId");
  ids->SetNumberOfTuples(n);
  for (vtkIdType k = 0; k < n; ++k)
  {
    ids->SetValue(k, k);
  }
  cd->AddArray(ids);
  for (const StrandParameter& p : strandParameters())
  {
    vtkSmartPointer<vtkDoubleArray> a =
        vtkSmartPointer<vtkDoubleArray>::Take(pointArray(p.array, 1, n));
    for (vtkIdType k = 0; k < n; ++k)
    {
      a->SetValue(k, p.get(guides[k]));
    }
    cd->AddArray(a);
  }
  for (const StrandVector& v : strandVectors())
  {
    vtkSmartPointer<vtkDoubleArray> a =
        vtkSmartPointer<vtkDoubleArray>::Take(pointArray(v.array, 3, n));
    for (vtkIdType k = 0; k < n; ++k)
    {
      a->SetTuple(k, v.get(guides[k]).data());
    }
    cd->AddArray(a);
  }
  vtkNew<vtkIntArray> groomed;
  groomed->SetName(GroomedArray);
  groomed->SetNumberOfTuples(n);
  for (vtkIdType k = 0; k < n; ++k)
  {
    groomed->SetValue(k, guides[k].curve.empty() ? 0 : 1);
  }
  cd->AddArray(groomed);
  cd->SetActiveScalars("StrandId");
}

Status toCurves(vtkPolyData* input, std::vector<std::vector<Eigen::Vector3d>>& curves,
                std::vector<Eigen::Vector3d>& normals)
{
  if (!input || input->GetNumberOfLines() == 0)
  {
    return Status::Error("the guide curves input has no polylines: give polylines, root first "
                         "(e.g. a frame of Hair Simulation, or curves drawn in another tool).");
  }
  const vtkIdType firstLine = input->GetNumberOfVerts();
  vtkDataArray* rootNormal = input->GetCellData()->GetArray("RootNormal");
  if (rootNormal && (rootNormal->GetNumberOfComponents() != 3 ||
                     rootNormal->GetNumberOfTuples() < input->GetNumberOfCells()))
  {
    rootNormal = nullptr;
  }
  curves.clear();
  normals.clear();
  vtkNew<vtkIdList> ids;
  vtkCellArray* lines = input->GetLines();
  vtkIdType cell = firstLine;
  for (lines->InitTraversal(); lines->GetNextCell(ids); ++cell)
  {
    std::vector<Eigen::Vector3d> c(static_cast<std::size_t>(ids->GetNumberOfIds()));
    for (vtkIdType i = 0; i < ids->GetNumberOfIds(); ++i)
    {
      input->GetPoint(ids->GetId(i), c[i].data());
    }
    curves.push_back(std::move(c));
    if (rootNormal)
    {
      Eigen::Vector3d n;
      rootNormal->GetTuple(cell, n.data());
      normals.push_back(n);
    }
  }
  return Status::Ok();
}

Status toGuides(vtkPolyData* input, std::vector<GuideStrand>& guides)
{
  if (!input || input->GetNumberOfLines() == 0)
  {
    return Status::Error("the strands input has no polylines: connect Hair Strands.");
  }
  vtkCellData* cd = input->GetCellData();
  const vtkIdType cells = input->GetNumberOfCells(), lines = input->GetNumberOfLines();
  // Cell data run over every cell: vertices, then lines (VTK's order in vtkPolyData).
  const vtkIdType firstLine = input->GetNumberOfVerts();
  auto cellArray = [&](const char* name, int components, vtkDataArray*& a) -> Status
  {
    a = cd->GetArray(name);
    if (!a)
    {
      return Status::Error(std::string("the strands input lacks the cell array '") + name +
                           "': make the strands with Hair Strands.");
    }
    if (a->GetNumberOfComponents() != components || a->GetNumberOfTuples() < cells)
    {
      return Status::Error(std::string("the strands input's cell array '") + name + "' has " +
                           std::to_string(a->GetNumberOfTuples()) + " tuples of " +
                           std::to_string(a->GetNumberOfComponents()) + " components for " +
                           std::to_string(cells) + " cells; it needs one tuple of " +
                           std::to_string(components) +
                           " per cell: make the strands with Hair Strands.");
    }
    return Status::Ok();
  };
  // The vectors read from the input: the root is the polyline's first point (StrandVector).
  std::vector<std::pair<const StrandVector*, vtkDataArray*>> vectors;
  for (const StrandVector& v : strandVectors())
  {
    if (v.input)
    {
      vectors.emplace_back(&v, nullptr);
      if (Status s = cellArray(v.array, 3, vectors.back().second); !s)
      {
        return s;
      }
    }
  }
  const auto& table = strandParameters();
  std::vector<vtkDataArray*> parameters(table.size());
  for (std::size_t p = 0; p < table.size(); ++p)
  {
    if (table[p].optional && !cd->GetArray(table[p].array))
    {
      continue; // keeps the field's default
    }
    if (Status s = cellArray(table[p].array, 1, parameters[p]); !s)
    {
      return s;
    }
  }
  vtkDataArray* groomed = cd->GetArray(GroomedArray);
  if (groomed && (groomed->GetNumberOfComponents() != 1 || groomed->GetNumberOfTuples() < cells))
  {
    return Status::Error(std::string("the strands input's cell array '") + GroomedArray +
                         "' needs one value per cell: make the strands with Hair Strands.");
  }
  vtkCellArray* polylines = input->GetLines();
  vtkNew<vtkIdList> ids;
  std::vector<GuideStrand> out;
  out.reserve(static_cast<std::size_t>(lines));
  vtkIdType cell = firstLine;
  for (polylines->InitTraversal(); polylines->GetNextCell(ids); ++cell)
  {
    if (ids->GetNumberOfIds() == 0)
    {
      return Status::Error("polyline " + std::to_string(cell - firstLine) +
                           " of the strands input has no points: remove it.");
    }
    GuideStrand g;
    input->GetPoint(ids->GetId(0), g.root.data());
    for (const auto& [v, a] : vectors)
    {
      Eigen::Vector3d x;
      a->GetTuple(cell, x.data());
      v->set(g, x);
    }
    for (std::size_t p = 0; p < table.size(); ++p)
    {
      if (parameters[p])
      {
        table[p].set(g, parameters[p]->GetTuple1(cell));
      }
    }
    if (groomed && groomed->GetTuple1(cell) == 1)
    {
      g.curve.resize(static_cast<std::size_t>(ids->GetNumberOfIds()));
      for (vtkIdType i = 0; i < ids->GetNumberOfIds(); ++i)
      {
        input->GetPoint(ids->GetId(i), g.curve[i].data());
      }
    }
    out.push_back(g);
  }
  guides = std::move(out);
  return Status::Ok();
}

void appendGhosts(vtkPolyData* strands, vtkPolyData* ghosts)
{
  const vtkIdType ownCells = strands->GetNumberOfCells(), ownPoints = strands->GetNumberOfPoints();
  vtkNew<vtkAppendPolyData> append;
  vtkNew<vtkPolyData> own;
  own->ShallowCopy(strands);
  append->AddInputData(own);
  append->AddInputData(ghosts);
  append->Update();
  strands->ShallowCopy(append->GetOutput());
  // Field data (the frame's Time) is not appended: the strands' own.
  strands->SetFieldData(own->GetFieldData());
  vtkNew<vtkUnsignedCharArray> cellGhosts, pointGhosts;
  cellGhosts->SetName(vtkDataSetAttributes::GhostArrayName());
  pointGhosts->SetName(vtkDataSetAttributes::GhostArrayName());
  cellGhosts->SetNumberOfTuples(strands->GetNumberOfCells());
  pointGhosts->SetNumberOfTuples(strands->GetNumberOfPoints());
  for (vtkIdType c = 0; c < strands->GetNumberOfCells(); ++c)
  {
    cellGhosts->SetValue(c, c < ownCells ? 0 : vtkDataSetAttributes::DUPLICATECELL);
  }
  for (vtkIdType p = 0; p < strands->GetNumberOfPoints(); ++p)
  {
    pointGhosts->SetValue(p, p < ownPoints ? 0 : vtkDataSetAttributes::DUPLICATEPOINT);
  }
  strands->GetCellData()->AddArray(cellGhosts);
  strands->GetPointData()->AddArray(pointGhosts);
}

Ranks toRanks(vtkMultiProcessController* controller)
{
  vtkMPIController* mpi = vtkMPIController::SafeDownCast(controller);
  if (!mpi || mpi->GetNumberOfProcesses() < 2)
  {
    return Ranks();
  }
  vtkMPICommunicator* communicator = vtkMPICommunicator::SafeDownCast(mpi->GetCommunicator());
  if (!communicator || !communicator->GetMPIComm() || !communicator->GetMPIComm()->GetHandle())
  {
    return Ranks();
  }
  return Ranks(*communicator->GetMPIComm()->GetHandle());
}

void toEnergyTable(const std::vector<double>& times,
                   const std::map<std::string, std::vector<double>>& columns,
                   const std::vector<std::string>& energyTerms, vtkTable* table)
{
  table->Initialize();
  vtkNew<vtkDoubleArray> time;
  time->SetName("Time");
  time->SetNumberOfTuples(static_cast<vtkIdType>(times.size()));
  for (std::size_t i = 0; i < times.size(); ++i)
  {
    time->SetValue(static_cast<vtkIdType>(i), times[i]);
  }
  table->AddColumn(time);
  vtkNew<vtkStringArray> terms;
  terms->SetName("EnergyTerms");
  for (const std::string& term : energyTerms)
  {
    terms->InsertNextValue(term);
  }
  table->GetFieldData()->AddArray(terms);
  for (const auto& [name, values] : columns)
  {
    vtkNew<vtkDoubleArray> column;
    column->SetName(name.c_str());
    column->SetNumberOfTuples(static_cast<vtkIdType>(times.size()));
    for (std::size_t i = 0; i < times.size(); ++i)
    {
      column->SetValue(static_cast<vtkIdType>(i), i < values.size() ? values[i] : 0.0);
    }
    table->AddColumn(column);
  }
}

Status toGuideCurves(vtkPolyData* input, std::vector<GuideStrand>& rest, GuideCurves& curves)
{
  if (Status s = toGuides(input, rest); !s)
  {
    return s;
  }
  vtkCellData* cd = input->GetCellData();
  vtkPointData* pd = input->GetPointData();
  const vtkIdType firstLine = input->GetNumberOfVerts();
  vtkDataArray* restRoot = cd->GetArray("RestRoot");
  if (restRoot && (restRoot->GetNumberOfComponents() != 3 ||
                   restRoot->GetNumberOfTuples() < input->GetNumberOfCells()))
  {
    return Status::Error("the guides' cell array 'RestRoot' needs 3 components per cell.");
  }
  const vtkIdType P = input->GetNumberOfPoints();
  auto inputArray = [&](const char* name, int components) -> vtkDataArray*
  {
    vtkDataArray* a = pd->GetArray(name);
    return a && a->GetNumberOfComponents() == components && a->GetNumberOfTuples() == P ? a
                                                                                        : nullptr;
  };
  vtkDataArray* tangent = inputArray("Tangent", 3);
  vtkDataArray* director = inputArray("Director1", 3);
  GuideCurves c;
  c.offsets.push_back(0);
  std::vector<vtkDataArray*> carried;
  std::vector<std::vector<double>*> carriedOut;
  for (const char* name : {"Speed", "curvature"})
  {
    if (vtkDataArray* a = inputArray(name, 1))
    {
      carried.push_back(a);
      carriedOut.push_back(&c.scalars[name]);
    }
  }
  vtkNew<vtkIdList> ids;
  vtkCellArray* lines = input->GetLines();
  vtkIdType cell = firstLine;
  std::size_t k = 0;
  for (lines->InitTraversal(); lines->GetNextCell(ids); ++cell, ++k)
  {
    if (restRoot)
    {
      restRoot->GetTuple(cell, rest[k].root.data());
    }
    for (vtkIdType i = 0; i < ids->GetNumberOfIds(); ++i)
    {
      const vtkIdType id = ids->GetId(i);
      Eigen::Vector3d x;
      input->GetPoint(id, x.data());
      c.points.push_back(x);
      if (tangent && director)
      {
        Eigen::Vector3d t, d;
        tangent->GetTuple(id, t.data());
        director->GetTuple(id, d.data());
        c.tangents.push_back(t);
        c.directors.push_back(d);
      }
      for (std::size_t a = 0; a < carried.size(); ++a)
      {
        carriedOut[a]->push_back(carried[a]->GetTuple1(id));
      }
    }
    c.offsets.push_back(c.points.size());
  }
  curves = std::move(c);
  return Status::Ok();
}

RenderedHairArrays prepareRenderedHair(vtkPolyData* output, vtkIdType strands, int n,
                                       const std::vector<std::string>& scalarNames,
                                       vtkSmartPointer<vtkCellArray>& lines)
{
  const vtkIdType P = strands * n;
  RenderedHairArrays arrays;
  output->Initialize();
  vtkNew<vtkFloatArray> xyz;
  xyz->SetNumberOfComponents(3);
  xyz->SetNumberOfTuples(P);
  arrays.points = xyz->GetPointer(0);
  vtkNew<vtkPoints> points;
  points->SetData(xyz);
  output->SetPoints(points);
  // The lines depend only on the counts: made once and shared by every frame's output.
  if (!lines || lines->GetNumberOfCells() != strands || lines->GetNumberOfConnectivityIds() != P)
  {
    vtkNew<vtkIdTypeArray> offsets, connectivity;
    offsets->SetNumberOfTuples(strands + 1);
    connectivity->SetNumberOfTuples(P);
    for (vtkIdType r = 0; r <= strands; ++r)
    {
      offsets->SetValue(r, r * n);
    }
    for (vtkIdType i = 0; i < P; ++i)
    {
      connectivity->SetValue(i, i);
    }
    lines = vtkSmartPointer<vtkCellArray>::New();
    lines->SetData(offsets, connectivity);
  }
  output->SetLines(lines);

  auto floats = [&](const char* name, int components)
  {
    vtkNew<vtkFloatArray> a;
    a->SetName(name);
    a->SetNumberOfComponents(components);
    a->SetNumberOfTuples(P);
    output->GetPointData()->AddArray(a);
    return a.GetPointer();
  };
  arrays.tangents = floats("Tangent", 3)->GetPointer(0);
  vtkFloatArray* parameter = floats("ArcParameter", 1);
  output->GetPointData()->SetScalars(parameter);
  arrays.parameter = parameter->GetPointer(0);
  for (const std::string& name : scalarNames)
  {
    arrays.scalars.push_back(
        floats(name == "curvature" ? "Curvature" : name.c_str(), 1)->GetPointer(0));
  }
  vtkNew<vtkIntArray> strandId, guideId;
  strandId->SetName("StrandId");
  guideId->SetName("GuideId");
  strandId->SetNumberOfTuples(strands);
  guideId->SetNumberOfTuples(strands);
  for (vtkIdType r = 0; r < strands; ++r)
  {
    strandId->SetValue(r, static_cast<int>(r));
  }
  arrays.guide = guideId->GetPointer(0);
  output->GetCellData()->AddArray(strandId);
  output->GetCellData()->AddArray(guideId);
  return arrays;
}

void addPushOutCounts(const PushOutCounts& counts, vtkPolyData* output)
{
  auto field = [&](const char* name, double value)
  {
    vtkNew<vtkDoubleArray> a;
    a->SetName(name);
    a->InsertNextValue(value);
    output->GetFieldData()->AddArray(a);
  };
  field("PointsLookedUp", double(counts.lookedUp));
  field("PointsPushedOut", double(counts.pushedOut));
  field("DeepestBeforePushOut", counts.deepest);
  field("PointsInsideAfterPushOut", double(counts.stillInside));
}

} // namespace convert
} // namespace hair

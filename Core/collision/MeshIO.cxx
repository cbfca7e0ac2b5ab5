#include "collision/MeshIO.h"

#include <cmath>
#include <fstream>
#include <sstream>

namespace hair
{

Status readVtkPolyData(const std::string& path, TriangleMesh& mesh)
{
  std::ifstream in(path);
  if (!in)
  {
    return Status::Error("cannot open the mesh file '" + path + "': check the path.");
  }
  std::string line;
  int lineNo = 0;
  auto error = [&](const std::string& what)
  {
    return Status::Error("the mesh file '" + path + "', line " + std::to_string(lineNo) + ": " +
                         what);
  };
  // Header: version line, title, ASCII, DATASET POLYDATA.
  std::vector<std::string> header;
  while (header.size() < 4 && std::getline(in, line))
  {
    ++lineNo;
    header.push_back(line);
  }
  if (header.size() < 4 || header[0].rfind("# vtk DataFile", 0) != 0)
  {
    return error("not a legacy VTK file (it must start with '# vtk DataFile').");
  }
  if (header[2].rfind("ASCII", 0) != 0)
  {
    return error("only ASCII legacy VTK files are read here; save the mesh as ASCII.");
  }
  if (header[3].find("POLYDATA") == std::string::npos)
  {
    return error("the dataset is not POLYDATA.");
  }
  TriangleMesh m;
  std::string keyword;
  while (in >> keyword)
  {
    if (keyword == "POINTS")
    {
      long n = 0;
      std::string type;
      if (!(in >> n >> type) || n < 0)
      {
        return error("a bad POINTS header.");
      }
      m.points.resize(n);
      for (long i = 0; i < n; ++i)
      {
        if (!(in >> m.points[i].x() >> m.points[i].y() >> m.points[i].z()))
        {
          return error("the file ends inside POINTS (point " + std::to_string(i) + " of " +
                       std::to_string(n) + "): it is truncated.");
        }
      }
    }
    else if (keyword == "POLYGONS")
    {
      long n = 0, size = 0;
      if (!(in >> n >> size) || n < 0)
      {
        return error("a bad POLYGONS header.");
      }
      for (long c = 0; c < n; ++c)
      {
        int k = 0;
        if (!(in >> k) || k < 0)
        {
          return error("the file ends inside POLYGONS: it is truncated.");
        }
        std::vector<int> ids(k);
        for (int& id : ids)
        {
          if (!(in >> id))
          {
            return error("the file ends inside POLYGONS: it is truncated.");
          }
        }
        for (int t = 1; t + 1 < k; ++t)
        {
          m.triangles.push_back({ids[0], ids[t], ids[t + 1]});
        }
      }
    }
    else
    {
      break; // point or cell data follow: not needed here
    }
  }
  if (Status s = m.validate("the mesh file '" + path + "'"); !s)
  {
    return s;
  }
  mesh = std::move(m);
  return Status::Ok();
}

Status readBodyParts(const std::string& path, std::vector<BodyPartSpec>& parts)
{
  std::ifstream in(path);
  if (!in)
  {
    return Status::Error("cannot open the body-part list '" + path + "': check the path.");
  }
  std::vector<BodyPartSpec> result;
  std::string line;
  int lineNo = 0;
  while (std::getline(in, line))
  {
    ++lineNo;
    if (auto hash = line.find('#'); hash != std::string::npos)
    {
      line.resize(hash);
    }
    std::istringstream s(line);
    BodyPartSpec part;
    std::string projection, maxRadius;
    if (!(s >> part.name))
    {
      continue;
    }
    TableSpec& t = part.spec;
    if (!(s >> projection >> t.frame.origin.x() >> t.frame.origin.y() >> t.frame.origin.z() >>
          t.frame.axis.x() >> t.frame.axis.y() >> t.frame.axis.z() >> t.frame.reference.x() >>
          t.frame.reference.y() >> t.frame.reference.z() >> t.azimuthSamples >> t.secondSamples >>
          t.heightMin >> t.heightMax >> maxRadius))
    {
      return Status::Error(
          "the body-part list '" + path + "', line " + std::to_string(lineNo) +
          ": expected 'name projection ox oy oz ax ay az rx ry rz azimuthSamples secondSamples "
          "hmin hmax maxRadius'.");
    }
    if (projection == "cylindrical")
    {
      t.projection = Projection::Cylindrical;
    }
    else if (projection == "spherical")
    {
      t.projection = Projection::Spherical;
    }
    else
    {
      return Status::Error("the body-part list '" + path + "', line " + std::to_string(lineNo) +
                           ": projection '" + projection +
                           "' is neither 'cylindrical' nor 'spherical'.");
    }
    t.maxRadius = maxRadius == "inf" ? std::numeric_limits<double>::infinity()
                                     : std::strtod(maxRadius.c_str(), nullptr);
    if (Status v = t.validate(); !v)
    {
      return Status::Error("the body-part list '" + path + "', line " + std::to_string(lineNo) +
                           " (" + part.name + "): " + v.message());
    }
    result.push_back(std::move(part));
  }
  if (result.empty())
  {
    return Status::Error("the body-part list '" + path + "' names no body part.");
  }
  parts = std::move(result);
  return Status::Ok();
}

} // namespace hair
